"""Predicted critical SA (rigid.collapse.predict): exactness on a pure pulse, ladder arithmetic,
search.

The pure-pulse cases run the rigid model (0.01 g ladders on 13-18 s records); the
ladder-arithmetic cases use stub regions with a closed-form answer.
"""

import math

import numpy as np
import pytest

from rigid import G, Pulse, pseudo_acceleration, ricker_record
from rigid.collapse.ladder import critical_sa
from rigid.collapse.predict import predict_critical_sa, pulse_region

DT = 0.01
STEP = 0.01 * G  # the paper's ladder


#: Candidate pulse periods [s] of the pure-pulse cases, in the order they are tried.
CANDIDATE_PERIODS = (2.5, 2.6, 3.0, 2.4)


def _steady_case(bearing, kind, criterion, weighting):
    """The first candidate pure pulse whose verdicts near its predicted answer are not chaotic:
    (its record, the prediction). The verdict at the predicted rung and at the rung below must
    not change under ±1e-6 changes of Ap."""
    region = pulse_region(bearing, kind)
    tried = []
    for period in CANDIDATE_PERIODS:
        _, a = ricker_record(1.0, period, kind, dt=DT, free=5.0)
        pred = predict_critical_sa(bearing, a, criterion=criterion, step=STEP, dt=DT,
                                   weighting=weighting)
        assert pred.sa is not None, f"Tp = {period} s: no predicted failure"
        first = next(r for r in pred.rungs if r.sa == pred.sa)
        below = next(r for r in pred.rungs if r.index == first.index - 1)
        if all({region(pred.pulse.period, rung.amplitude * (1 + e)) for e in (-1e-6, 1e-6)}
               == {verdict} for rung, verdict in ((first, 2), (below, below.region))):
            return period, a, pred
        tried.append(period)
    pytest.fail(f"the verdicts near the answer are chaotic for every candidate period {tried}")


@pytest.mark.parametrize("kind, criterion, weighting",
                         [("symmetric", 4, "all"), ("antisymmetric", 3, "1/sqrt(s)")])
def test_prediction_is_exact_for_a_pure_pulse(kind, criterion, weighting, light):
    """A record that *is* a Ricker pulse: the prediction equals the time-history critical SA
    within one 0.01 g ladder step (the method is exact for its own assumptions; what remains
    is the pulse's resampling and the extraction's ~1e-8 error). Measured: equal (0.67 g and
    0.59 g at Tp = 2.5 s). The weighting is one under which the extraction is exact on a pure
    pulse: criterion 4 under the paper's pooled weightings, criterion 3 only with 1/sqrt(s)
    (pooled, it takes a 1/s candidate 18 % short; tests/test_wavelet.py).

    Near the threshold the rigid model's verdict can flip under round-off-level changes of
    the input: a symmetric 2 s pulse used here before flipped between 0.38 and 0.63 g with a
    3e-9 change of Ap (docs/critical_sa.md), and the symmetric 2.5 s pulse's verdict at 0.67 g
    is steady under ±1e-6 on one machine and not on another (other CPU, other numpy). Such a
    case says nothing about the method, so the case is the first candidate period whose
    verdicts at the predicted rung and the rung below are steady (:func:`_steady_case`)."""
    period, a, pred = _steady_case(light, kind, criterion, weighting)
    actual = critical_sa(light, a, STEP, dt=DT)
    assert pred.pulse.kind == kind
    assert pred.pulse.period == pytest.approx(period, rel=1e-4)  # extraction: exact recovery
    assert actual.sa is not None
    assert abs(pred.sa - actual.sa) <= STEP * (1 + 1e-9), f"Tp = {period} s"
    assert pred.criterion == criterion


def _pulse(amplitude=-2.0, period=1.5, kind="antisymmetric"):
    return Pulse(kind, amplitude, period, 5.0, "1/sqrt(s)", "velocity", 0.9, 0.8)


def _noise(n=2000, seed=3):
    return np.random.default_rng(seed).standard_normal(n)


def test_ladder_arithmetic_with_a_threshold_region(light):
    """Region 2 from Ap ≥ A*: the prediction is the rung j* = ⌈(A*·SA_rec/|Ap| − start)/step⌉
    of the ladder (written here from the definition, with SA_rec from an independent call),
    the scaled pulse keeps Tp, and the amplitude scales with the record (rel 1e-12)."""
    acc, pulse, a_star = _noise(), _pulse(), 25.0
    seen = set()

    def region(tp, ap):
        seen.add(tp)
        return 2 if ap >= a_star else (1 if ap >= a_star / 2 else 0)

    pred = predict_critical_sa(light, acc, pulse, region=region, dt=DT)
    sa_rec = float(pseudo_acceleration(acc, DT, [4.5])[0])
    step = 0.01 * G
    j = math.ceil((a_star * sa_rec / abs(pulse.amplitude) - step) / step - 1e-9)
    assert pred.sa == pytest.approx(step + j * step, rel=1e-12)
    assert seen == {pulse.period}
    for r in pred.rungs:
        assert r.amplitude == pytest.approx(abs(pulse.amplitude) * r.sa / sa_rec, rel=1e-12)
    assert pred.critical_amplitude >= a_star > pred.rungs[-2].amplitude
    assert pred.criterion is None and pred.frequency_ratio == pytest.approx(4.5 / 1.5)
    fast = predict_critical_sa(light, acc, pulse, region=region, dt=DT, search="fast")
    assert fast.sa == pred.sa and len(fast.rungs) < len(pred.rungs)
    by_kind = predict_critical_sa(light, acc, pulse, region={"antisymmetric": region}, dt=DT)
    assert by_kind.sa == pred.sa
    bisect = predict_critical_sa(light, acc, pulse, region=region, dt=DT, search="bisect")
    assert bisect.sa == pred.sa and len(bisect.rungs) <= 10  # ⌈log2 300⌉ + 1 evaluations


def test_first_failure_of_a_non_monotone_region(light):
    """A failure window [A1, A2) below the main failure region: both searches stop in the
    window (the fast one scans it because its coarse ends are in the impact region)."""
    acc, pulse = _noise(), _pulse()
    sa_rec = float(pseudo_acceleration(acc, DT, [4.5])[0])
    k = abs(pulse.amplitude) / sa_rec  # Ap per unit SA

    def region(tp, ap):
        sa = ap / k / G
        if 0.42 <= sa < 0.45 or sa >= 0.9:
            return 2
        return 1 if sa >= 0.2 else 0

    full = predict_critical_sa(light, acc, pulse, region=region, dt=DT)
    fast = predict_critical_sa(light, acc, pulse, region=region, dt=DT, search="fast")
    assert full.sa / G == pytest.approx(0.42, abs=1e-9)
    assert fast.sa == full.sa
    # bisection assumes one boundary: it finds a failing rung with a survivor just below
    bisect = predict_critical_sa(light, acc, pulse, region=region, dt=DT, search="bisect")
    below = [r for r in bisect.rungs if r.index == round(bisect.sa / (0.01 * G)) - 2]
    assert bisect.sa / G == pytest.approx(0.42, abs=1e-9) or bisect.sa / G >= 0.9 - 1e-9
    assert below and below[0].region != 2


def test_no_failure_up_to_stop_and_bad_region(light):
    acc, pulse = _noise(), _pulse()
    pred = predict_critical_sa(light, acc, pulse, region=lambda tp, ap: 1, dt=DT, stop=0.2 * G)
    assert pred.sa is None and pred.scale is None and len(pred.rungs) == 20
    with pytest.raises(TypeError, match="region"):
        predict_critical_sa(light, acc, pulse, region=3, dt=DT)
    with pytest.raises(ValueError, match="antisymmetric"):
        predict_critical_sa(light, acc, pulse, region={"symmetric": lambda tp, ap: 2}, dt=DT)
    with pytest.raises(ValueError, match="search"):
        predict_critical_sa(light, acc, pulse, region=lambda tp, ap: 2, dt=DT, search="x")


def test_pulse_region_by_simulation(light):
    """A 0.01 g pulse cannot reach the rims (its ground displacement is < 1 cm against 0.3 m of
    capacity): region 0; the verdict is memoised, and the sign of Ap is ignored."""
    where = pulse_region(light, "symmetric")
    assert where(2.0, 0.01 * G) == 0
    assert where(2.0, -0.01 * G) == 0 and len(where._memo) == 1
    with pytest.raises(ValueError, match="kind"):
        pulse_region(light, "triangular")


def _row(actual, predicted, tp):
    return {"record": "r", "actual_sa_g": actual, "tp_4": tp, "predicted_sa_g_4": predicted,
            "error_4": predicted / actual - 1 if not math.isnan(predicted) else math.nan}


def test_table2_counts_and_figures(tmp_path, light):
    """Table 2 counts |error| ≤ 20 % (the boundary included), splits at Tp = 0.5 s, leaves out
    records without an actual failure and counts a missing prediction as not good; the
    Fig. 11/12 plots write PNG files."""
    from rigid.collapse.comparison import table2, write_csv
    from rigid.collapse.plots import plot_comparison, plot_prediction

    rows = [_row(1.0, 1.2, 2.0), _row(1.0, 1.25, 2.0), _row(0.5, 0.45, 0.4),
            _row(0.5, math.nan, 0.3), _row(math.nan, 0.3, 1.0)]
    for r in rows:
        r["error_4"] = (r["predicted_sa_g_4"] / r["actual_sa_g"] - 1
                        if not math.isnan(r["actual_sa_g"]) else math.nan)
    t = table2(rows, 4)
    assert t == {"all": (2, 4), "long": (1, 2), "short": (1, 2)}
    assert write_csv(rows, tmp_path / "t.csv").read_text().count("\n") == 6
    acc, pulse = _noise(), _pulse()
    pred = predict_critical_sa(light, acc, pulse, region=lambda tp, ap: 2 if ap > 9 else 1,
                               dt=DT)
    plot_prediction(pred).savefig(tmp_path / "f11.png")
    plot_comparison(rows, 4).savefig(tmp_path / "f12.png")
    assert (tmp_path / "f11.png").stat().st_size > 1000
    assert (tmp_path / "f12.png").stat().st_size > 1000
