"""A validation run: critical SA by time history and its pulse-based predictions for every
record of a set and every bearing pressure, and the FE model's critical SA searched around the
rigid one (:mod:`validation.fem_search`), run as tasks (local processes or Dask) whose results
are stored as they finish, then collected into tables for the report."""

from __future__ import annotations

import dataclasses
import os
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from rigid import DFPBearing, G
from rigid.reprs import install as install_short_repr
from rigid.tasks import ResultStore, Task, run_tasks, task_key

from .fem_search import FESearches, FESettings


@dataclass(frozen=True)
class Settings:
    """What a validation run computes. Accelerations in m/s².

    Attributes
    ----------
    pressures : tuple of float [Pa]
    criteria : tuple of int
        Pulse selection criteria of paper §4.1 to predict with.
    step, stop : float [m/s²]
        Ladder of SA(Tb): 0.01 g steps (paper) up to ``stop``.
    search : {"full", "fast"}
        Ladder search of :func:`rigid.critical_sa`.
    fem : FESettings or None
        FE critical SA search (None: no FE runs).
    fem_pressures : tuple of float [Pa], optional
        Pressures with FE runs; default all.
    fem_records : int, optional
        FE runs for this many records only, the shortest ones (FE cost grows with the
        simulated time); default all.
    rims : tuple of str
        Rim models of the rigid ladders: "rigid" (the paper's, always run: its predictions
        and tables) and "yielding" (:func:`rigid.simulate`'s yielding rims: one more ladder
        per limit state of ``yielding_states``; with FE runs, each FE search starts there).
    yielding_states : tuple of str
        Limit states of the yielding-rim ladders; default the FE limit states (or the hinge).
    bearing : tuple of (str, float)
        DFPBearing fields other than the pressure that differ from the baseline, in SI units
        (e.g. ``(("rim_thickness", 0.08),)`` for rims twice as thick); default none.
    rim_model : {"plane-strain", "ring"}
        Where the yielding rims' law comes from (:func:`fem.rim_law`'s ``model``); with
        "ring" the FE settings carry the ring's effective depth (``FESettings.rim_depth``).
    rim_fracture : {"steep", "median", "mild"} or None
        The yielding rims' law through tearing with that fracture set (:func:`fem.rim_law`'s
        ``fracture``); None: the law without tearing.
    rim_punch : {"face", "slider"}
        What pushes the plane-strain rim for that law (:func:`fem.rim_law`'s ``punch``; the
        slider only with ``rim_fracture``).
    rim_edge_radius : float [m]
        The pushing slider's rounded edges (``rim_punch="slider"``).
    rim_crush : float [-] or None
        The slider's push also crushes the rim's elements below this det F (Eq. F67b;
        :func:`fem.rim_law`'s ``crush_jacobian``); None: it does not.
    """

    pressures: tuple = (60e6, 10e6)
    criteria: tuple = (1, 2, 3, 4)
    step: float = 0.01 * G
    stop: float = 1.5 * G
    search: str = "fast"
    fem: FESettings | None = None
    fem_pressures: tuple | None = None
    fem_records: int | None = None
    rims: tuple = ("rigid",)
    yielding_states: tuple | None = None
    bearing: tuple = ()
    rim_model: str = "plane-strain"
    rim_fracture: str | None = None
    rim_punch: str = "face"
    rim_edge_radius: float = 0.02
    rim_crush: float | None = None

    def rim_law_options(self) -> dict:
        """:func:`fem.rim_law`'s keywords for the yielding rims' law."""
        options = {"model": self.rim_model, "fracture": self.rim_fracture}
        if self.rim_punch != "face":
            options.update(punch=self.rim_punch, edge_radius=self.rim_edge_radius)
        if self.rim_crush is not None:
            options.update(crush_jacobian=self.rim_crush)
        return options

    def bearing_at(self, pressure: float) -> DFPBearing:
        """The bearing of the run at ``pressure`` [Pa]."""
        return DFPBearing(**dict(self.bearing), pressure=pressure)

    def ladder_states(self) -> tuple:
        """Limit states of the yielding-rim ladders (none without yielding rims)."""
        if "yielding" not in self.rims:
            return ()
        if self.yielding_states is not None:
            return tuple(self.yielding_states)
        return tuple(self.fem.limit_states) if self.fem is not None else ("hinge",)

    def describe(self) -> dict:
        """The settings for the report: ``{"name [unit]": value}`` (no unit for text)."""
        out = {"pressures [MPa]": [p / 1e6 for p in self.pressures],
               "pulse criteria, paper §4.1 [-]": list(self.criteria),
               "SA step [g]": self.step / G,
               "SA stop [g]": self.stop / G, "ladder search": self.search,
               "rigid model's rims": ", ".join(self.rims)
               + (f" (yielding: {', '.join(self.ladder_states())}; law from the "
                  f"{self.rim_model} push"
                  + (f" by the slider (edges {self.rim_edge_radius * 1e3:g} mm)"
                     if self.rim_punch == "slider" else "")
                  + (f", crushed below det F = {self.rim_crush:g}" if self.rim_crush else "")
                  + (f", through tearing ({self.rim_fracture})" if self.rim_fracture else "")
                  + ")"
                  if self.ladder_states() else "")}
        if self.bearing:
            from .bearing_file import describe_variant

            out["bearing variant"] = describe_variant(self.bearing)
        if self.fem is None:
            return out | {"FE critical SA": "not run"}
        pressures = self.fem_pressures or self.pressures
        return out | {
            "FE critical SA": "bracket from the rigid critical SA (with yielding rims when "
                              "run), then bisect to one step",
            "FE pressures [MPa]": [p / 1e6 for p in pressures],
            "FE records": "all" if self.fem_records is None
            else f"the {self.fem_records} shortest",
        } | self.fem.describe()

    def fem_record_indices(self, motions) -> list[int]:
        """Indices of the records with FE runs, in set order."""
        if self.fem_records is None:
            return list(range(len(motions)))
        order = sorted(range(len(motions)),
                       key=lambda i: (motions[i].acceleration.size - 1) * motions[i].dt)
        return sorted(order[: self.fem_records])


def record_task(bearing: dict, name: str, dt: float, acceleration, criteria, step: float,
                stop: float, search: str, cache: str | None, yielding_states=(),
                rim_law=None) -> dict:
    """Actual and predicted critical SA of one record, and the critical SA with yielding rims
    under each of ``yielding_states`` (runs in a worker) with the rims' law ``rim_law``
    (:class:`rigid.rims.RimLaw`, from :func:`fem.rim_law`).

    Parameters are plain data (the bearing as ``dataclasses.asdict``; the record's samples
    [m/s²] and dt [s]) so that the task pickles cheaply and hashes exactly. ``cache`` is the
    rung cache's folder (absolute) inside the run's output folder; a worker that does not see
    that folder (a Dask worker without the client's file system) runs without it rather
    than create the path on its own disk: its results still go back to the client's store.
    """
    from rigid import GroundMotion, critical_sa, predict_critical_sa

    if cache is not None and not Path(cache).parent.is_dir():
        cache = None

    b = DFPBearing(**bearing)
    motion = GroundMotion(name=name, dt=dt, acceleration=np.asarray(acceleration, dtype=float))
    actual = critical_sa(b, motion, step, stop=stop, search=search, cache=cache)
    predictions = {
        str(c): predict_critical_sa(b, motion, criterion=c, step=step, stop=stop, search=search)
        for c in criteria
    }
    yielding = {state: dataclasses.asdict(critical_sa(
        b, motion, step, stop=stop, search=search, cache=cache, rims="yielding",
        limit_state=state, rim_law=rim_law)) for state in yielding_states}
    return {"actual": dataclasses.asdict(actual),
            "predictions": {c: dataclasses.asdict(p) for c, p in predictions.items()},
            "yielding": yielding}


def critical_from_json(d):
    """A :class:`rigid.collapse.ladder.CriticalSA` from its stored JSON form."""
    from rigid.collapse.ladder import CriticalSA, Rung

    d = dict(d)
    if "failure_criterion" in d:  # stored before the rename to limit_state
        d["limit_state"] = d.pop("failure_criterion")
    rungs = tuple(Rung(**{**r, "limit_states": tuple(r.get("limit_states", ()))})
                  for r in d["rungs"])
    return CriticalSA(**{**d, "rungs": rungs})


def predicted_from_json(d):
    """A :class:`rigid.collapse.predict.PredictedSA` from its stored JSON form."""
    from rigid import Pulse
    from rigid.collapse.predict import PredictedSA, PredictionRung

    return PredictedSA(**{**d, "pulse": Pulse(**d["pulse"]),
                          "rungs": tuple(PredictionRung(**r) for r in d["rungs"])})


@dataclass
class PressureResults:
    """Results for one bearing pressure, in record order."""

    bearing: DFPBearing
    actual: list = field(default_factory=list)
    predictions: dict = field(default_factory=dict)  # criterion → list of PredictedSA
    yielding: dict = field(default_factory=dict)  # limit state → list of CriticalSA


install_short_repr(PressureResults)


def rigid_tasks(motions, settings: Settings, out: Path):
    """The rigid record tasks and, by key, their (pressure [Pa], record index); their rung
    cache is ``<out>/ladders`` as an absolute path (workers may run elsewhere)."""
    cache = os.path.join(os.path.abspath(out), "ladders")
    tasks, index = [], {}
    for pressure in settings.pressures:
        bearing = dataclasses.asdict(settings.bearing_at(pressure))
        for i, m in enumerate(motions):
            kwargs = {"bearing": bearing, "name": m.name, "dt": m.dt,
                      "acceleration": m.acceleration, "criteria": list(settings.criteria),
                      "step": settings.step, "stop": settings.stop, "search": settings.search}
            if settings.ladder_states():
                from fem import rim_law

                kwargs["yielding_states"] = list(settings.ladder_states())
                kwargs["rim_law"] = rim_law(settings.bearing_at(pressure),  # cached
                                            **settings.rim_law_options())
            models = ("rigid", "rim-law", "motions", "collapse") if settings.ladder_states() \
                else ("rigid", "motions", "collapse")
            key = task_key("rigid-record", models, **kwargs)
            tasks.append(Task(key, "rigid-record", record_task, {**kwargs, "cache": cache}))
            index[key] = (pressure, i)
    return tasks, index


def _collect_rigid(tasks, index, results, settings) -> dict:
    out_by_pressure = {p: PressureResults(settings.bearing_at(p)) for p in settings.pressures}
    for task in tasks:
        r = out_by_pressure[index[task.key][0]]
        data = results[task.key]
        r.actual.append(critical_from_json(data["actual"]))
        for c, p in data["predictions"].items():
            r.predictions.setdefault(int(c), []).append(predicted_from_json(p))
        for state, c in data.get("yielding", {}).items():
            r.yielding.setdefault(state, []).append(critical_from_json(c))
    return out_by_pressure


def run_rigid(motions, settings: Settings, out: Path, *, scheduler=None,
              workers: int | None = None, progress: bool | None = None,
              worker_wait: float = 60.0) -> dict:
    """Critical SA and predictions for every record and pressure.

    Returns
    -------
    dict {pressure [Pa]: PressureResults}
    """
    tasks, index = rigid_tasks(motions, settings, out)
    with ResultStore(out / "results.sqlite") as store:
        results = run_tasks(tasks, store, scheduler=scheduler, workers=workers,
                            progress=progress, worker_wait=worker_wait,
                            description="rigid critical SA", log=out / "progress.log")
    return _collect_rigid(tasks, index, results, settings)


def run_validation(motions, settings: Settings, out: Path, *, scheduler=None,
                   workers: int | None = None, progress: bool | None = None,
                   fem_runner=None, worker_wait: float = 60.0, replay: bool = False,
                   seen: dict | None = None):
    """The rigid ladders and predictions, and the FE searches, in one run of tasks: a
    record's FE search starts as soon as its rigid critical SA is known (the FE records'
    rigid tasks are queued first), so FE runs overlap the remaining rigid work.

    ``fem_runner`` replaces :func:`validation.fem_search.fem_run` (tests); ``scheduler``,
    ``workers``, ``progress``, ``worker_wait`` [s], ``replay`` (compute nothing: every
    result from the store) and ``seen`` are :func:`rigid.tasks.run_tasks`'s.

    Returns
    -------
    (dict {pressure [Pa]: PressureResults}, dict {pressure [Pa]: list of FECritical})
    """
    tasks, index = rigid_tasks(motions, settings, out)
    targets = set()
    if settings.fem is not None:
        targets = {(p, i) for p in (settings.fem_pressures or settings.pressures)
                   for i in settings.fem_record_indices(motions)}
    # the FE records' ladders first (stable), the others marked as bringing no FE runs
    first = sorted((dataclasses.replace(t, leads=index[t.key] in targets) for t in tasks),
                   key=lambda t: not t.leads)
    owners, searches = [], None

    def follow_up(task, result):
        if task.kind != "rigid-record":
            return searches.follow_up(task, result)
        if index[task.key] not in targets:
            return ()
        pressure, i = index[task.key]
        owners.append((pressure, i))
        yielding = {s: critical_from_json(c) for s, c in result.get("yielding", {}).items()}
        return searches.add(settings.bearing_at(pressure), motions[i],
                            critical_from_json(result["actual"]), yielding=yielding)

    with ResultStore(out / "results.sqlite") as store:
        if settings.fem is not None:
            searches = FESearches(settings.fem, step=settings.step, start=settings.step,
                                  stop=settings.stop, stored=store.get,
                                  **({} if fem_runner is None else {"runner": fem_runner}))
        results = run_tasks(first, store, follow_up=follow_up, scheduler=scheduler,
                            workers=workers, progress=progress, worker_wait=worker_wait,
                            description="rigid ladders and FE runs",
                            log=None if replay else out / "progress.log", replay=replay,
                            seen=seen)
    rigid_results = _collect_rigid(tasks, index, results, settings)
    fem: dict = {}
    if searches is not None:
        order = {key: k for k, key in enumerate(sorted(targets, key=lambda t: (
            settings.pressures.index(t[0]), t[1])))}
        per_target = len(settings.fem.limit_states)
        found = searches.results()
        by_target = [found[k * per_target:(k + 1) * per_target] for k in range(len(owners))]
        for owner, searched in sorted(zip(owners, by_target, strict=True),
                                      key=lambda x: order[x[0]]):
            fem.setdefault(owner[0], []).extend(searched)
    return rigid_results, fem
