"""Impact velocity spectra and impact region spectra on grids of Ricker pulses (paper §3.1–3.2).

* :func:`impact_velocity_spectrum` — every impact's velocity (top plate relative to the bottom
  plate at first contact), its maximum and the failure flag, over Tb/Tp for one amplitude
  (paper Fig. 6);
* :func:`impact_region_spectrum` — the region and the maximum impact velocity over a grid of
  (Ap, Tp) (paper Fig. 8); its rows are the maximum impact velocity spectra of Fig. 7, also
  available as :func:`max_impact_velocity_spectra`.

Tb is ``bearing.design_period`` (paper: 4.5 s). Results are :class:`xarray.Dataset` objects
with units in the attributes and the bearing's parameters as ``bearing_*`` attributes;
:func:`save_spectrum` / :func:`load_spectrum` write and read NetCDF. Cells are computed by
:mod:`rigid.impact.sweep` (parallel, cached). xarray is imported on use.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from ..bearing import DFPBearing
from ..model import RIM_NAMES
from ..motions.pulses import KINDS
from ..units import G
from .regions import grid_boundaries, nonmonotonic_periods
from .sweep import SweepSettings, run_cells

__all__ = [
    "bearing_from_attrs",
    "check_sweep",
    "default_amplitudes",
    "default_periods",
    "impact_region_spectrum",
    "impact_velocity_spectrum",
    "load_spectrum",
    "max_impact_velocity_spectra",
    "period_coords",
    "save_spectrum",
    "settings_from_attrs",
    "spectrum_attrs",
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


def check_sweep(bearing, kind, periods=None, amplitudes=None):
    """Check a sweep's bearing and kind, and sort its periods [s] and amplitudes [m/s²]
    (positive, finite, not repeated); returns them (None where not given)."""
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


def spectrum_attrs(bearing: DFPBearing, kind: str, settings: SweepSettings, **extra) -> dict:
    """NetCDF attributes of a spectrum: the kind, Tb, the bearing (``bearing_*``) and the
    sweep settings (``settings_*``), plus ``extra``."""
    attrs = {"kind": kind, "design_period": bearing.design_period,
             "design_period_units": "s", "model_period": bearing.period,
             "displacement_capacity": bearing.displacement_capacity,
             "source": "rigid-body DFP model, Bao & Becker (2016) §3"}
    for f in dataclasses.fields(bearing):
        attrs[f"bearing_{f.name}"] = getattr(bearing, f.name)
    for f in dataclasses.fields(settings):
        if f.name == "rim_law":  # data, not a setting: in the cells' key only
            continue
        value = getattr(settings, f.name)
        if isinstance(value, bool):
            value = int(value)
        attrs[f"settings_{f.name}"] = "default" if value is None else value
    attrs.update(extra)
    return attrs


def bearing_from_attrs(ds) -> DFPBearing:
    """Rebuild the :class:`DFPBearing` recorded in a spectrum's ``bearing_*`` attributes (a
    field the file predates keeps its default)."""
    kwargs = {}
    for f in dataclasses.fields(DFPBearing):
        if f"bearing_{f.name}" not in ds.attrs:
            continue
        value = ds.attrs[f"bearing_{f.name}"]
        kwargs[f.name] = str(value) if f.name == "impact_mass" else float(value)
    return DFPBearing(**kwargs)


def settings_from_attrs(ds) -> SweepSettings:
    """Rebuild the :class:`SweepSettings` recorded in a spectrum's ``settings_*`` attributes."""
    kwargs = {}
    for f in dataclasses.fields(SweepSettings):
        if f.name == "rim_law":  # not stored (the law is data: rigid.rims.RimLaw)
            continue
        value = ds.attrs.get(f"settings_{f.name}", f.default)
        if f.name == "limit_state":  # files written before the rename
            value = ds.attrs.get("settings_failure_criterion", value)
        if f.name in ("rims", "limit_state"):  # names, stored as themselves
            value = None if value is None else str(value)
        elif isinstance(value, str):  # "default": None
            value = None
        elif f.name == "stop_when_quiet":
            value = bool(value)
        elif f.name == "max_impacts":
            value = int(value)
        else:
            value = float(value)
        kwargs[f.name] = value
    return SweepSettings(**kwargs)


def period_coords(bearing, periods):
    """The ``period`` [s] coordinate with ``frequency_ratio`` Tb/Tp beside it."""
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
    """Impact velocity spectrum for one pulse amplitude (paper Fig. 6; Eq. I5).

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
        ``True`` the default cache file, a path, or ``False`` (see :mod:`rigid.impact.sweep`).

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
    check_sweep(bearing, kind, periods)
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
    coords = period_coords(bearing, periods)
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
        attrs=spectrum_attrs(bearing, kind, settings, amplitude=float(amplitude),
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
    """Impact region spectrum over a grid of pulse amplitudes and periods (paper Fig. 8;
    Eq. I7).

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
    periods, amplitudes = check_sweep(bearing, kind, periods, amplitudes)
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
    coords = period_coords(bearing, periods)
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
        attrs=spectrum_attrs(bearing, kind, settings, amplitude_max=float(amplitudes[-1]),
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
