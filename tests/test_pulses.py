"""Ricker pulses (paper Eqs. 5–6) against the closed forms of docs/theory/ground-motions.md,
Eqs. M1–M7."""

import math

import numpy as np
import pytest
from scipy.integrate import cumulative_trapezoid, trapezoid

from rigid import ricker, ricker_displacement, ricker_record, ricker_velocity

KINDS = ("symmetric", "antisymmetric")


@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize("period", [0.5, 2.325, 7.5])
def test_velocity_and_displacement_are_the_integrals(kind, period):
    """Exact integrals against trapezoidal integration of the sampled acceleration.

    dt = Tp/4000: the trapezoid error ~ dt²·max|a''|·duration/12 is below 1e-6 of the peaks.
    """
    amp = 3.0
    t = np.linspace(-5 * period, 5 * period, 40001)
    a = ricker(t, amp, period, kind)
    v = cumulative_trapezoid(a, t, initial=0.0)
    d = cumulative_trapezoid(ricker_velocity(t, amp, period, kind), t, initial=0.0)
    v_exact = ricker_velocity(t, amp, period, kind)
    d_exact = ricker_displacement(t, amp, period, kind)
    assert np.max(np.abs(v - (v_exact - v_exact[0]))) < 1e-6 * np.max(np.abs(v_exact))
    assert np.max(np.abs(d - (d_exact - d_exact[0]))) < 1e-6 * np.max(np.abs(d_exact))


def test_closed_form_peaks():
    """Peak acceleration, PGV, PGD and energy of Eqs. M1–M7 (4-5 digits there)."""
    amp, tp = 2.0, 1.7
    t = np.linspace(-4 * tp, 4 * tp, 200001)
    sym = ricker(t, amp, tp)
    assert sym.max() == pytest.approx(amp, rel=1e-12)
    assert np.abs(ricker_velocity(t, amp, tp)).max() == pytest.approx(0.13652 * amp * tp, rel=1e-4)
    assert np.abs(ricker_displacement(t, amp, tp)).max() == pytest.approx(
        amp * tp**2 / (2 * math.pi**2), rel=1e-9
    )
    assert trapezoid(sym**2, t) == pytest.approx(0.29921 * amp**2 * tp, rel=1e-4)
    anti = ricker(t, amp, tp, "antisymmetric")
    assert anti.max() == pytest.approx(1.00009 * amp, rel=1e-5)
    assert t[np.argmax(anti)] == pytest.approx(-0.20453 * tp, abs=1e-4 * tp)
    assert np.abs(ricker_velocity(t, amp, tp, "antisymmetric")).max() == pytest.approx(
        0.19976 * amp * tp, rel=1e-4
    )
    assert np.abs(ricker_displacement(t, amp, tp, "antisymmetric")).max() == pytest.approx(
        0.03340 * amp * tp**2, rel=2e-4
    )
    assert trapezoid(anti**2, t) == pytest.approx(0.48106 * amp**2 * tp, rel=1e-4)


@pytest.mark.parametrize("kind", KINDS)
def test_fourier_peak_is_at_one_over_tp(kind):
    """Tp is the period of the Fourier amplitude peak; resolution 1/(duration) ≈ 0.2 % of 1/Tp."""
    tp, dt = 2.0, 0.002
    t = np.arange(-500, 500, dt)
    spectrum = np.abs(np.fft.rfft(ricker(t, 1.0, tp, kind)))
    f = np.fft.rfftfreq(t.size, dt)
    assert f[np.argmax(spectrum)] == pytest.approx(1 / tp, abs=1.5 / (t.size * dt))


def test_record_starts_and_ends_at_rest():
    t, a = ricker_record(4.0, 3.0, "antisymmetric", dt=0.01)
    assert t[0] == 0 and a.size == t.size
    assert abs(a[0]) < 1e-8 * 4.0 and abs(a[-1]) < 1e-8 * 4.0
    assert t[-1] == pytest.approx(2 * 3.0 + 2 * 3.0 + 10.0)


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"period": 0.0}, "period"),
        ({"period": -1.0}, "period"),
        ({"kind": "triangular"}, "kind"),
        ({"amplitude": float("inf")}, "amplitude"),
    ],
)
def test_bad_arguments(kwargs, match):
    args = {"amplitude": 1.0, "period": 1.0, "kind": "symmetric"} | kwargs
    with pytest.raises(ValueError, match=match):
        ricker(0.0, **args)
