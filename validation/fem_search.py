r"""FE critical SA of a record, searched around the rigid model's: bracket by 1, 2, 4, … rungs,
then bisect to one rung, every FE run a stored task, the searches of several records driven in
parallel as follow-up tasks (docs/theory/collapse.md, Eqs. C16–C17).
"""


from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

from rigid import DFPBearing
from rigid.tasks import ResultStore, Task, run_tasks, task_key

from .fem_runs import MESHES, fem_run

__all__ = ["BracketBisect", "FECritical", "FESearches", "FESettings", "run_fem_searches"]


class BracketBisect:
    """Lowest failing rung near ``start`` by bracketing (±1, 2, 4, … rungs) then bisection.

    Drive it with :meth:`next_rung` and :meth:`record`; it is a pure function of the outcomes
    recorded, so replaying stored outcomes reproduces the search.

    Parameters
    ----------
    start : int
        First rung run (clipped to [lowest, highest]).
    lowest, highest : int
        The ladder's rungs. If ``lowest`` fails, it is the answer; if ``highest`` survives,
        there is none (``critical`` None).
    """

    def __init__(self, start: int, lowest: int, highest: int):
        if highest < lowest:
            raise ValueError("highest must not be below lowest")
        self.lowest, self.highest = int(lowest), int(highest)
        self.start = min(max(int(start), self.lowest), self.highest)
        self.outcomes: dict[int, bool] = {}
        self.lo: int | None = None  # highest surviving rung known below the answer
        self.hi: int | None = None  # lowest failing rung known
        self._offset = 1
        self._direction = 0
        self.done = False

    def next_rung(self) -> int | None:
        """The rung to run next, or None when the search is over."""
        if self.done:
            return None
        if not self.outcomes:
            return self.start
        if self.lo is not None and self.hi is not None:
            return (self.lo + self.hi) // 2
        j = self.start + self._direction * self._offset
        return min(max(j, self.lowest), self.highest)

    def record(self, rung: int, failed: bool) -> None:
        """Enter the outcome of the rung returned by :meth:`next_rung`."""
        if rung != self.next_rung():
            raise ValueError(f"expected the outcome of rung {self.next_rung()}, got {rung}")
        self.outcomes[rung] = bool(failed)
        if failed:
            self.hi = rung if self.hi is None else min(self.hi, rung)
        else:
            self.lo = rung if self.lo is None else max(self.lo, rung)
        if len(self.outcomes) == 1:
            self._direction = -1 if failed else 1
        elif self.lo is None or self.hi is None:
            self._offset *= 2
        if self.hi is not None and self.hi == self.lowest:
            self.done = True
        elif self.hi is None and self.lo == self.highest:
            self.done = True
        elif self.lo is not None and self.hi is not None and self.hi - self.lo <= 1:
            self.done = True

    @property
    def critical(self) -> int | None:
        """The answer once :attr:`done`: the failing rung found, or None (none up to the top)."""
        return self.hi if self.done else None

    @property
    def runs(self) -> int:
        return len(self.outcomes)


@dataclass(frozen=True)
class FESettings:
    """How the FE critical SA is searched. Keyed into every stored FE run (with the bearing,
    the record and the scale)."""

    mesh: str = "coarse"
    max_step: float = 5e-3
    impact_step: float = 5e-4
    trim: str = "end"
    free: float = 20.0
    lead: float = 0.1
    margin: float = 1.0

    def describe(self) -> dict:
        return {"FE mesh": f"{self.mesh} ({MESHES[self.mesh] or 'generator defaults'})",
                "FE time step [s]": f"{self.max_step:g} free sliding, {self.impact_step:g} "
                "at a rim", "FE trimming": {"end": "after the strong motion, once quiet",
                                     "window": "strong-motion window",
                                     "none": "none"}[self.trim]}


@dataclass
class FECritical:
    """FE critical SA of one record at one pressure, and the runs that found it.

    Attributes
    ----------
    name : str
    pressure : float [Pa]
    rigid_sa : float or None [m/s²]
        The rigid model's critical SA (the search's start).
    sa : float or None [m/s²]
        FE critical SA: the failing rung found; None if the top rung survived.
    survived_below : float or None [m/s²]
        The bracket's highest surviving rung below ``sa`` (None when the lowest rung failed).
    failure_mode : str or None
        Of the run at ``sa``.
    failure_time : float or None [s]
    probes : list of dict
        Every run in the order made: ``sa`` [m/s²], ``scale``, and the run's result.
    """

    name: str
    pressure: float
    rigid_sa: float | None
    sa: float | None = None
    survived_below: float | None = None
    failure_mode: str | None = None
    failure_time: float | None = None
    probes: list = field(default_factory=list)

    @property
    def runs(self) -> int:
        return len(self.probes)

    @property
    def cpu_seconds(self) -> float:
        return sum(p["cpu_seconds"] for p in self.probes)


class FESearches:
    """Several FE critical-SA searches driven through :func:`rigid.tasks.runner.run_tasks`:
    :meth:`add` gives a search's first task, :meth:`follow_up` its next one from each result,
    :meth:`results` the answers. A caller can add searches from its own follow-ups (the
    validation pipeline starts a record's FE search as soon as its rigid result arrives).

    Parameters
    ----------
    settings : FESettings
    step, start, stop : float [m/s²]
        The ladder: rungs at start + j·step ≤ stop (the rigid ladder's).
    runner : callable
        ``runner(bearing=dict, acceleration, dt, scale, **settings)`` → dict with at least
        ``failed``, ``failure_mode``, ``failure_time``, ``cpu_seconds``; :func:`fem_run`, or a
        stand-in (tests).
    """

    kind = "fem-run"

    def __init__(self, settings: FESettings, *, step: float, start: float, stop: float,
                 runner=fem_run):
        self.step, self.start = float(step), float(start)
        self.highest = math.floor((stop - start) / step + 1e-9)
        self.runner = runner
        # a stand-in runner (tests) is keyed by its name; fem_run by the code of the models
        self.runner_name = (None if runner is fem_run
                            else f"{runner.__module__}.{runner.__qualname__}")
        self.options = dataclasses.asdict(settings)
        self.targets, self.searches, self.found, self.by_key = [], [], [], {}

    def _task(self, i, j) -> Task:
        bearing, motion, rigid_crit = self.targets[i]
        scale = (self.start + j * self.step) / rigid_crit.record_sa
        kwargs = {"bearing": dataclasses.asdict(bearing), "acceleration": motion.acceleration,
                  "dt": motion.dt, "scale": scale, **self.options}
        key = task_key(self.kind, ("rigid", "collapse", "fem"), runner=self.runner_name, **kwargs)
        self.by_key[key] = (i, j)
        return Task(key, self.kind, self.runner, kwargs)

    def add(self, bearing: DFPBearing, motion, rigid_crit) -> Task:
        """Start a search (``rigid_crit``: the rigid model's CriticalSA); its first task."""
        i = len(self.targets)
        self.targets.append((bearing, motion, rigid_crit))
        j0 = (self.highest if rigid_crit.sa is None
              else round((rigid_crit.sa - self.start) / self.step))
        self.searches.append(BracketBisect(j0, 0, self.highest))
        self.found.append(FECritical(motion.name, bearing.pressure, rigid_crit.sa))
        return self._task(i, self.searches[i].next_rung())

    def follow_up(self, done_task, result) -> tuple:
        """The search's next task after ``done_task`` (one of ours), or ()."""
        i, j = self.by_key[done_task.key]
        s = self.searches[i]
        if s.done or s.next_rung() != j:
            return ()  # a duplicate outcome (not expected: every rung is asked for once)
        s.record(j, bool(result["failed"]))
        self.found[i].probes.append({"sa": self.start + j * self.step,
                                     "scale": done_task.kwargs["scale"], **result})
        nxt = s.next_rung()
        return () if nxt is None else (self._task(i, nxt),)

    def results(self) -> list:
        """FECritical of every search, in the order added (complete once run_tasks returns)."""
        for s, r in zip(self.searches, self.found, strict=True):
            if s.critical is not None:
                r.sa = self.start + s.critical * self.step
                at = next(p for p in r.probes if math.isclose(p["sa"], r.sa))
                r.failure_mode, r.failure_time = at["failure_mode"], at["failure_time"]
            if s.lo is not None and (s.critical is None or s.lo < s.critical):
                r.survived_below = self.start + s.lo * self.step
        return self.found


def run_fem_searches(targets, settings: FESettings, store: ResultStore, *, step: float,
                     start: float, stop: float, runner=fem_run, scheduler=None,
                     workers: int | None = None, progress: bool | None = None) -> list:
    """FE critical SA of several records, searched in parallel around their rigid ones.

    Parameters
    ----------
    targets : sequence of (DFPBearing, GroundMotion, rigid.collapse.ladder.CriticalSA)
    settings, step, start, stop, runner
        As :class:`FESearches`.
    store : ResultStore
        Every FE run is stored there as it finishes (kind ``"fem-run"``).
    scheduler, workers, progress
        As :func:`rigid.tasks.runner.run_tasks`.

    Returns
    -------
    list of FECritical, in the order of ``targets``.
    """
    searches = FESearches(settings, step=step, start=start, stop=stop, runner=runner)
    first = [searches.add(*t) for t in targets]
    run_tasks(first, store, follow_up=searches.follow_up, scheduler=scheduler,
              workers=workers, progress=progress, description="FE critical SA")
    return searches.results()
