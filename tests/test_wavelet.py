"""Ricker pulse extraction by CWT (rigid.motions.pulse_extraction).

Oracles: the direct (time-domain) correlation sum for the FFT transform; closed-form wavelet
norms; exact recovery of synthetic pulses with w = 1/√s (docs/theory/ground-motions.md, Eqs.
M23–M24); the closed-form scale bias of w = 1/s and w = 1 (Eq. M25); the LS projection of the
noise for pulses buried in broadband noise; the paper's Eqs. 8–9 recomputed here with
trapezoids.
"""

import math

import numpy as np
import pytest
from scipy.integrate import cumulative_trapezoid, trapezoid
from scipy.signal import butter, sosfiltfilt

import rigid
from rigid.motions.cwt import WAVELET_NORM2, wavelet_transform
from rigid.motions.pulse_extraction import Pulse, best_pulse, extract_pulse, extract_pulses
from rigid.motions.pulses import ricker, ricker_velocity

G = rigid.G
KINDS = ("symmetric", "antisymmetric")
SOURCES = ("acceleration", "velocity")
PERIODS = (0.3, 0.7, 1.7, 3.0, 4.5, 7.5)  # the paper's Tp range is up to 7.5 s


def synthetic(kind, tp, seed, noise=None):
    """A Ricker pulse with random amplitude (±0.05–0.5 g) and arrival, optionally in noise.

    dt and duration follow Tp so the record holds the pulse with ±3·Tp to spare:
    dt = 0.005 s (Tp < 1 s), 0.01 s (< 4 s), 0.02 s otherwise; duration max(20 s, 8·Tp).
    noise: None, "high" (band 2.5/Tp–10/Tp Hz, above the pulse's band) or "broad"
    (0.2–10 Hz, overlapping it); peak 25 % of |Ap| (this test's choice).
    """
    rng = np.random.default_rng(seed)
    dt = 0.005 if tp < 1 else (0.01 if tp < 4 else 0.02)
    duration = max(20.0, 8 * tp)
    t = np.arange(round(duration / dt) + 1) * dt
    ap = rng.uniform(0.05, 0.5) * G * rng.choice([-1.0, 1.0])
    t0 = rng.uniform(3 * tp, duration - 3 * tp)
    a = ricker(t, ap, tp, kind, t0=t0)
    if noise is not None:
        band = (2.5 / tp, min(10 / tp, 0.4 / dt)) if noise == "high" else (0.2, 10.0)
        sos = butter(4, band, btype="band", fs=1 / dt, output="sos")
        n = sosfiltfilt(sos, rng.normal(size=t.size))
        a = a + 0.25 * abs(ap) * n / np.max(np.abs(n))
    return t, a, dt, ap, t0


# --------------------------------------------------------------------------- transform


@pytest.mark.parametrize("source", SOURCES)
@pytest.mark.parametrize("kind", KINDS)
def test_fft_transform_equals_direct_sum(kind, source):
    # W(s, ξ_n) = dt Σ_k x_k ψ((t_k − ξ_n)/s) evaluated by brute force. The FFT version uses
    # the analytic spectrum, so aliasing and the ±3·s truncation are the only differences:
    # both below 1e-12 of the peak (measured ~1e-15), tolerance 1e-10.
    rng = np.random.default_rng(1)
    dt, n = 0.01, 1500
    x = rng.normal(size=n)
    if source == "velocity":
        x = np.cumsum(x) * dt  # a velocity-like record that does not end at zero
    scales = np.array([0.25, 1.3, 6.0])
    w = wavelet_transform(x, dt, scales, kind, source)
    for i, s in enumerate(scales):
        m = math.ceil(4 * s / dt)
        u = np.arange(-m, m + 1) * dt / s
        kernel = (
            ricker(u, 1.0, 1.0, kind)
            if source == "acceleration"
            else ricker_velocity(u, 1.0, 1.0, kind)
        )
        # Outside the record: rest before; after, zero acceleration / the final velocity.
        after = x[-1] if source == "velocity" else 0.0
        ext = np.concatenate([np.zeros(m), x, np.full(m, after)])
        direct = dt * np.correlate(ext, kernel, mode="valid")
        assert np.max(np.abs(w[i] - direct)) < 1e-10 * np.max(np.abs(direct))


@pytest.mark.parametrize("key", list(WAVELET_NORM2))
def test_wavelet_norms(key):
    # ‖ψ‖² by quadrature of rigid.motions.pulses' own functions (a fine trapezoid on ±8 converges
    # spectrally for Gaussians: 1e-12).
    kind, source = key
    u = np.linspace(-8, 8, 160_001)
    f = (
        ricker(u, 1.0, 1.0, kind)
        if source == "acceleration"
        else ricker_velocity(u, 1.0, 1.0, kind)
    )
    assert WAVELET_NORM2[key] == pytest.approx(trapezoid(f * f, u), rel=1e-12)


@pytest.mark.parametrize("weighting,p", [("1/sqrt(s)", 0.5), ("1/s", 1.0), ("1", 0.0)])
@pytest.mark.parametrize("source", SOURCES)
@pytest.mark.parametrize("kind", KINDS)
def test_coefficient_gives_the_amplitude(kind, source, weighting, p):
    # Eqs. M22–M23: at any (s, ξ) the LS amplitude is Ap = C/(w(s)·s·‖ψ‖²) on
    # acceleration and C/(w(s)·s²·‖Ψ‖²) on velocity. Pulse.coefficient is taken at the grid
    # maximum (within half a grid step and half a sample of the polished point, where C is
    # stationary) and the velocity wavelet is continuous while v is trapezoidal: both
    # second-order effects, measured ≤ 0.22 %. Tolerance 0.5 %.
    _, a, dt, _, _ = synthetic(kind, 0.9, seed=21)
    pulse = extract_pulse(a, source=source, weighting=weighting, kind=kind, dt=dt)
    s = pulse.period
    power = 1 if source == "acceleration" else 2
    implied = pulse.coefficient / (s**-p * s**power * WAVELET_NORM2[(kind, source)])
    assert implied == pytest.approx(pulse.amplitude, rel=5e-3)


# --------------------------------------------------------------------------- recovery


@pytest.mark.parametrize("source", SOURCES)
@pytest.mark.parametrize("tp", PERIODS)
@pytest.mark.parametrize("kind", KINDS)
def test_pure_pulse_recovered_exactly(kind, tp, source):
    # w = 1/√s: max |C| is at the true (s, ξ) (Eq. M24). The grid maximum is
    # polished on the normalised projection |⟨x, T⟩|/‖T‖ with the sampled template T, which a
    # sampled pulse maximises exactly (Cauchy–Schwarz) and whose logarithm is even in ln s
    # about the truth, so parabolic steps land on it (measured ≤ 3e-8 on velocity, 1e-14 on
    # acceleration). Tolerance 1e-6 on Tp, Ap, t0 [s] and e_a = e_v = 1; kind exact.
    _, a, dt, ap, t0 = synthetic(kind, tp, seed=int(tp * 10) + len(source))
    p = extract_pulse(a, source=source, dt=dt)
    assert p.kind == kind
    assert p.period == pytest.approx(tp, rel=1e-6)
    assert p.time == pytest.approx(t0, abs=1e-6)
    assert p.amplitude == pytest.approx(ap, rel=1e-6)
    assert p.e_a == pytest.approx(1.0, abs=1e-6)
    assert p.e_v == pytest.approx(1.0, abs=1e-6)
    assert (p.source, p.weighting) == (source, "1/sqrt(s)")


@pytest.mark.parametrize("source", SOURCES)
@pytest.mark.parametrize("tp", PERIODS)
@pytest.mark.parametrize("kind", KINDS)
def test_pulse_in_high_frequency_noise(kind, tp, source):
    # Noise above the pulse's band (peak 25 % of Ap), as in pulse-like records: the issue's
    # 2 % on Tp and Ap, kind exact (measured ≤ 0.17 % and ≤ 0.12 %).
    _, a, dt, ap, _ = synthetic(kind, tp, seed=100 + int(tp * 10), noise="high")
    p = extract_pulse(a, source=source, dt=dt)
    assert p.kind == kind
    assert p.period == pytest.approx(tp, rel=0.02)
    assert p.amplitude == pytest.approx(ap, rel=0.02)


@pytest.mark.parametrize("tp", PERIODS)
@pytest.mark.parametrize("kind", KINDS)
def test_pulse_in_broadband_noise_matches_projection(kind, tp):
    # Noise 0.2–10 Hz overlaps the pulse's band, so no estimator can return Ap itself: the
    # LS amplitude at the true (s, ξ) is Ap + ⟨n, ψ⟩/‖ψ‖², computed here from the known
    # noise. Tolerances: kind exact; Tp 3 % (this test's choice); Ap within 2 % of |Ap| of that
    # projection (the residual comes from the small shift of (s, ξ); measured ≤ 0.9 %, and
    # Tp ≤ 1.7 %).
    t, a, dt, ap, t0 = synthetic(kind, tp, seed=200 + int(tp * 10), noise="broad")
    psi = ricker(t, 1.0, tp, kind, t0=t0)
    projection = ap + ((a - ap * psi) @ psi) / (psi @ psi)
    p = extract_pulse(a, source="acceleration", dt=dt)
    assert p.kind == kind
    assert p.period == pytest.approx(tp, rel=0.03)
    assert abs(p.amplitude - projection) <= 0.02 * abs(ap)


# Gaussian-derivative order n of the wavelet in the transform's domain: ψs = 2nd, ψa = 3rd;
# on velocity Ψ = ∫ψ lowers n by one.
ORDER = {
    ("symmetric", "acceleration"): 2,
    ("antisymmetric", "acceleration"): 3,
    ("symmetric", "velocity"): 1,
    ("antisymmetric", "velocity"): 2,
}


@pytest.mark.parametrize("weighting,p", [("1/s", 1.0), ("1", 0.0), ("1/sqrt(s)", 0.5)])
@pytest.mark.parametrize("source", SOURCES)
@pytest.mark.parametrize("kind", KINDS)
def test_scale_bias_closed_form(kind, source, weighting, p):
    # Eq. M25: correlating two n-th Gaussian derivatives of widths s0 and s gives
    # ∝ (s0 s)^(n+1)/(s0² + s²)^(n+½); with w = s^(−p) the maximum is at
    # r² = (s/s0)² = (n + 1 − p)/(n + p). Acceleration: r = 0.8165/1.2247 (symmetric) and
    # 0.8660/1.1547 (antisymmetric) for 1/s and 1; 1/√s gives r = 1. The closed form is for
    # continuous signals; sampling at Tp/dt = 170 shifts it by O((dt/Tp)²) ≈ 1e-4, so the
    # tolerance is 1e-3.
    tp = 1.7
    _, a, dt, _, t0 = synthetic(kind, tp, seed=3)
    n = ORDER[(kind, source)]
    r = math.sqrt((n + 1 - p) / (n + p))
    pulse = extract_pulse(a, source=source, weighting=weighting, kind=kind, dt=dt)
    assert pulse.period / tp == pytest.approx(r, rel=1e-3)
    assert abs(pulse.time - t0) <= dt  # the bias is in scale only


def test_sign_scaling_and_symmetry():
    # Linearity: scaling the record by k scales Ap by k and leaves Tp, t0, e_a, e_v
    # unchanged (all to 1e-9, round-off only); −record gives −Ap.
    _, a, dt, _, _ = synthetic("antisymmetric", 2.3, seed=11, noise="broad")
    p = extract_pulse(a, source="velocity", dt=dt)
    q = extract_pulse(-2.5 * a, source="velocity", dt=dt)
    assert q.amplitude == pytest.approx(-2.5 * p.amplitude, rel=1e-9)
    for name in ("period", "time", "e_a", "e_v"):
        assert getattr(q, name) == pytest.approx(getattr(p, name), rel=1e-9)
    assert p.scaled(-2.5).amplitude == pytest.approx(q.amplitude, rel=1e-9)


def test_match_indices_follow_eqs_8_and_9():
    # Paper Eqs. 8–9 recomputed with scipy's trapezoids (the integrals' quadrature in
    # rigid.motions.pulse_extraction too), on a noisy record that does not end at rest: only
    # round-off separates the two (1e-9). v_p is integrated like v_g, from the first sample.
    t, a, dt, _, _ = synthetic("symmetric", 1.2, seed=5, noise="broad")
    for source in SOURCES:
        p = extract_pulse(a, source=source, dt=dt)
        a_p = p.acceleration(t)
        v_g = cumulative_trapezoid(a, t, initial=0)
        v_p = cumulative_trapezoid(a_p, t, initial=0)
        e_a = trapezoid(a * a_p, t) / trapezoid(a * a, t)
        e_v = trapezoid(v_g * v_p, t) / trapezoid(v_g * v_g, t)
        assert p.e_a == pytest.approx(e_a, rel=1e-9)
        assert p.e_v == pytest.approx(e_v, rel=1e-9)
        assert 0 < p.e_a < 1 and 0 < p.e_v < 1


# --------------------------------------------------------------------------- candidates


def two_pulse_record():
    """A short strong symmetric pulse (0.4 s, 1 g at 5 s) and a long weak one (4 s, 0.15 g
    at 20 s). Acceleration energy ∝ Ap²Tp: 0.40 against 0.09, so the short pulse holds most
    of it; velocity energy ∝ Ap²Tp³: 0.064 against 1.44, so the long one dominates v."""
    dt = 0.01
    t = np.arange(0.0, 32.0, dt)
    short = ricker(t, 1.0 * G, 0.4, "symmetric", t0=5.0)
    long_ = ricker(t, 0.15 * G, 4.0, "symmetric", t0=20.0)
    return rigid.GroundMotion("two pulses", dt, short + long_)


def test_several_candidates_are_kept():
    # Both pulses appear among the acceleration candidates (Tp 2 %, t0 one sample), not only
    # the global maximum.
    found = extract_pulses(two_pulse_record(), sources=("acceleration",), weightings=("1/sqrt(s)",))
    cands = found[("acceleration", "1/sqrt(s)", "symmetric")]
    assert len(cands) >= 2
    for tp, t0 in ((0.4, 5.0), (4.0, 20.0)):
        assert any(abs(c.period / tp - 1) < 0.02 and abs(c.time - t0) <= 0.01 for c in cands)
    assert cands[0].period == pytest.approx(0.4, rel=0.02)  # the global maximum


@pytest.mark.parametrize("criterion,tp", [(1, 0.4), (2, 4.0), (3, 0.4), (4, 4.0)])
def test_four_criteria(criterion, tp):
    # By construction (see two_pulse_record): max e_a selects the short pulse, max e_v the
    # long one, from either record (paper §4.1). Tp to 2 %. One weighting, the unbiased one.
    p = best_pulse(two_pulse_record(), criterion=criterion, weighting="1/sqrt(s)")
    assert p.period == pytest.approx(tp, rel=0.02)
    assert p.source == ("acceleration" if criterion <= 2 else "velocity")


def _e_v_by_hand(record, period, t0, step=0.001):
    """Paper Eq. 9 for a symmetric pulse of (period, t0) fitted to ``record`` by least squares
    in acceleration, on a 10 times finer grid than the record's (the record interpolated
    linearly: the same piecewise-linear acceleration the trapezoids integrate)."""
    t = np.arange(0.0, record.duration + step / 2, step)
    a_g = np.interp(t, np.arange(record.acceleration.size) * record.dt, record.acceleration)
    a_1 = ricker(t, 1.0, period, "symmetric", t0=t0)
    amp = trapezoid(a_g * a_1, t) / trapezoid(a_1 * a_1, t)
    v_g = cumulative_trapezoid(a_g, t, initial=0)
    v_p = amp * cumulative_trapezoid(a_1, t, initial=0)
    return trapezoid(v_g * v_p, t) / trapezoid(v_g * v_g, t)


@pytest.mark.parametrize("weighting,p", [("1/sqrt(s)", 0.5), ("1/s", 1.0), ("1", 0.0)])
def test_each_weighting_finds_the_long_pulse_at_its_biased_period(weighting, p):
    # Criterion 2 (acceleration record, largest e_v) picks the long pulse of two_pulse_record
    # whatever the weighting, at the period Eq. M25 shifts by sqrt((n+1-p)/(n+p)), n = 2
    # (symmetric, acceleration): Tp to 2 % (the grid's step, refined); e_v recomputed by hand
    # to 1 % (the hand grid is 10 times finer than the record's).
    record = two_pulse_record()
    pulse = best_pulse(record, criterion=2, weighting=weighting)
    assert pulse.weighting == weighting
    assert pulse.period == pytest.approx(4.0 * math.sqrt((3 - p) / (2 + p)), rel=0.02)
    assert pulse.e_v == pytest.approx(_e_v_by_hand(record, pulse.period, pulse.time), rel=0.01)


def test_paper_procedure_pools_the_three_weightings():
    # The paper's procedure (weighting "all", the default) takes the criterion's maximum over
    # the candidates of the three weightings: the single-weighting answers above, e_v by hand
    # at their periods (M25), decide which one it returns; e_v is not maximised by the
    # unbiased period (it is the other domain's index, Eq. M30's note), so a biased one wins.
    record = two_pulse_record()
    by_hand = {w: _e_v_by_hand(record, 4.0 * math.sqrt((3 - p) / (2 + p)), 20.0)
               for w, p in (("1/sqrt(s)", 0.5), ("1/s", 1.0), ("1", 0.0))}
    winner = max(by_hand, key=by_hand.get)
    pooled = best_pulse(record, criterion=2)
    assert pooled.weighting == winner
    assert pooled == best_pulse(record, criterion=2, weighting=winner)
    assert by_hand[winner] > 1.02 * sorted(by_hand.values())[-2]  # the case is not a near-tie


@pytest.mark.parametrize("kind", KINDS)
def test_paper_procedure_on_a_pure_pulse(kind):
    # A record that is one Ricker pulse (Tp 2.5 s, 1 m/s²). Pooling the three weightings,
    # criteria 1 and 4 (each index in its transform's own domain) return it exactly (Tp, Ap
    # to 1e-6: Eq. M24), while criteria 2 and 3 (the other domain's index, unbounded above:
    # note to Eq. M30) take a biased candidate whose index exceeds 1: w = 1 on acceleration
    # and w = 1/s on velocity, at the periods of Eq. M25 (to 1 %, the refinement on a 2 % grid).
    dt, tp = 0.01, 2.5
    _, a = rigid.ricker_record(1.0, tp, kind, dt=dt, free=5.0)
    n = {"symmetric": 2, "antisymmetric": 3}[kind]
    for criterion in (1, 4):
        p = best_pulse(a, criterion=criterion, dt=dt)
        assert (p.weighting, p.kind) == ("1/sqrt(s)", kind)
        assert (p.period, p.amplitude) == pytest.approx((tp, 1.0), rel=1e-6)
    for criterion, weighting, m, exponent, index in ((2, "1", n, 0.0, "e_v"),
                                                     (3, "1/s", n - 1, 1.0, "e_a")):
        p = best_pulse(a, criterion=criterion, dt=dt)
        assert (p.weighting, p.kind) == (weighting, kind)
        ratio = math.sqrt((m + 1 - exponent) / (m + exponent))  # Eq. M25
        assert p.period == pytest.approx(tp * ratio, rel=0.01)
        assert getattr(p, index) > 1.0


def test_pulse_period_capped_at_the_papers_limit():
    # A pure 9 s pulse: with the paper's 7.5 s cap (the default) no period exceeds 7.5 s and the
    # grid's top is taken; with the cap at 12 s (the default before 2026-11-26) it is found
    # at 9 s to 2 %.
    dt = 0.02
    t = np.arange(0.0, 90.0, dt)
    record = rigid.GroundMotion("9 s pulse", dt, ricker(t, 0.2 * G, 9.0, "symmetric", t0=45.0))
    for criterion in (1, 2, 3, 4):
        assert best_pulse(record, criterion=criterion).period <= 7.5
    assert best_pulse(record, criterion=4, weighting="1/sqrt(s)").period == pytest.approx(7.5)
    assert best_pulse(record, criterion=4, weighting="1/sqrt(s)",
                      max_period=12.0).period == pytest.approx(9.0, rel=0.02)


def test_bad_arguments():
    m = two_pulse_record()
    with pytest.raises(ValueError):
        extract_pulse(m, weighting="1/s^2")
    with pytest.raises(ValueError):
        extract_pulse(m, source="displacement")
    with pytest.raises(ValueError):
        extract_pulse(m, kind="morlet")
    with pytest.raises(ValueError):
        best_pulse(m, criterion=5)
    with pytest.raises(ValueError, match="the paper's procedure"):
        best_pulse(m, weighting="paper")
    with pytest.raises(ValueError):
        extract_pulse(np.zeros(100), dt=0.01)


def test_pulse_is_frozen():
    p = Pulse("symmetric", 1.0, 1.0, 2.0, "1", "velocity", 0.5, 0.6)
    with pytest.raises(AttributeError):
        p.period = 2.0


def test_plot_writes_png(tmp_path):
    pytest.importorskip("matplotlib")
    from rigid.motions.plots import plot_record_pulses

    m = two_pulse_record()
    path = plot_record_pulses(m, [best_pulse(m, 1), best_pulse(m, 4)], tmp_path / "p.png")
    data = path.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 10_000
