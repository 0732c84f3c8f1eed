"""Pulse sweeps of the rigid model: one cell (a :func:`rigid.simulate` run of one Ricker pulse)
per (kind, Tp, Ap), on short records, cached under the library's one key and run in a process
pool (docs/theory/impact-spectra.md, Eqs. I1–I4; caching and parallel runs:
docs/impact_spectra.md).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..bearing import DFPBearing
from ..limit_states import check_limit_state, deprecated_attribute, renamed_limit_state
from ..model import DEFAULT_MAX_STEP, RIM_NAMES, NumericalInstabilityError, simulate
from ..motions.pulses import KINDS, ricker
from ..tasks import ResultStore, Task, cache_root, default_workers, run_tasks, task_key

#: Default half-width of the sampled pulse in units of Tp: beyond it |a| < 1e-5·Ap and the
#: ground velocity is below 1e-5 of its peak (docs/theory/impact-spectra.md, Eqs. I1–I2).
HALF_WIDTH = {"symmetric": 1.25, "antisymmetric": 1.6}

#: Region codes of a cell (paper §3.2, Fig. 8; Eq. I3); -1 marks a numerical failure (no
#: verdict).
NO_IMPACT, IMPACT, FAILURE, NUMERICAL = 0, 1, 2, -1


@dataclass(frozen=True)
class SweepSettings:
    """How each cell of a sweep is simulated (part of the cache key).

    Parameters
    ----------
    dt : float [s]
        Sampling interval of the pulse record (the model's accuracy does not depend on it).
    half_width : float, optional [-]
        Pulse sampled over t0 ± half_width·Tp; default :data:`HALF_WIDTH` of the kind.
    free : float [s]
        Longest simulated time after the sampled pulse (ground at rest).
    stop_when_quiet : bool
        End a run once the energy left cannot reach a rim (exact for impacts and failure, but
        ``max_displacement`` is then the peak up to that time only).
    max_step : float [s]
        Largest internal step of :func:`rigid.simulate`.
    impact_merge_time : float [s]
        See :func:`rigid.simulate`.
    max_impacts : int
        Capacity of the impact list of one run.
    rims : {"rigid", "yielding"}
        Rim model (:func:`rigid.simulate`).
    limit_state : {"hinge", "rupture", "containment"}, optional
        The limit state of region 2 (failure); default the rim model's
        (``failure_criterion``: its deprecated name).
    rim_law : rigid.rims.RimLaw, optional
        The yielding rims' law (``fem.rim_law(bearing)``; :func:`rigid.simulate`); part of
        the cells' key, not of a spectrum file's attributes nor of comparisons (``==``).
        None with yielding rims: the deprecated fallback of
        :func:`rigid.rims.resolve_rim_law`, once per sweep.
    """

    dt: float = 0.005
    half_width: float | None = None
    free: float = 20.0
    stop_when_quiet: bool = True
    max_step: float = DEFAULT_MAX_STEP
    impact_merge_time: float = 0.05
    max_impacts: int = 1000
    rims: str = "rigid"
    limit_state: str | None = None
    rim_law: object = dataclasses.field(default=None, repr=False, compare=False)

    failure_criterion = deprecated_attribute("failure_criterion")

    def __post_init__(self):
        object.__setattr__(self, "limit_state",
                           check_limit_state(self.limit_state, rims=self.rims))
        for name in ("dt", "free", "max_step"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0):
                raise ValueError(f"SweepSettings.{name} must be a positive number, got {value!r}")
        if self.half_width is not None and not (self.half_width >= 1.0):
            raise ValueError(
                f"SweepSettings.half_width must be ≥ 1 (in units of Tp), got {self.half_width!r}"
            )

    def width(self, kind: str) -> float:
        """Half-width of the sampled pulse for ``kind`` [units of Tp]."""
        return HALF_WIDTH[kind] if self.half_width is None else self.half_width


@dataclass(frozen=True)
class Cell:
    """Outcome of one pulse (one cell of a sweep).

    Attributes
    ----------
    region : int
        0 no impact, 1 impact without failure, 2 failure, -1 numerical failure.
    max_impact_velocity : float [m/s]
        Largest |top-plate velocity relative to the bottom plate| at first contact, 0 if none.
    failed : bool
    failure_time : float [s]
        NaN without failure; measured from the start of the record (pulse centre at
        half_width·Tp).
    max_displacement : float [m]
        Peak |displacement| of the top plate relative to the bottom plate, over the simulated
        time (see ``SweepSettings.stop_when_quiet``).
    max_uplift : float [m]
    simulated_time : float [s]
    impact_times, impact_velocities : tuple of float [s], [m/s]
        Every impact (velocity signed, +x positive).
    impact_rims : tuple of int
        Index into :data:`rigid.model.RIM_NAMES`.
    """

    region: int
    max_impact_velocity: float
    failed: bool
    failure_time: float
    max_displacement: float
    max_uplift: float
    simulated_time: float
    impact_times: tuple = ()
    impact_velocities: tuple = ()
    impact_rims: tuple = ()

    @classmethod
    def from_dict(cls, d: dict) -> Cell:
        """Inverse of ``dataclasses.asdict`` (as stored in the cache)."""
        tuples = ("impact_times", "impact_velocities", "impact_rims")
        return cls(**{k: tuple(v) if k in tuples else v for k, v in d.items()})


def pulse_record(kind: str, period: float, amplitude: float, settings: SweepSettings):
    """The sampled pulse of a cell and the total simulated duration (Eq. I1).

    Returns
    -------
    acceleration : ndarray [m/s²]
    duration : float [s]
        Record length plus ``settings.free``.
    """
    w = settings.width(kind)
    n = round(2.0 * w * period / settings.dt) + 1
    t = np.arange(n) * settings.dt
    a = ricker(t, amplitude, period, kind, t0=w * period)  # paper Eqs. 5–6
    return a, (n - 1) * settings.dt + settings.free


def compute_cell(
    bearing: DFPBearing, kind: str, period: float, amplitude: float, settings: SweepSettings
) -> Cell:
    """Simulate one pulse and classify it (no cache; regions Eq. I3)."""
    a, duration = pulse_record(kind, period, amplitude, settings)
    try:
        r = simulate(
            bearing,
            a,
            settings.dt,
            duration=duration,
            max_step=settings.max_step,
            record_every=1,
            impact_merge_time=settings.impact_merge_time,
            max_impacts=settings.max_impacts,
            on_instability="refine",
            stop_when_quiet=settings.stop_when_quiet,
            rims=settings.rims,
            limit_state=settings.limit_state,
            rim_law=settings.rim_law,
        )
    except NumericalInstabilityError:
        nan = math.nan
        return Cell(NUMERICAL, nan, False, nan, nan, nan, nan)
    region = FAILURE if r.failed else (IMPACT if r.impacts else NO_IMPACT)
    return Cell(
        region=region,
        max_impact_velocity=r.max_impact_velocity,
        failed=r.failed,
        failure_time=r.failure_time if r.failed else math.nan,
        max_displacement=r.max_displacement,
        max_uplift=r.max_uplift,
        simulated_time=float(r.time[-1]),
        impact_times=tuple(i.time for i in r.impacts),
        impact_velocities=tuple(i.velocity for i in r.impacts),
        impact_rims=tuple(RIM_NAMES.index(i.rim) for i in r.impacts),
    )


SweepSettings.__init__ = renamed_limit_state()(SweepSettings.__init__)


def with_rim_law(bearing: DFPBearing, settings: SweepSettings) -> SweepSettings:
    """``settings`` with the yielding rims' law filled in (:func:`rigid.rims.resolve_rim_law`;
    unchanged for rigid rims or a law already given)."""
    if settings.rims != "yielding" or settings.rim_law is not None:
        return settings
    from ..rims import resolve_rim_law

    return dataclasses.replace(settings, rim_law=resolve_rim_law(bearing, None, stacklevel=4))


# -- cache -------------------------------------------------------------------------------------


def cell_key(
    bearing: DFPBearing, kind: str, period: float, amplitude: float, settings: SweepSettings
) -> str:
    """Cache key of a cell (:func:`rigid.tasks.task_key`): every input that determines its
    outcome and the code of the rigid model and of the pulses."""
    models = ("rigid", "pulses") + (("rim-law",) if settings.rims == "yielding" else ())
    return task_key("impact-cell", models, bearing=bearing, settings=settings,
                    kind=kind, period=float(period), amplitude=float(amplitude))


def default_cache_path() -> Path:
    """``impact-cells.sqlite`` in the cache root (:func:`rigid.tasks.cache_root`)."""
    return cache_root() / "impact-cells.sqlite"


def resolve_cache(cache) -> Path | None:
    """``True`` → default file, ``False``/``None`` → no cache, else a path."""
    if cache is None or cache is False:
        return None
    if cache is True:
        return default_cache_path()
    return Path(cache)


_OPEN_CACHES: dict = {}


def _cache(path: Path | None):
    """The cell store at ``path`` (a :class:`rigid.tasks.ResultStore`), opened once per
    process."""
    if path is None:
        return None
    if path not in _OPEN_CACHES:
        _OPEN_CACHES[path] = ResultStore(path)
    return _OPEN_CACHES[path]


class Evaluator:
    """Cells through the cache: look up, else simulate and store at once. Counts both."""

    def __init__(self, bearing: DFPBearing, settings: SweepSettings, cache_path: Path | None):
        settings = with_rim_law(bearing, settings)
        self.bearing, self.settings, self.cache = bearing, settings, _cache(cache_path)
        self.computed = 0
        self.reused = 0

    def __call__(self, kind: str, period: float, amplitude: float) -> Cell:
        key = cell_key(self.bearing, kind, period, amplitude, self.settings)
        if self.cache is not None:
            stored = self.cache.get(key)
            if stored is not None:
                self.reused += 1
                return Cell.from_dict(stored)
        cell = compute_cell(self.bearing, kind, period, amplitude, self.settings)
        self.computed += 1
        if self.cache is not None:
            self.cache.put(key, "impact-cell", dataclasses.asdict(cell))
        return cell


# -- parallel execution --------------------------------------------------------------------------


def _warm_up() -> None:
    """Worker initializer: load the compiled kernel before the first task."""
    simulate(DFPBearing(), np.zeros(3), 0.01)


def _cells_task(bearing, settings, cache_path, cells):
    ev = Evaluator(bearing, settings, cache_path)
    out = [ev(kind, p, a) for kind, p, a in cells]
    return out, ev.computed, ev.reused


def _call(task, job):
    return task(*job)


def run_parallel(
    task: Callable,
    jobs: Sequence[tuple],
    sizes: Sequence[int],
    *,
    workers: int | None,
    progress: bool | None,
    desc: str,
):
    """Run ``task(*job)`` for each job through :func:`rigid.tasks.run_tasks` (a spawn
    process pool, default :func:`rigid.tasks.default_workers`), in this process when
    ``workers == 1`` or there is only one job.

    ``sizes`` are the progress units (cells) of each job; the bar is shown by default only on
    a terminal. Returns the results in job order. On any exception (Ctrl-C included) pending
    jobs are cancelled and the workers terminated; finished cells are already cached.
    """
    workers = default_workers() if workers is None else int(workers)
    if workers < 1:
        raise ValueError(f"workers must be ≥ 1, got {workers!r}")
    tasks = [Task(str(i), "sweep-job", _call, {"task": task, "job": tuple(job)}, size=size)
             for i, (job, size) in enumerate(zip(jobs, sizes, strict=True))]
    results = run_tasks(tasks, None, workers=1 if len(tasks) <= 1 else workers,
                        progress=progress, description=desc, unit="cell", initializer=_warm_up)
    return [results[t.key] for t in tasks]


def run_cells(
    bearing: DFPBearing,
    cells: Iterable[tuple[str, float, float]],
    settings: SweepSettings | None = None,
    *,
    workers: int | None = None,
    progress: bool | None = None,
    cache=True,
    chunk: int | None = None,
    desc: str = "cells",
) -> tuple[list[Cell], dict]:
    """Outcome of many cells ``(kind, period [s], amplitude [m/s²])``, cached and parallel.

    Returns
    -------
    cells : list of Cell
        In input order.
    stats : dict
        ``computed`` and ``reused`` cell counts.
    """
    settings = with_rim_law(bearing, SweepSettings() if settings is None else settings)
    cells = [(str(k), float(p), float(a)) for k, p, a in cells]
    for k, p, _a in cells:
        if k not in KINDS:
            raise ValueError(f"kind must be 'symmetric' or 'antisymmetric', got {k!r}")
        if not (math.isfinite(p) and p > 0):
            raise ValueError(f"periods must be positive numbers of seconds, got {p!r}")
    path = resolve_cache(cache)
    out: list[Cell | None] = [None] * len(cells)
    reused = 0
    if path is not None:
        store = _cache(path)
        keys = [cell_key(bearing, k, p, a, settings) for k, p, a in cells]
        found = store.get_many(keys)
        for i, key in enumerate(keys):
            if key in found:
                out[i] = Cell.from_dict(found[key])
        reused = len(found)
    missing = [i for i, c in enumerate(out) if c is None]
    # longest first (cost ∝ record length ∝ Tp), in chunks small enough to balance two workers
    missing.sort(key=lambda i: -cells[i][1] * settings.width(cells[i][0]))
    n_workers = default_workers() if workers is None else workers
    size = chunk or max(1, min(16, len(missing) // (8 * max(1, n_workers)) or 1))
    groups = [missing[i : i + size] for i in range(0, len(missing), size)]
    jobs = [(bearing, settings, path, [cells[i] for i in g]) for g in groups]
    computed = 0
    for g, (res, n_comp, n_reuse) in zip(
        groups,
        run_parallel(_cells_task, jobs, [len(g) for g in groups], workers=workers,
                     progress=progress, desc=desc),
        strict=True,
    ):
        computed += n_comp
        reused += n_reuse
        for i, cell in zip(g, res, strict=True):
            out[i] = cell
    return out, {"computed": computed, "reused": reused}
