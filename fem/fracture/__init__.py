"""The rim steel's ductile fracture (issue #31; docs/theory/finite-elements.md, "Rim
fracture", Eqs. F62–F68): the stress triaxiality, a stress-modified critical strain, the
damage it accumulates along a strain path, that damage over the rupture gauge step by step,
and the erosion of the rim elements it tears (:class:`RimFracture`, which
:func:`fem.simulate` runs with ``fracture=``)."""

from .criterion import (
    FRACTURE_SETS,
    StressModifiedStrain,
    accumulate_damage,
    criterion_of,
    triaxiality,
)
from .erosion import RimFracture
from .gauge import GaugeDamage

__all__ = ["FRACTURE_SETS", "GaugeDamage", "RimFracture", "StressModifiedStrain",
           "accumulate_damage", "criterion_of", "triaxiality"]
