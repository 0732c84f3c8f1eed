"""Ricker pulse extraction from a record (paper §4.1, Vassiliou & Makris 2011).

The record's wavelet transform (:mod:`rigid.motions.cwt`, paper Eq. 7) is searched for pulses.
Candidates are local maxima of |C| in the (s, ξ) plane (several, not only the global one),
refined by parabolas in ln s and ξ on the grid, then polished on the normalised projection of
the record on the sampled pulse template (docs/theory/ground-motions.md, "Pulse extraction",
Eqs. M26–M28). The amplitude is the least-squares projection of the record on the pulse in the
transform's own domain (Eq. M23), so a pure pulse is recovered exactly with w = 1/√s (Eq. M24),
while w = 1/s and w = 1 shift the scale by the closed-form ratio of Eq. M25. The match indices
are paper Eqs. 8–9 (Eqs. M29–M30):

    e_a = ∫ a_g a_p dt / ∫ a_g² dt,      e_v = ∫ v_g v_p dt / ∫ v_g² dt,

with v_g and v_p integrated the same way from the start of the record.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from .cwt import (
    MAX_PULSE_PERIOD,
    SOURCES,
    WEIGHT_EXPONENT,
    WEIGHTINGS,
    check_options,
    default_periods,
    wavelet_transform,
)
from .pulses import KINDS, ricker, ricker_velocity
from .record import cumulative_integral

__all__ = ["ALL_WEIGHTINGS", "CRITERIA", "Pulse", "best_pulse", "extract_pulse",
           "extract_pulses", "pulse_weightings"]

#: ``weighting`` of :func:`best_pulse` for the paper's procedure: the candidates of all three
#: weightings, then the criterion (docs/theory/ground-motions.md, Eq. M31).
ALL_WEIGHTINGS = "all"

@dataclass(frozen=True)
class Pulse:
    """A Ricker pulse extracted from a record.

    Parameters
    ----------
    kind : {"symmetric", "antisymmetric"}
        Shape of the *acceleration* pulse (paper Eq. 5 or 6).
    amplitude : float [m/s²]
        Ap, signed (a negative value flips the pulse).
    period : float [s]
        Tp.
    time : float [s]
        Arrival time t0 = ξ, the centre of the pulse, from the record's first sample.
    weighting : {"1/sqrt(s)", "1/s", "1"}
        w(s) of the transform that found it.
    source : {"acceleration", "velocity"}
        Record the transform was applied to.
    e_a, e_v : float [-]
        Match indices, paper Eqs. 8–9.
    coefficient : float
        Weighted wavelet coefficient C(s, ξ) at the grid maximum, w(s) = s^(−p):
        [m·s^(−1−p)] on acceleration, [m·s^(−p)] on velocity.
    """

    kind: str
    amplitude: float
    period: float
    time: float
    weighting: str
    source: str
    e_a: float
    e_v: float
    coefficient: float = float("nan")

    def acceleration(self, t):
        """Pulse acceleration [m/s²] at times ``t`` [s]."""
        return ricker(t, self.amplitude, self.period, self.kind, t0=self.time)

    def velocity(self, t):
        """Exact pulse velocity [m/s] at times ``t`` [s], zero at t = −∞."""
        return ricker_velocity(t, self.amplitude, self.period, self.kind, t0=self.time)

    def scaled(self, factor: float) -> Pulse:
        """The pulse of the record scaled by ``factor`` [-]: Ap scales, e_a and e_v do not."""
        return replace(
            self, amplitude=self.amplitude * factor, coefficient=self.coefficient * factor
        )


# --------------------------------------------------------------------------- candidates


def _row_maxima(mag):
    """Per-row 3-point running maximum of |W|, and the points that are maxima along ξ."""
    from scipy.ndimage import maximum_filter1d

    row_max = maximum_filter1d(mag, 3, axis=1, mode="constant", cval=-np.inf)
    rows, cols = np.nonzero(mag >= row_max)
    return row_max, rows, cols


def _local_maxima(mag, row_max, rows, cols, weights, periods, dt: float, count: int):
    """(row, col) of the ``count`` largest local maxima of w(s)·|W|, one per pulse
    (docs/theory/ground-motions.md, "Pulse extraction").

    A maximum is not exceeded by any of its 8 neighbours (grid edges count as −∞); ``rows``
    and ``cols`` are the maxima along ξ. Maxima within ±0.5·s in ξ and a factor 1.5 in s of
    a larger accepted one are duplicates of the same pulse (cf. the ±(10/25)·scale blocking
    of Shahi & Baker 2014) and are dropped.
    """
    values = weights[rows] * mag[rows, cols]
    ok = np.ones(rows.size, dtype=bool)
    up, down = rows < mag.shape[0] - 1, rows > 0
    ok[up] &= values[up] >= weights[rows[up] + 1] * row_max[rows[up] + 1, cols[up]]
    ok[down] &= values[down] >= weights[rows[down] - 1] * row_max[rows[down] - 1, cols[down]]
    rows, cols, values = rows[ok], cols[ok], values[ok]
    if rows.size == 0:  # no strict maximum (e.g. a plateau); fall back to the global one
        weighted = weights[:, None] * mag
        r, c = np.unravel_index(np.argmax(weighted), weighted.shape)
        return [(int(r), int(c))]
    keep = min(values.size, 20 * count)
    top = np.argpartition(values, values.size - keep)[values.size - keep :]
    top = top[np.argsort(values[top])[::-1]]
    accepted: list[tuple[int, int]] = []
    for k in top:
        r, c = int(rows[k]), int(cols[k])
        duplicate = False
        for r2, c2 in accepted:
            s_big, s_small = max(periods[r], periods[r2]), min(periods[r], periods[r2])
            if abs(c - c2) * dt < 0.5 * s_big and s_big < 1.5 * s_small:
                duplicate = True
                break
        if not duplicate:
            accepted.append((r, c))
            if len(accepted) == count:
                break
    return accepted


def _parabola_offset(y0: float, y1: float, y2: float) -> float:
    """Vertex of the parabola through (−1, y0), (0, y1), (1, y2), clipped to ±0.5 (Eq. M26)."""
    den = y0 - 2.0 * y1 + y2
    if not den < 0:
        return 0.0
    return float(np.clip(0.5 * (y0 - y2) / den, -0.5, 0.5))


def _refine(mag, weights, r: int, c: int, periods, dt: float):
    """Sub-grid (period, time) of a maximum of w(s)·|W| by parabolas in ln s and in ξ.

    The parabolas are fitted to ln|W| (Eq. M27): for a Ricker pulse ln|W| is even about the
    peak in ln s to third order (the profile r^(n+1−p)/(1 + r²)^(n+½) of Eq. M25 at p = ½), so
    the vertex is accurate to O(h⁴) rather than O(h²) on a grid of step h.
    """
    nrow, ncol = mag.shape
    tiny = np.finfo(float).tiny
    log_s = math.log(periods[r])
    if 0 < r < nrow - 1:
        y = np.log(np.maximum(weights[r - 1 : r + 2] * mag[r - 1 : r + 2, c], tiny))
        log_s += _parabola_offset(*y) * (math.log(periods[r + 1]) - math.log(periods[r - 1])) / 2
    t0 = c * dt
    if 0 < c < ncol - 1:
        t0 += _parabola_offset(*np.log(np.maximum(mag[r, c - 1 : c + 2], tiny))) * dt
    return math.exp(log_s), t0


def _match(x, t, dt, kind, source, p, period, t0):
    """s^(½−p)·|⟨x, T⟩|/‖T‖ with T the sampled pulse template in the source's domain (Eq. M28).

    Equal to the weighted coefficient w(s)·|C| up to a constant and O(dt²) (‖T‖² ≈ s‖ψ‖²),
    but built from the very templates the amplitude fit uses (on velocity, the trapezoidal
    integral of the sampled pulse), so with p = ½ a sampled pulse maximises it exactly
    (Cauchy–Schwarz). Evaluated on ±3.5·s around t0.
    """
    lo = max(0, math.floor((t0 - 3.5 * period) / dt))
    hi = min(x.size, math.ceil((t0 + 3.5 * period) / dt) + 1)
    template = ricker(t[lo:hi], 1.0, period, kind, t0=t0)
    if source == "velocity":
        template = cumulative_integral(template, dt)
    norm = math.sqrt(float(template @ template))
    if norm == 0.0:
        return 0.0
    return period ** (0.5 - p) * abs(float(x[lo:hi] @ template)) / norm


def _polish(x, t, dt, kind, source, p, period, t0, log_step: float, rounds: int = 2):
    """Alternating parabolic steps on ln of :func:`_match` in ln s and ξ.

    Removes the small biases of the grid refinement: the maximum over ξ is taken on whole
    samples, and the continuous velocity wavelet differs from the trapezoidal velocity by
    O(dt²).
    """
    h_s, h_t = 0.5 * log_step, 0.5 * dt
    for _ in range(rounds):
        y = [_match(x, t, dt, kind, source, p, period * math.exp(k * h_s), t0) for k in (-1, 0, 1)]
        if min(y) > 0:
            period *= math.exp(_parabola_offset(*np.log(y)) * h_s)
        y = [_match(x, t, dt, kind, source, p, period, t0 + k * h_t) for k in (-1, 0, 1)]
        if min(y) > 0:
            t0 += _parabola_offset(*np.log(y)) * h_t
        h_s, h_t = 0.5 * h_s, 0.5 * h_t
    return period, t0


def _inner(x, y) -> float:
    """∫x·y dt / dt by the trapezoidal rule over the record."""
    return float(x @ y) - 0.5 * (x[0] * y[0] + x[-1] * y[-1])


def _fit(acc, vel, t, dt, kind, source, weighting, period, t0, coefficient):
    """Least-squares amplitude in the source's domain and e_a, e_v (paper Eqs. 8–9; Eqs. M23,
    M29–M30).

    All integrals over the record by the trapezoidal rule; v_p is integrated from the first
    sample like v_g.
    """
    a1 = ricker(t, 1.0, period, kind, t0=t0)
    v1 = cumulative_integral(a1, dt)
    x, unit = (acc, a1) if source == "acceleration" else (vel, v1)
    den = _inner(unit, unit)
    amp = _inner(x, unit) / den if den > 0 else 0.0
    # Eq. 8: e_a = ∫a_g a_p dt / ∫a_g² dt; Eq. 9 likewise with velocities (dt cancels).
    e_a = amp * _inner(acc, a1) / _inner(acc, acc)
    vv = _inner(vel, vel)
    e_v = amp * _inner(vel, v1) / vv if vv > 0 else 0.0
    return Pulse(kind, amp, period, t0, weighting, source, e_a, e_v, coefficient)


def _as_arrays(motion, dt):
    if dt is None:
        acc, dt = np.asarray(motion.acceleration, dtype=float), float(motion.dt)
    else:
        acc = np.asarray(motion, dtype=float)
    if not (np.isfinite(dt) and dt > 0):
        raise ValueError(f"dt must be a positive number of seconds, got {dt!r}")
    if acc.ndim != 1 or acc.size < 4 or not np.all(np.isfinite(acc)):
        raise ValueError("the record must be a finite 1-D acceleration with at least 4 samples")
    if not np.any(acc):
        raise ValueError("the record is identically zero; there is no pulse to extract")
    return acc, dt


def extract_pulses(
    motion,
    sources=SOURCES,
    weightings=WEIGHTINGS,
    kinds=KINDS,
    periods=None,
    count: int = 5,
    dt: float | None = None,
    max_period: float = MAX_PULSE_PERIOD,
):
    """Candidate Ricker pulses for every (source, weighting, kind) combination.

    Each wavelet transform is computed once per (source, kind) and reused for the three
    weightings. This is the full extraction of the benchmark.

    Parameters
    ----------
    motion : GroundMotion or array_like [m/s²]
        The record; an array needs ``dt``.
    sources : iterable of {"acceleration", "velocity"}
    weightings : iterable of {"1/sqrt(s)", "1/s", "1"}
    kinds : iterable of {"symmetric", "antisymmetric"}
    periods : array_like [s], optional
        Scale grid; default :func:`default_periods` (0.2 s to ``max_period``, 2 % steps).
        No pulse period leaves the grid's range.
    count : int
        Number of local maxima kept per combination.
    dt : float [s], optional
        Time step when ``motion`` is an array.
    max_period : float [s]
        Longest period of the default grid (the paper's 7.5 s; ignored with ``periods``).

    Returns
    -------
    dict
        ``{(source, weighting, kind): [Pulse, …]}``, each list in order of decreasing
        weighted coefficient |C|.
    """
    acc, dt = _as_arrays(motion, dt)
    for src in sources:
        check_options(source=src)
    for wgt in weightings:
        check_options(weighting=wgt)
    for knd in kinds:
        check_options(kind=knd)
    t = np.arange(acc.size) * dt
    if periods is None:
        periods = default_periods(dt, t[-1], longest=max_period)
    else:  # sorted, so grid neighbours are neighbouring scales
        periods = np.unique(np.asarray(periods, dtype=float))
        if periods.size < 3 or not np.all(np.isfinite(periods)) or periods[0] <= 0:
            raise ValueError("periods must hold at least 3 distinct positive scales [s]")
    vel = cumulative_integral(acc, dt)
    log_step = float(np.median(np.diff(np.log(periods))))
    result = {}
    for src in sources:
        x = acc if src == "acceleration" else vel
        for knd in kinds:
            w_raw = wavelet_transform(x, dt, periods, knd, src)
            mag = np.abs(w_raw)
            row_max, rows, cols = _row_maxima(mag)
            for wgt in weightings:
                weights = periods ** (-WEIGHT_EXPONENT[wgt])
                found = _local_maxima(mag, row_max, rows, cols, weights, periods, dt, count)
                pulses = []
                for r, c in found:
                    period, t0 = _refine(mag, weights, r, c, periods, dt)
                    period, t0 = _polish(
                        x, t, dt, knd, src, WEIGHT_EXPONENT[wgt], period, t0, log_step
                    )
                    period = min(max(period, periods[0]), periods[-1])  # the grid's range
                    coef = float(weights[r] * w_raw[r, c])
                    pulses.append(_fit(acc, vel, t, dt, knd, src, wgt, period, t0, coef))
                result[(src, wgt, knd)] = pulses
    return result


def _own_index(pulse: Pulse) -> float:
    return pulse.e_a if pulse.source == "acceleration" else pulse.e_v


def extract_pulse(
    motion,
    source: str = "acceleration",
    weighting: str = "1/sqrt(s)",
    kind: str | None = None,
    periods=None,
    dt: float | None = None,
    max_period: float = MAX_PULSE_PERIOD,
) -> Pulse:
    """The Ricker pulse at the largest weighted wavelet coefficient (Vassiliou & Makris 2011).

    For each kind the pulse sits at the global maximum of w(s)·|C| over (s, ξ); with
    ``kind=None`` the kind whose pulse has the larger match index in the transform's own
    domain (e_a on acceleration, e_v on velocity) is returned.

    Parameters
    ----------
    motion : GroundMotion or array_like [m/s²]
        The record; an array needs ``dt``.
    source : {"acceleration", "velocity"}
        Record the transform is applied to.
    weighting : {"1/sqrt(s)", "1/s", "1"}
        w(s) of paper Eq. 7. Only 1/√s returns the period of a pure pulse unbiased;
        1/s and 1 shift it by the factors of docs/theory/ground-motions.md, Eq. M25.
    kind : {"symmetric", "antisymmetric"} or None
        Mother wavelet; None tries both.
    periods : array_like [s], optional
        Scale grid (default 0.2 s to ``max_period`` in 2 % steps).
    dt : float [s], optional
        Time step when ``motion`` is an array.
    max_period : float [s]
        Longest period of the default grid (the paper's 7.5 s).

    Returns
    -------
    Pulse
        A period at an end of the scale grid means the maximum is not resolved there
        (e.g. long-period drift of an uncorrected velocity record with w = 1).
    """
    check_options(kind, source, weighting)
    kinds = KINDS if kind is None else (kind,)
    found = extract_pulses(motion, (source,), (weighting,), kinds, periods, 1, dt, max_period)
    best = [found[(source, weighting, k)][0] for k in kinds]
    return max(best, key=_own_index)


#: Paper §4.1: criterion → (source record, index maximised) (Eq. M31).
CRITERIA = {
    1: ("acceleration", "e_a"),
    2: ("acceleration", "e_v"),
    3: ("velocity", "e_a"),
    4: ("velocity", "e_v"),
}


def best_pulse(
    motion,
    criterion: int = 4,
    weighting: str = ALL_WEIGHTINGS,
    periods=None,
    count: int = 5,
    dt: float | None = None,
    max_period: float = MAX_PULSE_PERIOD,
) -> Pulse:
    """The best-matching Ricker pulse by one of the paper's four criteria (§4.1).

    1. from the acceleration record, maximum e_a;   2. from the acceleration record, max e_v;
    3. from the velocity record, maximum e_a;       4. from the velocity record, max e_v.

    The maximum is taken over ``count`` candidate maxima of each kind (both kinds) and, by
    default, of each of the three weightings, as the paper does (Eq. M31).
    Note that e_a and e_v are linear in Ap, so an index computed in the other domain can
    exceed 1 for an over-scaled pulse (docs/theory/ground-motions.md, after Eq. M30).

    Parameters
    ----------
    motion : GroundMotion or array_like [m/s²]
        The record; an array needs ``dt``.
    criterion : {1, 2, 3, 4}
        Paper §4.1 (the paper recommends 4; an earlier study preferred 3).
    weighting : {"all", "1/sqrt(s)", "1/s", "1"}
        w(s) of paper Eq. 7; ``"all"`` (the paper's procedure) pools the candidates of the
        three. The returned pulse's ``weighting`` names the one that found it.
    periods : array_like [s], optional
        Scale grid.
    count : int
        Candidates per kind and weighting.
    dt : float [s], optional
        Time step when ``motion`` is an array.
    max_period : float [s]
        Longest period of the default grid (the paper's 7.5 s).

    Returns
    -------
    Pulse
    """
    if criterion not in CRITERIA:
        raise ValueError(f"criterion must be 1, 2, 3 or 4, got {criterion!r}")
    weightings = pulse_weightings(weighting)
    source, index = CRITERIA[criterion]
    found = extract_pulses(motion, (source,), weightings, KINDS, periods, count, dt, max_period)
    # ties (one pulse found by several weightings) go to the first in WEIGHTINGS' order
    candidates = [p for w in weightings for k in KINDS for p in found[(source, w, k)]]
    return max(candidates, key=lambda p: getattr(p, index))


def pulse_weightings(weighting: str) -> tuple:
    """The weightings a ``weighting`` option names: all three for ``"all"``, else itself
    (ValueError for anything else)."""
    if weighting == ALL_WEIGHTINGS:
        return WEIGHTINGS
    if weighting not in WEIGHTINGS:
        raise ValueError(f"weighting must be {ALL_WEIGHTINGS!r} (the paper's procedure) or one "
                         f"of {WEIGHTINGS}, got {weighting!r}")
    return (weighting,)
