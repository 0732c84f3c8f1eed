"""Ricker pulses (paper Eqs. 5–6) with their exact velocity and displacement.

Symmetric:      a(t) = Ap (1 − 2π²τ²) exp(−π²τ²),                 τ = (t − t0)/Tp   (Eq. 5)
Antisymmetric:  a(t) = (Ap/1.38) (4π²τ²/3 − 3)(2πτ/√3) exp(−2π²τ²/3)                  (Eq. 6)

Velocity and displacement are the exact integrals from t = −∞ (both pulses leave no residual
velocity or displacement; docs/theory/ground-motions.md, Eqs. M1–M7).
"""

from __future__ import annotations

import math

import numpy as np

#: Normaliser of the antisymmetric pulse as printed in the paper (Eq. 6); the exact peak
#: normaliser is 1.380119 (Eq. M3), so the printed one gives a peak of 1.00009·Ap.
ANTISYMMETRIC_NORM = 1.38

KINDS = ("symmetric", "antisymmetric")


def _check(amplitude: float, period: float, kind: str) -> None:
    if kind not in KINDS:
        raise ValueError(f"kind must be 'symmetric' or 'antisymmetric', got {kind!r}")
    if not (np.isfinite(period) and period > 0):
        raise ValueError(f"period must be a positive number of seconds, got {period!r}")
    if not np.isfinite(amplitude):
        raise ValueError(f"amplitude must be finite, got {amplitude!r}")


def ricker(t, amplitude: float, period: float, kind: str = "symmetric", t0: float = 0.0):
    """Ricker acceleration pulse.

    Parameters
    ----------
    t : array_like [s]
        Times.
    amplitude : float [m/s²]
        Ap, the peak acceleration (exact for the symmetric pulse, 1.00009·Ap for the
        antisymmetric one, as printed in the paper).
    period : float [s]
        Tp, the period at the peak of the Fourier amplitude spectrum.
    kind : {"symmetric", "antisymmetric"}
        Paper Eq. 5 or Eq. 6.
    t0 : float [s]
        Centre of the pulse.

    Returns
    -------
    ndarray [m/s²]
    """
    _check(amplitude, period, kind)
    tau = (np.asarray(t, dtype=float) - t0) / period
    if kind == "symmetric":  # Eq. M1 (paper Eq. 5)
        x = (math.pi * tau) ** 2
        return amplitude * (1.0 - 2.0 * x) * np.exp(-x)
    u = 2.0 * math.pi * tau / math.sqrt(3.0)  # Eq. M2 (paper Eq. 6)
    return amplitude / ANTISYMMETRIC_NORM * (u * u - 3.0) * u * np.exp(-0.5 * u * u)


def ricker_velocity(t, amplitude: float, period: float, kind: str = "symmetric", t0: float = 0.0):
    """Exact ground velocity of :func:`ricker` [m/s], zero at t = −∞ (same parameters;
    Eq. M4)."""
    _check(amplitude, period, kind)
    s = np.asarray(t, dtype=float) - t0
    tau = s / period
    if kind == "symmetric":
        return amplitude * s * np.exp(-((math.pi * tau) ** 2))
    u = 2.0 * math.pi * tau / math.sqrt(3.0)
    scale = math.sqrt(3.0) * period / (2.0 * math.pi)
    return amplitude / ANTISYMMETRIC_NORM * scale * (1.0 - u * u) * np.exp(-0.5 * u * u)


def ricker_displacement(
    t, amplitude: float, period: float, kind: str = "symmetric", t0: float = 0.0
):
    """Exact ground displacement of :func:`ricker` [m], zero at t = −∞ (same parameters;
    Eq. M5)."""
    _check(amplitude, period, kind)
    s = np.asarray(t, dtype=float) - t0
    tau = s / period
    if kind == "symmetric":
        return -amplitude * period**2 / (2.0 * math.pi**2) * np.exp(-((math.pi * tau) ** 2))
    u = 2.0 * math.pi * tau / math.sqrt(3.0)
    scale = math.sqrt(3.0) * period / (2.0 * math.pi)
    return amplitude / ANTISYMMETRIC_NORM * scale**2 * u * np.exp(-0.5 * u * u)


def ricker_record(
    amplitude: float,
    period: float,
    kind: str = "symmetric",
    dt: float = 0.005,
    duration: float | None = None,
    lead: float | None = None,
    free: float = 10.0,
):
    """A sampled Ricker pulse ready for :func:`rigid.simulate`.

    Parameters
    ----------
    amplitude : float [m/s²]
    period : float [s]
    kind : {"symmetric", "antisymmetric"}
    dt : float [s]
        Sampling interval.
    duration : float [s], optional
        Total length; default ``lead + 2·Tp + free``: the pulse, then ``free`` seconds.
    lead : float [s], optional
        Time of the pulse centre; default 2·Tp, where both pulses are below 1e-8·Ap, so the
        record starts at rest.
    free : float [s]
        Free vibration kept after the pulse (its end taken at t0 + 2·Tp) when ``duration``
        is not given; default 10 s, over two periods of the baseline bearing.

    Returns
    -------
    t, acceleration : ndarray [s], ndarray [m/s²]
    """
    from ..limits import MAX_MODEL_DURATION, MAX_MODEL_SAMPLES

    if not (np.isfinite(dt) and dt > 0):
        raise ValueError(f"dt must be a positive number of seconds, got {dt!r}")
    _check(amplitude, period, kind)
    lead = 2.0 * period if lead is None else lead
    duration = lead + 2.0 * period + free if duration is None else duration
    if not (np.isfinite(duration) and 0 < duration <= MAX_MODEL_DURATION):
        raise ValueError(f"a Ricker record lasts between 0 and {MAX_MODEL_DURATION:g} s "
                         f"(docs/limits.md), got {duration!r} s (Tp = {period!r} s)")
    if duration / dt > MAX_MODEL_SAMPLES:
        raise ValueError(f"a Ricker record of {duration:g} s at dt = {dt:g} s would have "
                         f"{duration / dt:.3g} samples, more than {MAX_MODEL_SAMPLES:.0e} "
                         "(docs/limits.md)")
    t = np.arange(round(duration / dt) + 1) * dt
    return t, ricker(t, amplitude, period, kind, t0=lead)
