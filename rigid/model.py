"""Rigid-body model of the DFP bearing: :func:`simulate` (paper §2; the equations are in
docs/theory/rigid-body.md), the kernel's parameters and the static state; the result classes
are in :mod:`rigid.results` (importable from here too)."""

from __future__ import annotations

import math
import warnings

import numpy as np

from . import _kernel as K
from .bearing import DFPBearing
from .inputs import check_model_input
from .limit_states import RIM_MODELS, check_limit_state, renamed_limit_state
from .results import EnergyBalance, Impact, NumericalInstabilityError, SimulationResult
from .units import G

#: Default largest internal step [s], the fine step near and at the rims; chosen by a step
#: study (docs/theory/rigid-body.md §Time steps, "Choice of the step sizes").
DEFAULT_MAX_STEP = 2e-5

#: Step far from the rims [s]: the kernel's coarse steps, with the contacts' stiffness in a
#: modified mass M + βh²K (Eqs. R35–R36), which removes the explicit stability limit of the
#: stiff contact modes and leaves the sliding motion resolved; chosen by a step study
#: (docs/theory/rigid-body.md §Time steps, "Choice of the step sizes").
FAR_STEP = 5e-4

RIM_NAMES = ("bottom -x", "bottom +x", "top -x", "top +x")
_FAILURE_DETAIL = {
    K.FAIL_BOTTOM_RIM: "a bottom vertex cleared a bottom rim",
    K.FAIL_TOP_RIM: "a top vertex cleared a top rim",
    K.FAIL_CENTROID: "the slider's centroid passed a rim",
    K.FAIL_OVERTURN: "the slider overturned (|θ| > 45°)",
    K.NUM_NAN: "the state became non-finite",
    K.NUM_PENETRATION: "a contact penetration exceeded the rim thickness",
    K.NUM_ENERGY: "the energy balance failed to close within 5 % of the input energy",
    K.NUM_JUMP: "a body moved further in one step than a quarter of the rim thickness",
    K.FAIL_HINGE: "a rim's root section became fully plastic (a hinge)",
    K.FAIL_RUPTURE: "a rim reached its rupture set",
    K.FAIL_THROUGH_BOTTOM: "a bottom vertex got through a bent bottom rim",
    K.FAIL_THROUGH_TOP: "a top vertex got through a bent top rim",
    K.FAIL_TORN_OFF: "a torn rim came off",
}
_YIELDING = (K.FAIL_HINGE, K.FAIL_RUPTURE, K.FAIL_THROUGH_BOTTOM, K.FAIL_THROUGH_TOP,
             K.FAIL_TORN_OFF)
_PHYSICAL = (K.FAIL_BOTTOM_RIM, K.FAIL_TOP_RIM, K.FAIL_CENTROID, K.FAIL_OVERTURN, *_YIELDING)
__all__ = ["DEFAULT_MAX_STEP", "FAR_STEP", "RIM_NAMES", "EnergyBalance", "Impact",
           "NumericalInstabilityError", "SimulationResult", "check_model_input", "simulate"]


def __getattr__(name):
    if name == "RIMS":  # the rim models, now rigid.limit_states.RIM_MODELS ("RIMS" also
        # named the four rims in fem)
        warnings.warn("rigid.model.RIMS is deprecated, use rigid.limit_states.RIM_MODELS",
                      DeprecationWarning, stacklevel=2)
        return RIM_MODELS
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def kernel_parameters(bearing: DFPBearing) -> np.ndarray:
    """Pack a bearing into the kernel's parameter vector (SI; geometry Eqs. R1–R14 of
    docs/theory/rigid-body.md)."""
    p = np.zeros(K.N_PARAMS)
    ms, m = bearing.slider_mass, bearing.supported_mass
    p[K.P_R] = bearing.radius
    p[K.P_HALF_B] = bearing.slider_diameter / 2
    p[K.P_HS] = bearing.slider_height
    p[K.P_HALF_HE] = bearing.edge_height / 2
    p[K.P_RIN] = bearing.rim_radius
    p[K.P_TR] = bearing.rim_thickness
    p[K.P_ZTOP] = bearing.rim_top
    p[K.P_K] = bearing.contact_stiffness
    p[K.P_XI] = bearing.damping_ratio
    p[K.P_MU] = bearing.friction
    p[K.P_MU_RIM] = bearing.rim_friction
    p[K.P_Y] = bearing.friction_yield_slip
    p[K.P_MS] = ms
    p[K.P_JS] = bearing.slider_inertia
    p[K.P_M] = m
    p[K.P_G] = G
    # m1·m2/(m1 + m2) of paper Eq. 3 for contacts with the bottom and with the top plate
    # (Eq. R19: why the supported mass by default)
    if bearing.impact_mass == "supported":
        p[K.P_MEFF_BOT], p[K.P_MEFF_TOP] = m + ms, m
    else:
        p[K.P_MEFF_BOT], p[K.P_MEFF_TOP] = ms, ms * m / (ms + m)
    # a penetration beyond the rim thickness means the contact geometry no longer holds
    p[K.P_DMAX] = bearing.rim_thickness
    # the coarse step needs the contacts near their static load (Eq. R34): twice the static
    # penetration
    p[K.P_DFAR] = 2.0 * _static_penetration((m + ms) * G, bearing)
    # ... and every vertex seated: at least a quarter of the smaller static penetration
    p[K.P_DNEAR] = 0.25 * _static_penetration(m * G, bearing)
    return p


def _static_penetration(load: float, bearing: DFPBearing) -> float:
    """Radial penetration δ of two vertices carrying ``load`` [N]: 2kδ^1.5·cos α = load
    (Eq. R38)."""
    r, half_b, k = bearing.radius, bearing.slider_diameter / 2, bearing.contact_stiffness
    delta = (load / (2 * k)) ** (2 / 3)
    for _ in range(20):  # fixed point; cos α changes by < 1e-6 between iterations
        cos_a = math.sqrt(1 - (half_b / (r + delta)) ** 2)
        delta = (load / (2 * k * cos_a)) ** (2 / 3)
    return delta


def static_state(bearing: DFPBearing) -> np.ndarray:
    """Exact static equilibrium under gravity: (x_S, z_S, θ, x_T, z_T) [m, m, rad, m, m]
    (Eq. R39)."""
    r, half_b = bearing.radius, bearing.slider_diameter / 2
    ms, m = bearing.slider_mass, bearing.supported_mass
    d_bot = _static_penetration((m + ms) * G, bearing)
    d_top = _static_penetration(m * G, bearing)
    z_vertex_bot = r - math.sqrt((r + d_bot) ** 2 - half_b**2)
    z_s = z_vertex_bot + bearing.edge_height / 2
    z_vertex_top = z_s + bearing.edge_height / 2
    z_centre_top = z_vertex_top - math.sqrt((r + d_top) ** 2 - half_b**2)
    z_t = z_centre_top - bearing.slider_height + r
    return np.array([0.0, z_s, 0.0, 0.0, z_t])


def explicit_step(bearing: DFPBearing) -> float:
    """Medium step [s] away from the rims while a contact is unsettled: 1.5/ω of the stiffest
    mode at rest, below the explicit stability limit (Eq. R37).

    Modes of the slider on its four vertex springs k_c = 1.5·k·√δ (linearised Hertz at the
    static penetration δ): vertical √(4k_c/m_s), rocking √(4k_c(b/2)²/J), and horizontal on
    the friction springs √(4·μ(W/2)/Y / m_s). Velocity Verlet is stable up to h·ω = 2 (the
    dampers are implicit and do not limit the step), so 1.5 leaves a 25 % margin, chosen by a
    step study (docs/theory/rigid-body.md §Time steps).
    """
    k_c = 1.5 * bearing.contact_stiffness * math.sqrt(bearing.static_penetration)
    ms = bearing.slider_mass
    omega = max(
        math.sqrt(4 * k_c / ms),
        math.sqrt(4 * k_c * (bearing.slider_diameter / 2) ** 2 / bearing.slider_inertia),
        math.sqrt(4 * bearing.friction * bearing.weight / 2 / bearing.friction_yield_slip / ms),
    )
    return 1.5 / omega


def reach_energy(bearing: DFPBearing) -> float:
    """Least gravitational energy for the slider to touch a rim [J] (Eq. R40).

    One surface at its capacity with the other centred lifts the supported mass by
    (R − h/2)(1 − cos φ_cap); sliding on both surfaces lifts it more.
    """
    arm = bearing.radius - bearing.slider_height / 2
    return bearing.supported_mass * G * arm * (1 - math.cos(bearing.capacity_tilt))


def internal_steps(dt: float, max_step: float, far_step: float = FAR_STEP,
                   coarse_factor: int | None = None) -> tuple[int, int]:
    """Fine steps per input sample and fine steps per coarse step, ``(n, m_c)``: the fine step
    dt/n is at most ``max_step`` [s], the coarse step m_c·dt/n at most ``far_step`` [s] (or
    ``coarse_factor`` fine steps), and m_c divides n, so that every input sample is covered
    by whole coarse steps (docs/theory/rigid-body.md, Eq. R34b). ``dt`` [s] is the record's
    sampling."""
    if coarse_factor:
        return coarse_factor * math.ceil(dt / (coarse_factor * max_step) - 1e-9), coarse_factor
    per_sample = math.ceil(dt / far_step - 1e-9)  # coarse steps per input sample
    coarse = math.ceil(dt / per_sample / max_step - 1e-9)
    return per_sample * coarse, coarse


@renamed_limit_state()
def simulate(
    bearing: DFPBearing,
    acceleration,
    dt: float,
    *,
    duration: float | None = None,
    max_step: float = DEFAULT_MAX_STEP,
    record_every: int = 1,
    stop_at_failure: bool = True,
    impact_merge_time: float = 0.05,
    max_impacts: int = 1000,
    on_instability: str = "raise",
    coarse_factor: int | None = None,
    stop_when_quiet: bool = False,
    rims: str = "rigid",
    limit_state: str | None = None,
    rim_law=None,
) -> SimulationResult:
    """Run the rigid-body DFP model on a horizontal ground acceleration.

    Parameters
    ----------
    bearing : DFPBearing
    acceleration : array_like [m/s²]
        Ground acceleration sampled every ``dt``; linear between samples.
    dt : float [s]
        Sampling interval of ``acceleration`` (and of the returned histories).
    duration : float [s], optional
        Simulated time; default the record's length. Beyond the record the ground is at rest.
    max_step : float [s]
        Largest internal step; the step used is dt/n with the smallest integer n that keeps
        it ≤ ``max_step``. Accuracy does not depend on ``dt``.
    record_every : int
        Keep every n-th sample of the histories (decimation; impacts, maxima and failure are
        found at every internal step regardless).
    stop_at_failure : bool
        Stop at physical failure (default). Otherwise go on until the end or instability.
    impact_merge_time : float [s]
        Contacts of a rim that reopen within this time of its last contact belong to the same
        impact (the light slider chatters against the rim on the ms scale).
    max_impacts : int
        Capacity of the impact list.
    on_instability : {"raise", "report", "refine"}
        What to do when the integration goes unstable (non-finite state, penetration beyond
        the rim thickness, or an energy balance off by more than 5 % of the input, Eq. R46):
        raise
        :class:`NumericalInstabilityError`; return a result with ``numerical_failure`` set
        (and a warning); or rerun with the step halved up to three times, then raise.
    coarse_factor : int, optional
        Far from the rims, with every vertex seated near its static load, the kernel takes
        this many internal steps at once (1 disables it); with a contact unsettled, the
        fewer steps of :func:`explicit_step`. Default: as many as make :data:`FAR_STEP` (25
        steps of 2e-5 s).
    stop_when_quiet : bool
        After the record ends, stop once the mechanical energy is below 95 % of what the
        supported mass needs to reach a rim: no later impact or failure is possible (Eqs.
        R40–R41). Impacts
        and failure are then exact, but histories and maximum displacement end early. For
        sweeps (impact spectra, critical SA).
    rims : {"rigid", "yielding"}
        Rims that cannot yield (the paper's model, default), or elastoplastic rims in series
        with the contacts, bending outward by a permanent set (docs/theory/rigid-body.md,
        "Yielding rims", Eqs. R55–R63).
    limit_state : {"hinge", "rupture", "containment"}, optional
        The limit state that defines ``failed`` and ends the run (with ``stop_at_failure``):
        a rim's hinge, its rupture, or the loss of containment, which is failure under any
        limit state (:func:`rigid.limit_states.check_limit_state`). Default "hinge" with
        yielding rims (as :func:`fem.simulate`); rigid rims have only "containment".
        (``failure_criterion``: deprecated name.)
    rim_law : rigid.rims.RimLaw
        The yielding rims' law, needed with ``rims="yielding"``: computed by the FE companion,
        ``fem.rim_law(bearing)`` (pushes of its rim, cached per rim geometry). Without it
        the law is still computed through ``fem`` with a DeprecationWarning (for one
        release); the rigid model itself never imports ``fem``.

    Returns
    -------
    SimulationResult
    """
    a, duration = check_model_input(bearing, acceleration, dt, duration)
    if not (math.isfinite(max_step) and max_step > 0):
        raise ValueError(f"max_step must be a positive number of seconds, got {max_step!r}")
    if int(record_every) != record_every or record_every < 1:
        raise ValueError(f"record_every must be a positive integer, got {record_every!r}")
    if on_instability not in ("raise", "report", "refine"):
        raise ValueError(
            f"on_instability must be 'raise', 'report' or 'refine', got {on_instability!r}"
        )
    if coarse_factor is not None and (int(coarse_factor) != coarse_factor or coarse_factor < 1):
        raise ValueError(f"coarse_factor must be a positive integer, got {coarse_factor!r}")
    if int(max_impacts) != max_impacts or max_impacts < 1:
        raise ValueError(f"max_impacts must be a positive integer, got {max_impacts!r}")
    if impact_merge_time < 0:
        raise ValueError(f"impact_merge_time must be ≥ 0 s, got {impact_merge_time!r}")
    limit_state = check_limit_state(limit_state, rims=rims)

    p = kernel_parameters(bearing)
    p[K.P_MERGE] = impact_merge_time
    law = np.zeros((1, 3))
    if rims == "yielding":
        law = _set_rim_parameters(p, bearing, limit_state, rim_law)
    n_samples = math.floor(duration / dt + 1e-9)
    hist = np.empty((n_samples + 1, K.N_CHANNELS))
    events = np.zeros((int(max_impacts), K.EVENT_FIELDS))
    summary = np.zeros(K.N_SUMMARY)
    quiet_energy = 0.95 * reach_energy(bearing) if stop_when_quiet else 0.0  # Eq. R41
    for attempt in range(4 if on_instability == "refine" else 1):
        n_sub, coarse = internal_steps(dt, max_step / 2**attempt, FAR_STEP / 2**attempt,
                                       coarse_factor)
        h = dt / n_sub
        medium = min(coarse, max(1, math.floor(explicit_step(bearing) / 2**attempt / h)))
        K.integrate(p, static_state(bearing), a, n_sub, h, n_samples * n_sub, medium, int(coarse),
                    quiet_energy, bool(stop_at_failure), hist, events, summary, law)
        if int(summary[K.S_STATUS]) != K.STATUS_NUMERICAL:
            break

    return _result(bearing, dt, record_every, on_instability, rims, limit_state, h, summary,
                   hist, events)


def _result(bearing, dt, record_every, on_instability, rims, limit_state, h, summary, hist,
            events) -> SimulationResult:
    """The run's :class:`SimulationResult` from the kernel's outputs (``summary``, histories
    ``hist``, impact ``events``; ``h`` [s]: the internal step of the last attempt): the
    verdict (a numerical failure raised, reported with a warning, as ``on_instability``
    says), the limit states (Eq. R62), the failure mode and the histories kept every
    ``record_every`` samples of ``dt`` [s]."""
    status = int(summary[K.S_STATUS])
    code = int(summary[K.S_FAIL_CODE])
    fail_time = float(summary[K.S_FAIL_TIME])
    numerical = status == K.STATUS_NUMERICAL
    if numerical:
        message = f"{_FAILURE_DETAIL[code]} at t = {fail_time:.4f} s (internal step {h:.3g} s)"
        if on_instability == "report":
            warnings.warn(message, RuntimeWarning, stacklevel=4)
    physical = (not numerical) and code in _PHYSICAL
    limit_states = _limit_states(summary, rims, physical, fail_time)
    mode = None
    if physical:
        mode = "yielding" if code in _YIELDING or (
            code == K.FAIL_CENTROID and limit_states["hinge"] is not None) else "uplift"
    n_rec = int(summary[K.S_N_REC])
    hs = hist[:n_rec:record_every]
    n_events = int(summary[K.S_N_EVENTS])
    impacts = tuple(
        Impact(float(e[0]), RIM_NAMES[int(e[1])], float(e[2]), float(e[3]), float(e[4]))
        for e in events[:n_events]
    )
    result = SimulationResult(
        time=np.arange(n_rec)[::record_every] * dt,
        displacement=hs[:, K.H_XT].copy(),
        top_plate_rise=hs[:, K.H_ZT].copy(),
        slider_displacement=hs[:, K.H_XS].copy(),
        slider_rise=hs[:, K.H_ZS].copy(),
        slider_rotation=hs[:, K.H_TH].copy(),
        velocity=hs[:, K.H_VT].copy(),
        base_shear=hs[:, K.H_SHEAR].copy(),
        rim_force=hs[:, K.H_RIMF].copy(),
        energy=EnergyBalance(*(hs[:, c].copy() for c in (
            K.H_EIN, K.H_EKIN, K.H_EPOT, K.H_EFRIC, K.H_EIMP, K.H_EPLAS))),
        impacts=impacts,
        failed=physical,
        failure_time=fail_time if (physical or numerical) else None,
        failure_mode=mode,
        failure_detail=_FAILURE_DETAIL.get(code) if code else None,
        numerical_failure=numerical,
        max_uplift=float(summary[K.S_MAX_UPLIFT]),
        max_rotation=float(summary[K.S_MAX_ROT]),
        max_penetration=float(summary[K.S_MAX_PEN]),
        max_rim_force=float(summary[K.S_MAX_RIMF]),
        internal_step=h,
        steps=int(summary[K.S_STEPS]),
        steps_taken=int(summary[K.S_TAKEN]),
        bearing=bearing,
        rims=rims,
        limit_state=limit_state,
        limit_states=limit_states,
        rim_sets=tuple(float(x) for x in summary[K.S_SET:K.S_SET + K.N_RIMS]),
        rim_set=hs[:, K.H_SET].copy(),
    )
    if numerical and on_instability != "report":
        raise NumericalInstabilityError(message, result)
    return result


def _set_rim_parameters(p, bearing: DFPBearing, limit_state: str, law) -> np.ndarray:
    """Put the yielding rims' parameters into the kernel's vector; their backbone table."""
    from .rims import resolve_rim_law

    law = resolve_rim_law(bearing, law, stacklevel=4)
    p[K.P_YIELDING] = 1.0
    p[K.P_HR] = bearing.rim_height
    p[K.P_KEL] = law.stiffness
    p[K.P_LEVER] = law.lever
    p[K.P_UP_HINGE] = law.hinge_set
    p[K.P_UP_RUPTURE] = law.rupture_set
    p[K.P_CORNER] = 1.0 if law.corner_height.size else 0.0
    p[K.P_UP_OFF] = law.off_set
    p[K.P_CRITERION] = {"containment": K.CRIT_CONTAINMENT, "hinge": K.CRIT_HINGE,
                        "rupture": K.CRIT_RUPTURE}[limit_state]
    return law.table


def _limit_states(summary, rims: str, physical: bool, fail_time: float) -> dict:
    """Limit state → time [s] first reached, or None (Eq. R62)."""
    if rims == "rigid":
        return {"hinge": None, "rupture": None,
                "containment": fail_time if physical else None}
    return {name: (None if summary[i] < 0 else float(summary[i]))
            for name, i in (("hinge", K.S_T_HINGE), ("rupture", K.S_T_RUPTURE),
                            ("containment", K.S_T_CONTAINMENT))}
