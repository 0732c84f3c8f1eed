"""One FE run of a scaled record for the FE critical-SA search: the record trimmed to what can
matter (:mod:`rigid.collapse.trimming`), the FE model run up to a guessed quiet time, and run
again to the end if the energy left there could still reach a rim (the end argument:
docs/theory/collapse.md, "Trimming", Eqs. C13–C15)."""

from __future__ import annotations

import time

import numpy as np

from fem.geometry import COARSE_MESH
from rigid import DFPBearing, G
from rigid.collapse.trimming import QUIET_FRACTION, quiet_after, trimmed_window
from rigid.limit_states import LIMIT_STATES, renamed_limit_state
from rigid.model import reach_energy
from rigid.model import simulate as rigid_simulate

__all__ = ["MESHES", "fem_mechanical_energy", "fem_run"]

#: FE mesh sizes [m] (:func:`fem.geometry.build_mesh`): ``coarse`` is
#: :data:`fem.geometry.COARSE_MESH` (several times cheaper per Newton iteration than the
#: default; BENCHMARKS.md, "FE model").
MESHES = {
    "coarse": COARSE_MESH,
    "default": {},
}


def fem_mechanical_energy(result) -> np.ndarray:
    """Mechanical energy of an FE run [J]: kinetic + elastic (steel and penalty springs) +
    gravitational (supported mass and slider, from their rise). The kinetic energy of torn-off
    material falling free of the bearing is part of it; the quiet test (docs/theory/
    collapse.md, Eq. C15) leaves that out (Eq. F69b of docs/theory/finite-elements.md)."""
    b = result.bearing
    e = result.energy
    return (e["kinetic"] + e["strain"] + e["contact"]
            + b.supported_mass * G * result.top_plate_rise
            + b.slider_mass * G * result.slider_rise)


def _duration_guess(bearing, a, dt, window, total, margin) -> float:
    """Seconds to simulate from the window's start: the rigid model's quiet time after the
    window's end on the same input, plus ``margin``; at most the rest of the record + free."""
    t_end = (window.end - window.start) * dt
    r = rigid_simulate(bearing, a[window.start:], dt, duration=total, stop_at_failure=True,
                 on_instability="report")
    e = r.energy.kinetic + r.energy.potential
    q = quiet_after(e, r.time, t_end, QUIET_FRACTION * reach_energy(bearing))
    guess = (t_end if q is None or r.failed else q) + margin
    return min(total, max(guess, t_end + margin))


@renamed_limit_state("criterion")
def fem_run(bearing: dict, acceleration, dt: float, scale: float, *, mesh: str = "coarse",
            max_step: float = 5e-3, impact_step: float = 5e-4, trim: str = "end",
            free: float = 20.0, lead: float = 0.1, margin: float = 1.0,
            kinematics: str = "finite", limit_state: str = "hinge",
            rim_depth: float | None = None, fracture: str | None = None,
            edge_radius: float = 0.0, crush_jacobian: float | None = None,
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
    kinematics : {"finite", "small"}
        :func:`fem.simulate`'s kinematics.
    limit_state : {"hinge", "rupture", "containment"}
        The limit state that ends the run (:func:`fem.simulate`'s); the earlier ones are
        recorded on the way (``limit_states``). ``criterion``: its deprecated name.
    lead, margin : float [s]
        Start this long before the first strong sample; simulate this long beyond the guessed
        quiet time.
    rim_depth : float [m], optional
        :func:`fem.simulate`'s out-of-plane depth of the rims (default the model's πb/4).
    fracture : {"steep", "median", "mild"}, optional
        :func:`fem.simulate`'s ductile fracture of the rims: torn elements let go and the
        rupture is the first tear (default none: the rupture is the gauge strain reaching
        the rupture strain, and the steel never tears).
    edge_radius : float [m]
        :func:`fem.simulate`'s rounded slider edges (default 0: sharp).
    crush_jacobian : float [-], optional
        With ``fracture``: :func:`fem.simulate`'s crushing of rim elements (Eq. F67b; default
        none).
    simulate : callable, optional
        Stand-in for :func:`fem.simulate` (tests).

    Returns
    -------
    dict
        ``failed``, ``failure_mode``, ``failure_time`` [s from the record's start],
        ``numerical_failure``, ``detail``, ``limit_states`` (name → time [s from the record's
        start] or None, as far as the run went), ``kinematics``, ``limit_state``, ``start``,
        ``strong_end``, ``end`` [s] (what was simulated), ``energy_end`` (the mechanical
        energy at the end, torn-off pieces included), ``reach_energy``
        [J], ``quiet`` (energy below the bound at the end, the pieces left out: the verdict
        is final), ``runs``
        (1, or 2 when the guessed end was not quiet), ``steps``, ``newton_iterations``,
        ``dofs``, ``max_plastic_strain``,
        ``max_rim_force`` [N], ``cpu_seconds``, ``wall_seconds``; with ``fracture`` also
        ``torn_elements`` (how many tore) and ``fracture_energy`` [J] (the energy they
        released); with ``crush_jacobian`` also ``crushed_elements`` (how many of those were
        crushed); ``friction_carried_from`` [s from the record's start] if a step was retried
        with the friction carried across the slider's rounded edges (Eq. F16a).
    """

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
           "numerical_failure": False, "detail": None,
           "limit_states": dict.fromkeys(LIMIT_STATES), "kinematics": kinematics,
           "limit_state": limit_state, "start": None, "strong_end": None,
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
    options = {"rim_depth": rim_depth, "fracture": fracture, "edge_radius": edge_radius,
               "crush_jacobian": crush_jacobian}
    options = {k: v for k, v in options.items() if v}  # what is set: the model's defaults
    for duration in dict.fromkeys(durations):  # the guess, then (if needed) the whole rest
        res = simulate(b, a[window.start:], dt, duration=duration,
                       mesh_options=MESHES[mesh], max_step=max_step, impact_step=impact_step,
                       kinematics=kinematics, limit_state=limit_state, **options)
        energy = fem_mechanical_energy(res)
        out.update(
            failed=bool(res.failed), failure_mode=res.failure_mode,
            failure_time=None if res.failure_time is None else t0 + res.failure_time,
            numerical_failure=bool(res.numerical_failure), detail=res.failure_detail,
            limit_states={k: None if v is None else t0 + v
                          for k, v in res.limit_states.items()},
            start=t0, strong_end=window.end * dt, end=t0 + float(res.time[-1]),
            energy_end=float(energy[-1]), runs=out["runs"] + 1,
            steps=out["steps"] + res.steps,
            newton_iterations=out["newton_iterations"] + res.newton_iterations,
            dofs=res.dofs, max_plastic_strain=float(res.max_plastic_strain),
            max_rim_force=float(res.rim_force.max()) if res.rim_force.size else 0.0,
        )
        if fracture:  # the last run's, as the verdict
            out.update(torn_elements=len(res.torn_elements),
                       fracture_energy=float(res.energy["fracture"][-1]))
        if crush_jacobian:
            out["crushed_elements"] = len(res.crushed_elements)
        if res.friction_carried_from is not None:  # only then, as the runs stored before it
            out["friction_carried_from"] = t0 + res.friction_carried_from
        # Eq. C15, on what can still move the bearing: less the falling pieces (Eq. F69b)
        out["quiet"] = bool(energy[-1] - res.energy["loose_kinetic"][-1] < QUIET_FRACTION * reach)
        if res.failed or res.numerical_failure or out["quiet"]:
            break
    if res.failed or res.numerical_failure:
        out["quiet"] = True  # the verdict is final
    out["cpu_seconds"] = time.process_time() - cpu0
    out["wall_seconds"] = time.perf_counter() - wall0
    return out
