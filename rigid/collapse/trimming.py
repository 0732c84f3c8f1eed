"""Trimming a scaled record to the part of it that can matter for failure, and the check of that
trimming with the rigid model.

Before the first sample with |a_g| ≥ a* (:func:`sliding_threshold`) the bearing cannot start to
slide, and after the last one the ground cannot add mechanical energy, so once that energy is
below what reaches a rim no impact, hence no failure, can follow (the argument and its limits:
``docs/theory/collapse.md``, "Trimming"). The FE runs of the validation use the end trimming;
:func:`trimmed_outcome` and :func:`critical_sa_trimmed` apply the same procedure to the rigid
model, whose untrimmed answer is cheap, to check it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from types import SimpleNamespace

import numpy as np

from ..bearing import DFPBearing
from ..units import G

__all__ = ["QUIET_FRACTION", "TRIMS", "Window", "critical_sa_trimmed", "quiet_after",
           "sliding_threshold", "strong_motion_window", "trimmed_outcome", "trimmed_window"]

#: Stop once the mechanical energy is below this fraction of the reach energy (the rigid
#: model's ``stop_when_quiet`` margin; Eq. C15, docs/theory/rigid-body.md Eq. R41).
QUIET_FRACTION = 0.95


def sliding_threshold(bearing: DFPBearing) -> float:
    """a* = μ·g·cos φ_cap·M/(M + m_s) [m/s²]: below it the bearing cannot start to slide, and
    while it slides the ground cannot add mechanical energy (docs/theory/collapse.md,
    Eqs. C13–C14)."""
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
    """Where a scaled record can move the bearing (docs/theory/collapse.md, "Trimming": the
    start and the end arguments).

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
    window's end (default; docs/theory/collapse.md, "Trimming", says why the start is kept),
    ``"window"``
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


def quiet_after(energy: np.ndarray, time: np.ndarray, t_from: float, bound: float):
    """First time [s] ≥ t_from with energy [J] < bound [J], or None."""
    ok = np.flatnonzero((time >= t_from - 1e-9) & (energy < bound))
    return None if ok.size == 0 else float(time[ok[0]])


def trimmed_outcome(bearing: DFPBearing, acceleration, dt: float, scale: float, *,
                  trim: str = "end", free: float = 20.0, lead: float = 0.1) -> dict:
    """The rigid model's verdict at one scale, with the FE runs' trimming (to verify it).

    With ``trim`` "end" or "window" (:func:`trimmed_window`) the run starts at rest at the
    window's start and its verdict is the one at the first time after the window's end at
    which the mechanical energy (kinetic + potential) is below ``QUIET_FRACTION`` × the reach
    energy (Eq. C15); ``late_impacts`` counts rim impacts after that time (the end argument
    says there are none; the run is continued to the record's end, and after it until quiet,
    to check it). With "none": the whole record plus up to ``free`` seconds, as
    :func:`rigid.critical_sa` runs it.

    Returns
    -------
    dict
        ``failed``, ``failure_time`` [s from the record's start], ``impacts``,
        ``max_impact_velocity`` [m/s], ``late_impacts``, ``late_failure``, ``start``, ``stop``
        [s] (the trimmed run's start and verdict time).
    """
    from ..model import reach_energy, simulate

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
        q = quiet_after(e, r.time, (window.end - window.start) * dt,
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


def critical_sa_trimmed(bearing: DFPBearing, motion, step: float = 0.01 * G, *,
                              stop: float = 3.0 * G, search: str = "fast", coarse: int = 10,
                              refine_ratio: float = 0.8, free: float = 20.0,
                              trim: str = "end", lead: float = 0.1) -> dict:
    """Critical SA of the rigid model with every rung trimmed (:func:`trimmed_outcome`), by the
    same ladder search as :func:`rigid.critical_sa` (whose ``search="fast"`` logic it reuses),
    to compare with the untrimmed result.

    Returns
    -------
    dict
        ``sa`` [m/s²] or None, ``rungs`` {rung index: :func:`trimmed_outcome` dict}.
    """
    from .ladder import record_ladder
    from .search import fast_search

    acc = np.asarray(motion.acceleration, dtype=float)
    record_sa, n_rungs = record_ladder(acc, motion.dt, bearing.design_period, 0.05,
                                       motion.name, step, step, stop)
    done, outcomes = {}, {}

    def rung(j):
        if j not in done:
            out = trimmed_outcome(bearing, acc, motion.dt, (step + j * step) / record_sa,
                                trim=trim, free=free, lead=lead)
            outcomes[j] = out
            done[j] = SimpleNamespace(failed=out["failed"],
                                      max_impact_velocity=out["max_impact_velocity"])
        return done[j]

    if search == "full":
        first = next((j for j in range(n_rungs) if rung(j).failed), None)
    else:
        first = fast_search(rung, done, n_rungs, int(coarse), float(refine_ratio))
    return {"sa": None if first is None else step + first * step,
            "rungs": dict(sorted(outcomes.items()))}
