"""The two region boundaries of an impact region spectrum, Ap(Tb/Tp), found directly by
bisection on each pulse period instead of a full grid (paper §3.2;
docs/theory/impact-spectra.md)."""

from __future__ import annotations

import math

import numpy as np

from ..bearing import DFPBearing
from ..units import G
from .regions import nonmonotonic_periods
from .spectra import check_sweep, default_periods, period_coords, spectrum_attrs
from .sweep import FAILURE, IMPACT, NUMERICAL, Evaluator, SweepSettings, resolve_cache, run_parallel

__all__ = ["region_boundaries"]


def _find_transition(f, k, evals, guess, tol, a_max):
    """Bracket [lo, hi] of the lowest transition to region ≥ k, hi − lo ≤ 2·tol (Eqs. I11–I12).

    ``f(A)`` simulates (cached in ``evals``). Starts from the evaluations so far; with a
    guess, steps out from it by 2·tol, 4·tol, …; then bisects. Returns (lo, None) when no
    evaluated amplitude up to ``a_max`` reaches region k.
    """

    def reached(a):
        r = f(a)
        return r >= k or r == NUMERICAL

    above = [a for a, r in evals.items() if r >= k or r == NUMERICAL]
    hi = min(above) if above else None
    below = [a for a in evals if a < (hi if hi is not None else math.inf)
             and not (evals[a] >= k or evals[a] == NUMERICAL)]
    lo = max([*below, 0.0])
    step = 2.0 * tol
    top = hi if hi is not None else a_max
    if guess is not None and lo + tol < guess < top - tol:
        if reached(guess):
            hi, s = guess, step
            while hi - s > lo:
                if reached(hi - s):
                    hi, s = hi - s, 2 * s
                else:
                    lo = hi - s
                    break
        else:
            lo, s = guess, step
            while lo + s < top:
                if reached(lo + s):
                    hi = lo + s
                    break
                lo, s = lo + s, 2 * s
    if hi is None:
        if a_max > lo and reached(a_max):
            hi = a_max
        else:
            return lo, None
    while hi - lo > 2.0 * tol * (1 + 1e-9):
        mid = 0.5 * (lo + hi)
        if reached(mid):
            hi = mid
        else:
            lo = mid
    return lo, hi


def _scan_transition(f, k, start, step, tol, a_max):
    """Lowest transition to region ≥ k on the amplitudes j·step ≥ ``start`` (j integer, and
    ``a_max``), then bisected to 2·tol (Eq. I13). Returns (lo, hi) or (lo, None) if not
    reached."""

    def reached(a):
        r = f(a)
        return r >= k or r == NUMERICAL

    lo = start
    j = math.floor(start / step) + 1
    hi = None
    while True:
        a = min(j * step, a_max)
        if reached(a):
            hi = a
            break
        lo = a
        if a >= a_max:
            return lo, None
        j += 1
    while hi - lo > 2.0 * tol * (1 + 1e-9):
        mid = 0.5 * (lo + hi)
        if reached(mid):
            hi = mid
        else:
            lo = mid
    return lo, hi


def _bisect_task(bearing, settings, cache_path, kind, periods, a_max, tol, scan_step,
                 failure=True):
    """Both boundaries for consecutive periods: impact by bisection from the previous period's
    boundary, failure by an upward scan from the impact boundary then bisection."""
    ev = Evaluator(bearing, settings, cache_path)
    out = []
    guess_i = guess_f = None
    for p in periods:
        evals: dict[float, int] = {}

        def f(a, p=p, evals=evals):
            if a not in evals:
                evals[a] = ev(kind, p, a).region
            return evals[a]

        lo_i, hi_i = _find_transition(f, IMPACT, evals, guess_i, tol, a_max)
        if hi_i is None or not failure:
            lo_f, hi_f = (lo_i, None) if failure else (math.nan, math.nan)
        elif scan_step is None:
            lo_f, hi_f = _find_transition(f, FAILURE, evals, guess_f, tol, a_max)
        else:
            lo_f, hi_f = _scan_transition(f, FAILURE, lo_i, scan_step, tol, a_max)
        amps = sorted(evals)
        regions = np.array([[evals[a]] for a in amps])
        fail_flag, impact_flag = nonmonotonic_periods(regions)
        out.append({
            "impact": (lo_i, hi_i), "failure": (lo_f, hi_f),
            "nonmonotonic_failure": bool(fail_flag[0]),
            "nonmonotonic_impact": bool(impact_flag[0]),
            "numerical": sum(r == NUMERICAL for r in evals.values()),
            "evaluations": len(evals),
        })
        guess_i = None if hi_i is None else 0.5 * (lo_i + hi_i)
        guess_f = None if hi_f is None else 0.5 * (lo_f + hi_f)
    return out, ev.computed, ev.reused


#: Periods per bisection task; each task walks its periods in order, starting every bisection
#: from the previous period's boundary. Fixed (not tied to the worker count) so that results
#: do not depend on the number of processes.
BISECTION_CHUNK = 10


def bracket_midpoint(bracket) -> float:
    """A boundary from its final bracket (lo, hi) [m/s²]: the midpoint, NaN when there is no
    upper end (no transition up to the highest amplitude tried)."""
    lo, hi = bracket
    return math.nan if hi is None else 0.5 * (lo + hi)


def boundaries_many(specs, settings, a_max, tol, scan_step, workers, progress, cache,
                     failure=True):
    """Bisection for several (bearing, kind, periods) in one process pool (the work of
    :func:`region_boundaries` and :func:`rigid.design_chart`; arguments as theirs, checked
    here)."""
    if not (a_max > 0 and tol > 0):
        raise ValueError("amplitude_max and tolerance must be positive accelerations [m/s²]")
    if scan_step is not None and not scan_step > 2 * tol:
        raise ValueError("scan_step must exceed twice the tolerance")
    path = resolve_cache(cache)
    jobs, owners = [], []
    for s, (bearing, kind, periods) in enumerate(specs):
        for i in range(0, len(periods), BISECTION_CHUNK):
            jobs.append((bearing, settings, path, kind, list(periods[i : i + BISECTION_CHUNK]),
                         a_max, tol, scan_step, failure))
            owners.append(s)
    results = run_parallel(_bisect_task, jobs, [len(j[4]) for j in jobs], workers=workers,
                           progress=progress, desc="region boundaries")
    per_spec = [[] for _ in specs]
    stats = [{"computed": 0, "reused": 0} for _ in specs]
    for s, (rows, computed, reused) in zip(owners, results, strict=True):
        per_spec[s].extend(rows)
        stats[s]["computed"] += computed
        stats[s]["reused"] += reused
    return per_spec, stats


def _boundary_dataset(bearing, kind, periods, rows, settings, a_max, tol, stats):
    import xarray as xr

    def arr(key, fn):
        return np.array([fn(r[key]) for r in rows])

    data = {}
    for name in ("impact", "failure"):
        data[f"{name}_boundary"] = ("period", arr(name, bracket_midpoint), {
            "units": "m/s2", "method": "bisection",
            "long_name": f"lowest Ap with {name} (midpoint of the final bracket)"})
        data[f"{name}_lower"] = ("period", arr(name, lambda p: p[0]), {"units": "m/s2"})
        data[f"{name}_upper"] = ("period", arr(name, lambda p: math.nan if p[1] is None
                                                else p[1]), {"units": "m/s2"})
    for flag in ("nonmonotonic_failure", "nonmonotonic_impact"):
        data[flag] = ("period", np.array([r[flag] for r in rows]), {
            "long_name": "non-monotonic among the evaluated amplitudes (bisection cannot "
                         "prove monotonicity; use the grid)"})
    data["numerical_failures"] = ("period", np.array([r["numerical"] for r in rows]))
    data["evaluations"] = ("period", np.array([r["evaluations"] for r in rows]))
    return xr.Dataset(
        data, coords=period_coords(bearing, periods),
        attrs=spectrum_attrs(bearing, kind, settings, amplitude_max=float(a_max),
                             tolerance=float(tol), tolerance_units="m/s2",
                             cells_computed=stats["computed"], cells_reused=stats["reused"]),
    )


def region_boundaries(
    bearing: DFPBearing,
    kind: str,
    periods=None,
    *,
    amplitude_max: float = 1.0 * G,
    tolerance: float = 0.005 * G,
    scan_step: float | None = 0.05 * G,
    failure: bool = True,
    settings: SweepSettings | None = None,
    workers: int | None = None,
    progress: bool | None = None,
    cache=True,
):
    """The two region boundaries Ap(Tb/Tp), found directly by bisection.

    *Impact boundary* (lowest Ap with a rim impact): bracketed and bisected until the bracket
    is at most 2·``tolerance`` wide; the boundary is its midpoint (within ± ``tolerance``).
    Consecutive periods (in tasks of :data:`BISECTION_CHUNK`) start from the previous
    period's boundary and step out by 2·tol, 4·tol, … This assumes that impact is monotonic in
    Ap; evaluations that contradict it set ``nonmonotonic_impact``.

    *Failure boundary* (lowest Ap with failure): the failure verdict of the rigid model is
    not monotonic in Ap (a slider lifted far above the rim may fall back inside or out, and a
    change of Ap in the 16th digit can flip it), so plain bisection could land on any of
    several transitions. With ``scan_step`` (default 0.05 g) the amplitudes j·scan_step above
    the impact boundary are tried upwards until the first failure, and that interval is
    bisected: the result is the lowest transition at the scan's resolution (the same
    amplitudes as a grid of multiples of ``scan_step``). With ``scan_step=None`` it is bisected
    like the impact boundary (cheaper, monotonic assumption). Only the full grid
    (:func:`impact_region_spectrum`) can show that a column is monotonic.

    Parameters
    ----------
    bearing : DFPBearing
    kind : {"symmetric", "antisymmetric"}
    periods : array_like [s], optional
        Default :func:`default_periods`.
    amplitude_max : float [m/s²]
        Highest amplitude tried; a boundary above it is NaN.
    tolerance : float [m/s²]
        Half-width of the final bracket (default 0.005 g).
    scan_step : float or None [m/s²]
        Step of the upward scan for the failure boundary (see above).
    failure : bool
        Also find the failure boundary (else its variables are NaN).
    settings, workers, progress, cache
        As in :func:`impact_velocity_spectrum`.

    Returns
    -------
    xarray.Dataset
        Along ``period``: ``impact_boundary``, ``failure_boundary`` [m/s²] with their brackets
        ``*_lower``, ``*_upper``; flags ``nonmonotonic_failure``, ``nonmonotonic_impact``
        (among the evaluated amplitudes); ``numerical_failures`` and ``evaluations`` counts.
    """
    periods = default_periods(bearing) if periods is None else periods
    (periods, _) = check_sweep(bearing, kind, periods)
    settings = SweepSettings() if settings is None else settings
    rows, stats = boundaries_many([(bearing, kind, periods)], settings, amplitude_max,
                                   tolerance, scan_step, workers, progress, cache, failure)
    return _boundary_dataset(bearing, kind, periods, rows[0], settings, amplitude_max,
                             tolerance, stats[0])
