r"""The stress-modified critical strain of the rim steel and the damage it accumulates
(docs/theory/finite-elements.md, "Rim fracture", Eqs. F62–F65).

Stresses are Mandel 4-vectors ``[xx, yy, zz, √2·xy]`` [Pa] as in :mod:`fem.material` (plane
strain carries σ_zz). Strains are equivalent plastic strains [-].

    crit = FRACTURE_SETS["median"](rupture_strain=bearing.rupture_strain)
    damage = accumulate_damage(crit, plastic_strain_increments, triaxialities)
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["FRACTURE_SETS", "StressModifiedStrain", "accumulate_damage", "criterion_of",
           "triaxiality"]

#: Stress triaxiality of uniaxial tension, where the critical strain is the rupture strain
#: of a tensile test (Eq. F63).
UNIAXIAL = 1.0 / 3.0
#: No ductile damage at or below this triaxiality (Eq. F64; Bao & Wierzbicki 2005).
CUTOFF = -1.0 / 3.0


def triaxiality(stress: np.ndarray) -> np.ndarray:
    """Stress triaxiality T = σ_m/σ_eq (Eq. F62) of Mandel stresses ``(..., 4)`` [Pa]; 0
    where the stress is nil (no deviator: T would be undefined, and no plastic strain grows
    there)."""
    s = np.asarray(stress, dtype=float)
    mean = s[..., :3].sum(axis=-1) / 3.0
    dev = s.copy()
    dev[..., :3] -= mean[..., None]
    eq = np.sqrt(1.5 * np.einsum("...i,...i->...", dev, dev))
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(eq > 0.0, mean / np.where(eq > 0.0, eq, 1.0), 0.0)


@dataclass(frozen=True)
class StressModifiedStrain:
    """The critical equivalent plastic strain ε_c(T) = ε_r exp(−c (T − 1/3)) (Eq. F63).

    Attributes
    ----------
    rupture_strain : float [-]
        ε_r: the critical strain in uniaxial tension (T = 1/3), the bearing's
        ``rupture_strain`` (Eq. F51).
    exponent : float [-]
        c: how fast the critical strain falls with the triaxiality (1.5: Rice & Tracey).
    """

    rupture_strain: float = 0.1906
    exponent: float = 1.5

    def __post_init__(self):
        if not (self.rupture_strain > 0 and math.isfinite(self.rupture_strain)):
            raise ValueError(f"rupture_strain must be positive, got {self.rupture_strain}")
        if not (self.exponent >= 0 and math.isfinite(self.exponent)):
            raise ValueError(f"exponent must be non-negative, got {self.exponent}")

    def critical_strain(self, triax) -> np.ndarray:
        """ε_c at stress triaxiality ``triax`` (Eq. F63); inf at or below the cut-off
        T = −1/3 (Eq. F64), where no damage accrues."""
        t = np.asarray(triax, dtype=float)
        with np.errstate(over="ignore"):
            crit = self.rupture_strain * np.exp(-self.exponent * (t - UNIAXIAL))
        return np.where(t > CUTOFF, crit, np.inf)

    def damage_increment(self, plastic_strain_increment, triax) -> np.ndarray:
        """ΔD = Δp / ε_c(T) (Eq. F64) of equivalent plastic strain increments [-] at
        triaxialities ``triax``."""
        return np.asarray(plastic_strain_increment, dtype=float) / self.critical_strain(triax)


def accumulate_damage(criterion: StressModifiedStrain, plastic_strain_increments,
                      triaxialities) -> np.ndarray:
    """The damage D along a strain path (Eq. F64): the running sum over the increments (the
    first axis) of Δp/ε_c(T), each at its own triaxiality; tearing where D ≥ 1."""
    increments = criterion.damage_increment(plastic_strain_increments, triaxialities)
    return np.cumsum(increments, axis=0)


#: Three sets of the criterion, named by how steeply the critical strain falls with the
#: triaxiality: the exponent c from published values of the triaxiality term
#: (docs/theory/finite-elements.md, "Rim fracture": 2.12, Johnson & Cook 1985's 4340 steel;
#: 1.5, Rice & Tracey 1969; 0.47, Johnson & Cook's Armco iron), each anchored at the bearing's
#: uniaxial rupture strain. Steeper is less ductile above T = 1/3 (tension) and more ductile
#: below it (shear), where the rims tear. Call with ``rupture_strain=``.
FRACTURE_SETS = {
    "steep": lambda rupture_strain=0.1906: StressModifiedStrain(rupture_strain, 2.12),
    "median": lambda rupture_strain=0.1906: StressModifiedStrain(rupture_strain, 1.5),
    "mild": lambda rupture_strain=0.1906: StressModifiedStrain(rupture_strain, 0.47),
}


def criterion_of(fracture, rupture_strain: float) -> StressModifiedStrain:
    """The criterion that ``fracture`` names: a set of :data:`FRACTURE_SETS` (``"steep"``,
    ``"median"``, ``"mild"``) anchored at ``rupture_strain`` [-], or a
    :class:`StressModifiedStrain` given as it is."""
    if isinstance(fracture, str):
        if fracture not in FRACTURE_SETS:
            raise ValueError(f"fracture must be one of {', '.join(FRACTURE_SETS)} or a "
                             f"StressModifiedStrain, got {fracture!r}")
        return FRACTURE_SETS[fracture](rupture_strain=rupture_strain)
    if not isinstance(fracture, StressModifiedStrain):
        raise TypeError(f"fracture must be a set's name or a StressModifiedStrain, got "
                        f"{type(fracture).__name__}")
    return fracture
