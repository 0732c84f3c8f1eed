"""The inputs both models share, checked before anything is allocated (a module of the
neutral base, docs/architecture.md): :func:`check_model_input`, called by
:func:`rigid.simulate` and :func:`fem.simulate`."""

from __future__ import annotations

import math

import numpy as np

from .bearing import DFPBearing

__all__ = ["check_model_input"]


def check_model_input(bearing, acceleration, dt, duration) -> tuple[np.ndarray, float]:
    """The inputs shared by the rigid and the FE model checked before anything is allocated:
    ``bearing`` a DFPBearing (TypeError) with a slider pressure [Pa] in
    :data:`rigid.limits.PRESSURE_RANGE`; the ground acceleration [m/s²] 1-D with at least two
    finite samples, none beyond :data:`rigid.limits.MAX_MODEL_ACCELERATION`; dt [s] positive;
    ``duration`` [s] (None: the record's length) positive, at most
    :data:`rigid.limits.MAX_MODEL_DURATION` and at most
    :data:`rigid.limits.MAX_MODEL_SAMPLES` samples of dt (ValueError naming what is wrong;
    the limits and their reasons are in docs/limits.md). Returns the acceleration as a
    contiguous float array and the duration."""
    from .limits import (
        MAX_MODEL_ACCELERATION,
        MAX_MODEL_DURATION,
        MAX_MODEL_SAMPLES,
        PRESSURE_RANGE,
        check_range,
    )

    if not isinstance(bearing, DFPBearing):
        raise TypeError(f"bearing must be a DFPBearing, got {type(bearing).__name__}")
    check_range("the slider pressure", bearing.pressure, *PRESSURE_RANGE, "Pa",
                why="what sliding bearings are designed for")
    a = np.asarray(acceleration, dtype=float)
    if a.ndim != 1:
        raise ValueError(f"acceleration must be one-dimensional, got shape {a.shape}")
    if a.size < 2:
        raise ValueError("acceleration must have at least two samples")
    if not np.all(np.isfinite(a)):
        bad = int(np.flatnonzero(~np.isfinite(a))[0])
        raise ValueError(f"acceleration has a non-finite value at sample {bad}")
    peak = int(np.argmax(np.abs(a)))
    check_range(f"the ground acceleration (sample {peak})", abs(a[peak]), None,
                MAX_MODEL_ACCELERATION, "m/s2",
                why="beyond it a response is numerical, not physical")
    if not (isinstance(dt, (int, float, np.floating)) and math.isfinite(dt) and dt > 0):
        raise ValueError(f"dt must be a positive number of seconds, got {dt!r}")
    duration = (a.size - 1) * dt if duration is None else float(duration)
    if not (math.isfinite(duration) and duration > 0):
        raise ValueError(f"duration must be a positive number of seconds, got {duration!r}")
    check_range("the simulated duration", duration, None, MAX_MODEL_DURATION, "s",
                why="the longest record and its free vibration")
    if duration / dt > MAX_MODEL_SAMPLES:
        raise ValueError(f"the simulation would keep {duration / dt:.3g} samples (duration "
                         f"{duration:g} s / dt {dt:g} s), more than {MAX_MODEL_SAMPLES:.0e}; "
                         "use a longer dt")
    return np.ascontiguousarray(a), duration
