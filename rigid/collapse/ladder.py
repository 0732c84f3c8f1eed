"""Critical SA(Tb) of a record by time history: the 0.01 g scaling ladder of the rigid model
(paper §4.2), with every rung kept (resurrections), an optional coarse-then-fine search
(:mod:`rigid.collapse.search`), record sets in parallel (:mod:`rigid.collapse.record_set`),
and a resumable cache of rungs in ``ladders.sqlite`` under the library's one
key (docs/theory/collapse.md, Eqs. C1–C4; its "Trimming" section says why records are not
trimmed here).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..bearing import DFPBearing
from ..limit_states import check_limit_state, deprecated_attribute, renamed_limit_state
from ..motions.spectra import pseudo_acceleration
from ..tasks import ResultStore, cache_root, task_key
from ..units import G
from .search import coarse_scan, fast_search

__all__ = ["CriticalSA", "Rung", "as_record", "check_ladder", "coarse_scan", "critical_sa",
           "fast_search", "record_ladder"]


def __getattr__(name):
    # record sets (critical_sas) live in .record_set, which imports this module: re-exported
    # lazily so that ``from rigid.collapse.ladder import critical_sas`` keeps working
    if name in ("critical_sas", "pool_context"):
        from . import record_set

        return getattr(record_set, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")

_SEARCHES = ("full", "fast")


@dataclass(frozen=True)
class Rung:
    """Outcome of the rigid model at one rung of the scaling ladder.

    Attributes
    ----------
    index : int
        Rung number j; the target is SA = start + j·step.
    sa : float [m/s²]
        Target SA(Tb) of the scaled record.
    scale : float [-]
        Factor applied to the record.
    failed : bool
        Physical failure (the slider escaped over a rim).
    numerical_failure : bool
        The integration stayed unstable after three step halvings: the outcome is unknown,
        neither a failure nor a survival.
    failure_time : float or None [s]
        From the record's first sample.
    impacts : int
        Number of rim impacts.
    max_impact_velocity : float [m/s]
        Largest |relative velocity| at a rim impact (0 without impact).
    max_uplift : float [m]
        Largest separation of a slider face from its dish.
    failure_mode : {"uplift", "yielding", None}
        How the rung failed (:attr:`rigid.SimulationResult.failure_mode`).
    limit_states : tuple of str
        The yielding rims' limit states ("hinge", "rupture") the run reached before it ended
        (empty with rigid rims).
    """

    index: int
    sa: float
    scale: float
    failed: bool
    numerical_failure: bool
    failure_time: float | None
    impacts: int
    max_impact_velocity: float
    max_uplift: float
    failure_mode: str | None = None
    limit_states: tuple = ()


@dataclass(frozen=True)
class CriticalSA:
    """Critical SA(Tb) of one record and the ladder that found it.

    Attributes
    ----------
    sa : float or None [m/s²]
        SA(Tb) of the first failing rung; None if no rung up to ``stop`` failed.
    scale : float or None [-]
        Record scale factor at that rung.
    name : str
        Record name.
    record_sa : float [m/s²]
        SA(Tb) of the record as given (unscaled).
    period : float [s]
        Tb, the scaling period.
    start, step, stop : float [m/s²]
        The ladder: rungs at start + j·step ≤ stop.
    search : {"full", "fast"}
    rungs : tuple of Rung
        Every rung run, in increasing SA.
    cpu_seconds : float [s]
        Processor time spent simulating in this call (cached rungs cost nothing).
    capped : bool
        The ladder stops below the ``stop`` asked for: higher rungs would scale the record's
        peak acceleration beyond :data:`rigid.limits.MAX_MODEL_ACCELERATION`.
    rims, limit_state : str
        The rim model and the limit state that defined failure (:func:`rigid.simulate`;
        ``failure_criterion``: the deprecated name of ``limit_state``).
    """

    sa: float | None
    scale: float | None
    name: str
    record_sa: float
    period: float
    start: float
    step: float
    stop: float
    search: str
    rungs: tuple
    cpu_seconds: float = 0.0
    capped: bool = False
    rims: str = "rigid"
    limit_state: str = "containment"

    failure_criterion = deprecated_attribute("failure_criterion")

    @property
    def failed(self) -> bool:
        """A failure was found within the ladder."""
        return self.sa is not None

    @property
    def resurrections(self) -> tuple:
        """Rungs that survived although a lower rung failed (Vamvatsikos & Cornell 2002);
        numerical rungs are not survivals."""
        if self.sa is None:
            return ()
        return tuple(r for r in self.rungs
                     if r.sa > self.sa and not r.failed and not r.numerical_failure)

    @property
    def resurrected(self) -> bool:
        """True when at least one rung above the critical one survived."""
        return bool(self.resurrections)

    @property
    def numerical_failures(self) -> tuple:
        """Rungs whose integration stayed unstable (outcome unknown)."""
        return tuple(r for r in self.rungs if r.numerical_failure)

    @property
    def uncertain(self) -> bool:
        """The answer depends on numerical rungs: one lies below the first failure (it might
        have failed first), or no rung failed and some were numerical (they might have)."""
        return any(r.numerical_failure and (self.sa is None or r.sa < self.sa)
                   for r in self.rungs)

    def table(self) -> dict:
        """The ladder as columns: sa [m/s²], scale, failed, impacts, velocity [m/s], uplift [m]."""
        return {
            "sa": np.array([r.sa for r in self.rungs]),
            "scale": np.array([r.scale for r in self.rungs]),
            "failed": np.array([r.failed for r in self.rungs]),
            "numerical_failure": np.array([r.numerical_failure for r in self.rungs]),
            "impacts": np.array([r.impacts for r in self.rungs]),
            "max_impact_velocity": np.array([r.max_impact_velocity for r in self.rungs]),
            "max_uplift": np.array([r.max_uplift for r in self.rungs]),
        }

    def summary(self) -> str:
        """One line for the console (SA in g)."""
        crit = (f"no failure up to {self.stop / G:.2f} g" if self.sa is None
                else f"critical SA {self.sa / G:.2f} g")
        extra = ""
        if self.resurrected:
            extra = "; resurrections at " + ", ".join(f"{r.sa / G:.2f}" for r in self.resurrections)
            extra += " g"
        numerical = self.numerical_failures
        if numerical:
            extra += (f"; {len(numerical)} numerical rung(s) (integration unstable, outcome "
                      "unknown) at " + ", ".join(f"{r.sa / G:.2f}" for r in numerical) + " g")
        if self.uncertain:
            extra += ("; UNCERTAIN: all rungs numerical" if len(numerical) == len(self.rungs)
                      else "; UNCERTAIN: the answer depends on numerical rungs")
        if self.capped:
            from ..limits import MAX_MODEL_ACCELERATION

            extra += (f"; ladder ends at {self.stop / G:.2f} g (higher rungs would scale the "
                      f"record beyond the models' {MAX_MODEL_ACCELERATION / G:g} g)")
        rims = ("" if self.rims == "rigid"
                else f", {self.rims} rims, failure = {self.limit_state}")
        return f"{self.name}: {crit} ({len(self.rungs)} rungs, {self.search}{rims}){extra}"


# --------------------------------------------------------------------------- cache


class _Store:
    """Rungs of one ladder in ``directory/ladders.sqlite``, one row per rung (key: the rung and
    the ladder's inputs, :func:`rigid.tasks.task_key`), written as soon as the rung is done."""

    def __init__(self, directory, ladder: dict):
        self.ladder = ladder
        self.db = None if directory is None else ResultStore(Path(directory) / "ladders.sqlite")

    def _key(self, j: int) -> str:
        yielding = self.ladder["simulate"]["rims"] == "yielding"
        models = ("rigid", "rim-law") if yielding else ("rigid",)
        return task_key("ladder-rung", models, rung=j, **self.ladder)

    def get(self, j: int):
        return None if self.db is None else self.db.get(self._key(j))

    def put(self, j: int, value: dict) -> None:
        if self.db is not None:
            self.db.put(self._key(j), "ladder-rung", value)


# --------------------------------------------------------------------------- ladder


def check_ladder(bearing, search, searches, step, coarse, start, stop) -> float:
    """Check the arguments shared by the actual and the predicted ladder; return ``start``
    [m/s²] (one ``step`` when None)."""
    if not isinstance(bearing, DFPBearing):
        raise TypeError(f"bearing must be a DFPBearing, got {type(bearing).__name__}")
    if search not in searches:
        raise ValueError(f"search must be one of {', '.join(searches)}, got {search!r}")
    if not (math.isfinite(step) and step > 0):
        raise ValueError(f"step must be a positive acceleration [m/s²], got {step!r}")
    if int(coarse) != coarse or coarse < 1:
        raise ValueError(f"coarse must be a positive integer, got {coarse!r}")
    start = step if start is None else float(start)
    if not (math.isfinite(start) and start > 0):
        raise ValueError(f"start must be a positive acceleration [m/s²], got {start!r}")
    if not stop >= start:
        raise ValueError("stop must not be below start")
    return start


def record_ladder(acc, dt, period, damping, name, start, step, stop) -> tuple[float, int]:
    """SA(T) of the unscaled record [m/s²] and the number of rungs start + j·step ≤ stop (to
    1e-9 of a step) of a ladder that scales it (Eq. C1), fewer if higher rungs would scale the
    record's peak beyond :data:`rigid.limits.MAX_MODEL_ACCELERATION` (the models refuse such
    input); ValueError if the record has no SA at T or even the first rung is beyond that
    limit. Shared by the actual and the predicted ladder."""
    from ..limits import MAX_MODEL_ACCELERATION

    record_sa = float(pseudo_acceleration(acc, dt, [period], damping)[0])
    if not record_sa > 0:
        raise ValueError(f"{name}: the record has zero SA at T = {period} s; it cannot be scaled")
    n_rungs = math.floor((stop - start) / step + 1e-9) + 1
    top_sa = MAX_MODEL_ACCELERATION / float(np.max(np.abs(acc))) * record_sa
    if top_sa < start:
        raise ValueError(f"{name}: the first rung, SA = {start / G:.3g} g, scales the record's "
                         f"peak beyond {MAX_MODEL_ACCELERATION / G:g} g (docs/limits.md)")
    return record_sa, min(n_rungs, math.floor((top_sa - start) / step + 1e-9) + 1)


def as_record(motion, dt):
    """(acceleration [m/s²], dt [s], name) of a GroundMotion, or of an array with its dt."""
    if dt is None:
        if not hasattr(motion, "acceleration"):
            raise TypeError("pass a GroundMotion, or an acceleration array together with dt")
        return np.asarray(motion.acceleration, dtype=float), float(motion.dt), motion.name
    return np.asarray(motion, dtype=float), float(dt), "record"


def _run_rung(bearing, acc, dt, scale, sim) -> dict:
    from ..model import NumericalInstabilityError, simulate

    sim = dict(sim)
    duration = (acc.size - 1) * dt + sim.pop("free")
    try:
        r = simulate(bearing, acc * scale, dt, duration=duration, stop_at_failure=True,
                     stop_when_quiet=True, record_every=max(1, acc.size), **sim)
    except NumericalInstabilityError as error:  # the limit states reached before it count
        reached = [] if error.result is None else [
            s for s, t in error.result.limit_states.items() if t is not None]
        return {"failed": False, "numerical_failure": True, "failure_time": None,
                "impacts": 0, "max_impact_velocity": float("nan"), "max_uplift": float("nan"),
                "failure_mode": None, "limit_states": reached}
    return {
        "failed": bool(r.failed),
        "numerical_failure": bool(r.numerical_failure),
        "failure_time": r.failure_time,
        "impacts": len(r.impacts),
        "max_impact_velocity": float(r.max_impact_velocity),
        "max_uplift": float(r.max_uplift),
        "failure_mode": r.failure_mode,
        "limit_states": [s for s, t in r.limit_states.items() if t is not None],
    }


def _rung_options(bearing, rims, limit_state, rim_law, *, max_step, impact_merge_time,
                  coarse_factor, free) -> dict:
    """What every rung of a ladder runs with: :func:`rigid.simulate`'s options (and ``free``
    [s] after the record), part of the rungs' key; with yielding rims the law itself
    (:func:`rigid.rims.resolve_rim_law`)."""
    sim = {"max_step": max_step, "impact_merge_time": float(impact_merge_time),
           "coarse_factor": coarse_factor, "on_instability": "refine", "free": float(free),
           "rims": rims, "limit_state": limit_state}
    if rims == "yielding":
        from ..rims import resolve_rim_law

        sim["rim_law"] = resolve_rim_law(bearing, rim_law, stacklevel=4)
    if sim["max_step"] is None:
        from ..model import DEFAULT_MAX_STEP

        sim["max_step"] = DEFAULT_MAX_STEP
    return sim


class _Rungs:
    """The rungs of one ladder (:func:`_ladder`), each run once (or read from the store) when
    first asked for: ``rungs(j)`` is rung j, a :class:`Rung`; ``done`` maps the rungs so far;
    ``cpu_seconds`` [s] is the processor time spent simulating them here; ``n_rungs`` rungs
    in all, ``capped`` below the top asked for."""

    def __init__(self, bearing, acc, dt, name, period, start, step, record_sa, n_rungs, capped,
                 sim, store):
        self.bearing, self.acc, self.dt, self.sim, self.store = bearing, acc, dt, sim, store
        self.name, self.period, self.n_rungs, self.capped = name, period, n_rungs, capped
        self.start, self.step, self.record_sa = start, step, record_sa
        self.done: dict[int, Rung] = {}
        self.cpu_seconds = 0.0

    def critical(self, first: int | None, search: str, limit_state: str) -> CriticalSA:
        """The :class:`CriticalSA` whose first failing rung is ``first`` (None: none), with
        every rung run so far."""
        return CriticalSA(
            sa=None if first is None else self.done[first].sa,
            scale=None if first is None else self.done[first].scale,
            name=self.name, record_sa=self.record_sa, period=self.period, start=self.start,
            step=float(self.step), stop=float(self.start + (self.n_rungs - 1) * self.step),
            search=search, rungs=tuple(self.done[j] for j in sorted(self.done)),
            cpu_seconds=self.cpu_seconds, capped=self.capped, rims=self.sim["rims"],
            limit_state=limit_state)

    def __call__(self, j: int) -> Rung:
        if j not in self.done:
            sa = self.start + j * self.step
            scale = sa / self.record_sa  # Eq. C2
            out = self.store.get(j)
            if out is None or "limit_states" not in out:  # not stored, or stored without the mode
                t0 = time.process_time()
                out = _run_rung(self.bearing, self.acc, self.dt, scale, self.sim)
                self.cpu_seconds += time.process_time() - t0
                self.store.put(j, out)
            out = {**out, "limit_states": tuple(out["limit_states"])}
            self.done[j] = Rung(index=j, sa=sa, scale=scale, **out)
        return self.done[j]


def _ladder(bearing, motion, dt, *, start, step, stop, period, damping, free, cache, rims,
            limit_state, rim_law, max_step, impact_merge_time, coarse_factor) -> _Rungs:
    """The rungs of a ladder whose search ``start`` [m/s²] is checked
    (:func:`check_ladder`): the record and ``free`` checked, the record's SA and the rungs
    (capped below the models' limit), each rung's options (:func:`_rung_options`) and its
    store (``cache``, as :func:`critical_sa`'s)."""
    period = bearing.design_period if period is None else float(period)
    acc, dt, name = as_record(motion, dt)
    if acc.ndim != 1 or acc.size < 2 or not np.all(np.isfinite(acc)):
        raise ValueError("the record must be a finite 1-D acceleration with at least 2 samples")

    record_sa, n_rungs = record_ladder(acc, dt, period, damping, name, start, step, stop)
    capped = n_rungs < math.floor((stop - start) / step + 1e-9) + 1

    if not (math.isfinite(free) and free >= 0):
        raise ValueError(f"free must be a non-negative number of seconds, got {free!r}")
    sim = _rung_options(bearing, rims, check_limit_state(limit_state, rims=rims), rim_law,
                        max_step=max_step, impact_merge_time=impact_merge_time,
                        coarse_factor=coarse_factor, free=free)
    cache_dir = cache_root() if cache is True else (None if cache is False else cache)
    store = _Store(cache_dir, {"bearing": bearing, "acceleration": acc, "dt": dt,
                               "start": start, "step": float(step), "period": period,
                               "damping": float(damping), "simulate": sim})
    return _Rungs(bearing, acc, dt, name, period, start, step, record_sa, n_rungs, capped, sim,
                  store)


@renamed_limit_state()
def critical_sa(
    bearing: DFPBearing,
    motion,
    step: float = 0.01 * G,
    *,
    start: float | None = None,
    stop: float = 3.0 * G,
    search: str = "full",
    coarse: int = 10,
    refine_ratio: float = 0.8,
    after_failure: int = 0,
    period: float | None = None,
    damping: float = 0.05,
    dt: float | None = None,
    free: float = 20.0,
    cache=None,
    max_step: float | None = None,
    impact_merge_time: float = 0.05,
    coarse_factor: int | None = None,
    rims: str = "rigid",
    limit_state: str | None = None,
    rim_law=None,
) -> CriticalSA:
    """Critical SA(Tb) of a record: the first failing rung of a scaling ladder (paper §4.2;
    Eqs. C1–C3).

    Parameters
    ----------
    bearing : DFPBearing
    motion : GroundMotion or array_like [m/s²]
        The record (an array needs ``dt``).
    step : float [m/s²]
        Rung spacing of SA(Tb); paper: 0.01 g.
    start : float [m/s²], optional
        First rung; default one ``step``.
    stop : float [m/s²]
        Highest rung tried (default 3 g); ``sa`` is None if no rung up to it fails.
    search : {"full", "fast"}
        ``"full"``: every rung from ``start`` up to the first failure. ``"fast"``: every
        ``coarse``-th rung up to the first failure, then the fine rungs of every coarse
        interval that may hide a failure (see ``refine_ratio``), lowest first. Both return
        the lowest failing rung they ran; they agree unless a failure hides in a coarse
        interval whose ends both survived with slow impacts (a heuristic, not a proof).
    coarse : int
        Rungs per coarse step of the fast search (10 → 0.1 g with the default step).
    refine_ratio : float [-]
        Fast search: a coarse interval below the first failure is scanned at the fine step
        when the larger maximum impact velocity at its two ends reaches this fraction of the
        smallest maximum impact velocity of any failing rung run so far (failure needs a
        fast rim impact, paper §3.1; Eq. C4). The interval just below the first coarse failure
        is always scanned. 0 scans every interval (the full ladder).
    after_failure : int
        Rungs to run above the first failure, to reveal resurrections.
    period : float [s], optional
        Tb of the scaling; default ``bearing.design_period`` (4.5 s).
    damping : float [-]
        Damping ratio of the scaling spectrum (5 %).
    dt : float [s], optional
        Time step when ``motion`` is an array.
    free : float [s]
        Longest time simulated after the record ends (ground at rest): a bearing still
        swinging can hit a rim or escape then. Each run stops earlier once no rim can be
        reached (``stop_when_quiet``), so this costs time only when it matters.
    cache : None, bool, str or Path
        Folder of the rung cache (``True``: the cache root; see the module docstring); None or
        False disables it.
    max_step, impact_merge_time, coarse_factor
        Passed to :func:`rigid.simulate` (which runs with ``stop_when_quiet=True``,
        ``stop_at_failure=True`` and ``on_instability="refine"``, for the record plus ``free``).
    rims, limit_state : str
        The rim model and the limit state that defines failure (:func:`rigid.simulate`;
        default the rim model's: "containment" for rigid rims, "hinge" for yielding ones;
        ``failure_criterion``: the deprecated name of ``limit_state``).
    rim_law : rigid.rims.RimLaw
        The yielding rims' law (``fem.rim_law(bearing)``), needed with ``rims="yielding"``
        (:func:`rigid.simulate`); part of the rungs' key.

    Returns
    -------
    CriticalSA
    """
    start = check_ladder(bearing, search, _SEARCHES, step, coarse, start, stop)
    if int(after_failure) != after_failure or after_failure < 0:
        raise ValueError(f"after_failure must be a non-negative integer, got {after_failure!r}")
    rung = _ladder(bearing, motion, dt, start=start, step=step, stop=stop, period=period,
                   damping=damping, free=free, cache=cache, rims=rims, limit_state=limit_state,
                   rim_law=rim_law, max_step=max_step, impact_merge_time=impact_merge_time,
                   coarse_factor=coarse_factor)
    done, n_rungs = rung.done, rung.n_rungs

    first = None
    if search == "full":
        for j in range(n_rungs):
            if rung(j).failed:
                first = j
                break
    else:
        first = fast_search(rung, done, n_rungs, int(coarse), float(refine_ratio))
    if first is not None:
        for j in range(first + 1, min(first + 1 + int(after_failure), n_rungs)):
            rung(j)
    return rung.critical(first, search, rung.sim["limit_state"])
