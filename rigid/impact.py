"""Impact velocity spectra and impact region spectra of the rigid model (paper §3).

For Ricker pulses (paper Eqs. 5–6) of kind, period Tp and amplitude Ap, the bearing either
never touches a rim (region 0), hits a rim and survives (region 1), or fails (region 2):

* :func:`impact_velocity_spectrum` — every impact's velocity (top plate relative to the bottom
  plate at first contact), its maximum and the failure flag, over Tb/Tp for one amplitude
  (paper Fig. 6);
* :func:`impact_region_spectrum` — the region and the maximum impact velocity over a grid of
  (Ap, Tp) (paper Fig. 8); its rows are the maximum impact velocity spectra of Fig. 7, also
  available as :func:`max_impact_velocity_spectra`;
* :func:`region_boundaries` — the two region boundaries Ap(Tb/Tp) found directly by bisection;
* :func:`region_at` — "which region is (Tp, Ap) in", for the prediction step (paper §4.2);
* :func:`design_chart` — beyond the paper: the boundaries as Ap·Tp²/d_cap against Tb/Tp for
  several bearings (the "generalized graphs" of the abstract).

Tb is ``bearing.design_period`` (paper: 4.5 s). Results are :class:`xarray.Dataset` objects
with units in the attributes and the bearing's parameters as ``bearing_*`` attributes;
:func:`save_spectrum` / :func:`load_spectrum` write and read NetCDF. Cells are computed by
:mod:`rigid.sweep` (parallel, cached). xarray is imported on use.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence

import numpy as np

from .bearing import DFPBearing, G
from .model import RIM_NAMES
from .pulses import KINDS
from .sweep import (
    FAILURE,
    IMPACT,
    NO_IMPACT,
    NUMERICAL,
    Evaluator,
    SweepSettings,
    resolve_cache,
    run_cells,
    run_parallel,
)

__all__ = [
    "bearing_from_attrs",
    "default_amplitudes",
    "default_periods",
    "design_chart",
    "grid_boundaries",
    "impact_region_spectrum",
    "impact_velocity_spectrum",
    "load_spectrum",
    "max_impact_velocity_spectra",
    "nonmonotonic_periods",
    "region_at",
    "region_boundaries",
    "save_spectrum",
]

#: Longest pulse period considered (paper §3.1: "longer period pulse is not realistic") [s].
PERIOD_MAX = 7.5

REGION_MEANINGS = "no_impact impact_without_failure impact_with_failure"


# -- grids ----------------------------------------------------------------------------------------


def default_periods(bearing: DFPBearing, n: int = 100, ratio_max: float = 6.0) -> np.ndarray:
    """Pulse periods Tp [s], uniform in Tb/Tp from Tb/7.5 s to ``ratio_max``, ascending in Tp."""
    ratios = np.linspace(bearing.design_period / PERIOD_MAX, ratio_max, n)
    return np.sort(bearing.design_period / ratios)


def default_amplitudes(n: int = 100, top: float = 1.0 * G) -> np.ndarray:
    """Pulse amplitudes Ap [m/s²]: ``n`` equal steps up to ``top`` (default 0.01 g … 1.0 g)."""
    return top * np.arange(1, n + 1) / n


def _check(bearing, kind, periods=None, amplitudes=None):
    if not isinstance(bearing, DFPBearing):
        raise TypeError(f"bearing must be a DFPBearing, got {type(bearing).__name__}")
    if kind not in KINDS:
        raise ValueError(f"kind must be 'symmetric' or 'antisymmetric', got {kind!r}")
    out = []
    for name, values in (("periods", periods), ("amplitudes", amplitudes)):
        if values is None:
            out.append(None)
            continue
        v = np.atleast_1d(np.asarray(values, dtype=float))
        if v.ndim != 1 or v.size == 0 or not np.all(np.isfinite(v)) or np.any(v <= 0):
            raise ValueError(f"{name} must be a non-empty 1-D array of positive numbers")
        if np.any(np.diff(np.sort(v)) == 0):
            raise ValueError(f"{name} must not repeat values")
        out.append(np.sort(v))
    return out


# -- dataset helpers ---------------------------------------------------------------------------


def _attrs(bearing: DFPBearing, kind: str, settings: SweepSettings, **extra) -> dict:
    attrs = {"kind": kind, "design_period": bearing.design_period,
             "design_period_units": "s", "model_period": bearing.period,
             "displacement_capacity": bearing.displacement_capacity,
             "source": "rigid-body DFP model, Bao & Becker (2016) §3"}
    for f in dataclasses.fields(bearing):
        attrs[f"bearing_{f.name}"] = getattr(bearing, f.name)
    for f in dataclasses.fields(settings):
        value = getattr(settings, f.name)
        if isinstance(value, bool):
            value = int(value)
        attrs[f"settings_{f.name}"] = "default" if value is None else value
    attrs.update(extra)
    return attrs


def bearing_from_attrs(ds) -> DFPBearing:
    """Rebuild the :class:`DFPBearing` recorded in a spectrum's ``bearing_*`` attributes."""
    kwargs = {}
    for f in dataclasses.fields(DFPBearing):
        value = ds.attrs[f"bearing_{f.name}"]
        kwargs[f.name] = str(value) if f.name == "impact_mass" else float(value)
    return DFPBearing(**kwargs)


def settings_from_attrs(ds) -> SweepSettings:
    """Rebuild the :class:`SweepSettings` recorded in a spectrum's ``settings_*`` attributes."""
    kwargs = {}
    for f in dataclasses.fields(SweepSettings):
        value = ds.attrs[f"settings_{f.name}"]
        if isinstance(value, str):
            value = None
        elif f.name == "stop_when_quiet":
            value = bool(value)
        elif f.name == "max_impacts":
            value = int(value)
        else:
            value = float(value)
        kwargs[f.name] = value
    return SweepSettings(**kwargs)


def _period_coords(bearing, periods):
    return {
        "period": ("period", periods, {"units": "s", "long_name": "pulse period Tp"}),
        "frequency_ratio": ("period", bearing.design_period / periods,
                            {"units": "1", "long_name": "Tb/Tp"}),
    }


def save_spectrum(ds, path) -> None:
    """Write a spectrum Dataset to NetCDF (``path``, e.g. ``*.nc``)."""
    ds.to_netcdf(path)


def load_spectrum(path):
    """Read a spectrum Dataset written by :func:`save_spectrum` (fully loaded, file closed)."""
    import xarray as xr

    with xr.open_dataset(path) as ds:
        return ds.load()


# -- region analysis (pure functions on arrays) ---------------------------------------------------


def nonmonotonic_periods(region) -> tuple[np.ndarray, np.ndarray]:
    """Columns whose regions are not monotonic in amplitude.

    Parameters
    ----------
    region : array_like of int, shape (n_amplitudes, n_periods)
        Region codes with amplitudes ascending along axis 0; -1 (numerical failure) cells are
        ignored.

    Returns
    -------
    failure_below_nonfailure : ndarray of bool, shape (n_periods,)
        Some failure cell lies below a cell without failure.
    impact_below_no_impact : ndarray of bool, shape (n_periods,)
        Some cell with an impact lies below a cell without impact.
    """
    r = np.asarray(region)
    if r.ndim != 2:
        raise ValueError("region must be two-dimensional (amplitude, period)")
    valid = r >= 0
    failed = np.maximum.accumulate((r == FAILURE) & valid, axis=0)
    hit = np.maximum.accumulate((r >= IMPACT) & valid, axis=0)
    fail_flag = np.any(failed & valid & (r != FAILURE), axis=0)
    impact_flag = np.any(hit & valid & (r == NO_IMPACT), axis=0)
    return fail_flag, impact_flag


def grid_boundaries(region, amplitudes) -> tuple[np.ndarray, np.ndarray]:
    """Region boundaries read from a grid [m/s²], one per period column.

    The boundary of region k is placed midway between the first cell (lowest amplitude) whose
    region is ≥ k and the cell below it (Ap = 0, no motion, below the first row), i.e. the
    true boundary is within half an amplitude step of it when the column is monotonic. NaN if
    the region is not reached on the grid. In a non-monotonic column this is the lowest
    transition (conservative); see :func:`nonmonotonic_periods`.

    Returns
    -------
    impact_boundary, failure_boundary : ndarray [m/s²]
    """
    r = np.asarray(region)
    a = np.concatenate([[0.0], np.asarray(amplitudes, dtype=float)])
    out = []
    for k in (IMPACT, FAILURE):
        reached = (r >= k) | (r == NUMERICAL) if k == FAILURE else (r >= k)
        first = np.argmax(reached, axis=0)
        b = 0.5 * (a[first] + a[first + 1])
        b[~np.any(reached, axis=0)] = np.nan
        out.append(b)
    return out[0], out[1]


def region_at(spectrum, period, amplitude):
    """Region (0, 1, 2) of a pulse (Tp, Ap) from a spectrum's boundaries.

    Rule (documented interpolation): the boundaries ``impact_boundary`` and
    ``failure_boundary`` of the two grid periods that bracket Tp are interpolated linearly in
    Tb/Tp (the paper's abscissa); the pulse is in region 2 if Ap ≥ the failure boundary, else
    in region 1 if Ap ≥ the impact boundary, else 0. A boundary that is NaN (not reached up to
    the spectrum's highest amplitude) counts as +∞, so an interpolation with it is +∞.
    Works with the grids of :func:`impact_region_spectrum` (boundaries midway between cells)
    and the bisected boundaries of :func:`region_boundaries`.

    Parameters
    ----------
    spectrum : xarray.Dataset
        With ``impact_boundary`` and ``failure_boundary`` [m/s²] along ``period``, and the
        attribute ``amplitude_max`` [m/s²].
    period : float or array_like [s]
    amplitude : float or array_like [m/s²]

    Returns
    -------
    int or ndarray of int

    Raises
    ------
    ValueError
        Tp outside the spectrum's periods, or Ap above ``amplitude_max`` where the region is
        not known there (no failure boundary at or below it).
    """
    periods = np.asarray(spectrum["period"].values, dtype=float)
    tb = float(spectrum.attrs["design_period"])
    tp, ap = np.broadcast_arrays(np.asarray(period, dtype=float),
                                 np.asarray(amplitude, dtype=float))
    if np.any(~np.isfinite(tp)) or np.any(tp < periods.min() * (1 - 1e-12)) or np.any(
        tp > periods.max() * (1 + 1e-12)
    ):
        raise ValueError(
            f"period outside the spectrum's range [{periods.min():.4g}, {periods.max():.4g}] s"
        )
    x_grid = tb / periods
    order = np.argsort(x_grid)
    x = tb / tp
    bounds = []
    for name in ("impact_boundary", "failure_boundary"):
        b = np.asarray(spectrum[name].values, dtype=float)[order]
        b = np.where(np.isnan(b), np.inf, b)
        xs = x_grid[order]
        j = np.clip(np.searchsorted(xs, x), 1, len(xs) - 1) if len(xs) > 1 else np.zeros_like(x)
        if len(xs) == 1:
            bounds.append(np.full_like(x, b[0]))
            continue
        x0, x1, b0, b1 = xs[j - 1], xs[j], b[j - 1], b[j]
        w = np.clip((x - x0) / (x1 - x0), 0.0, 1.0)
        with np.errstate(invalid="ignore"):
            bi = np.where(np.isinf(b0) | np.isinf(b1), np.inf, b0 + w * (b1 - b0))
        bi = np.where(w == 0.0, b0, np.where(w == 1.0, b1, bi))  # at a grid period: its own
        bounds.append(bi)
    impact_b, failure_b = bounds
    top = float(spectrum.attrs["amplitude_max"])
    unknown = (ap > top * (1 + 1e-12)) & ~(failure_b <= top)
    if np.any(unknown):
        raise ValueError(
            f"amplitude above the spectrum's highest amplitude ({top / G:.3f} g) where the "
            "failure boundary is not known"
        )
    region = np.where(ap >= failure_b, FAILURE, np.where(ap >= impact_b, IMPACT, NO_IMPACT))
    return int(region) if region.ndim == 0 else region.astype(int)


# -- spectra ---------------------------------------------------------------------------------------


def impact_velocity_spectrum(
    bearing: DFPBearing,
    kind: str,
    amplitude: float,
    periods=None,
    *,
    settings: SweepSettings | None = None,
    workers: int | None = None,
    progress: bool | None = None,
    cache=True,
):
    """Impact velocity spectrum for one pulse amplitude (paper Fig. 6).

    Parameters
    ----------
    bearing : DFPBearing
    kind : {"symmetric", "antisymmetric"}
    amplitude : float [m/s²]
        Ap.
    periods : array_like [s], optional
        Tp; default :func:`default_periods`.
    settings : SweepSettings, optional
    workers : int, optional
        Processes (default all cores; 1 runs in this process).
    progress : bool, optional
        Progress bar; default only on a terminal.
    cache : bool or path
        ``True`` the default cache file, a path, or ``False`` (see :mod:`rigid.sweep`).

    Returns
    -------
    xarray.Dataset
        Dimensions ``period`` [s] (with coordinate ``frequency_ratio`` Tb/Tp) and ``impact``.
        ``impact_velocity`` [m/s] (signed, NaN-padded), ``impact_time`` [s], ``impact_rim``
        (index into ``rims`` attr, -1 padded), ``n_impacts``, ``max_impact_velocity`` [m/s],
        ``failed``, ``failure_time`` [s], ``region``, ``max_displacement`` [m].
    """
    import xarray as xr

    periods = default_periods(bearing) if periods is None else periods
    _check(bearing, kind, periods)
    periods = np.sort(np.asarray(periods, dtype=float))
    if not (math.isfinite(amplitude) and amplitude > 0):
        raise ValueError(f"amplitude must be a positive acceleration [m/s²], got {amplitude!r}")
    settings = SweepSettings() if settings is None else settings
    cells, stats = run_cells(bearing, [(kind, p, amplitude) for p in periods], settings,
                             workers=workers, progress=progress, cache=cache,
                             desc=f"impact velocity spectrum {kind}")
    n = max([len(c.impact_times) for c in cells] + [1])
    vel = np.full((len(cells), n), np.nan)
    tim = np.full((len(cells), n), np.nan)
    rim = np.full((len(cells), n), -1, dtype=np.int8)
    for i, c in enumerate(cells):
        m = len(c.impact_times)
        vel[i, :m], tim[i, :m], rim[i, :m] = c.impact_velocities, c.impact_times, c.impact_rims
    coords = _period_coords(bearing, periods)
    ds = xr.Dataset(
        {
            "impact_velocity": (("period", "impact"), vel, {"units": "m/s", "long_name":
                                "top-plate velocity relative to the bottom plate at impact"}),
            "impact_time": (("period", "impact"), tim, {"units": "s"}),
            "impact_rim": (("period", "impact"), rim, {"units": "1", "_FillValue": -1}),
            "n_impacts": ("period", np.array([len(c.impact_times) for c in cells])),
            "max_impact_velocity": ("period", np.array([c.max_impact_velocity for c in cells]),
                                    {"units": "m/s"}),
            "failed": ("period", np.array([c.failed for c in cells])),
            "failure_time": ("period", np.array([c.failure_time for c in cells]),
                             {"units": "s"}),
            "region": ("period", np.array([c.region for c in cells], dtype=np.int8),
                       {"flag_values": "0 1 2", "flag_meanings": REGION_MEANINGS}),
            "max_displacement": ("period", np.array([c.max_displacement for c in cells]),
                                 {"units": "m"}),
        },
        coords=coords,
        attrs=_attrs(bearing, kind, settings, amplitude=float(amplitude),
                     amplitude_units="m/s2", rims=", ".join(RIM_NAMES),
                     cells_computed=stats["computed"], cells_reused=stats["reused"]),
    )
    return ds


def impact_region_spectrum(
    bearing: DFPBearing,
    kind: str,
    periods=None,
    amplitudes=None,
    *,
    settings: SweepSettings | None = None,
    workers: int | None = None,
    progress: bool | None = None,
    cache=True,
):
    """Impact region spectrum over a grid of pulse amplitudes and periods (paper Fig. 8).

    Parameters
    ----------
    bearing : DFPBearing
    kind : {"symmetric", "antisymmetric"}
    periods : array_like [s], optional
        Tp; default :func:`default_periods` (100 periods, Tb/Tp from 0.6 to 6).
    amplitudes : array_like [m/s²], optional
        Ap; default :func:`default_amplitudes` (0.01 g to 1.0 g by 0.01 g).
    settings, workers, progress, cache
        As in :func:`impact_velocity_spectrum`.

    Returns
    -------
    xarray.Dataset
        Dimensions ``amplitude`` [m/s²] and ``period`` [s] (coordinate ``frequency_ratio``
        Tb/Tp). Variables: ``region`` (0 no impact, 1 impact without failure, 2 failure, -1
        numerical failure), ``max_impact_velocity`` [m/s], ``n_impacts``, ``max_uplift``
        [m]; per period ``impact_boundary`` and ``failure_boundary`` [m/s²] (see
        :func:`grid_boundaries`) and the flags ``nonmonotonic_failure`` and
        ``nonmonotonic_impact`` (see :func:`nonmonotonic_periods`). The attributes hold
        the bearing (``bearing_*``), the settings (``settings_*``), ``amplitude_max`` and the
        cell counts.
    """
    import xarray as xr

    periods = default_periods(bearing) if periods is None else periods
    amplitudes = default_amplitudes() if amplitudes is None else amplitudes
    periods, amplitudes = _check(bearing, kind, periods, amplitudes)
    settings = SweepSettings() if settings is None else settings
    grid = [(kind, p, a) for a in amplitudes for p in periods]
    cells, stats = run_cells(bearing, grid, settings, workers=workers, progress=progress,
                             cache=cache, desc=f"impact region spectrum {kind}")
    shape = (len(amplitudes), len(periods))

    def field(name, dtype=float):
        return np.array([getattr(c, name) for c in cells], dtype=dtype).reshape(shape)

    region = field("region", np.int8)
    n_imp = np.array([len(c.impact_times) for c in cells]).reshape(shape)
    ib, fb = grid_boundaries(region, amplitudes)
    f_flag, i_flag = nonmonotonic_periods(region)
    coords = _period_coords(bearing, periods)
    coords["amplitude"] = ("amplitude", amplitudes, {"units": "m/s2",
                                                     "long_name": "pulse amplitude Ap"})
    dims = ("amplitude", "period")
    ds = xr.Dataset(
        {
            "region": (dims, region, {"flag_values": "-1 0 1 2",
                                      "flag_meanings": "numerical_failure " + REGION_MEANINGS}),
            "max_impact_velocity": (dims, field("max_impact_velocity"), {"units": "m/s"}),
            "n_impacts": (dims, n_imp),
            "max_uplift": (dims, field("max_uplift"), {"units": "m"}),
            "impact_boundary": ("period", ib, {"units": "m/s2", "method": "grid midpoint"}),
            "failure_boundary": ("period", fb, {"units": "m/s2", "method": "grid midpoint"}),
            "nonmonotonic_failure": ("period", f_flag),
            "nonmonotonic_impact": ("period", i_flag),
        },
        coords=coords,
        attrs=_attrs(bearing, kind, settings, amplitude_max=float(amplitudes[-1]),
                     amplitude_units="m/s2", cells_computed=stats["computed"],
                     cells_reused=stats["reused"]),
    )
    return ds


def max_impact_velocity_spectra(bearing, kind, amplitudes, periods=None, **kwargs):
    """Maximum impact velocity spectra for several amplitudes (paper Fig. 7).

    The same computation as :func:`impact_region_spectrum` (and the same cached cells); each
    row ``ds.max_impact_velocity.sel(amplitude=Ap)`` is one spectrum, ``ds.region == 2``
    marks failures.
    """
    return impact_region_spectrum(bearing, kind, periods, amplitudes, **kwargs)


# -- bisection -------------------------------------------------------------------------------------


def _find_transition(f, k, evals, guess, tol, a_max):
    """Bracket [lo, hi] of the lowest transition to region ≥ k, hi − lo ≤ 2·tol.

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
    ``a_max``), then bisected to 2·tol. Returns (lo, hi) or (lo, None) if not reached."""

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


def _boundaries_many(specs, settings, a_max, tol, scan_step, workers, progress, cache,
                     failure=True):
    """Bisection for several (bearing, kind, periods) in one process pool."""
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

    def mid(pair):
        lo, hi = pair
        return math.nan if hi is None else 0.5 * (lo + hi)

    def arr(key, fn):
        return np.array([fn(r[key]) for r in rows])

    data = {}
    for name in ("impact", "failure"):
        data[f"{name}_boundary"] = ("period", arr(name, mid), {
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
        data, coords=_period_coords(bearing, periods),
        attrs=_attrs(bearing, kind, settings, amplitude_max=float(a_max), tolerance=float(tol),
                     tolerance_units="m/s2", cells_computed=stats["computed"],
                     cells_reused=stats["reused"]),
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
    (periods, _) = _check(bearing, kind, periods)
    if not (amplitude_max > 0 and tolerance > 0):
        raise ValueError("amplitude_max and tolerance must be positive accelerations [m/s²]")
    settings = SweepSettings() if settings is None else settings
    if scan_step is not None and not scan_step > 2 * tolerance:
        raise ValueError("scan_step must exceed twice the tolerance")
    rows, stats = _boundaries_many([(bearing, kind, periods)], settings, amplitude_max,
                                   tolerance, scan_step, workers, progress, cache, failure)
    return _boundary_dataset(bearing, kind, periods, rows[0], settings, amplitude_max,
                             tolerance, stats[0])


# -- beyond the paper: dimensionless design charts ------------------------------------------------


def design_chart(
    bearings: Sequence[DFPBearing],
    kind: str,
    ratios=None,
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
    """Region boundaries of several bearings in dimensionless form.

    Dimensional analysis of a pendulum of period Tb under a pulse (Tp, Ap) with a stop at the
    displacement capacity d_cap: without friction the displacement scales with Ap·Tp², so
    impact occurs when Π = Ap·Tp²/d_cap exceeds a function of Tb/Tp only; friction adds the
    group μg/Ap, the rims' geometry and the mass the rest. The chart shows how far the
    boundaries of different μ and capacities collapse on Π(Tb/Tp).

    Parameters
    ----------
    bearings : sequence of DFPBearing
        The cases (e.g. several ``friction`` and ``capacity`` values).
    kind : {"symmetric", "antisymmetric"}
    ratios : array_like [-], optional
        Tb/Tp values; default 40 from Tb/7.5 s to 6.
    amplitude_max, tolerance, scan_step, failure, settings, workers, progress, cache
        As in :func:`region_boundaries`.

    Returns
    -------
    xarray.Dataset
        Dimensions ``case`` and ``frequency_ratio``; ``impact_pi`` and ``failure_pi``
        (Ap·Tp²/d_cap [-]) and the boundaries ``impact_boundary``, ``failure_boundary``
        [m/s²]; per case coordinates ``friction``, ``capacity`` (per surface [m]),
        ``displacement_capacity`` [m], ``pressure`` [Pa].
    """
    import xarray as xr

    if not bearings:
        raise ValueError("design_chart needs at least one bearing")
    tb = {b.design_period for b in bearings}
    if len(tb) != 1:
        raise ValueError("all bearings must share the design period Tb")
    tb = tb.pop()
    if ratios is None:
        ratios = np.linspace(tb / PERIOD_MAX, 6.0, 40)
    ratios = np.sort(np.asarray(ratios, dtype=float))
    periods = np.sort(tb / ratios)
    for b in bearings:
        _check(b, kind, periods)
    settings = SweepSettings() if settings is None else settings
    rows, _stats = _boundaries_many([(b, kind, periods) for b in bearings], settings,
                                    amplitude_max, tolerance, scan_step, workers, progress,
                                    cache, failure)
    order = np.argsort(tb / periods)  # rows follow ascending period; chart ascending ratio

    def boundary(r, name):
        lo, hi = r[name]
        return math.nan if hi is None else 0.5 * (lo + hi)

    ib = np.array([[boundary(r, "impact") for r in case] for case in rows])[:, order]
    fb = np.array([[boundary(r, "failure") for r in case] for case in rows])[:, order]
    tp = periods[order]
    dcap = np.array([b.displacement_capacity for b in bearings])
    pi_scale = tp[None, :] ** 2 / dcap[:, None]
    dims = ("case", "frequency_ratio")
    return xr.Dataset(
        {
            "impact_pi": (dims, ib * pi_scale, {"units": "1", "long_name": "Ap·Tp²/d_cap"}),
            "failure_pi": (dims, fb * pi_scale, {"units": "1", "long_name": "Ap·Tp²/d_cap"}),
            "impact_boundary": (dims, ib, {"units": "m/s2"}),
            "failure_boundary": (dims, fb, {"units": "m/s2"}),
        },
        coords={
            "frequency_ratio": ("frequency_ratio", tb / tp, {"units": "1", "long_name": "Tb/Tp"}),
            "period": ("frequency_ratio", tp, {"units": "s"}),
            "friction": ("case", [b.friction for b in bearings], {"units": "1"}),
            "capacity": ("case", [b.capacity for b in bearings], {"units": "m"}),
            "displacement_capacity": ("case", dcap, {"units": "m"}),
            "pressure": ("case", [b.pressure for b in bearings], {"units": "Pa"}),
        },
        attrs={"kind": kind, "design_period": tb, "amplitude_max": float(amplitude_max),
               "tolerance": float(tolerance), "tolerance_units": "m/s2"},
    )
