"""A validation run: critical SA by time history and its pulse-based predictions for every
record of a set and every bearing pressure, run as tasks (local processes or Dask) whose
results are stored as they finish, then collected into tables for the report."""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from rigid import DFPBearing, G
from rigid.parallel import Task, run_tasks
from rigid.store import ResultStore, task_key


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
    """

    pressures: tuple = (60e6, 10e6)
    criteria: tuple = (1, 2, 3, 4)
    step: float = 0.01 * G
    stop: float = 1.5 * G
    search: str = "fast"

    def describe(self) -> dict:
        return {"pressures [MPa]": [p / 1e6 for p in self.pressures],
                "criteria": list(self.criteria), "SA step [g]": self.step / G,
                "SA stop [g]": self.stop / G, "ladder search": self.search}


def record_task(bearing: dict, name: str, dt: float, acceleration, criteria, step: float,
                stop: float, search: str, cache: str | None) -> dict:
    """Actual and predicted critical SA of one record (runs in a worker).

    Parameters are plain data (the bearing as ``dataclasses.asdict``; the record's samples
    [m/s²] and dt [s]) so that the task pickles cheaply and hashes exactly.
    """
    from rigid import GroundMotion, critical_sa, predict_critical_sa

    b = DFPBearing(**bearing)
    motion = GroundMotion(name=name, dt=dt, acceleration=np.asarray(acceleration, dtype=float))
    actual = critical_sa(b, motion, step, stop=stop, search=search, cache=cache)
    predictions = {
        str(c): predict_critical_sa(b, motion, criterion=c, step=step, stop=stop, search=search)
        for c in criteria
    }
    return {"actual": dataclasses.asdict(actual),
            "predictions": {c: dataclasses.asdict(p) for c, p in predictions.items()}}


def _critical_from_json(d):
    from rigid.ida import CriticalSA, Rung

    return CriticalSA(**{**d, "rungs": tuple(Rung(**r) for r in d["rungs"])})


def _predicted_from_json(d):
    from rigid import Pulse
    from rigid.predict import PredictedSA, PredictionRung

    return PredictedSA(**{**d, "pulse": Pulse(**d["pulse"]),
                          "rungs": tuple(PredictionRung(**r) for r in d["rungs"])})


@dataclass
class PressureResults:
    """Results for one bearing pressure, in record order."""

    bearing: DFPBearing
    actual: list = field(default_factory=list)
    predictions: dict = field(default_factory=dict)  # criterion → list of PredictedSA


def run_rigid(motions, settings: Settings, out: Path, *, scheduler=None,
              workers: int | None = None, progress: bool | None = None) -> dict:
    """Critical SA and predictions for every record and pressure.

    Returns
    -------
    dict {pressure [Pa]: PressureResults}
    """
    store = ResultStore(out / "results.sqlite")
    cache = str(out / "ladders")
    tasks, index = [], {}
    for pressure in settings.pressures:
        bearing = dataclasses.asdict(DFPBearing(pressure=pressure))
        for m in motions:
            kwargs = {"bearing": bearing, "name": m.name, "dt": m.dt,
                      "acceleration": m.acceleration, "criteria": list(settings.criteria),
                      "step": settings.step, "stop": settings.stop, "search": settings.search}
            key = task_key("rigid-record", **kwargs)
            tasks.append(Task(key, "rigid-record", record_task, {**kwargs, "cache": cache}))
            index[key] = pressure
    results = run_tasks(tasks, store, scheduler=scheduler, workers=workers, progress=progress,
                        description="rigid critical SA")
    out_by_pressure = {p: PressureResults(DFPBearing(pressure=p)) for p in settings.pressures}
    for task in tasks:
        r = out_by_pressure[index[task.key]]
        data = results[task.key]
        r.actual.append(_critical_from_json(data["actual"]))
        for c, p in data["predictions"].items():
            r.predictions.setdefault(int(c), []).append(_predicted_from_json(p))
    store.close()
    return out_by_pressure
