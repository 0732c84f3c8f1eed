"""One FE run of a scaled Ricker pulse, run to the limit state asked for (a task of the
yielding-rims study, :mod:`validation.studies.yielding_rims`). Kept apart from the study so
that its code alone, with the FE companion's, keys the stored runs: editing the study's rigid
side does not throw the FE runs away."""

from __future__ import annotations

import time

import numpy as np

from rigid import DFPBearing
from rigid.limit_states import renamed_limit_state

__all__ = ["fe_pulse_run"]


@renamed_limit_state("criterion")
def fe_pulse_run(bearing: dict, acceleration, dt: float, scale: float, *, mesh: str = "coarse",
                 max_step: float = 5e-3, impact_step: float = 5e-4,
                 kinematics: str = "finite", limit_state: str = "containment",
                 **_unused) -> dict:
    """FE run of ``scale · acceleration`` (a unit-amplitude pulse record [m/s²], sampled every
    ``dt`` [s]) from rest to the record's end or to ``limit_state`` (``criterion``: its
    deprecated name).

    ``bearing`` is ``dataclasses.asdict`` of a DFPBearing. Options as :func:`fem.simulate`
    (``mesh``: "coarse", :data:`fem.geometry.COARSE_MESH`, or "default"); the trimming
    options of :class:`validation.fem_search.FESettings` are accepted and unused (a pulse
    record is short and starts at rest).

    Returns
    -------
    dict
        ``failed``, ``failure_mode``, ``failure_time`` [s], ``numerical_failure``,
        ``detail``, ``limit_states`` (name → time [s] or None), ``end`` [s] simulated,
        ``max_rim_force`` [N], ``max_plastic_strain`` [-], ``steps``, ``cpu_seconds``,
        ``wall_seconds``.
    """
    from fem import simulate
    from fem.geometry import COARSE_MESH

    cpu0, wall0 = time.process_time(), time.perf_counter()
    res = simulate(DFPBearing(**bearing), scale * np.asarray(acceleration, dtype=float), dt,
                   mesh_options={"coarse": COARSE_MESH, "default": {}}[mesh],
                   max_step=max_step, impact_step=impact_step, kinematics=kinematics,
                   limit_state=limit_state)
    return {
        "failed": bool(res.failed), "failure_mode": res.failure_mode,
        "failure_time": res.failure_time, "numerical_failure": bool(res.numerical_failure),
        "detail": res.failure_detail, "limit_states": dict(res.limit_states),
        "end": float(res.time[-1]),
        "max_rim_force": float(res.rim_force.max()) if res.rim_force.size else 0.0,
        "max_plastic_strain": float(res.max_plastic_strain), "steps": int(res.steps),
        "cpu_seconds": time.process_time() - cpu0, "wall_seconds": time.perf_counter() - wall0,
    }
