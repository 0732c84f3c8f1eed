"""The rim's damage over the rupture gauge, step by step (docs/theory/finite-elements.md,
Eq. F66): what an FE run will accumulate at every accepted step in place of the uniaxial
rupture of Eq. F51, with the same non-local average (Eq. F52).

    damage = GaugeDamage(criterion, operator)        # operator: fem.limit_states.rim_gauge_average
    for p, stress in steps:                          # per quadrature point of the rim
        d = damage.update(p, stress)                 # the gauge-averaged damage, per point
"""

from __future__ import annotations

import numpy as np

from .criterion import StressModifiedStrain, triaxiality

__all__ = ["GaugeDamage"]


class GaugeDamage:
    """Damage accumulated over a gauge (Eq. F66).

    Each step, the gauge averages of the equivalent plastic strain increments, Δp̄ = A Δp,
    and of the triaxiality weighted by them, T̄ = A(T Δp)/A Δp, give D̄ += Δp̄ / ε_c(T̄).
    With the exponent c = 0 this is the rupture of Eq. F51: D̄ = p̄/ε_r.

    Parameters
    ----------
    criterion : StressModifiedStrain
    operator : sparse matrix or ndarray, shape (m, n)
        The gauge average A: from the n quadrature points of the rim to the m points where
        the damage is read (:func:`fem.limit_states.rim_gauge_average`).

    Attributes
    ----------
    damage : ndarray, shape (m,) [-]
    triaxiality : ndarray, shape (m,) [-]
        T̄ at each gauge point in the last step in which its plastic strain grew.
    """

    def __init__(self, criterion: StressModifiedStrain, operator):
        self.criterion = criterion
        self.operator = operator
        self.damage = np.zeros(operator.shape[0])
        self.triaxiality = np.zeros(operator.shape[0])  # T̄ of the last step with growth
        self._plastic_strain = np.zeros(operator.shape[1])

    def update(self, plastic_strain, stress, intact=None) -> np.ndarray:
        """Add the step that brought the rim's points to ``plastic_strain`` [-] (n) under
        Mandel ``stress`` (n, 4) [Pa]; return the damage at the m gauge points.

        ``intact`` (n bools, optional) leaves out the points of torn elements: their strain
        adds nothing, and the averages are taken over the intact points alone (Eq. F67)."""
        p = np.asarray(plastic_strain, dtype=float)
        dp = np.maximum(p - self._plastic_strain, 0.0)
        self._plastic_strain = p.copy()
        share = 1.0
        if intact is not None:
            keep = np.asarray(intact, dtype=float)
            dp = dp * keep
            share = self.operator @ keep  # the intact fraction of each gauge
            share = np.where(share > 0.0, share, np.inf)  # a gauge wholly torn: no growth
        mean_dp = (self.operator @ dp) / share
        weighted = (self.operator @ (triaxiality(stress) * dp)) / share
        with np.errstate(invalid="ignore", divide="ignore"):
            mean_t = np.where(mean_dp > 0.0, weighted / np.where(mean_dp > 0, mean_dp, 1.0),
                              0.0)
        self.damage += self.criterion.damage_increment(mean_dp, mean_t)
        self.triaxiality = np.where(mean_dp > 0.0, mean_t, self.triaxiality)
        return self.damage.copy()
