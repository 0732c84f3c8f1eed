"""The rim steel's ductile fracture (issue #31; docs/theory/finite-elements.md, "Rim
fracture", Eqs. F62–F65): the stress triaxiality, a stress-modified critical strain and the
damage it accumulates along a strain path. Not yet used by an FE run."""

from .criterion import FRACTURE_SETS, StressModifiedStrain, accumulate_damage, triaxiality

__all__ = ["FRACTURE_SETS", "StressModifiedStrain", "accumulate_damage", "triaxiality"]
