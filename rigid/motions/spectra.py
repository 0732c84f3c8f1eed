"""Elastic response spectra by the exact piecewise-linear method, and FEMA P695 scaling.

The single-degree-of-freedom oscillator ü + 2ξωu̇ + ω²u = −a_g(t) is integrated exactly for
a ground acceleration that is linear between samples (Nigam & Jennings 1969, BSSA 59(2)). The
two-step state recurrence [u, u̇]_{i+1} = A·[u, u̇]_i + B·[a_i, a_{i+1}] is rewritten as a
second-order IIR filter and run by :func:`scipy.signal.lfilter`, one call per period, so the
time loop is compiled. Peaks between samples are not sought: at T ≥ 10·dt the sampled peak is
at most 5 % (about 1–2 % typically) below the continuous one, and at Tb = 4.5 s there are
hundreds of samples per period (docs/theory/ground-motions.md, Eqs. M9–M14).
"""

from __future__ import annotations

import math

import numpy as np

from ..units import G

__all__ = [
    "nigam_jennings_coefficients",
    "pseudo_acceleration",
    "scale_factor",
    "scaling_ladder",
    "spectral_displacement",
]


def nigam_jennings_coefficients(period: float, dt: float, damping: float = 0.05):
    """State-transition matrices of the exact piecewise-linear recurrence.

    Parameters
    ----------
    period : float [s]
        Natural period T of the oscillator.
    dt : float [s]
        Time step of the record.
    damping : float [-]
        Damping ratio ξ, 0 ≤ ξ < 1.

    Returns
    -------
    A, B : ndarray, shape (2, 2)
        ``[u, u̇]_{i+1} = A @ [u, u̇]_i + B @ [a_i, a_{i+1}]`` for ü + 2ξωu̇ + ω²u = −a_g,
        with u [m], u̇ [m/s] and a [m/s²] (Nigam & Jennings 1969, Eqs. 5–6;
        docs/theory/ground-motions.md, Eqs. M10–M11).
    """
    xi = float(damping)
    w = 2.0 * math.pi / period
    wd = w * math.sqrt(1.0 - xi * xi)
    q = xi / math.sqrt(1.0 - xi * xi)
    e = math.exp(-xi * w * dt)
    s = math.sin(wd * dt)
    c = math.cos(wd * dt)
    a = np.array(
        [
            [e * (q * s + c), e * s / wd],
            [-w / math.sqrt(1.0 - xi * xi) * e * s, e * (c - q * s)],
        ]
    )
    k1 = (2.0 * xi * xi - 1.0) / (w * w * dt)
    k2 = 2.0 * xi / (w**3 * dt)
    b = np.array(
        [
            [
                e * ((k1 + xi / w) * s / wd + (k2 + 1.0 / w**2) * c) - k2,
                -e * (k1 * s / wd + k2 * c) - 1.0 / w**2 + k2,
            ],
            [
                e * ((k1 + xi / w) * (c - q * s) - (k2 + 1.0 / w**2) * (wd * s + xi * w * c))
                + 1.0 / (w * w * dt),
                -e * (k1 * (c - q * s) - k2 * (wd * s + xi * w * c)) - 1.0 / (w * w * dt),
            ],
        ]
    )
    return a, b


def _displacement_filter(period: float, dt: float, damping: float):
    """(b, a) of the IIR filter a_g → u equivalent to the N-J recurrence (Eq. M12).

    With z-transforms, X = (zI − A)⁻¹ (B₀ + z B₁) a_g, where B₀ and B₁ are B's columns; the
    first row of the adjugate gives the numerator, det(zI − A) the denominator.
    """
    a, b = nigam_jennings_coefficients(period, dt, damping)
    num = np.array(
        [
            b[0, 1],
            b[0, 0] - a[1, 1] * b[0, 1] + a[0, 1] * b[1, 1],
            -a[1, 1] * b[0, 0] + a[0, 1] * b[1, 0],
        ]
    )
    den = np.array([1.0, -(a[0, 0] + a[1, 1]), a[0, 0] * a[1, 1] - a[0, 1] * a[1, 0]])
    # Initial filter state for rest at t = 0 with the first sample a_0 already applied
    # (u_0 = 0, u_1 = B₁₀a_0 + B₁₁a_1), i.e. the same convention as lsim with X0 = 0.
    zi_per_a0 = np.array([-num[0], a[1, 1] * b[0, 1] - a[0, 1] * b[1, 1]])
    return num, den, zi_per_a0


def _check_inputs(acceleration, dt, periods, damping):
    acc = np.asarray(acceleration, dtype=float)
    if acc.ndim == 0 or acc.shape[-1] < 2:
        raise ValueError("acceleration must hold at least two samples along its last axis")
    if not np.all(np.isfinite(acc)):
        raise ValueError("acceleration contains NaN or infinite values")
    if not (np.isfinite(dt) and dt > 0):
        raise ValueError(f"dt must be a positive number of seconds, got {dt!r}")
    per = np.atleast_1d(np.asarray(periods, dtype=float))
    if per.ndim != 1 or not np.all(np.isfinite(per)) or np.any(per <= 0):
        raise ValueError("periods must be a 1-D array of positive numbers of seconds")
    if not 0 <= damping < 1:
        raise ValueError(f"damping must lie in [0, 1), got {damping!r}")
    return acc, per


def spectral_displacement(acceleration, dt: float, periods, damping: float = 0.05):
    """Peak relative displacement Sd of linear oscillators under a ground acceleration.

    Parameters
    ----------
    acceleration : array_like [m/s²]
        Ground acceleration, sampled every ``dt``; the last axis is time, leading axes
        (several records of the same length and step) are kept.
    dt : float [s]
        Time step.
    periods : float or array_like [s]
        Natural periods T.
    damping : float [-]
        Damping ratio ξ (default 5 %).

    Returns
    -------
    ndarray [m]
        Shape ``acceleration.shape[:-1] + (len(periods),)``.
    """
    from scipy.signal import lfilter  # lazy: scipy.signal takes ~0.5 s to import

    acc, per = _check_inputs(acceleration, dt, periods, damping)
    out = np.empty((*acc.shape[:-1], per.size))
    a0 = acc[..., :1]
    for j, period in enumerate(per):
        num, den, zi1 = _displacement_filter(period, dt, damping)
        u, _ = lfilter(num, den, acc, axis=-1, zi=a0 * zi1)
        out[..., j] = np.max(np.abs(u), axis=-1)
    return out


def pseudo_acceleration(acceleration, dt: float, periods, damping: float = 0.05):
    """5 %-damped (by default) pseudo-spectral acceleration PSA = ω²·Sd (Eq. M13).

    Exact for a ground acceleration that is linear between samples (Nigam & Jennings 1969),
    run as an IIR filter with :func:`scipy.signal.lfilter`; the oscillator starts at rest at
    the first sample.

    Parameters
    ----------
    acceleration : array_like [m/s²]
        Ground acceleration; last axis is time (leading axes are kept).
    dt : float [s]
        Time step.
    periods : float or array_like [s]
        Natural periods T.
    damping : float [-]
        Damping ratio ξ, 0 ≤ ξ < 1.

    Returns
    -------
    ndarray [m/s²]
        Shape ``acceleration.shape[:-1] + (len(periods),)``.

    Examples
    --------
    >>> import numpy as np, rigid
    >>> t, a = rigid.ricker_record(1.0, 1.0, dt=0.001)
    >>> round(float(rigid.pseudo_acceleration(a, 0.001, [1.0])[0]), 4)  # ground-motions.md
    2.0834
    """
    sd = spectral_displacement(acceleration, dt, periods, damping)
    return sd * (2.0 * np.pi / np.atleast_1d(np.asarray(periods, dtype=float))) ** 2


def scale_factor(
    acceleration, dt: float, target: float, period: float = 4.5, damping: float = 0.05
) -> float:
    """Factor k that brings the record's PSA at ``period`` to ``target`` (PSA is linear in k;
    Eq. M15).

    Parameters
    ----------
    acceleration : array_like [m/s²]
        Ground acceleration (1-D).
    dt : float [s]
        Time step.
    target : float [m/s²]
        Wanted PSA(T). Multiply a value in g by :data:`rigid.G`.
    period : float [s]
        T, the bearing period Tb (paper: 4.5 s).
    damping : float [-]
        Damping ratio ξ.

    Returns
    -------
    float [-]
    """
    sa = float(pseudo_acceleration(acceleration, dt, [period], damping)[..., 0])
    if sa <= 0:
        raise ValueError("the record has zero spectral acceleration at this period")
    return target / sa


def scaling_ladder(
    acceleration,
    dt: float,
    stop: float,
    step: float = 0.01 * G,
    start: float | None = None,
    period: float = 4.5,
    damping: float = 0.05,
):
    """The FEMA P695-style ladder of record scales in equal steps of PSA(T).

    Bao & Becker (2016, §4.2) step SA(Tb = 4.5 s) up by 0.01 g until the bearing fails; the
    scale of rung j is k_j = SA*_j / SA_record(T), with SA*_j = start + j·step ≤ stop
    (Eq. M16).

    Parameters
    ----------
    acceleration : array_like [m/s²]
        Ground acceleration (1-D), as recorded (or as normalised).
    dt : float [s]
        Time step.
    stop : float [m/s²]
        Highest target PSA (inclusive, to 1e-9 of a step).
    step : float [m/s²]
        Rung spacing; default 0.01 g.
    start : float [m/s²], optional
        First rung; default one ``step``.
    period : float [s]
        Scaling period T (paper: Tb = 4.5 s).
    damping : float [-]
        Damping ratio ξ.

    Returns
    -------
    targets : ndarray [m/s²]
        PSA(T) of each rung.
    factors : ndarray [-]
        Scale factor of the record for each rung.
    """
    if not (step > 0 and np.isfinite(step)):
        raise ValueError(f"step must be a positive acceleration [m/s²], got {step!r}")
    start = step if start is None else start
    n = math.floor((stop - start) / step + 1e-9) + 1
    if n < 1:
        raise ValueError("stop must not be below start")
    targets = start + step * np.arange(n)
    sa = float(pseudo_acceleration(acceleration, dt, [period], damping)[..., 0])
    if sa <= 0:
        raise ValueError("the record has zero spectral acceleration at this period")
    return targets, targets / sa
