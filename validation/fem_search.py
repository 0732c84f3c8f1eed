r"""FE critical SA of a record, searched around the rigid model's: bracket, then bisect.

The FE model (:func:`fem.simulate`) costs minutes per run, so its critical SA(Tb) is not found
by climbing the 0.01 g ladder from the bottom as the rigid model's is. The search starts at the
rigid model's critical rung (the top of the ladder when the rigid model did not fail), steps
down (if the FE model fails there) or up (if it does not) by 1, 2, 4, 8 … rungs until the
outcome changes, then bisects the bracket to one rung (0.01 g). Every FE run is one stored task
(:func:`run_fem_searches` through :func:`rigid.parallel.run_tasks`), keyed by the bearing, the
record, the scale, the model and its settings, so a resumed search replays the stored runs and
runs only what is missing; the searches of different records run in parallel, each search's
next run being a follow-up task of its previous one.

Cost of a search whose answer is k rungs from the start (see :class:`BracketBisect`): at most
2 + 2⌈log₂(k + 1)⌉ runs (⌈log₂(k + 1)⌉ + 1 bracketing runs, then a bisection of a bracket whose
width is a power of two).

Like any bisection this finds *a* failing rung whose rung below survives, within the bracket.
If the FE outcome is not monotonic in the scale (resurrections, as the rigid model has on many
records) a lower failing rung may exist outside the bracket; the table reports the bracket's
lowest surviving rung, and the runs made, so that a reader can see what was tried.

Trimming (:func:`trimmed_window`)
---------------------------------
Each FE run simulates only the part of the scaled record that can matter. Let
a* = μ·g·cos φ_cap·M/(M + m_s) (μ friction, φ_cap the surface tilt at the capacity, M the
supported mass, m_s the slider's), slightly below μ·g.

(ii) **End** (used by default, ``trim="end"``). After the last sample with |a_g| ≥ a* the
ground acceleration (linear between samples, zero after the record) stays below a*. While the
slider slides, friction on the two surfaces dissipates at least μ·N·(|v₁| + |v₂|) with
N ≥ W·cos φ_cap (normal force of the pendulum, vertical inertia neglected), and the inertial
load inputs at most (M + m_s)·|a_g|·(|v₁| + |v₂|), which is smaller: the mechanical energy E
(kinetic + gravitational + elastic) cannot grow. Once E is below the energy needed to bring the
slider to a rim (:func:`rigid.model.reach_energy`, with the rigid model's 5 % margin
``QUIET_FRACTION``), no later impact, and so no failure, is possible and the run can stop.
Up to that time the run is the untrimmed run itself, so its verdict can differ from the
untrimmed one only if the argument fails. The FE run is made up to a guessed end (the rigid
model's quiet time on the same input, plus ``margin``); if the FE model's own energy there is
not below the bound, the run is repeated up to the record's end plus ``free`` seconds (what
the rigid ladder simulates). A run that still has the energy to reach a rim at that point is
flagged (``quiet`` false), like a rigid rung that ends with its ``free`` time.

(i) **Start** (only with ``trim="window"``). A bearing at rest at the dish centres carries no
pendulum force, so it slides only once the inertial force (M + m_s)·|a_g| exceeds the friction
capacity ≈ μ·W: before the first sample with |a_g| ≥ a* (the record being linear between
samples) the rigid-plastic bearing does not move, and starting at rest ``lead`` seconds before
that sample (at least one sample) gives the same motion. This neglects the elastic stick
motion (the friction springs' 0.1 mm elastic slip in the rigid model, the steel's elasticity
in the FE model): micrometres. It is *not* the default because the rigid-model check
(below) found that those micrometres, or mere round-off, flip the verdict at rungs where the
rigid model's failure is chaotic (README, docs/impact_spectra.md): with the start trimmed too,
7 of the 56 record–pressure cases changed their critical SA (one rung verdict each; by 0.01 g
in six, 0.07 g in one), with no impact after the trimmed end
(``docs/results/trimming_check_window.csv``).
On the scaled FEMA records the window starts 0.1–2.6 s into the record (21–26 s for the
90 s Chi-Chi records), so the saving would be small except for those.

The trimming is verified with the rigid model, which is fast: :func:`rigid_outcome` applies
exactly this procedure to the rigid model, and ``benchmarks/check_trimming.py`` compares its
critical SA with the untrimmed :func:`rigid.critical_sa` on the 28 FEMA P695 near-field pulse
records at both pressures (``tests/test_fem_search.py`` on one of them). At the critical
scales most samples of the FEMA records exceed 0.05 g, so the end trimming's saving is the
quiet tail after the strong motion and the record (the FE model has no early stop of its own).
"""

from __future__ import annotations

import dataclasses
import hashlib
import math
import time
from dataclasses import dataclass, field
from pathlib import Path
from types import SimpleNamespace

import numpy as np

from fem.geometry import COARSE_MESH
from rigid import DFPBearing, G
from rigid.parallel import Task, run_tasks
from rigid.store import ResultStore, task_key

#: Stop once the mechanical energy is below this fraction of the reach energy (the rigid
#: model's ``stop_when_quiet`` margin).
QUIET_FRACTION = 0.95

#: FE mesh sizes [m] (:func:`fem.geometry.build_mesh`): ``coarse`` is
#: :data:`fem.geometry.COARSE_MESH` (≈ 10× cheaper per Newton iteration than the default).
MESHES = {
    "coarse": COARSE_MESH,
    "default": {},
}


# --------------------------------------------------------------------------- trimming


def sliding_threshold(bearing: DFPBearing) -> float:
    """a* = μ·g·cos φ_cap·M/(M + m_s) [m/s²]: below it the bearing cannot start to slide, and
    while it slides the ground cannot add mechanical energy (module docstring)."""
    m, ms = bearing.supported_mass, bearing.slider_mass
    return bearing.friction * G * math.cos(bearing.capacity_tilt) * m / (m + ms)


@dataclass(frozen=True)
class Window:
    """Strong-motion window of a scaled record (sample indices of the record).

    Attributes
    ----------
    start : int
        The run starts here, at rest.
    end : int
        From this sample on, |a_g| < a* to the end of the record.
    """

    start: int
    end: int


def strong_motion_window(bearing: DFPBearing, acceleration, dt: float, *,
                         lead: float = 0.1) -> Window | None:
    """Where a scaled record can move the bearing (module docstring, (i) and (ii)).

    Parameters
    ----------
    bearing : DFPBearing
    acceleration : array_like [m/s²]
        The scaled record.
    dt : float [s]
    lead : float [s]
        The run starts this long before the first sample with |a_g| ≥ a* (at least one
        sample before it).

    Returns
    -------
    Window, or None when no sample reaches a* (the bearing does not slide).
    """
    a = np.abs(np.asarray(acceleration, dtype=float))
    strong = np.flatnonzero(a >= sliding_threshold(bearing))
    if strong.size == 0:
        return None
    start = max(0, int(strong[0]) - max(1, math.ceil(lead / dt - 1e-9)))
    end = min(a.size - 1, int(strong[-1]) + 1)
    return Window(start, end)


TRIMS = ("end", "window", "none")


def trimmed_window(bearing: DFPBearing, acceleration, dt: float, trim: str = "end", *,
                   lead: float = 0.1) -> Window | None:
    """The part of a scaled record a run simulates: ``"end"`` from the first sample to the
    window's end (default; see the module docstring for why the start is kept), ``"window"``
    the strong-motion window, ``"none"`` the whole record. None: the bearing cannot slide
    (``"end"`` and ``"window"`` only)."""
    n = np.asarray(acceleration).size
    if trim == "none":
        return Window(0, n - 1)
    if trim not in TRIMS:
        raise ValueError(f"trim must be one of {', '.join(TRIMS)}, got {trim!r}")
    w = strong_motion_window(bearing, acceleration, dt, lead=lead)
    if w is None or trim == "window":
        return w
    return Window(0, w.end)


def _quiet_after(energy: np.ndarray, time: np.ndarray, t_from: float, bound: float):
    """First time ≥ t_from with energy < bound, or None."""
    ok = np.flatnonzero((time >= t_from - 1e-9) & (energy < bound))
    return None if ok.size == 0 else float(time[ok[0]])


def rigid_outcome(bearing: DFPBearing, acceleration, dt: float, scale: float, *,
                  trim: str = "end", free: float = 20.0, lead: float = 0.1) -> dict:
    """The rigid model's verdict at one scale, with the FE runs' trimming (to verify it).

    With ``trim`` "end" or "window" (:func:`trimmed_window`) the run starts at rest at the
    window's start and its verdict is the one at the first time after the window's end at
    which the mechanical energy (kinetic + potential) is below ``QUIET_FRACTION`` × the reach
    energy; ``late_impacts`` counts rim impacts after that time (the end argument says there
    are none; the run is continued to the record's end, and after it until quiet, to check
    it). With "none": the whole record plus up to ``free`` seconds, as
    :func:`rigid.critical_sa` runs it.

    Returns
    -------
    dict
        ``failed``, ``failure_time`` [s from the record's start], ``impacts``,
        ``max_impact_velocity`` [m/s], ``late_impacts``, ``late_failure``, ``start``, ``stop``
        [s] (the trimmed run's start and verdict time).
    """
    from rigid import simulate
    from rigid.model import reach_energy

    a = scale * np.asarray(acceleration, dtype=float)
    total = (a.size - 1) * dt + free
    window = trimmed_window(bearing, a, dt, trim, lead=lead)
    if window is None:
        return {"failed": False, "failure_time": None, "impacts": 0,
                "max_impact_velocity": 0.0, "late_impacts": 0, "late_failure": False,
                "start": None, "stop": None}
    t0 = window.start * dt
    r = simulate(bearing, a[window.start:], dt, duration=total - t0, stop_at_failure=True,
                 on_instability="refine", stop_when_quiet=True)
    stop = total
    if trim != "none":
        e = r.energy.kinetic + r.energy.potential
        q = _quiet_after(e, r.time, (window.end - window.start) * dt,
                         QUIET_FRACTION * reach_energy(bearing))
        stop = total if q is None else t0 + q
    fail_time = None if r.failure_time is None else t0 + r.failure_time
    failed = bool(r.failed) and fail_time <= stop + 1e-9
    early = [i for i in r.impacts if t0 + i.time <= stop + 1e-9]
    return {
        "failed": failed,
        "failure_time": fail_time if failed else None,
        "impacts": len(early),
        "max_impact_velocity": max((abs(i.velocity) for i in early), default=0.0),
        "late_impacts": len(r.impacts) - len(early),
        "late_failure": bool(r.failed) and not failed,
        "start": t0,
        "stop": stop,
    }


def rigid_critical_sa_trimmed(bearing: DFPBearing, motion, step: float = 0.01 * G, *,
                              stop: float = 3.0 * G, search: str = "fast", coarse: int = 10,
                              refine_ratio: float = 0.8, free: float = 20.0,
                              trim: str = "end", lead: float = 0.1) -> dict:
    """Critical SA of the rigid model with every rung trimmed (:func:`rigid_outcome`), by the
    same ladder search as :func:`rigid.critical_sa` (whose ``search="fast"`` logic it reuses),
    to compare with the untrimmed result.

    Returns
    -------
    dict
        ``sa`` [m/s²] or None, ``rungs`` {rung index: :func:`rigid_outcome` dict}.
    """
    from rigid.ida import _fast_search, record_ladder

    acc = np.asarray(motion.acceleration, dtype=float)
    record_sa, n_rungs = record_ladder(acc, motion.dt, bearing.design_period, 0.05,
                                       motion.name, step, step, stop)
    done, outcomes = {}, {}

    def rung(j):
        if j not in done:
            out = rigid_outcome(bearing, acc, motion.dt, (step + j * step) / record_sa,
                                trim=trim, free=free, lead=lead)
            outcomes[j] = out
            done[j] = SimpleNamespace(failed=out["failed"],
                                      max_impact_velocity=out["max_impact_velocity"])
        return done[j]

    if search == "full":
        first = next((j for j in range(n_rungs) if rung(j).failed), None)
    else:
        first = _fast_search(rung, done, n_rungs, int(coarse), float(refine_ratio))
    return {"sa": None if first is None else step + first * step,
            "rungs": dict(sorted(outcomes.items()))}


# --------------------------------------------------------------------------- one FE run


def fem_mechanical_energy(result) -> np.ndarray:
    """Mechanical energy of an FE run [J]: kinetic + elastic (steel and penalty springs) +
    gravitational (supported mass and slider, from their rise)."""
    b = result.bearing
    e = result.energy
    return (e["kinetic"] + e["strain"] + e["contact"]
            + b.supported_mass * G * result.top_plate_rise
            + b.slider_mass * G * result.slider_rise)


def _duration_guess(bearing, a, dt, window, total, margin) -> float:
    """Seconds to simulate from the window's start: the rigid model's quiet time after the
    window's end on the same input, plus ``margin``; at most the rest of the record + free."""
    from rigid import simulate
    from rigid.model import reach_energy

    t_end = (window.end - window.start) * dt
    r = simulate(bearing, a[window.start:], dt, duration=total, stop_at_failure=True,
                 on_instability="report")
    e = r.energy.kinetic + r.energy.potential
    q = _quiet_after(e, r.time, t_end, QUIET_FRACTION * reach_energy(bearing))
    guess = (t_end if q is None or r.failed else q) + margin
    return min(total, max(guess, t_end + margin))


def fem_run(bearing: dict, acceleration, dt: float, scale: float, *, mesh: str = "coarse",
            max_step: float = 5e-3, impact_step: float = 5e-4, trim: str = "end",
            free: float = 20.0, lead: float = 0.1, margin: float = 1.0,
            simulate=None) -> dict:
    """One FE run of a scaled record, trimmed (module docstring); runs in a worker.

    Parameters
    ----------
    bearing : dict
        ``dataclasses.asdict`` of a DFPBearing (plain data pickles and hashes exactly).
    acceleration : array_like [m/s²]
        The unscaled record.
    dt : float [s]
    scale : float [-]
    mesh : {"coarse", "default"}
        :data:`MESHES`.
    max_step, impact_step : float [s]
        :func:`fem.simulate`'s time steps.
    trim : {"end", "window", "none"}
        :func:`trimmed_window`: stop after the strong motion once the energy check allows
        (default), also start at its beginning, or run the record plus ``free`` seconds.
    free : float [s]
        Longest time simulated after the record.
    lead, margin : float [s]
        Start this long before the first strong sample; simulate this long beyond the guessed
        quiet time.
    simulate : callable, optional
        Stand-in for :func:`fem.simulate` (tests).

    Returns
    -------
    dict
        ``failed``, ``failure_mode``, ``failure_time`` [s from the record's start],
        ``numerical_failure``, ``detail``, ``start``, ``strong_end``, ``end`` [s] (what was
        simulated), ``energy_end``, ``reach_energy`` [J], ``quiet`` (energy below the bound
        at the end: the verdict is final), ``runs`` (1, or 2 when the guessed end was not
        quiet), ``steps``, ``newton_iterations``, ``dofs``, ``max_plastic_strain``,
        ``max_rim_force`` [N], ``cpu_seconds``, ``wall_seconds``.
    """
    from rigid.model import reach_energy

    if simulate is None:
        from fem import simulate
    b = DFPBearing(**bearing)
    if mesh not in MESHES:
        raise ValueError(f"mesh must be one of {', '.join(MESHES)}, got {mesh!r}")
    cpu0, wall0 = time.process_time(), time.perf_counter()
    a = scale * np.asarray(acceleration, dtype=float)
    record_end = (a.size - 1) * dt
    reach = reach_energy(b)
    window = trimmed_window(b, a, dt, trim, lead=lead)
    out = {"failed": False, "failure_mode": None, "failure_time": None,
           "numerical_failure": False, "detail": None, "start": None, "strong_end": None,
           "end": None, "energy_end": 0.0, "reach_energy": reach, "quiet": True, "runs": 0,
           "steps": 0, "newton_iterations": 0, "dofs": 0, "max_plastic_strain": 0.0,
           "max_rim_force": 0.0}
    if window is None:  # |a_g| < a* throughout: the bearing cannot slide
        out["detail"] = "the scaled record never reaches the sliding threshold"
        return {**out, "cpu_seconds": 0.0, "wall_seconds": 0.0}
    t0 = window.start * dt
    total = record_end + free - t0
    durations = [total if trim == "none" else _duration_guess(b, a, dt, window, total, margin),
                 total]
    for duration in dict.fromkeys(durations):  # the guess, then (if needed) the whole rest
        res = simulate(b, a[window.start:], dt, duration=duration,
                       mesh_options=MESHES[mesh], max_step=max_step, impact_step=impact_step)
        energy = fem_mechanical_energy(res)
        out.update(
            failed=bool(res.failed), failure_mode=res.failure_mode,
            failure_time=None if res.failure_time is None else t0 + res.failure_time,
            numerical_failure=bool(res.numerical_failure), detail=res.failure_detail,
            start=t0, strong_end=window.end * dt, end=t0 + float(res.time[-1]),
            energy_end=float(energy[-1]), runs=out["runs"] + 1,
            steps=out["steps"] + res.steps,
            newton_iterations=out["newton_iterations"] + res.newton_iterations,
            dofs=res.dofs, max_plastic_strain=float(res.max_plastic_strain),
            max_rim_force=float(res.rim_force.max()) if res.rim_force.size else 0.0,
        )
        out["quiet"] = bool(energy[-1] < QUIET_FRACTION * reach)
        if res.failed or res.numerical_failure or out["quiet"]:
            break
    if res.failed or res.numerical_failure:
        out["quiet"] = True  # the verdict is final
    out["cpu_seconds"] = time.process_time() - cpu0
    out["wall_seconds"] = time.perf_counter() - wall0
    return out


# --------------------------------------------------------------------------- the search


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


def _source_hash() -> str:
    """SHA-256 of the FE model's sources (fem/*.py, meshes/*.geo): a model change
    invalidates stored FE runs."""
    root = Path(__file__).resolve().parent.parent
    h = hashlib.sha256()
    for path in sorted([*(root / "fem").glob("*.py"), *(root / "meshes").glob("*.geo")]):
        h.update(path.name.encode())
        h.update(path.read_bytes())
    return h.hexdigest()


class FESearches:
    """Several FE critical-SA searches driven through :func:`rigid.parallel.run_tasks`:
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
        self.model = (_source_hash() if runner is fem_run
                      else f"{runner.__module__}.{runner.__qualname__}")
        self.options = dataclasses.asdict(settings)
        self.targets, self.searches, self.found, self.by_key = [], [], [], {}

    def _task(self, i, j) -> Task:
        bearing, motion, rigid_crit = self.targets[i]
        scale = (self.start + j * self.step) / rigid_crit.record_sa
        kwargs = {"bearing": dataclasses.asdict(bearing), "acceleration": motion.acceleration,
                  "dt": motion.dt, "scale": scale, **self.options}
        key = task_key(self.kind, model=self.model, **kwargs)
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
    targets : sequence of (DFPBearing, GroundMotion, rigid.ida.CriticalSA)
    settings, step, start, stop, runner
        As :class:`FESearches`.
    store : ResultStore
        Every FE run is stored there as it finishes (kind ``"fem-run"``).
    scheduler, workers, progress
        As :func:`rigid.parallel.run_tasks`.

    Returns
    -------
    list of FECritical, in the order of ``targets``.
    """
    searches = FESearches(settings, step=step, start=start, stop=stop, runner=runner)
    first = [searches.add(*t) for t in targets]
    run_tasks(first, store, follow_up=searches.follow_up, scheduler=scheduler,
              workers=workers, progress=progress, description="FE critical SA")
    return searches.results()
