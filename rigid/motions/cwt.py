"""Continuous wavelet transform of a record with Ricker wavelets (paper Eq. 7).

    C(s, ξ) = w(s) ∫ x(t) ψ((t − ξ)/s) dt,

with ψ the unit-period, unit-peak Ricker pulse (paper Eqs. 5–6) on an acceleration record, or
its time integral Ψ(u) = ∫ψ du on a velocity record, so the scale s *is* the pulse period Tp.
:func:`wavelet_transform` evaluates the unweighted transform for all ξ at once per scale by
FFT correlation against the wavelet's analytic Fourier transform; the weightings w(s) and the
wavelets' norms are here too (docs/theory/ground-motions.md, Eqs. M19–M22).
"""

from __future__ import annotations

import math

import numpy as np

from .pulses import ANTISYMMETRIC_NORM, KINDS

__all__ = ["MAX_PULSE_PERIOD", "SOURCES", "WAVELET_NORM2", "WEIGHTINGS", "WEIGHT_EXPONENT",
           "check_options", "default_periods", "wavelet_transform"]

WEIGHTINGS = ("1/sqrt(s)", "1/s", "1")
#: Longest pulse period of the default scale grid [s]: paper §3.1 limits Tp to 7.5 s, "because
#: longer period pulse is not realistic" (docs/theory/ground-motions.md, after Eq. M31).
MAX_PULSE_PERIOD = 7.5
SOURCES = ("acceleration", "velocity")
#: Exponent p of w(s) = s^(−p) (Eq. M20).
WEIGHT_EXPONENT = {"1/sqrt(s)": 0.5, "1/s": 1.0, "1": 0.0}
#: Half-width of the wavelet support in units of s: ψ < e^(−22) beyond (the note to Eq. M8 of
#: docs/theory/ground-motions.md); it sets the padding of the FFT (Eq. M21).
SUPPORT = 3.0


#: ‖ψ‖² = ∫ψ(u)² du of the unit-period wavelets (docs/theory/ground-motions.md, Eq. M22).
WAVELET_NORM2 = {
    ("symmetric", "acceleration"): 3.0 / (4.0 * math.sqrt(2.0 * math.pi)),
    ("antisymmetric", "acceleration"): 15.0
    * math.sqrt(3.0)
    / (16.0 * math.sqrt(math.pi) * ANTISYMMETRIC_NORM**2),
    ("symmetric", "velocity"): math.sqrt(math.pi) / (2.0 * (2.0 * math.pi**2) ** 1.5),
    ("antisymmetric", "velocity"): 9.0
    * math.sqrt(3.0 * math.pi)
    / (32.0 * math.pi**3 * ANTISYMMETRIC_NORM**2),
}


def _wavelet_spectrum(f, kind: str, source: str):
    """Fourier transform ∫ψ(u) e^(−2πifu) du of the unit-period wavelet, as phase × real part
    (Eq. M8).

    Symmetric (Eq. 5): ψ̂ = (2/√π) f² e^(−f²). Antisymmetric (Eq. 6, ψ ∝ −h‴(τ), h = e^(−τ²/2),
    τ = 2πu/√3): ψ̂ = i·9√(2π)/(2πβ) f³ e^(−3f²/2). On velocity Ψ = ∫ψ, so Ψ̂ = ψ̂/(2πif).
    Both ψ̂ peak at f = 1, i.e. at the pulse period.

    Returns
    -------
    phase : complex
        1, i or −i.
    magnitude : ndarray
        Real factor, the same shape as ``f`` (f ≥ 0).
    """
    f = np.asarray(f, dtype=float)
    f2 = f * f
    if kind == "symmetric":
        phase, mag = 1.0 + 0j, (2.0 / math.sqrt(math.pi)) * f2 * np.exp(-f2)
    else:
        coef = 9.0 * math.sqrt(2.0 * math.pi) / (2.0 * math.pi * ANTISYMMETRIC_NORM)
        phase, mag = 1j, coef * f2 * f * np.exp(-1.5 * f2)
    if source == "velocity":  # divide by 2πif; ψ̂ vanishes at f = 0 at least like f²
        phase = phase / 1j
        mag = mag / (2.0 * math.pi * np.where(f == 0, 1.0, f))
    return phase, mag


#: Beyond s·f = 7 the wavelet spectra are below 1e-19 of their peak and are not evaluated.
_BAND_LIMIT = 7.0


def check_options(kind=None, source=None, weighting=None):
    """ValueError unless each given option is one of its allowed values."""
    if kind is not None and kind not in KINDS:
        raise ValueError(f"kind must be one of {KINDS} or None, got {kind!r}")
    if source is not None and source not in SOURCES:
        raise ValueError(f"source must be one of {SOURCES}, got {source!r}")
    if weighting is not None and weighting not in WEIGHTINGS:
        raise ValueError(f"weighting must be one of {WEIGHTINGS}, got {weighting!r}")


def default_periods(dt: float, duration: float, step: float = 0.02,
                    longest: float = MAX_PULSE_PERIOD):
    """Default scale grid: geometric from max(0.2 s, 10·dt) to min(``longest``, duration) [s].

    Parameters
    ----------
    dt : float [s]
    duration : float [s]
    step : float [-]
        Relative spacing of consecutive scales (default 2 %).
    longest : float [s]
        Longest period searched (default 7.5 s, the paper's limit; 12 s before 2026-11-26).
    """
    if not longest > 0:
        raise ValueError(f"longest must be a positive period in s, got {longest!r}")
    lo = max(0.2, 10.0 * dt)
    hi = max(min(longest, duration), 2.0 * lo)
    n = math.ceil(math.log(hi / lo) / math.log1p(step)) + 1
    return np.geomspace(lo, hi, n)


def wavelet_transform(x, dt: float, periods, kind: str, source: str = "acceleration"):
    """Unweighted CWT  W(s, ξ) = ∫ x(t) ψ((t − ξ)/s) dt  at every sample ξ = t_n (paper Eq. 7;
    Eqs. M19 and M21).

    Multiply row i by w(s_i) for the weighted transform C. Computed by FFT with the
    wavelet's analytic spectrum, padded so nothing wraps around. Outside the record the
    ground is at rest before the first sample and, after the last, keeps its final value
    on velocity (a velocity record need not return to zero; padding it with zeros would
    add a step that the velocity wavelets, odd or even, pick up at long periods) and zero
    on acceleration.

    Parameters
    ----------
    x : array_like [m/s²] or [m/s]
        Acceleration record (``source="acceleration"``) or velocity record.
    dt : float [s]
        Time step.
    periods : array_like [s]
        Scales s (= Ricker period Tp).
    kind : {"symmetric", "antisymmetric"}
        Mother wavelet (acceleration shape).
    source : {"acceleration", "velocity"}
        Use ψ (acceleration) or Ψ = ∫ψ (velocity) as the wavelet.

    Returns
    -------
    ndarray, shape (len(periods), len(x)) [m/s] or [m]
    """
    from scipy.fft import irfft, next_fast_len, rfft  # lazy: keeps `import rigid` light

    check_options(kind, source)
    x = np.asarray(x, dtype=float)
    scales = np.asarray(periods, dtype=float)
    n = x.size
    out = np.empty((scales.size, n))
    order = np.argsort(scales)
    chunk = 16
    for start in range(0, scales.size, chunk):
        idx = order[start : start + chunk]
        reach = math.ceil(SUPPORT * scales[idx].max() / dt) + 1
        nfft = next_fast_len(n + 2 * reach, real=True)
        padded = np.zeros(nfft)
        padded[:n] = x
        if source == "velocity":  # hold the last value for half the pad, then rest
            padded[n : n + (nfft - n) // 2] = x[-1]
        f = np.fft.rfftfreq(nfft, dt)
        band = int(np.searchsorted(f, _BAND_LIMIT / scales[idx].min())) + 1
        phase, _ = _wavelet_spectrum(1.0, kind, source)
        spec_x = rfft(padded)[:band] * np.conj(phase)
        s = scales[idx, None]
        # ψ(t/s) ↔ s·ψ̂(s f); correlation = inverse transform of X·conj(Ĥ); the 1/dt of the
        # discrete spectrum cancels the dt of the integral.
        product = np.zeros((idx.size, nfft // 2 + 1), dtype=complex)
        product[:, :band] = spec_x * (s * _wavelet_spectrum(s * f[:band], kind, source)[1])
        out[idx] = irfft(product, nfft, axis=-1)[:, :n]
    return out
