"""Fragility fit and collapse margin (rigid.collapse.fragility) against closed forms written
here."""

import math

import numpy as np
import pytest
from scipy import optimize, stats

from rigid import G
from rigid.collapse.fragility import collapse_margin, fit_lognormal, set_collapse_intensity
from rigid.collapse.ladder import CriticalSA


def _result(sa, record_sa, stop=3 * G):
    return CriticalSA(sa, None if sa is None else sa / record_sa, "r", record_sa, 4.5,
                      0.01 * G, 0.01 * G, stop, "full", ())


def test_fit_without_censoring_is_the_closed_form_mle():
    """No censoring: median = exp(mean ln x), β = std(ln x, ddof=0). rel 1e-4: scipy solves
    the same likelihood numerically (its optimiser stops at ~1e-6)."""
    x = np.exp(np.random.default_rng(0).normal(np.log(0.6 * G), 0.45, 30))
    fit = fit_lognormal(list(x))
    assert fit.median == pytest.approx(math.exp(np.mean(np.log(x))), rel=1e-4)
    assert fit.beta == pytest.approx(np.std(np.log(x)), rel=1e-4)
    assert (fit.n, fit.n_censored) == (30, 0)
    assert fit.probability(fit.median) == pytest.approx(0.5, abs=1e-12)
    assert fit.probability(fit.median * math.exp(fit.beta)) == pytest.approx(
        stats.norm.cdf(1.0), abs=1e-12)


def test_censored_fit_matches_an_independent_likelihood():
    """Records without failure are right-censored at their ladder top. Oracle: the censored
    normal log-likelihood of ln x, written here and maximised with Nelder-Mead (tolerances
    1e-10), parameters agree to 1e-3 relative (the two optimisers' stopping rules)."""
    rng = np.random.default_rng(1)
    x = np.exp(rng.normal(np.log(1.0 * G), 0.5, 40))
    top = 1.3 * G
    results = [_result(v if v <= top else None, 0.2 * G, stop=top) for v in x]
    fit = fit_lognormal(results)
    failed = np.log([v for v in x if v <= top])
    n_cens = int(np.sum(x > top))

    def nll(p):
        mu, s = p
        return -(np.sum(stats.norm.logpdf(failed, mu, s))
                 + n_cens * stats.norm.logsf(math.log(top), mu, s))

    opt = optimize.minimize(nll, [np.mean(failed), np.std(failed)], method="Nelder-Mead",
                            options={"xatol": 1e-10, "fatol": 1e-10, "maxiter": 4000})
    assert n_cens > 3 and fit.n_censored == n_cens
    assert fit.median == pytest.approx(math.exp(opt.x[0]), rel=1e-3)
    assert fit.beta == pytest.approx(opt.x[1], rel=1e-3)


def test_set_scaling_equals_per_record_median_for_equal_spectra():
    """If every normalised record has the same SA(T), scaling the set by one factor *is*
    scaling each record to the same SA, so Ŝ_CT equals the median per-record critical SA
    (exact up to round-off, rel 1e-12)."""
    crit = np.array([0.5, 0.8, 0.6, 1.1, 0.7]) * G
    nm = np.array([0.5, 2.0, 1.0, 4.0, 0.25])
    rec = 0.3 * G / nm  # SA as recorded; NM·SA = 0.3 g for all
    res = [_result(c, r) for c, r in zip(crit, rec, strict=True)]
    assert set_collapse_intensity(res, nm) == pytest.approx(np.median(crit), rel=1e-12)


def test_set_scaling_general_case():
    """Ŝ_CT = median_i(SA_crit,i / SA_norm,i)·geomean(SA_norm), with one record that never
    fails (its factor is ∞, above the median)."""
    crit = [0.5 * G, 0.9 * G, None]
    sa_norm = np.array([0.2, 0.4, 0.1]) * G
    res = [_result(c, s) for c, s in zip(crit, sa_norm, strict=True)]
    k = sorted([0.5 / 0.2, 0.9 / 0.4, math.inf])[1]
    expected = k * (0.2 * 0.4 * 0.1) ** (1 / 3) * G
    assert set_collapse_intensity(res) == pytest.approx(expected, rel=1e-12)


def test_collapse_margin_closed_forms():
    """CMR = median/S_MT; ACMR = SSF·CMR; ACMR20 = exp(β_TOT·Φ⁻¹(0.8)) (FEMA P695 §7.4,
    Table 7-3, the lognormal quantile); β_TOT = √(β_RTR² + 3·0.2²) rounded to 0.025 for
    ratings B (0.2 each), β_RTR = 0.1 + 0.1·μT; S_MT = S_M1/T at a long period.
    rel 1e-9 (closed forms; the median is a numerical MLE, rel 1e-4)."""
    crit = np.exp(np.random.default_rng(2).normal(np.log(0.8 * G), 0.4, 20))
    res = [_result(c, 0.2 * G) for c in crit]
    cm = collapse_margin(res, 0.3 * G, period=4.5, mu_t=2.0, sdc="dmax")
    median = math.exp(np.mean(np.log(crit)))
    assert cm.median_critical_sa == pytest.approx(median, rel=1e-4)
    assert cm.cmr == pytest.approx(cm.median_critical_sa / (0.3 * G), rel=1e-12)
    assert cm.acmr == pytest.approx(cm.ssf * cm.cmr, rel=1e-12)
    beta = round(math.sqrt(0.3**2 + 3 * 0.2**2) * 40) / 40
    assert cm.beta_total == pytest.approx(beta, rel=1e-12)
    assert cm.acmr20 == pytest.approx(math.exp(beta * stats.norm.ppf(0.8)), rel=1e-9)
    assert cm.acmr10 == pytest.approx(math.exp(beta * stats.norm.ppf(0.9)), rel=1e-9)
    assert cm.ssf > 1.0  # μT > 1 earns spectral-shape credit (App. B, β1 > 0)
    assert cm.s_ct_set == pytest.approx(set_collapse_intensity(res), rel=1e-12)
    no_credit = collapse_margin(res, 0.3 * G, mu_t=1.0, set_scaling=False)
    assert no_credit.ssf == pytest.approx(1.0, abs=1e-12) and no_credit.s_ct_set is None
    # default S_MT from the SDC: S_M1/T with S_M1 = 0.9 g for Dmax (FEMA P695 Table 5-1)
    default = collapse_margin(res, period=4.5, sdc="dmax")
    assert default.s_mt == pytest.approx(0.9 / 4.5 * G, rel=1e-9)


def test_bad_input():
    with pytest.raises(ValueError, match="two failing"):
        fit_lognormal([0.5 * G])
    with pytest.raises(ValueError, match="stop"):
        fit_lognormal([0.5 * G, 0.6 * G, None])
    with pytest.raises(ValueError, match="s_mt"):
        collapse_margin([0.5 * G, 0.6 * G], -1.0, set_scaling=False)
