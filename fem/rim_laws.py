"""The yielding rims' law computed by the FE companion: :func:`rim_law` pushes the bearing's
rim (:func:`fem.rim_pushover`, finite deformation, default mesh) and builds the law that the
rigid model takes as data (:class:`rigid.rims.RimLaw`, :func:`rigid.rims.rim_law_from_push`;
docs/theory/rigid-body.md, "Yielding rims", Eqs. R55–R57; docs/theory/finite-elements.md,
"Rim push").

Call ``law = fem.rim_law(bearing)`` and pass it on: ``rigid.simulate(bearing, a, dt,
rims="yielding", rim_law=law)``.
"""

from __future__ import annotations

import functools
import math

from rigid.bearing import DFPBearing
from rigid.rims import (
    ELASTIC_PUSH,
    FINE_PUSH,
    TEARING_PUSH,
    RimLaw,
    load_rim_law,
    rim_law_cache_file,
    rim_law_from_push,
    rim_law_through_tearing,
    save_rim_law,
)

from .pushover import rim_pushover
from .slider_push import EDGE_RADIUS, rim_slider_push

__all__ = ["PUNCHES", "rim_law"]

#: What pushes the plane-strain rim for its law (:func:`rim_law`'s ``punch``).
PUNCHES = ("face", "slider")


def rim_law(bearing: DFPBearing, *, model: str = "plane-strain", fracture: str | None = None,
            punch: str = "face", edge_radius: float = EDGE_RADIUS,
            crush_jacobian: float | None = None, cache: bool = True) -> RimLaw:
    """The law of the bearing's rims, from pushes of its rim by the FE companion, cached in the
    library's cache folder (:func:`rigid.rims.rim_law_cache_file`) per model, geometry and
    steel.

    Parameters
    ----------
    bearing : DFPBearing
        Its rims' geometry, steel and rupture strain (the pressure does not matter).
    model : {"plane-strain", "ring"}
        ``"plane-strain"``: pushes of the 2-D rim (finite deformation, default mesh;
        docs/theory/finite-elements.md, "Rim push") times the depth πb/4 (Eqs. F1–F3), about
        20 s of CPU the first time. ``"ring"``: the 3-D push of the rim as a ring by the
        slider, a rigid cylinder (small strain, default 3-D mesh; "The rim as a ring", Eqs.
        F54–F58), minutes of CPU the first time.
    fracture : {"steep", "median", "mild"}, optional
        The law through tearing (plane strain only): the push goes on with the rim's ductile
        damage and lets its torn elements go (Eqs. F66–F68) until the rim is off, and the law
        follows the falling force and the corner's height (Eqs. R55b, R56c, R64;
        :func:`rigid.rims.rim_law_through_tearing`), about a minute of CPU the first time.
    punch : {"face", "slider"}
        What pushes the plane-strain rim: ``"face"`` (default) a uniform displacement of the
        upper half of its inner face (:func:`fem.rim_pushover`); ``"slider"`` the slider
        itself moved along its pendulum path into the rim, through the penalty contact
        (:func:`fem.slider_push.rim_slider_push`, Eq. F71), for the elastic, the fine and the
        tearing pushes alike: the law through tearing only (``fracture`` needed), a few
        minutes of CPU the first time. The slider tears a thick rim that the face push does
        not (docs/fe-companion.md, "The rim pushed by the slider").
    edge_radius : float [m]
        With ``punch="slider"``: the slider's rounded edges (default 20 mm).
    crush_jacobian : float [-], optional
        With ``fracture``: the push through tearing also crushes the rim's elements below this
        det F and lets the faces they uncover carry contact (Eqs. F67b, F68c; default none).
    cache : bool
        Read and write the cache.

    Returns
    -------
    rigid.rims.RimLaw
    """
    if punch not in PUNCHES:
        raise ValueError(f"punch must be one of {', '.join(PUNCHES)}, got {punch!r}")
    if punch == "slider" and fracture is None:
        raise ValueError("punch='slider' gives the law through tearing: give fracture= (the "
                         "law without tearing comes from the face push)")
    path = rim_law_cache_file(bearing, model, fracture,
                              edge_radius=edge_radius if punch == "slider" else None,
                              crush_jacobian=crush_jacobian)
    if cache and path.exists():
        return load_rim_law(path)
    if model == "ring":
        law = _ring_law(bearing)
    elif punch == "slider":
        law = _plane_strain_law(bearing, fracture, functools.partial(
            rim_slider_push, edge_radius=edge_radius), crush_jacobian)
    else:
        if crush_jacobian is not None:
            raise ValueError("crush_jacobian goes with punch='slider'")
        law = _plane_strain_law(bearing, fracture, rim_pushover)
    if cache:
        save_rim_law(law, path)
    return law


def _plane_strain_law(bearing: DFPBearing, fracture: str | None, push,
                      crush_jacobian: float | None = None) -> RimLaw:
    """The law from pushes of the plane-strain rim by ``push`` (:func:`fem.rim_pushover` or
    :func:`fem.slider_push.rim_slider_push`): elastic, fine to the hinge, then to half the
    rim height (without ``fracture``) or through tearing (with; crushing too with
    ``crush_jacobian``)."""
    elastic = push(bearing, displacement=ELASTIC_PUSH, steps=2, plasticity=False)
    stiffness = float(elastic.force[-1] / elastic.displacement[-1])
    reach, steps = FINE_PUSH
    fine = push(bearing, displacement=reach, steps=steps)
    while fine.hinge_displacement is None and 2 * reach <= bearing.rim_height / 2:
        reach, steps = 2 * reach, 2 * steps
        fine = push(bearing, displacement=reach, steps=steps)
    if fracture is None:
        return rim_law_from_push(bearing, stiffness, fine, push(bearing))
    increment, erosion_steps = TEARING_PUSH
    reach = bearing.rim_thickness + bearing.rim_height
    crush = {} if crush_jacobian is None else {"crush_jacobian": crush_jacobian}
    torn = push(bearing, displacement=reach, steps=round(reach / increment),
                fracture=fracture, erosion_steps=erosion_steps, stop_short=True, **crush)
    return rim_law_through_tearing(bearing, stiffness, fine, torn)


def _ring_law(bearing: DFPBearing) -> RimLaw:
    """The law from one 3-D push by the cylinder to half the rim height: its curve, hinge and
    gauge-averaged plastic strain (Eq. F58) in the roles of the 2-D pushes'."""
    from types import SimpleNamespace

    from .ring import Load, ring_push

    elastic = ring_push(bearing, Load("cylinder"), displacement=ELASTIC_PUSH, plasticity=False)
    stiffness = float(elastic.force[-1] / elastic.displacement[-1])
    push = ring_push(bearing, Load("cylinder"))
    hinged = math.isfinite(push.hinge_displacement)
    curve = SimpleNamespace(
        displacement=push.displacement, force=push.force,
        averaged_plastic_strain=push.gauge_plastic_strain,
        hinge_displacement=push.hinge_displacement if hinged else None,
        hinge_force=push.hinge_force if hinged else None)
    return rim_law_from_push(bearing, stiffness, curve, curve)


def effective_rim_depth(bearing: DFPBearing, limit_state: str) -> float:
    """The 3-D rim's effective depth at a limit state [m] (Eq. F59): the force of the 3-D push
    of the rim as a ring at that state over the 2-D push's force per unit depth there, so that
    the plane-strain rim given this depth carries the ring's force at the state checked.

    Parameters
    ----------
    bearing : DFPBearing
    limit_state : {"hinge", "rupture", "containment"}
        The hinge, the rupture strain, or (for the loss of containment) the push's largest
        force.

    Returns
    -------
    float [m]
        ValueError if either push does not reach the state.
    """
    import numpy as np

    from rigid.limit_states import check_limit_state

    from .dfp import out_of_plane_depth

    limit_state = check_limit_state(limit_state)

    def force(law: RimLaw) -> float:
        if limit_state == "hinge":
            return law.hinge_force
        if limit_state == "rupture":
            if not math.isfinite(law.rupture_displacement):
                raise ValueError("the rim does not reach the rupture strain within the push")
            return float(np.interp(law.rupture_displacement, law.push_displacement,
                                   law.push_force))
        return float(np.max(law.push_force))

    ring, plane = rim_law(bearing, model="ring"), rim_law(bearing)
    return force(ring) / force(plane) * out_of_plane_depth(bearing)
