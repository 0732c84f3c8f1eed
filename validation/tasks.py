"""Task functions sent to workers: module-level, plain arguments in, JSON-ready dicts out."""

from __future__ import annotations

import dataclasses

import numpy as np


def rigid_run(bearing: dict, acceleration, dt: float, scale: float) -> dict:
    """The rigid model on ``scale × acceleration``: outcome and peak response.

    Parameters
    ----------
    bearing : dict
        ``dataclasses.asdict(DFPBearing)``.
    acceleration : array_like [m/s²]
    dt : float [s]
    scale : float [-]

    Returns
    -------
    dict with failed, failure_time [s], max_impact_velocity [m/s], impacts, max_uplift [m].
    """
    from rigid import DFPBearing, simulate

    result = simulate(DFPBearing(**bearing), scale * np.asarray(acceleration, dtype=float), dt,
                      stop_when_quiet=True, on_instability="refine", record_every=50)
    return {
        "failed": result.failed,
        "failure_time": result.failure_time,
        "max_impact_velocity": result.max_impact_velocity,
        "impacts": len(result.impacts),
        "max_uplift": result.max_uplift,
    }


def bearing_dict(bearing) -> dict:
    """A bearing as plain data for :func:`rigid_run`."""
    return dataclasses.asdict(bearing)
