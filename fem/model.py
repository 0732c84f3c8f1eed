r"""``fem.simulate``: the plane-strain FE model of a DFP bearing under horizontal ground motion.

Same input conventions as :func:`rigid.simulate` (a ground acceleration sampled every ``dt``,
linear in between, at rest beyond the record). Steps: mesh and system
(:func:`fem.dfp.build_system`), gravity (static), then HHT-α (:mod:`fem.dynamics`) in the frame
of the ground, with the failure checks below after every accepted step.

* **plastic hinge** — every quadrature point of a rim's first element row above its root,
  across the whole rim thickness, has yielded: the root section has reached its plastic
  capacity and the rim turns into a mechanism. Hinge times are recorded for every rim.
* **escape** — a bottom (top) vertex of the slider lies beyond the *deformed* inner top corner
  of a bottom (top) rim, horizontally outside it and vertically past it; or its centroid passes
  a rim's inner face; or it overturns (|Θ| > 45°): the rigid model's criteria on deformed rims.

``failure_criterion`` picks which of them ends the run and how ``failure_mode`` is labelled
(yielding: the rim let go; uplift: the slider climbed over a rim that held). The definitions
and why they were chosen are in ``docs/theory/finite-elements.md`` ("Failure"); what the
model found with them (yielding against uplift, the rims' strength, vertex contact) is in
``docs/fe-companion.md``.
"""

from __future__ import annotations

import math
import time as _time
from dataclasses import dataclass, field

import numpy as np

from rigid.bearing import DFPBearing

RIMS = ("bottom -x", "bottom +x", "top -x", "top +x")


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
    max_plastic_strain : float [-]
        Largest equivalent plastic strain anywhere, at the end.
    hinge_times : dict
        Rim name → time [s] its root section became fully plastic (only rims that did).
    energy : dict of ndarray [J]
        ``input``, ``kinetic``, ``strain``, ``plastic``, ``contact``, ``friction``,
        ``residual`` (3-D, i.e. times the depth), at ``time``.
    failed : bool
    failure_mode : {"yielding", "uplift", None}
    failure_time : float or None [s]
    failure_detail : str or None
    numerical_failure : bool
        The time integration could not continue (message in ``failure_detail``).
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
    max_plastic_strain: float
    hinge_times: dict
    energy: dict
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

    @property
    def max_displacement(self) -> float:
        """Largest |displacement| [m]."""
        return float(np.max(np.abs(self.displacement)))

    def summary(self) -> str:
        """One paragraph for the console."""
        head = (
            f"FE: {self.steps} steps, {self.newton_iterations} Newton iterations, "
            f"{self.dofs} dofs, {self.wall_time:.1f} s; max displacement "
            f"{self.max_displacement:.3f} m; max plastic strain {self.max_plastic_strain:.4f}; "
            f"max rim force {self.rim_force.max() / 1e6:.2f} MN"
        )
        if self.failed:
            return head + (
                f"\nFAILED by {self.failure_mode} at t = {self.failure_time:.3f} s: "
                f"{self.failure_detail}"
            )
        if self.numerical_failure:
            return head + f"\nNUMERICAL FAILURE: {self.failure_detail}"
        return head + "\nno failure"


def _corner_nodes(mesh, bearing: DFPBearing) -> dict:
    """Mesh vertices at the rims' inner top corners, per rim."""
    r_in, z_t = bearing.rim_radius, bearing.rim_top
    h = bearing.slider_height
    targets = {
        "bottom -x": (-r_in, z_t),
        "bottom +x": (r_in, z_t),
        "top -x": (-r_in, h - z_t),
        "top +x": (r_in, h - z_t),
    }
    return {k: int(np.argmin(np.hypot(mesh.p[0] - x, mesh.p[1] - z))) for k, (x, z) in
            targets.items()}


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
    failure_criterion: str = "hinge",
    vertex_contact: bool = False,
    plasticity: bool = True,
    kinematics: str = "small",
    energy_tolerance: float = 1e-3,
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
    failure_criterion : {"hinge", "escape"}
        ``"hinge"``: failure by yielding as soon as a rim root is fully plastic (module
        docstring). ``"escape"``: only the slider's escape is failure, labelled "yielding" if it
        passed a hinged rim that was pushed out of its way, "uplift" if it climbed over (see
        the module docstring and docs/theory/finite-elements.md, Eqs. F36–F38; hinge times are
        still recorded).
    vertex_contact : bool
        Make the slider's vertices contact points against the rims
        (docs/theory/finite-elements.md, Eq. F20; why it is off by default:
        docs/fe-companion.md, "Slider vertices").
    kinematics : {"small", "finite"}
        Small strain, or finite deformation of the plates and rims (large rotations and
        strains; :func:`fem.dfp.build_system`).
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
    cache_dir : path-like, optional
        Mesh cache directory.

    Returns
    -------
    FEMResult
    """
    from rigid.model import check_model_input

    from .dfp import build_system
    from .dynamics import HHTParameters, Integrator, StepControl

    a, duration = check_model_input(bearing, acceleration, dt, duration)
    record_end = (a.size - 1) * dt
    if failure_criterion not in ("hinge", "escape"):
        raise ValueError(
            f"failure_criterion must be 'hinge' or 'escape', got {failure_criterion!r}"
        )
    if not (0 < impact_step <= max_step):
        raise ValueError("need 0 < impact_step ≤ max_step")
    t_grid = np.arange(a.size) * dt

    def ground(t: float) -> float:
        return float(np.interp(t, t_grid, a, right=0.0)) if t <= record_end else 0.0

    wall0 = _time.perf_counter()
    model = build_system(
        bearing, mesh_options=mesh_options, penalty_factor=penalty_factor,
        vertex_contact=vertex_contact, plasticity=plasticity, kinematics=kinematics,
        cache_dir=cache_dir,
    )
    sysm, red, mesh = model.system, model.reduction, model.mesh
    depth = model.depth
    nodes = sysm.nodes
    # slave nodes per rim (inner face and top), for forces and the impact step control
    rim_of = np.full(len(nodes), -1)
    for plate in ("bottom", "top"):
        on_rim = np.unique(
            np.concatenate(
                [mesh.facets[:, mesh.boundaries[f"{plate}_{k}"]].ravel()
                 for k in ("rim_inner", "rim_top")]
            )
        )
        mask = np.isin(nodes.nodes, on_rim)
        side = mesh.p[0, nodes.nodes] > 0
        base = 0 if plate == "bottom" else 2
        rim_of[mask & ~side] = base
        rim_of[mask & side] = base + 1
    rim_mask = rim_of >= 0
    corners = _corner_nodes(mesh, bearing)
    nd = sysm.fe.basis.nodal_dofs
    top_rows = red.P.getcol(model.top_x).nonzero()[0]
    top_z_rows = red.P.getcol(model.top_z).nonzero()[0]
    roots = [model.rim_roots[k] for k in RIMS]
    vertices = sysm.shape.vertices

    hist: dict[str, list] = {k: [] for k in (
        "t", "x", "z", "xs", "zs", "th", "shear", "dish", "rim", "root_p", "root_frac")}
    snaps = []
    failure: dict = {}
    hinges: dict = {}
    z_top0 = [None]

    def observer(t, d, ev, state) -> bool:
        pose = sysm.slider_pose(d)
        con = ev.contact
        p = state.material.eq_plastic_strain
        hist["t"].append(t)
        hist["x"].append(float(d[top_rows].mean()))
        zt = float(d[top_z_rows].mean())
        if z_top0[0] is None:
            z_top0[0] = zt
        hist["z"].append(zt - z_top0[0])
        hist["xs"].append(pose[0])
        hist["zs"].append(pose[1] - sysm.pose[1])
        hist["th"].append(pose[2])
        bottom = nodes.plate == 0
        hist["shear"].append(float(con.node_force[0, bottom].sum()) * depth)
        hist["dish"].append(
            [float(con.normal[(nodes.plate == k) & ~rim_mask].sum()) * depth for k in (0, 1)]
        )
        hist["rim"].append(
            [float(con.normal[rim_of == k].sum()) * depth for k in range(4)]
        )
        root_p = [float(p[e].max()) if e.size else 0.0 for e in roots]
        frac = [float((p[e] > 0).mean()) if e.size else 0.0 for e in roots]
        hist["root_p"].append(root_p)
        hist["root_frac"].append(frac)
        if snapshot_every and (len(hist["t"]) - 1) % snapshot_every == 0:
            snaps.append((t, d.copy(), p.copy(), ev.material.stress.copy()))
        for k, f in enumerate(frac):  # the root row fully plastic: a hinge (Eq. F36)
            if f >= 1.0 and RIMS[k] not in hinges:
                hinges[RIMS[k]] = t
        if failure:
            return False
        mode, detail = _check_failure(
            bearing, sysm, d, pose, vertices, corners, nd, frac, failure_criterion == "hinge"
        )
        if mode is not None:
            failure.update(mode=mode, detail=detail, time=t)
            return stop_at_failure
        return False

    integ = Integrator(
        model, ground, hht=HHTParameters(alpha),
        control=StepControl(
            max_step=max_step, impact_step=impact_step,
            energy_tol=energy_tolerance * bearing.weight / depth * bearing.rim_height,
        ),
        rim_mask=rim_mask,
    )
    out = integ.run(duration, observer)
    state = out["state"]
    d_final = red.expand(out["d"])
    ev = sysm.evaluate(d_final, state)
    H = {k: np.asarray(v) for k, v in hist.items()}
    numerical = bool(out["failed_numerically"]) and not failure
    return FEMResult(
        time=H["t"],
        displacement=H["x"],
        top_plate_rise=H["z"],
        slider_displacement=H["xs"],
        slider_rise=H["zs"],
        slider_rotation=H["th"],
        base_shear=H["shear"],
        dish_force=H["dish"],
        rim_force=H["rim"],
        rim_root_plastic_strain=H["root_p"],
        rim_root_yielded_fraction=H["root_frac"],
        max_plastic_strain=float(state.material.eq_plastic_strain.max()),
        hinge_times=dict(hinges),
        energy={k: v * depth for k, v in out["energy"].items()},
        failed=bool(failure),
        failure_mode=failure.get("mode"),
        failure_time=failure.get("time"),
        failure_detail=failure.get("detail") if failure else (out["message"] or None),
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
        snapshots=tuple(snaps),
        bearing=bearing,
        mesh=mesh,
    )


def _check_failure(bearing, sysm, d, pose, vertices, corners, nd, frac, stop_at_hinge):
    """(mode, detail) of a failure at this state, or (None, None): the hinge, escape and
    labelling rules of docs/theory/finite-elements.md, Eqs. F36–F38."""
    hinge = [f >= 1.0 for f in frac]
    for k, name in enumerate(RIMS):
        if hinge[k] and stop_at_hinge:
            return "yielding", f"plastic hinge across the root of the {name} rim"
    c, s = math.cos(pose[2]), math.sin(pose[2])
    vx = pose[0] + c * vertices[0] - s * vertices[1]
    vz = pose[1] + s * vertices[0] + c * vertices[1]
    p = sysm.fe.mesh.p
    for name in RIMS:
        node = corners[name]
        cx = p[0, node] + d[nd[0, node]]
        cz = p[1, node] + d[nd[1, node]]
        side = math.copysign(1.0, cx)
        top = name.startswith("top")
        idx = (2, 3) if top else (0, 1)
        for j in idx:
            outside = side * (vx[j] - cx) > 0
            past = (vz[j] < cz) if top else (vz[j] > cz)
            if outside and past:
                which = "top" if top else "bottom"
                # climbed above the rim's undeformed corner: uplift; passed only because the
                # hinged rim was pushed out of the way: yielding
                z0 = p[1, node]
                climbed = (vz[j] < z0) if top else (vz[j] > z0)
                mode = "yielding" if hinge[RIMS.index(name)] and not climbed else "uplift"
                return mode, f"a {which} slider vertex cleared the {name} rim"
    r_in = bearing.rim_radius
    x_top = float(np.mean(d[nd[0, corners["top -x"]]]))
    if abs(pose[0]) > r_in or abs(pose[0] - x_top) > r_in:
        return ("yielding" if any(hinge) else "uplift"), "the slider's centroid passed a rim"
    if abs(pose[2]) > 0.25 * math.pi:
        return "uplift", "the slider overturned (|θ| > 45°)"
    return None, None
