r"""``fem.simulate``: the plane-strain FE model of a DFP bearing under horizontal ground motion —
mesh and system (:func:`fem.dfp.build_system`), gravity, then HHT-α (:mod:`fem.dynamics`) in the
frame of the ground, with the three limit states (the first rim hinge, rupture of a rim, loss of
containment; :mod:`fem.limit_states`) watched after every accepted step and one of them chosen
as failure (docs/theory/finite-elements.md, "Limit states"; what the model found:
docs/fe-companion.md). Same input conventions as :func:`rigid.simulate`."""

from __future__ import annotations

import time as _time
from collections.abc import Mapping
from dataclasses import dataclass, field, fields

import numpy as np

from rigid.bearing import DFPBearing
from rigid.limit_states import check_limit_state, deprecated_attribute, renamed_limit_state

from .limit_states import LIMIT_STATES, RIMS, LimitStates
from .observer import PLASTIC_STRAIN_LIMIT, Observer, rim_of_nodes

__all__ = ["LIMIT_STATES", "PLASTIC_STRAIN_LIMIT", "RIMS", "FEEnergy", "FEMResult", "simulate"]

#: With torn elements letting go, the accepted steps after a step Newton could not do during
#: which the step does not grow (:class:`fem.dynamics.StepControl`'s ``hold``; measured:
#: docs/theory/finite-elements.md, "Time steps").
TEARING_STEP_HOLD = 8


@dataclass(frozen=True)
class FEEnergy(Mapping):
    """Energy histories of an FE run [J] (3-D, i.e. times the depth), at the result's
    ``time``, zero at the start of the dynamic phase (docs/theory/finite-elements.md, Eqs.
    F29–F31). Read as attributes (``res.energy.kinetic``) or, as before, as a mapping
    (``res.energy["kinetic"]``, ``.items()``).

    Attributes
    ----------
    input, kinetic, strain, plastic, contact, friction : ndarray [J]
        Work of the ground motion, kinetic energy, elastic strain energy, plastic
        dissipation, the penalty springs' energy, friction work.
    fracture : ndarray [J]
        Strain and penalty energy released by torn rim elements as they let go (Eq. F69; 0
        without ``fracture``).
    loose_kinetic : ndarray [J]
        The part of ``kinetic`` in material that no element holds any more, falling free of
        the bearing (Eq. F69b; 0 without ``fracture``).
    residual : ndarray [J]
        input − all the others but ``loose_kinetic``: HHT's algorithmic dissipation plus the
        work sums' error.
    """

    input: np.ndarray
    kinetic: np.ndarray
    strain: np.ndarray
    plastic: np.ndarray
    contact: np.ndarray
    friction: np.ndarray
    fracture: np.ndarray
    loose_kinetic: np.ndarray
    residual: np.ndarray

    def __getitem__(self, key: str) -> np.ndarray:
        if key not in self._names():
            raise KeyError(key)
        return getattr(self, key)

    def __iter__(self):
        return iter(self._names())

    def __len__(self) -> int:
        return len(self._names())

    @classmethod
    def _names(cls) -> tuple[str, ...]:
        return tuple(f.name for f in fields(cls))


@dataclass(frozen=True)
class FEMResult:
    """Response of the FE model. Histories are at the accepted time steps (not uniform).

    Attributes
    ----------
    time : ndarray [s]
    displacement : ndarray [m]
        Horizontal displacement of the top plate (superstructure) relative to the bottom plate.
    top_plate_rise : ndarray [m]
        Vertical displacement of the superstructure from its static position.
    slider_displacement, slider_rise : ndarray [m]
        Slider centroid horizontal position and vertical displacement from its initial pose.
    slider_rotation : ndarray [rad]
        Counter-clockwise positive.
    base_shear : ndarray [N]
        Horizontal contact force of the slider on the bottom plate (3-D: times the depth).
    dish_force : ndarray, shape (nt, 2) [N]
        Total normal contact force on the bottom and top dish.
    rim_force : ndarray, shape (nt, 4) [N]
        Total normal contact force on each rim, in the order of :data:`RIMS`.
    rim_root_plastic_strain : ndarray, shape (nt, 4) [-]
        Largest equivalent plastic strain in each rim's root row.
    rim_root_yielded_fraction : ndarray, shape (nt, 4) [-]
        Fraction of the root row's quadrature points that have yielded (1 = hinge).
    rim_regularised_plastic_strain : ndarray, shape (nt, 4) [-]
        Largest equivalent plastic strain of each rim averaged over a gauge of the rim's
        thickness (the rupture measure, docs/theory/finite-elements.md, Eq. F52).
    max_plastic_strain : float [-]
        Largest equivalent plastic strain anywhere, at the end.
    hinge_times : dict
        Rim name → time [s] its root section became fully plastic (only rims that did).
    limit_states : dict
        ``"hinge"``, ``"rupture"``, ``"containment"`` → the time [s] the run first reached it,
        or None (not reached before the run ended; Eqs. F36, F51–F53).
    limit_state : {"hinge", "rupture", "containment"}
        The limit state that defines ``failed`` (containment is failure under any limit
        state); ``failure_criterion`` is its deprecated alias.
    kinematics : {"small", "finite"}
    energy : FEEnergy
        ``input``, ``kinetic``, ``strain``, ``plastic``, ``contact``, ``friction``,
        ``residual`` [J] (3-D, i.e. times the depth), at ``time``: attributes, or keys as a
        mapping.
    failed : bool
    failure_mode : {"yielding", "uplift", None}
        "yielding": the rim let go (a hinge or rupture first, or the slider passed a rim bent
        out of its way); "uplift": the slider climbed over a rim that held, or overturned.
    failure_time : float or None [s]
    failure_detail : str or None
    numerical_failure : bool
        The time integration could not continue, or the response left the model's range (a
        failure at the first step without motion, a rim's averaged plastic strain
        beyond :data:`PLASTIC_STRAIN_LIMIT`); the message is in ``failure_detail``.
    steps, newton_iterations, rejected_steps, dofs : int
    wall_time : float [s]
    depth : float [m]
        Out-of-plane depth of the plane-strain model (:func:`fem.dfp.out_of_plane_depth`).
    final_displacement : ndarray
        Full dof vector at the end (plates [m], then the slider's (X, Z, Θ) increments).
    final_plastic_strain : ndarray, shape (nelems, nqp) [-]
    final_stress : ndarray, shape (4, nelems, nqp) [Pa]
    snapshots : tuple
        ``(t, d_full, plastic_strain, stress)`` every ``snapshot_every`` steps (for movies).
    bearing : rigid.DFPBearing
    mesh : skfem.MeshQuad1
    edge_radius : float [m]
        Radius of the slider's rounded edges in the run (0: sharp).
    rim_damage : ndarray, shape (nt, 4) [-]
        With ``fracture``: the largest ductile damage of an element of each rim (Eq. F67);
        an empty array without.
    torn_elements : dict
        With ``fracture``: element → (time [s], rim) at which it tore, in that order (the
        crushed ones of Eq. F67b included).
    crushed_elements : dict
        With ``crush_jacobian``: element → (time [s], rim) of those crushed (Eq. F67b).
    retained : ndarray, shape (nelems,) [-] or None
        With ``fracture``: the fraction of its stiffness each element keeps at the end (0:
        eroded; Eq. F68).
    friction_carried_from : float or None [s]
        With rounded slider edges: when a step that failed at the smallest size was retried
        with the friction history carried across the edges (Eq. F16a); None: never.
    """

    time: np.ndarray
    displacement: np.ndarray
    top_plate_rise: np.ndarray
    slider_displacement: np.ndarray
    slider_rise: np.ndarray
    slider_rotation: np.ndarray
    base_shear: np.ndarray
    dish_force: np.ndarray
    rim_force: np.ndarray
    rim_root_plastic_strain: np.ndarray
    rim_root_yielded_fraction: np.ndarray
    rim_regularised_plastic_strain: np.ndarray
    max_plastic_strain: float
    hinge_times: dict
    limit_states: dict
    limit_state: str
    kinematics: str
    energy: FEEnergy
    failed: bool
    failure_mode: str | None
    failure_time: float | None
    failure_detail: str | None
    numerical_failure: bool
    steps: int
    newton_iterations: int
    rejected_steps: int
    dofs: int
    wall_time: float
    depth: float
    final_displacement: np.ndarray
    final_plastic_strain: np.ndarray
    final_stress: np.ndarray
    snapshots: tuple
    bearing: DFPBearing
    mesh: object = field(repr=False)
    edge_radius: float = 0.0
    rim_damage: np.ndarray = field(default_factory=lambda: np.zeros((0, 4)), repr=False)
    torn_elements: dict = field(default_factory=dict)
    crushed_elements: dict = field(default_factory=dict)
    retained: np.ndarray | None = field(default=None, repr=False)
    friction_carried_from: float | None = None

    failure_criterion = deprecated_attribute("failure_criterion")

    @property
    def max_displacement(self) -> float:
        """Largest |displacement| [m]."""
        return float(np.max(np.abs(self.displacement)))

    def summary(self) -> str:
        """One paragraph for the console."""
        head = (
            f"FE ({self.kinematics} kinematics): {self.steps} steps, {self.newton_iterations} "
            f"Newton iterations, {self.dofs} dofs, {self.wall_time:.1f} s; max displacement "
            f"{self.max_displacement:.3f} m; max plastic strain {self.max_plastic_strain:.4f}; "
            f"max rim force {self.rim_force.max() / 1e6:.2f} MN; limit states: "
            + ", ".join(f"{k} " + ("not reached" if t is None else f"at {t:.3f} s")
                        for k, t in self.limit_states.items())
        )
        if self.failed:
            return head + (
                f"\nFAILED by {self.failure_mode} at t = {self.failure_time:.3f} s: "
                f"{self.failure_detail}"
            )
        if self.numerical_failure:
            return head + f"\nNUMERICAL FAILURE: {self.failure_detail}"
        return head + "\nno failure"


@renamed_limit_state()
def simulate(
    bearing: DFPBearing,
    acceleration,
    dt: float,
    *,
    duration: float | None = None,
    mesh_options: dict | None = None,
    max_step: float = 5e-3,
    impact_step: float = 5e-4,
    alpha: float = -0.3,
    penalty_factor: float = 10.0,
    stop_at_failure: bool = True,
    snapshot_every: int = 0,
    limit_state: str = "hinge",
    vertex_contact: bool = False,
    plasticity: bool = True,
    kinematics: str = "finite",
    energy_tolerance: float = 1e-3,
    edge_radius: float = 0.0,
    rim_depth: float | None = None,
    fracture=None,
    erosion_steps: int = 10,
    crush_jacobian: float | None = None,
    cache_dir=None,
) -> FEMResult:
    """Run the plane-strain FE model of the DFP bearing on a horizontal ground acceleration.

    Parameters
    ----------
    bearing : rigid.DFPBearing
    acceleration : array_like [m/s²]
        Ground acceleration sampled every ``dt``; linear between samples, zero after the end.
    dt : float [s]
        Sampling interval of ``acceleration``.
    duration : float [s], optional
        Simulated time; default the record's length.
    mesh_options : dict, optional
        :func:`fem.geometry.build_mesh` sizes [m] (``rim_size``, ``contact_size``,
        ``coarse_size``, ``block_height``); default the generator's defaults.
    max_step : float [s]
        Time step while sliding freely.
    impact_step : float [s]
        Time step while a rim is in contact.
    alpha : float [-]
        HHT-α parameter, −1/3 ≤ α ≤ 0 (:class:`fem.dynamics.HHTParameters`).
    penalty_factor : float [-]
        ε_N = factor · E / h_contact.
    stop_at_failure : bool
        Stop at the first failure (default).
    snapshot_every : int
        Keep the full field every n accepted steps for movies (0: none).
    limit_state : {"hinge", "rupture", "containment"}
        The limit state that ends the run (with ``stop_at_failure``) and defines ``failed``:
        the first rim hinge, the rupture of a rim, or the loss of containment (the slider got
        past a rim or overturned), which is failure under any limit state (checked by
        :func:`rigid.limit_states.check_limit_state`; ``failure_criterion``: its deprecated
        name). All three are
        recorded in ``limit_states`` as far as the run goes (docs/theory/finite-elements.md,
        "Limit states").
    vertex_contact : bool
        Make the slider's vertices contact points against the rims
        (docs/theory/finite-elements.md, Eq. F20; why it is off by default:
        docs/fe-companion.md, "Slider vertices").
    kinematics : {"finite", "small"}
        Finite deformation of the plates and rims (large rotations and strains; default), or
        small strain (:func:`fem.dfp.build_system`; docs/theory/finite-elements.md, "Finite
        deformation").
    plasticity : bool
        False keeps the steel linear elastic: rims that cannot yield, as in the rigid model
        (what that gives: docs/fe-companion.md, "Rims that cannot yield: uplift").
    energy_tolerance : float [-]
        Largest change of the energy-balance residual in one step, as a fraction of W·h_r
        (the work of lifting the supported weight W over the rim height h_r); a step that
        exceeds it is redone at half the size, down to impact_step/8
        (:class:`fem.dynamics.StepControl`). ``math.inf``: no energy control. The default
        suits runs that end in yielding; for runs that end in uplift use 1e-4 (the
        measurements behind this advice: docs/fe-companion.md, "Numerical settings").
    edge_radius : float [m]
        Radius of the slider's rounded edges, smaller than half the height of its flat sides
        (0: sharp edges, the rigid model's slider; what rounding changes: docs/fe-companion.md,
        "Rounded slider edges").
    rim_depth : float [m], optional
        Out-of-plane depth of the rims' steel instead of the model's πb/4: the 3-D rim's
        effective depth at the limit state checked (:func:`fem.effective_rim_depth`; Eq.
        F59).
    fracture : {"steep", "median", "mild"} or fem.fracture.StressModifiedStrain, optional
        Let the rims tear: ductile damage along the strain path with a critical strain that
        falls with the stress triaxiality (docs/theory/finite-elements.md, "Rim fracture",
        Eqs. F62–F69; the named sets: :data:`fem.fracture.FRACTURE_SETS`, anchored at the
        bearing's ``rupture_strain``). Rupture is then the first torn element, and torn
        elements let go. Default None: the uniaxial rupture of Eq. F51, nothing tears.
    erosion_steps : int
        With ``fracture``: the accepted steps over which a torn element lets go of its
        stress and stiffness (Eq. F68); 0 tracks the damage and tears nothing. Needs
        ``kinematics="finite"`` when positive.
    crush_jacobian : float [-], optional
        With ``fracture``: a rim element whose det F at a point falls below this (in (0, 1))
        is crushed, and lets go as a torn one (Eq. F67b), and the faces that the elements
        letting go uncover carry contact (Eq. F68c); default None: nothing is crushed, and a
        torn rim's inside is no contact surface.
    cache_dir : path-like, optional
        Mesh cache directory.

    Returns
    -------
    FEMResult
    """
    from rigid.inputs import check_model_input

    from .dfp import build_system
    from .dynamics import HHTParameters, Integrator, StepControl

    a, duration = check_model_input(bearing, acceleration, dt, duration)
    record_end = (a.size - 1) * dt
    limit_state = check_limit_state(limit_state)
    if not (0 < impact_step <= max_step):
        raise ValueError("need 0 < impact_step ≤ max_step")
    t_grid = np.arange(a.size) * dt

    def ground(t: float) -> float:
        return float(np.interp(t, t_grid, a, right=0.0)) if t <= record_end else 0.0

    wall0 = _time.perf_counter()
    model = build_system(
        bearing, mesh_options=mesh_options, penalty_factor=penalty_factor,
        vertex_contact=vertex_contact, plasticity=plasticity, kinematics=kinematics,
        edge_radius=edge_radius, rim_depth=rim_depth, cache_dir=cache_dir,
        uncovered_rims=crush_jacobian is not None,
    )
    red, depth = model.reduction, model.depth
    rim_of = rim_of_nodes(model)
    rim_mask = rim_of >= 0
    tearing = _rim_fracture(fracture, erosion_steps, bearing, model, kinematics,
                            crush_jacobian)
    watch = LimitStates(bearing, model, fracture=tearing)
    observer = Observer(
        model=model, rim_of=rim_of, watch=watch, limit_state=limit_state,
        stop_at_failure=stop_at_failure, snapshot_every=snapshot_every, first_step=max_step,
        top_rows=red.P.getcol(model.top_x).nonzero()[0],
        top_z_rows=red.P.getcol(model.top_z).nonzero()[0],
    )

    integ = Integrator(
        model, ground, hht=HHTParameters(alpha),
        control=StepControl(
            max_step=max_step, impact_step=impact_step,
            energy_tol=energy_tolerance * bearing.weight / depth * bearing.rim_height,
            hold=TEARING_STEP_HOLD if tearing is not None and tearing.steps else 0,
        ),
        rim_mask=rim_mask, fracture=tearing,
    )
    out = integ.run(duration, observer)
    return _result(bearing, model, integ, out, observer, limit_state=limit_state,
                   kinematics=kinematics, edge_radius=edge_radius, wall0=wall0)


def _rim_fracture(fracture, erosion_steps, bearing, model, kinematics, crush_jacobian=None):
    """The :class:`fem.fracture.RimFracture` of a run, or None without ``fracture``."""
    from .fracture import RimFracture, criterion_of

    if fracture is None:
        if crush_jacobian is not None:
            raise ValueError("crush_jacobian needs fracture")
        return None
    fracture = criterion_of(fracture, bearing.rupture_strain)
    if erosion_steps and kinematics != "finite":
        raise ValueError("torn elements let go only with kinematics='finite' (or pass "
                         "erosion_steps=0 to track the damage alone)")
    if crush_jacobian is not None and kinematics != "finite":
        raise ValueError("crush_jacobian needs kinematics='finite' (det F)")
    return RimFracture(fracture, model.system.fe, model.mesh, bearing.rim_thickness,
                       steps=erosion_steps, crush_jacobian=crush_jacobian)


def _result(bearing, model, integ, out, observer, *, limit_state, kinematics, edge_radius,
            wall0) -> FEMResult:
    """The run's :class:`FEMResult` from the integrator's outcome (``out``,
    :class:`fem.dynamics.RunResult`) and what the observer recorded: histories, verdict
    (failed, numerical, or neither), final fields, cost (``wall0``: the start's
    ``perf_counter`` [s])."""
    sysm, red, mesh, depth = model.system, model.reduction, model.mesh, model.depth
    watch = observer.watch
    state = out.state
    d_final = red.expand(out.d)
    ev = sysm.evaluate(d_final, state)
    h = observer.history.arrays()
    verdict = observer.verdict
    numerical = verdict.numerical is not None or (bool(out.failed_numerically)
                                                  and not verdict.reached)
    failed = verdict.time is not None and not numerical
    message = verdict.numerical or out.message or None
    return FEMResult(
        time=h.t,
        displacement=h.x,
        top_plate_rise=h.z,
        slider_displacement=h.xs,
        slider_rise=h.zs,
        slider_rotation=h.th,
        base_shear=h.shear,
        dish_force=h.dish,
        rim_force=h.rim,
        rim_root_plastic_strain=h.root_p,
        rim_root_yielded_fraction=h.root_frac,
        rim_regularised_plastic_strain=h.regular,
        max_plastic_strain=float(state.material.eq_plastic_strain.max()),
        hinge_times=dict(watch.hinge_times),
        limit_states=dict(watch.times),
        limit_state=limit_state,
        kinematics=kinematics,
        energy=FEEnergy(**{k: v * depth for k, v in out.energy.items()}),
        failed=failed,
        failure_mode=verdict.mode if failed else None,
        failure_time=verdict.time if failed else None,
        failure_detail=verdict.detail if failed else message,
        numerical_failure=numerical,
        steps=integ.steps,
        newton_iterations=integ.newton_iterations,
        rejected_steps=integ.rejected,
        dofs=red.nreduced,
        wall_time=_time.perf_counter() - wall0,
        depth=depth,
        final_displacement=d_final,
        final_plastic_strain=state.material.eq_plastic_strain,
        final_stress=ev.material.stress,
        snapshots=tuple(observer.snapshots),
        bearing=bearing,
        mesh=mesh,
        edge_radius=edge_radius,
        rim_damage=h.damage if h.damage.size else np.zeros((0, 4)),
        torn_elements=dict(watch.fracture.torn) if watch.fracture is not None else {},
        crushed_elements=dict(watch.fracture.crushed) if watch.fracture is not None else {},
        retained=None if watch.fracture is None else watch.fracture.retained.copy(),
        friction_carried_from=out.friction_carried_from,
    )
