"""The cases of the rim design space (``validation.studies.rim_design``): a record and a
bearing with rigid rims (:func:`rigid_case`), and with yielding rims of one geometry
(:func:`yielding_case`). Its code is part of the stored cases' key (``rim-design-case`` in
:data:`rigid.tasks.cache.MODEL_CODE`)."""

from __future__ import annotations

import time
import warnings

import numpy as np

import rigid
from rigid import DFPBearing, G
from rigid.collapse.limit_state_ladder import critical_sa_by_limit_state, failure_mode

from .hinge_vs_impact import lowest_rung

#: The code a stored case depends on (:func:`rigid.tasks.task_key`).
CASE_CODE = ("rigid", "rim-law", "collapse", "motions", "rim-design-case")
#: Governing modes, in the order a rising SA meets them (see :func:`governing_mode`).
MODES = ("hinge", "rupture", "containment", "uplift", "none")


def _g(sa):
    return None if sa is None else round(sa / G, 4)


def rigid_case(bearing: DFPBearing, motion, stop: float, cache) -> dict:
    """One record and bearing with rigid rims: critical SA [g] and the first touch [g]. The
    rigid-rim model sees a rim's thickness only where a corner sinks deeper than it into the
    rim (a numerical stop), so this is run once per record, pressure and rim height."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        t0 = time.process_time()
        ladder = rigid.critical_sa(bearing, motion, search="fast", stop=stop, cache=cache)
        touched = [r.sa for r in ladder.rungs if r.impacts or r.failed]
        start = round(min(touched, default=stop) / (0.01 * G))
        touch, numerical = first_touch(bearing, motion, max(1, start))
    return {"rigid_sa_g": _g(ladder.sa), "rigid_uncertain": ladder.uncertain,
            "first_touch_sa_g": touch / 100, "first_touch_numerical": numerical,
            "rigid_cpu_s": round(time.process_time() - t0, 2)}


def yielding_case(bearing: DFPBearing, motion, rim_law, stop: float, cache) -> dict:
    """One record, bearing and rim with yielding rims: critical SA [g] per limit state, how
    each fails, and what fails first."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        t0 = time.process_time()
        yielding = critical_sa_by_limit_state(bearing, motion, rim_law, stop=stop, cache=cache)
    row = {}
    for state, c in yielding.items():
        row[f"{state}_sa_g"] = _g(c.sa)
        row[f"{state}_mode"] = failure_mode(c)
        row[f"{state}_uncertain"] = c.uncertain
    row["governing_mode"] = governing_mode(yielding)
    row["yielding_cpu_s"] = round(time.process_time() - t0, 2)
    return row


def first_touch(bearing: DFPBearing, motion, start: int) -> tuple[int, bool]:
    """(k, numerical): the lowest rung k (SA(Tb) = k × 0.01 g) at which the rigid-rim model
    touches a rim, searched from ``start`` (:func:`.hinge_vs_impact.lowest_rung`);
    ``numerical``: a rung on the way went unstable, counted as a touch (instabilities start
    at contacts)."""
    a = np.asarray(motion.acceleration)
    per_sa = rigid.scale_factor(a, motion.dt, 1.0, period=bearing.design_period)
    unstable = False

    def touches(k):
        nonlocal unstable
        r = rigid.simulate(bearing, a * (k * 0.01 * G * per_sa), motion.dt,
                           duration=(a.size - 1) * motion.dt + 20.0, stop_at_failure=True,
                           stop_when_quiet=True, record_every=a.size, on_instability="report")
        unstable |= bool(r.numerical_failure)
        return bool(r.impacts) or bool(r.numerical_failure)

    return lowest_rung(touches, start), unstable


def governing_mode(yielding: dict) -> str:
    """What a rising SA meets first with yielding rims: the rim's hinge, its rupture, the loss
    of containment through the rim, or uplift over it ("none": nothing up to the top)."""
    found = [c for c in yielding.values() if c.sa is not None]
    if not found:
        return "none"
    first = min(found, key=lambda c: c.sa)
    rung = next(r for r in first.rungs if r.sa == first.sa)
    for state in ("hinge", "rupture"):
        if state in rung.limit_states:
            return state
    return "containment" if rung.failure_mode == "yielding" else "uplift"
