"""The yielding rims' law computed by the FE companion: :func:`rim_law` pushes the bearing's
rim (:func:`fem.rim_pushover`, finite deformation, default mesh) and builds the law that the
rigid model takes as data (:class:`rigid.rims.RimLaw`, :func:`rigid.rims.rim_law_from_push`;
docs/theory/rigid-body.md, "Yielding rims", Eqs. R55–R57; docs/theory/finite-elements.md,
"Rim push").

Call ``law = fem.rim_law(bearing)`` and pass it on: ``rigid.simulate(bearing, a, dt,
rims="yielding", rim_law=law)``.
"""

from __future__ import annotations

from rigid.bearing import DFPBearing
from rigid.rims import (
    ELASTIC_PUSH,
    FINE_PUSH,
    RimLaw,
    load_rim_law,
    rim_law_cache_file,
    rim_law_from_push,
    save_rim_law,
)

from .pushover import rim_pushover

__all__ = ["rim_law"]


def rim_law(bearing: DFPBearing, *, cache: bool = True) -> RimLaw:
    """The law of the bearing's rims, from pushes of the FE companion's rim (finite
    deformation, default mesh; docs/theory/finite-elements.md, "Rim push"), cached in the
    library's cache folder (:func:`rigid.rims.rim_law_cache_file`) per geometry and steel; the
    first call for a bearing runs the pushes (about 20 s of CPU).

    Parameters
    ----------
    bearing : DFPBearing
        Its rims' geometry, steel and rupture strain (the pressure does not matter).
    cache : bool
        Read and write the cache.

    Returns
    -------
    rigid.rims.RimLaw
    """
    path = rim_law_cache_file(bearing)
    if cache and path.exists():
        return load_rim_law(path)
    elastic = rim_pushover(bearing, displacement=ELASTIC_PUSH, steps=2, plasticity=False)
    stiffness = float(elastic.force[-1] / elastic.displacement[-1])
    reach, steps = FINE_PUSH
    fine = rim_pushover(bearing, displacement=reach, steps=steps)
    while fine.hinge_displacement is None and 2 * reach <= bearing.rim_height / 2:
        reach, steps = 2 * reach, 2 * steps
        fine = rim_pushover(bearing, displacement=reach, steps=steps)
    full = rim_pushover(bearing)
    law = rim_law_from_push(bearing, stiffness, fine, full)
    if cache:
        save_rim_law(law, path)
    return law
