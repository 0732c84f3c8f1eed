"""The rim steel's ductile fracture (issue #31; docs/theory/finite-elements.md, "Rim
fracture", Eqs. F62–F66): the stress triaxiality, a stress-modified critical strain, the
damage it accumulates along a strain path, and that damage over the rupture gauge step by
step. Not yet used by an FE run."""

from .criterion import FRACTURE_SETS, StressModifiedStrain, accumulate_damage, triaxiality
from .gauge import GaugeDamage

__all__ = ["FRACTURE_SETS", "GaugeDamage", "StressModifiedStrain", "accumulate_damage",
           "triaxiality"]
