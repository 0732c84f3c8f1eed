"""Static push of a restraining rim, its force–deflection curve at small strain or finite
deformation: the bottom plate of the bearing's own mesh, its back face fixed, the upper half of
its +x rim's inner face pushed outward by a prescribed horizontal displacement (a rigid punch
guided horizontally; displacement control passes the limit load), the horizontal reaction and
the hinge of the rim root recorded (docs/theory/finite-elements.md, "Rim push"). Call
:func:`rim_pushover`; :func:`bottom_plate` gives the mesh and its node sets (also used by the
check with CalculiX, ``validation/studies/rim_pushover_ccx.py``)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from rigid.bearing import DFPBearing

__all__ = ["BottomPlate", "PushRecord", "Pushover", "bottom_plate", "rim_pushover"]

#: A push with erosion ends once its force is below this fraction of its peak after a tear.
SEPARATED = 0.02


@dataclass(frozen=True)
class BottomPlate:
    """The bottom plate and rims cut from the bearing's mesh (:func:`bottom_plate`).

    Attributes
    ----------
    mesh : skfem.MeshQuad1
        Coordinates [m]; subdomains ``bottom_plate`` and ``bottom_rim``.
    support : ndarray of int
        Nodes of the plate's back face (fixed).
    face : ndarray of int
        Nodes of the upper half of the +x rim's inner face (pushed), bottom to top.
    root_row : ndarray of int
        Elements of the +x rim's first row above its root (the hinge section).
    depth : float [m]
        Out-of-plane depth of the plane-strain model (forces are per unit depth inside).
    """

    mesh: object
    support: np.ndarray
    face: np.ndarray
    root_row: np.ndarray
    depth: float


@dataclass(frozen=True)
class Pushover:
    """Force–deflection curve of a rim push (:func:`rim_pushover`).

    Attributes
    ----------
    displacement : ndarray [m]
        Horizontal displacement δ of the rim's inner face, from 0.
    force : ndarray [N]
        Horizontal force on the face (3-D: times the model's depth).
    yielded_fraction : ndarray [-]
        Fraction of the root row's quadrature points that have yielded at each step.
    hinge_displacement, hinge_force : float or None [m, N]
        At the first step with the whole root row plastic (the hinge, Eq. F36).
    max_plastic_strain : ndarray [-]
        Largest equivalent plastic strain in the plate at each step.
    averaged_plastic_strain : ndarray [-]
        Largest plastic strain of the pushed rim averaged over the rupture gauge (Eq. F52, a
        disc of the rim thickness) at each step: what the rupture criterion (Eq. F51) reads.
    kinematics : {"small", "finite"}
    dofs : int
    plate : BottomPlate
    final_displacement : ndarray [m]
        Nodal displacements at the last step (plate dofs).
    final_plastic_strain : ndarray [-]
        Equivalent plastic strain at the quadrature points (elements, points) at the last step.
    damage : ndarray [-]
        With ``fracture``: the largest ductile damage of an element of the pushed rim at each
        step (Eqs. F66–F67); an empty array without.
    triaxiality : ndarray [-]
        With ``fracture``: the gauge's triaxiality T̄ at the most damaged point at each step
        (Eq. F66).
    fracture_displacement, fracture_force : float or None [m, N]
        With ``fracture``: at the first step at which an element's damage reached 1 (the
        tear begins).
    torn_elements : int
        With ``fracture``: the pushed rim's elements torn by the end of the push.
    corner : ndarray, shape (steps, 2) [m]
        Where the rim's inner top corner K is at each step (x, z, deformed).
    separated : bool
        With erosion: the push ended because the torn rim was off (its force below
        :data:`SEPARATED` of its peak).
    """

    displacement: np.ndarray
    force: np.ndarray
    yielded_fraction: np.ndarray
    hinge_displacement: float | None
    hinge_force: float | None
    max_plastic_strain: np.ndarray
    averaged_plastic_strain: np.ndarray
    kinematics: str
    dofs: int
    plate: BottomPlate
    final_displacement: np.ndarray
    final_plastic_strain: np.ndarray
    damage: np.ndarray = field(default_factory=lambda: np.zeros(0))
    triaxiality: np.ndarray = field(default_factory=lambda: np.zeros(0))
    fracture_displacement: float | None = None
    fracture_force: float | None = None
    torn_elements: int = 0
    corner: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))
    separated: bool = False


def bottom_plate(bearing: DFPBearing, *, mesh_options: dict | None = None,
                 cache_dir=None) -> BottomPlate:
    """The bottom plate and rims of the bearing's mesh (:func:`fem.geometry.build_mesh`), with
    the node and element sets of the push.

    Parameters
    ----------
    bearing : rigid.DFPBearing
    mesh_options : dict, optional
        :func:`fem.geometry.build_mesh` sizes [m]; default the generator's (5 mm at the rims).
    cache_dir : path-like, optional
        Mesh cache.
    """
    from .dfp import out_of_plane_depth, rim_root_rows
    from .geometry import build_mesh

    full = build_mesh(bearing, cache_dir=cache_dir, **(mesh_options or {})).mesh
    elements = np.concatenate([full.subdomains["bottom_plate"], full.subdomains["bottom_rim"]])
    mesh = full.restrict(np.sort(elements))
    x, z = mesh.p
    tol = 1e-9
    support = np.flatnonzero(np.abs(z + bearing.plate_thickness) < tol)
    z_root = bearing.dish_depth(bearing.rim_radius)
    face = np.flatnonzero((np.abs(x - bearing.rim_radius) < tol)
                          & (z > z_root + 0.5 * bearing.rim_height - tol)
                          & (z < bearing.rim_top + tol))
    face = face[np.argsort(z[face])]
    root = rim_root_rows(mesh, bearing, plates=("bottom",))["bottom +x"]
    return BottomPlate(mesh, support, face, root, out_of_plane_depth(bearing))


class PushRecord:
    """The accepted increments of a push of the +x bottom rim, recorded as a
    :class:`Pushover`: the force, the root row's yielded fraction (the hinge), the plastic
    strains, the corner K, and with ``fracture`` the rim's damage, its first tear and its
    torn elements let go over ``erosion_steps`` increments (Eqs. F66–F68). Shared by the face
    push (:func:`rim_pushover`) and the slider's push (:func:`fem.slider_push.rim_slider_push`).

    Call :meth:`loose` before each increment (the dofs no element holds any more), then
    :meth:`add` with each accepted state (True once the torn rim is off), and
    :meth:`pushover` at the end.
    """

    def __init__(self, bearing: DFPBearing, fe, plate: BottomPlate, fracture=None,
                 erosion_steps: int = 0, crush_jacobian: float | None = None):
        from .limit_states import rim_gauge_average

        self.fe, self.plate = fe, plate
        self.rows = {"d": [0.0], "f": [0.0], "frac": [0.0], "p": [0.0], "avg": [0.0],
                     "damage": [0.0], "triax": [0.0], "corner": [(0.0, 0.0)]}
        self.hinge = self.tear = None
        self.separated = False
        self.tracker = None
        if fracture is not None:
            from .fracture import RimFracture, criterion_of

            self.tracker = RimFracture(criterion_of(fracture, bearing.rupture_strain), fe,
                                       plate.mesh, bearing.rim_thickness, steps=erosion_steps,
                                       rims=("bottom +x",), crush_jacobian=crush_jacobian)
            # the pushed rim's elements and its rupture gauge (Eq. F52)
            self.rim, self.average = self.tracker.elements[0], self.tracker.gauges[0].operator
        else:
            self.rim, self.average = rim_gauge_average(fe, plate.mesh, "bottom +x",
                                                       bearing.rim_thickness)
        self.erosion = bool(erosion_steps)

    def loose(self, fixed: np.ndarray) -> np.ndarray:
        """The dofs, less ``fixed``, that no element holds any more (all of theirs let go);
        empty before the first tear."""
        fe = self.fe
        if getattr(fe, "retained", None) is None:
            return np.zeros(0, dtype=int)
        held = fe.element_dofs[:, fe.retained > 0].ravel()
        return np.setdiff1d(np.setdiff1d(fe.basis.nodal_dofs.ravel(), held), fixed)

    def add(self, delta: float, force: float, u: np.ndarray, state, stress,
            jacobian: np.ndarray | None = None) -> bool:
        """Record one accepted increment: the push δ [m], its force [N], the displacements
        [m], the material state, the stresses [Pa] and det F (nelems, nqp) [-] (for crushing,
        Eq. F67b). True once the torn rim is off (the force below :data:`SEPARATED` of its peak
        after a tear, with erosion)."""
        out, p = self.rows, state.eq_plastic_strain
        frac = float((p[self.plate.root_row] > 0).mean())
        out["d"].append(delta)
        out["f"].append(force)
        out["frac"].append(frac)
        out["p"].append(float(p.max()))
        out["avg"].append(float((self.average @ p[self.rim].ravel()).max()))
        out["corner"].append(u[self.fe.basis.nodal_dofs[:, self.plate.face[-1]]])
        if self.hinge is None and frac >= 1.0:
            self.hinge = (delta, force)
        tracker = self.tracker
        if tracker is None:
            return False
        if tracker.update(delta, p, stress, jacobian):
            self.fe.retained = tracker.retained.copy()
        out["damage"].append(tracker.rim_damage[0])
        out["triax"].append(tracker.rim_triaxiality[0])
        if self.tear is None and tracker.first_tear is not None:
            self.tear = (delta, force)
        self.separated = (self.tear is not None and self.erosion
                          and force < SEPARATED * max(out["f"]))
        return self.separated

    def pushover(self, kinematics: str, u: np.ndarray, state) -> Pushover:
        """The push recorded, its last displacements [m] and material state."""
        out, tracker = self.rows, self.tracker
        hinge, tear = self.hinge, self.tear
        return Pushover(
            displacement=np.array(out["d"]), force=np.array(out["f"]),
            yielded_fraction=np.array(out["frac"]),
            hinge_displacement=None if hinge is None else hinge[0],
            hinge_force=None if hinge is None else hinge[1],
            max_plastic_strain=np.array(out["p"]),
            averaged_plastic_strain=np.array(out["avg"]), kinematics=kinematics,
            dofs=self.fe.ndofs, plate=self.plate, final_displacement=u,
            final_plastic_strain=state.eq_plastic_strain,
            damage=np.array(out["damage"]) if tracker is not None else np.zeros(0),
            triaxiality=np.array(out["triax"]) if tracker is not None else np.zeros(0),
            fracture_displacement=None if tear is None else tear[0],
            fracture_force=None if tear is None else tear[1],
            torn_elements=0 if tracker is None else len(tracker.torn),
            corner=self.plate.mesh.p[:, self.plate.face[-1]] + np.array(out["corner"]),
            separated=self.separated,
        )


def rim_pushover(bearing: DFPBearing, *, kinematics: str = "finite",
                 displacement: float | None = None, steps: int = 40,
                 mesh_options: dict | None = None, plasticity: bool = True,
                 fracture=None, erosion_steps: int = 0, stop_short: bool = False,
                 cache_dir=None) -> Pushover:
    """Push the +x bottom rim outward by a uniform horizontal displacement of the upper half of
    its inner face.

    The plate's back face is fixed; every node of the upper half of the rim's inner face gets
    the horizontal displacement δ (their vertical displacement is free), in Newton increments
    of at most 1/``steps`` of the final ``displacement`` (halved when Newton fails), each
    accepted state recorded.

    Parameters
    ----------
    bearing : rigid.DFPBearing
        Geometry and steel (``rim_height``, ``rim_thickness``, ``yield_stress``, …).
    kinematics : {"finite", "small"}
    displacement : float [m], optional
        Final δ; default half the rim height.
    steps : int
        Increments at most (an increment whose Newton iteration fails is halved).
    mesh_options : dict, optional
        :func:`fem.geometry.build_mesh` sizes [m].
    plasticity : bool
        False keeps the steel elastic.
    fracture : {"steep", "median", "mild"} or fem.fracture.StressModifiedStrain, optional
        Track the pushed rim's ductile damage (as :func:`fem.simulate` does) and record where
        it first tears.
    erosion_steps : int
        With ``fracture``: N > 0 lets each torn element go over N accepted increments (Eq.
        F68, as :func:`fem.simulate` does over time steps) and ends the push once the force
        has fallen below :data:`SEPARATED` of its peak after a tear (the rim is off); 0
        (default) lets nothing go.
    stop_short : bool
        Where Newton fails even with tiny increments, return the push as far as it went
        (its ``displacement[-1]`` short of the final δ) instead of raising RuntimeError.
    cache_dir : path-like, optional
        Mesh cache.

    Returns
    -------
    Pushover
    """
    from .assembly import PlaneStrainQ1
    from .finite_element import FiniteStrainQ1
    from .hencky import FiniteState
    from .material import Material, MaterialState
    from .newton import solve_increment

    if kinematics not in ("small", "finite"):
        raise ValueError(f"kinematics must be 'small' or 'finite', got {kinematics!r}")
    if int(steps) != steps or steps < 1:
        raise ValueError(f"steps must be a positive integer, got {steps!r}")
    if erosion_steps and (fracture is None or kinematics != "finite"):
        raise ValueError("erosion_steps needs fracture and finite kinematics (the torn "
                         "elements let go through the finite-strain element's weights)")
    delta_end = 0.5 * bearing.rim_height if displacement is None else float(displacement)
    if not (math.isfinite(delta_end) and delta_end > 0):
        raise ValueError(f"displacement must be a positive length [m], got {displacement!r}")
    plate = bottom_plate(bearing, mesh_options=mesh_options, cache_dir=cache_dir)
    fe = FiniteStrainQ1(plate.mesh) if kinematics == "finite" else PlaneStrainQ1(plate.mesh)
    steel = Material.from_bearing(bearing)
    steel = steel if plasticity else steel.elastic()
    nd = fe.basis.nodal_dofs
    fixed = np.concatenate([nd[0, plate.support], nd[1, plate.support], nd[0, plate.face]])
    n_support = 2 * plate.support.size
    state = (FiniteState if kinematics == "finite" else MaterialState).virgin(fe.point_shape)
    u, zero = np.zeros(fe.ndofs), np.zeros(fe.ndofs)
    record = PushRecord(bearing, fe, plate, fracture, erosion_steps)
    delta, h = 0.0, delta_end / steps
    while delta < delta_end * (1 - 1e-12):
        target = min(delta + h, delta_end)
        values = np.concatenate([np.zeros(n_support), np.full(plate.face.size, target)])
        loose = record.loose(fixed)  # nodes whose elements all let go: held
        held = np.concatenate([fixed, loose])
        kept = np.concatenate([values, u[loose]])
        res = solve_increment(fe, steel, state, u, zero, held, kept, rtol=1e-8, max_iter=15)
        if not res.converged:  # cut the increment back
            h *= 0.5
            if h < 1e-6 * delta_end:
                if stop_short:
                    break
                raise RuntimeError(f"rim push: Newton did not converge beyond δ = {delta:.4g} m "
                                   f"even with increments of {h:.2g} m")
            continue
        delta, u, state = target, res.displacement, res.state
        if res.iterations <= 6:
            h = min(2.0 * h, delta_end / steps)
        force = float(res.internal_force[nd[0, plate.face]].sum()) * plate.depth
        if record.add(delta, force, u, state, res.stress):
            break  # the rim is off: nothing left to push
    return record.pushover(kinematics, u, state)
