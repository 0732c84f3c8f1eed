r"""FE critical SA of a record, searched around the rigid model's: bracket by 1, 2, 4, … rungs,
then bisect to one rung, every FE run a stored task, the searches of several records driven in
parallel as follow-up tasks (docs/theory/collapse.md, Eqs. C16–C17).
"""


from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

from fem.dfp import KINEMATICS
from fem.fracture import FRACTURE_SETS
from rigid import DFPBearing
from rigid.limit_states import LIMIT_STATES, check_limit_states
from rigid.reprs import install as install_short_repr
from rigid.tasks import ResultStore, Task, run_tasks, task_key

from .fem_runs import MESHES, fem_run

__all__ = ["BracketBisect", "FECritical", "FESearches", "FESettings", "decides",
           "failed_under", "run_criterion", "run_fem_searches", "run_limit_state",
           "verdict_of"]


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
    the record and the scale), except ``limit_states``: the runs stop at the last of them
    (:func:`run_limit_state`), so the searches of all of them share their runs. ``rim_depth``,
    ``fracture``, ``edge_radius`` [m] and ``crush_jacobian`` [-] (:func:`fem_run`'s) key a run
    only when set, so the runs of the model's defaults keep their keys."""

    mesh: str = "coarse"
    max_step: float = 5e-3
    impact_step: float = 5e-4
    trim: str = "end"
    free: float = 20.0
    lead: float = 0.1
    margin: float = 1.0
    kinematics: str = "finite"
    limit_states: tuple = ("hinge",)
    rim_depth: float | None = None
    fracture: str | None = None
    edge_radius: float = 0.0
    crush_jacobian: float | None = None

    def __post_init__(self):
        object.__setattr__(self, "limit_states", check_limit_states(self.limit_states))
        if self.kinematics not in KINEMATICS:
            raise ValueError(f"kinematics must be one of {', '.join(KINEMATICS)}, got "
                             f"{self.kinematics!r}")
        if self.fracture is not None and self.fracture not in FRACTURE_SETS:
            raise ValueError(f"fracture must be one of {', '.join(FRACTURE_SETS)} or None, "
                             f"got {self.fracture!r}")
        if not (math.isfinite(self.edge_radius) and self.edge_radius >= 0):
            raise ValueError(f"edge_radius must be a length ≥ 0 [m], got {self.edge_radius!r}")
        if self.crush_jacobian is not None and (
                self.fracture is None or not 0.0 < self.crush_jacobian < 1.0):
            raise ValueError("crush_jacobian goes with fracture and lies in (0, 1), got "
                             f"{self.crush_jacobian!r}")

    def run_options(self) -> dict:
        """Keyword arguments of :func:`fem_run` (what keys a stored run)."""
        options = dataclasses.asdict(self)
        del options["limit_states"]
        for name, default in (("rim_depth", None), ("fracture", None), ("edge_radius", 0.0),
                              ("crush_jacobian", None)):
            if options[name] == default:  # the model's: the keys of runs without it
                del options[name]
        return {**options, "limit_state": run_limit_state(self.limit_states)}

    def describe(self) -> dict:
        sizes = MESHES[self.mesh]
        names = {"rim_size": "rims", "contact_size": "contact", "coarse_size": "elsewhere"}
        sizes = ", ".join(f"{names.get(k, k)} {v * 1e3:g} mm" for k, v in sizes.items()) \
            if sizes else "the generator's defaults"
        return {"FE mesh": f"{self.mesh} (element sizes: {sizes})",
                "FE time step [s]": f"{self.max_step:g} free sliding, {self.impact_step:g} "
                "at a rim", "FE trimming": {"end": "after the strong motion, once quiet",
                                     "window": "strong-motion window",
                                     "none": "none"}[self.trim],
                "FE kinematics": {"finite": "finite deformation",
                                  "small": "small strain"}[self.kinematics],
                "FE limit states": ", ".join(self.limit_states),
                "FE rims' depth [m]": ("πb/4, the model's" if self.rim_depth is None
                                       else f"{self.rim_depth:.3f} (3-D effective depth)"),
                "FE rim fracture": ("none: the rupture is the rupture strain over its gauge"
                                    if self.fracture is None else
                                    f"{self.fracture} ductile damage; torn elements let go"
                                    + ("" if self.crush_jacobian is None else
                                       f", and crushed ones (det F < {self.crush_jacobian:g}),"
                                       " uncovering faces that carry contact")),
                "FE slider edges": ("sharp" if not self.edge_radius
                                    else f"rounded, radius {self.edge_radius * 1e3:g} mm")}


def run_limit_state(limit_states) -> str:
    """The limit state an FE run must go on to so that it decides all of ``limit_states``:
    the last of them in :data:`rigid.limit_states.LIMIT_STATES` order (a run that stops at
    containment has recorded the hinge and the rupture before it)."""
    return max(check_limit_states(limit_states), key=LIMIT_STATES.index)


def run_criterion(limit_states) -> str:
    """Deprecated alias of :func:`run_limit_state`."""
    import warnings

    warnings.warn("run_criterion is deprecated, use run_limit_state", DeprecationWarning,
                  stacklevel=2)
    return run_limit_state(limit_states)


def failed_under(result: dict, limit_state: str) -> bool | None:
    """The verdict of a stored FE run under ``limit_state``: True if the run reached it or lost
    containment (failure under any limit state), also when it failed numerically later on;
    False if it reached neither and ran to its end; None if it failed numerically before
    reaching either (neither a failure nor a survival). Runs without ``limit_states``
    (stand-in runners) give their own ``failed``, or None if numerical."""
    times = result.get("limit_states")
    if times is not None and (times.get(limit_state) is not None
                              or times.get("containment") is not None):
        return True
    if result.get("numerical_failure"):
        return None
    return bool(result["failed"]) if times is None else False


def decides(result: dict, run_state: str, limit_state: str) -> bool:
    """Whether a stored FE run made to the limit state ``run_state`` (it stops there) answers
    ``limit_state``: a run records every limit state it reaches, so it answers the limit
    states up to its own (:data:`rigid.limit_states.LIMIT_STATES` order: the hinge, then the
    rupture, then the loss of containment), any it reached, and all of them when it ran to its
    end without reaching its own. A numerical failure answers only up to its own. Runs
    without ``limit_states`` (stand-in runners) answer only their own limit state."""
    times = result.get("limit_states")
    if LIMIT_STATES.index(limit_state) <= LIMIT_STATES.index(run_state):
        return True
    if times is None or result.get("numerical_failure"):
        return False
    stopped = times.get(run_state) is not None or times.get("containment") is not None
    return times.get(limit_state) is not None or not stopped


@dataclass
class FECritical:
    """FE critical SA of one record at one pressure under one limit state, and the runs that
    found it.

    Attributes
    ----------
    name : str
    pressure : float [Pa]
    rigid_sa : float or None [m/s²]
        The rigid model's critical SA with rigid rims (the search's start without
        ``yielding_sa``).
    yielding_sa : float or None [m/s²]
        The rigid model's critical SA with yielding rims under the same limit state (the
        search's start when known); None when not run or no failure.
    sa : float or None [m/s²]
        FE critical SA: the failing rung found; None if the top rung survived.
    survived_below : float or None [m/s²]
        The bracket's highest surviving rung below ``sa`` (None when the lowest rung failed).
    failure_mode : str or None
        Of the run at ``sa``: "yielding" or "uplift" if it lost containment there, "yielding"
        if it only reached a hinge or a rupture.
    failure_time : float or None [s]
        When the run at ``sa`` reached the limit state (or lost containment, if earlier).
    probes : list of dict
        Every run of this search in the order made: ``sa`` [m/s²], ``scale``, ``failed``
        (under this limit state; None if numerical) and the run's result.
    limit_state : str
        "hinge", "rupture" or "containment" (docs/theory/finite-elements.md, "Limit states").
    """

    name: str
    pressure: float
    rigid_sa: float | None
    sa: float | None = None
    survived_below: float | None = None
    failure_mode: str | None = None
    failure_time: float | None = None
    probes: list = field(default_factory=list)
    limit_state: str = "hinge"
    yielding_sa: float | None = None

    @property
    def runs(self) -> int:
        return len(self.probes)

    @property
    def cpu_seconds(self) -> float:
        return sum(p["cpu_seconds"] for p in self.probes)

    @property
    def numerical_runs(self) -> int:
        """Probes that failed numerically (taken as failures to steer the bisection)."""
        return sum(p["failed"] is None for p in self.probes)

    @property
    def uncertain(self) -> bool:
        """True when a numerical probe lies at or below the answer (or there is no answer and
        a probe was numerical): the critical SA depends on it."""
        return any(p["failed"] is None and (self.sa is None or p["sa"] <= self.sa + 1e-9)
                   for p in self.probes)


install_short_repr(FECritical)


def verdict_of(result: dict, limit_state: str):
    """(mode, time [s]) of a run that failed under ``limit_state`` (:func:`failed_under`
    True): the loss of containment if it came first, else the limit state's own time."""
    times = result.get("limit_states")
    if times is None:
        return result.get("failure_mode"), result.get("failure_time")
    t_state, t_lost = times.get(limit_state), times.get("containment")
    if t_lost is not None and (t_state is None or t_lost <= t_state):
        return result.get("failure_mode") or "yielding", t_lost
    return "yielding", t_state


class FESearches:
    """Several FE critical-SA searches driven through :func:`rigid.tasks.runner.run_tasks`:
    :meth:`add` gives a record's first tasks, :meth:`follow_up` the next ones from each
    result, :meth:`results` the answers. One search per record and limit state; searches that
    ask for the same run share it (one stored task). A caller can add records from its own
    follow-ups (the validation pipeline starts a record's FE searches as soon as its rigid
    result arrives).

    Parameters
    ----------
    settings : FESettings
    step, start, stop : float [m/s²]
        The ladder: rungs at start + j·step ≤ stop (the rigid ladder's).
    runner : callable
        ``runner(bearing=dict, acceleration, dt, scale, **settings.run_options())`` → dict
        with at least ``failed``, ``failure_mode``, ``failure_time``, ``cpu_seconds`` (and
        ``limit_states``, ``numerical_failure`` when it has them); :func:`fem_run`, or a
        stand-in (tests).
    models : tuple of str
        The models whose code keys the stored runs (:data:`rigid.tasks.cache.MODEL_CODE`);
        default those :func:`fem_run` runs.
    stored : callable, optional
        ``stored(key)`` → a stored result or None (:meth:`ResultStore.get`). With it, a rung
        already run to another limit state is reused when that run answers the search's limit
        state (:func:`decides`): adding the rupture to a study stored for the hinge replays
        the hinge searches and reruns only what the rupture needs.
    """

    kind = "fem-run"

    def __init__(self, settings: FESettings, *, step: float, start: float, stop: float,
                 runner=fem_run, models=("rigid", "trimming", "fem", "fem-run"),
                 stored=None):
        self.step, self.start = float(step), float(start)
        self.stored = stored
        self.highest = math.floor((stop - start) / step + 1e-9)
        self.runner, self.models = runner, tuple(models)
        # a stand-in runner (tests) is keyed by its name; fem_run by the code of the models
        self.runner_name = (None if runner is fem_run
                            else f"{runner.__module__}.{runner.__qualname__}")
        self.limit_states = tuple(settings.limit_states)
        self.options = settings.run_options()
        self.targets, self.searches, self.found = [], [], []
        self.by_key: dict = {}     # task key → (target, rung)
        self.waiting: dict = {}    # task key → searches waiting for its result
        self.outcomes: dict = {}   # task key → result

    def run_key(self, i: int, j: int, limit_state: str | None = None) -> tuple[str, dict]:
        """Task key and keyword arguments of the FE run of target ``i`` at rung ``j``
        (``limit_state``: a stored run made to another limit state, see :func:`decides`)."""
        bearing, motion, rigid_crit = self.targets[i]
        scale = (self.start + j * self.step) / rigid_crit.record_sa
        kwargs = {"bearing": dataclasses.asdict(bearing), "acceleration": motion.acceleration,
                  "dt": motion.dt, "scale": scale, **self.options}
        if limit_state is not None:
            kwargs["limit_state"] = limit_state
        key = task_key(self.kind, self.models, runner=self.runner_name, **kwargs)
        return key, kwargs

    def _reusable(self, k, i, j) -> str | None:
        """Key of a stored run of rung j to another limit state that answers search k, or
        None. It joins the outcomes (it is never run, so never a duplicate)."""
        if self.stored is None:
            return None
        for state in LIMIT_STATES:
            if state == self.options["limit_state"]:
                continue
            key, _ = self.run_key(i, j, state)
            result = self.outcomes.get(key) or self.stored(key)
            if result is not None and decides(result, state, self.found[k].limit_state):
                self.outcomes[key] = result
                return key
        return None

    def _advance(self, k) -> list:
        """Ask for search k's next rung: new tasks to run (none if its run is already known or
        under way)."""
        tasks = []
        while True:
            j = self.searches[k].next_rung()
            if j is None:
                return tasks
            i = k // len(self.limit_states)
            key, kwargs = self.run_key(i, j)
            if key not in self.outcomes:
                key = self._reusable(k, i, j) or key
            if key in self.outcomes:
                self._record(k, j, key)
                continue
            if key not in self.waiting:
                self.waiting[key] = []
                self.by_key[key] = (i, j)
                tasks.append(Task(key, self.kind, self.runner, kwargs))
            self.waiting[key].append(k)
            return tasks

    def _record(self, k, j, key) -> None:
        result = self.outcomes[key]
        failed = failed_under(result, self.found[k].limit_state)
        self.searches[k].record(j, True if failed is None else failed)
        record_sa = self.targets[k // len(self.limit_states)][2].record_sa
        sa = self.start + j * self.step
        self.found[k].probes.append({"sa": sa, **result, "scale": sa / record_sa,
                                     "failed": failed})

    def add(self, bearing: DFPBearing, motion, rigid_crit, yielding=None) -> tuple:
        """Start a record's searches, one per limit state; their first tasks. Each starts at
        the rung of the rigid model's CriticalSA with yielding rims under its limit state
        (``yielding``: limit state → CriticalSA), when given and failing, else at that of
        ``rigid_crit`` (rigid rims)."""
        self.targets.append((bearing, motion, rigid_crit))
        yielding = yielding or {}
        tasks = []
        for state in self.limit_states:
            y = yielding.get(state)
            sa = y.sa if y is not None and y.sa is not None else rigid_crit.sa
            j0 = self.highest if sa is None else round((sa - self.start) / self.step)
            self.searches.append(BracketBisect(j0, 0, self.highest))
            self.found.append(FECritical(motion.name, bearing.pressure, rigid_crit.sa,
                                         limit_state=state,
                                         yielding_sa=None if y is None else y.sa))
            tasks += self._advance(len(self.searches) - 1)
        return tuple(tasks)

    def follow_up(self, done_task, result) -> tuple:
        """The next tasks after ``done_task`` (one of ours), or ()."""
        key = done_task.key
        if key in self.outcomes:
            return ()  # a duplicate outcome (not expected: every run is asked for once)
        self.outcomes[key] = result
        _, j = self.by_key[key]
        tasks = []
        for k in self.waiting.pop(key, []):
            self._record(k, j, key)
            tasks += self._advance(k)
        return tuple(tasks)

    def results(self) -> list:
        """FECritical of every search, by record in the order added, then by limit state
        (complete once run_tasks returns)."""
        for s, r in zip(self.searches, self.found, strict=True):
            if s.critical is not None:
                r.sa = self.start + s.critical * self.step
                at = next(p for p in r.probes if math.isclose(p["sa"], r.sa))
                if at["failed"]:
                    r.failure_mode, r.failure_time = verdict_of(at, r.limit_state)
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
    list of FECritical, by target in the order of ``targets``, then by limit state.
    """
    searches = FESearches(settings, step=step, start=start, stop=stop, runner=runner,
                          stored=store.get)
    first = [task for t in targets for task in searches.add(*t)]
    run_tasks(first, store, follow_up=searches.follow_up, scheduler=scheduler,
              workers=workers, progress=progress, description="FE critical SA")
    return searches.results()
