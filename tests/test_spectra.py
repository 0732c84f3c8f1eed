"""Response spectra (Nigam–Jennings via lfilter) and scaling helpers.

Three independent checks of the spectrum: scipy.signal.lsim (first-order hold, an exact
discretisation computed by matrix exponential), the Ricker PSA table of
docs/theory/ground-motions.md (after Eq. M14) (itself from two methods: N-J at dt = Tp/2000 and
solve_ivp on the analytic forcing), and an undamped closed form (resonant sine). FEMA P695
comparisons live in test_record_sets.py.
"""

import math

import numpy as np
import pytest
from scipy.signal import lsim

import rigid
from rigid.motions.spectra import nigam_jennings_coefficients, scaling_ladder, spectral_displacement


def lsim_displacement(acc, dt, period, damping):
    """Relative displacement of ü + 2ξωu̇ + ω²u = −a_g by lsim with linear interpolation."""
    w = 2.0 * math.pi / period
    system = ([[0.0, 1.0], [-w * w, -2.0 * damping * w]], [[0.0], [-1.0]], [[1.0, 0.0]], [[0.0]])
    t = np.arange(acc.size) * dt
    _, u, _ = lsim(system, acc, t, interp=True)
    return u


@pytest.mark.parametrize("damping", [0.0, 0.05, 0.2])
@pytest.mark.parametrize("period", [0.07, 0.5, 4.5])
def test_sd_matches_lsim(period, damping):
    # Tolerance 1e-8 relative (issue 3): both methods are exact for piecewise-linear input,
    # so only round-off separates them (measured ≤ 3e-13). A nonzero first sample checks the
    # rest-at-t=0 initial state of the filter.
    rng = np.random.default_rng(7)
    dt = 0.01
    acc = rng.normal(size=1500)
    acc[0] = 0.8
    ours = spectral_displacement(acc, dt, [period], damping)[0]
    ref = np.max(np.abs(lsim_displacement(acc, dt, period, damping)))
    assert ours == pytest.approx(ref, rel=1e-8)


def test_state_matrices_against_matrix_exponential():
    # The closed-form A of Nigam & Jennings must equal expm(F·dt) of ẋ = F x (1e-12: round-off).
    from scipy.linalg import expm

    period, dt, xi = 1.3, 0.02, 0.05
    w = 2 * math.pi / period
    a, _ = nigam_jennings_coefficients(period, dt, xi)
    f = np.array([[0.0, 1.0], [-w * w, -2 * xi * w]])
    np.testing.assert_allclose(a, expm(f * dt), rtol=1e-12, atol=1e-14)


# docs/theory/ground-motions.md, table after Eq. M14: PSA/Ap of Ricker pulses, 5 % damping.
RICKER_PSA = {
    "symmetric": [1.1121, 1.7076, 2.3739, 2.0834, 1.5235, 1.0719, 0.5984, 0.2170, 0.1070],
    "antisymmetric": [1.0961, 1.8681, 2.9750, 2.7446, 2.0150, 1.3628, 0.6318, 0.2510, 0.1238],
}
RATIOS = [0.25, 0.5, 0.75, 1.0, 1.25, 1.5, 2.0, 3.0, 4.0]


@pytest.mark.parametrize("kind", ["symmetric", "antisymmetric"])
def test_ricker_psa_table(kind):
    # The table is printed to 4 decimals, so it is exact to ±5e-5 (half a unit in the last
    # place; 4.7e-4 relative for the smallest entry, 0.1070), plus 1e-5 relative for the two
    # methods behind it (they agree to 1.6e-6). dt = Tp/1000 keeps the sampled-peak error at
    # T = Tp/4 far below that; 20·Tp of free vibration covers the 4·Tp oscillator's peak.
    tp, ap = 1.0, 2.0
    dt = tp / 1000
    _, a = rigid.ricker_record(ap, tp, kind, dt=dt, free=20.0)
    psa = rigid.pseudo_acceleration(a, dt, np.array(RATIOS) * tp)
    np.testing.assert_allclose(psa / ap, RICKER_PSA[kind], rtol=1e-5, atol=5e-5)


def test_undamped_resonance_closed_form():
    # Undamped oscillator under a resonant sine a_g = A sin(ωt) from rest: u(t) =
    # A/(2ω²)(sin ωt − ωt cos ωt). Over n cycles the peak |u| is within one dt of
    # A/(2ω²)·2πn; the relative sampling error of the peak is ~(ω dt)²/2 (tolerance 1e-4).
    period, n, dt = 2.0, 10, 0.001
    w = 2 * math.pi / period
    t = np.arange(0.0, n * period + dt / 2, dt)
    acc = 0.3 * np.sin(w * t)
    u = 0.3 / (2 * w * w) * (np.sin(w * t) - w * t * np.cos(w * t))
    sd = spectral_displacement(acc, dt, [period], 0.0)[0]
    # The piecewise-linear input differs from the sine by O(dt²): compare to 1e-4.
    assert sd == pytest.approx(np.max(np.abs(u)), rel=1e-4)


def test_vectorised_over_records_and_linear():
    # Leading axes are independent records; PSA is linear in the record (exact up to
    # round-off, 1e-12).
    rng = np.random.default_rng(3)
    acc = rng.normal(size=(3, 800))
    periods = [0.2, 1.0, 4.5]
    both = rigid.pseudo_acceleration(acc, 0.01, periods)
    assert both.shape == (3, 3)
    for i in range(3):
        np.testing.assert_allclose(both[i], rigid.pseudo_acceleration(acc[i], 0.01, periods), 1e-12)
    np.testing.assert_allclose(
        rigid.pseudo_acceleration(2.5 * acc[0], 0.01, periods), 2.5 * both[0], 1e-12
    )


def test_scale_factor_reaches_target():
    # The scaled record's PSA must hit the target (1e-10: PSA is linear in the scale).
    rng = np.random.default_rng(5)
    acc = rng.normal(size=3000)
    target = 0.15 * rigid.G
    k = rigid.scale_factor(acc, 0.01, target, period=4.5)
    assert rigid.pseudo_acceleration(k * acc, 0.01, [4.5])[0] == pytest.approx(target, rel=1e-10)


def test_scaling_ladder_in_001g_steps():
    # Rungs are 0.01 g apart from 0.01 g to 0.30 g inclusive; each rung's factor gives that
    # SA(4.5 s) (1e-10: linearity).
    rng = np.random.default_rng(6)
    acc = rng.normal(size=3000)
    targets, factors = scaling_ladder(acc, 0.01, stop=0.30 * rigid.G)
    assert targets.size == 30
    np.testing.assert_allclose(np.diff(targets), 0.01 * rigid.G, rtol=1e-12)
    assert targets[0] == pytest.approx(0.01 * rigid.G)
    assert targets[-1] == pytest.approx(0.30 * rigid.G)
    for j in (0, 14, 29):
        sa = rigid.pseudo_acceleration(factors[j] * acc, 0.01, [4.5])[0]
        assert sa == pytest.approx(targets[j], rel=1e-10)


@pytest.mark.parametrize(
    "kwargs",
    [
        {"periods": [0.0]},
        {"periods": [-1.0]},
        {"damping": 1.0},
        {"dt": 0.0},
        {"acceleration": [1.0, np.nan, 0.0]},
    ],
)
def test_bad_input_raises(kwargs):
    args = {"acceleration": np.ones(10), "dt": 0.01, "periods": [1.0], "damping": 0.05}
    args.update(kwargs)
    with pytest.raises(ValueError):
        rigid.pseudo_acceleration(**args)
