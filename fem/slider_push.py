"""The rim pushed by the slider itself: the rigid slider, with its rounded edges, moved along
its pendulum path into the +x bottom rim and pressing it through the dynamic model's penalty
contact (docs/theory/finite-elements.md, Eqs. F15–F19, F71), at finite deformation, with the
rim's ductile damage and its torn elements let go when asked (Eqs. F66–F68). Call
:func:`rim_slider_push`; :func:`fem.rim_law` builds a law through tearing from it with
``punch="slider"``.

The path (Eq. F71): the slider's spherical face stays concentric with the dish, its centroid
at R − h/2 from the dish's centre, so δ, its horizontal advance past the first touch, is the
only load parameter; the dish is left out of the contact.
"""

from __future__ import annotations

import dataclasses
import math
import warnings

import numpy as np

from rigid.bearing import DFPBearing

from .pushover import Pushover, PushRecord, bottom_plate

__all__ = ["rim_slider_push", "slider_pose", "touching_angle"]

#: The slider's edge radius [m] of a push by the slider when none is given: 20 mm, the
#: validation runs' ``--fem-edge-radius`` (docs/fe-companion.md, "Rounded slider edges").
EDGE_RADIUS = 0.02


def slider_pose(bearing: DFPBearing, angle: float) -> np.ndarray:
    """The slider's pose (X [m], Z [m], Θ [rad]) on its pendulum path at ``angle`` [rad]
    (Eq. F71): its spherical face concentric with the dish, its centroid at R − h/2 from the
    dish's centre (0, R), turned by the same angle."""
    arm = bearing.radius - bearing.slider_height / 2
    return np.array([arm * math.sin(angle), bearing.radius - arm * math.cos(angle), angle])


def touching_angle(bearing: DFPBearing, shape, points: np.ndarray) -> float:
    """The path angle [rad] at which the slider (``shape``) first reaches any of ``points``
    (2, n) [m]: bisection on the deepest point's penetration (Eq. F14), to 1e-12 rad."""
    from .contact import body_coordinates, penetration

    def deepest(angle):
        return penetration(shape, body_coordinates(points, slider_pose(bearing, angle)))[0].max()

    lo, hi = 0.0, math.asin(bearing.rim_radius / (bearing.radius - bearing.slider_height / 2))
    if deepest(lo) >= 0.0 or deepest(hi) < 0.0:
        raise ValueError("the slider must start clear of the rim and reach it on its path")
    while hi - lo > 1e-12:
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if deepest(mid) < 0.0 else (lo, mid)
    return hi


def rim_slider_push(bearing: DFPBearing, *, edge_radius: float = EDGE_RADIUS,
                    displacement: float | None = None, steps: int = 40,
                    mesh_options: dict | None = None, plasticity: bool = True,
                    fracture=None, erosion_steps: int = 0, stop_short: bool = False,
                    crush_jacobian: float | None = None,
                    penalty_factor: float = 10.0, tangential_ratio: float = 0.1,
                    cache_dir=None) -> Pushover:
    """Push the +x bottom rim with the slider moved along its pendulum path (Eq. F71), at
    finite deformation.

    The plate's back face is fixed; the slider's pose is prescribed, its advance δ measured
    horizontally from where it first touches the rim; the rim's inner face and top press on
    it through the dynamic model's penalty contact with Coulomb friction (Eqs. F15–F19; the
    dish is left out: the slider rides on it concentrically). Increments of at most
    1/``steps`` of the final δ, halved when Newton fails.

    Parameters
    ----------
    bearing : rigid.DFPBearing
    edge_radius : float [m]
        The slider's rounded edges (:class:`fem.contact.SliderShape`; default 20 mm, the
        validation runs' ``--fem-edge-radius``).
    displacement : float [m], optional
        Final δ; default half the rim height.
    steps : int
        Increments at most.
    mesh_options : dict, optional
        :func:`fem.geometry.build_mesh` sizes [m].
    plasticity : bool
        False keeps the steel elastic.
    fracture, erosion_steps, stop_short
        As :func:`fem.rim_pushover`: the rim's ductile damage, its torn elements let go over
        N increments (a node no element holds any more leaves the contact), the push ended
        once the rim is off; stop where Newton fails instead of raising RuntimeError.
    crush_jacobian : float [-], optional
        With ``fracture``: rim elements crushed below this det F let go (Eq. F67b).
    penalty_factor, tangential_ratio : float [-]
        As :func:`fem.dfp.build_system` (ε_N = factor · E / h_c, ε_T / ε_N).
    cache_dir : path-like, optional
        Mesh cache.

    Returns
    -------
    Pushover
        ``displacement`` is the slider's advance δ, ``force`` the horizontal contact force
        on it [N] (times the model's depth).
    """
    from . import contact as C
    from .finite_element import FiniteStrainQ1
    from .hencky import FiniteState
    from .material import Material

    if erosion_steps and fracture is None:
        raise ValueError("erosion_steps needs fracture")
    delta_end = 0.5 * bearing.rim_height if displacement is None else float(displacement)
    if not (math.isfinite(delta_end) and delta_end > 0):
        raise ValueError(f"displacement must be a positive length [m], got {displacement!r}")
    shape = C.SliderShape.from_bearing(bearing, edge_radius)
    plate = bottom_plate(bearing, mesh_options=mesh_options, cache_dir=cache_dir)
    mesh = plate.mesh
    fe = FiniteStrainQ1(mesh)
    steel = Material.from_bearing(bearing)
    steel = steel if plasticity else steel.elastic()
    nd = fe.basis.nodal_dofs
    faces = {"bottom_rim_inner": bearing.rim_friction, "bottom_rim_top": bearing.rim_friction}
    nodes = C.ContactNodes.from_mesh(mesh, faces)
    surface = None
    if crush_jacobian is not None:  # every rim vertex a contact node once uncovered (F68c)
        nodes, surface = C.with_rim_vertices(mesh, nodes, faces, bearing.rim_friction)
    keep = mesh.p[0, nodes.nodes] > 0.0  # the +x rim only
    nodes = dataclasses.replace(nodes, nodes=nodes.nodes[keep], length=nodes.length[keep],
                                friction=nodes.friction[keep], plate=nodes.plate[keep])
    node_dofs = nd[:, nodes.nodes]
    dish = mesh.facets[:, mesh.boundaries["bottom_dish"]]
    h_c = float(np.mean(np.linalg.norm(mesh.p[:, dish[1]] - mesh.p[:, dish[0]], axis=0)))
    eps_n = penalty_factor * bearing.youngs_modulus / h_c
    # Eq. F71: δ = X(angle) − X(touch); the path's X is monotone on the way to the rim
    touch = touching_angle(bearing, shape, mesh.p[:, nodes.nodes])
    arm = bearing.radius - bearing.slider_height / 2
    x_touch = arm * math.sin(touch)

    def pose_at(delta):
        return slider_pose(bearing, math.asin((x_touch + delta) / arm))

    friction, offset = C.initial_state(shape, mesh.p[:, nodes.nodes], pose_at(0.0))
    uncovered = np.zeros(len(nodes), dtype=bool)
    fixed = np.concatenate([nd[0, plate.support], nd[1, plate.support]])
    state = FiniteState.virgin(fe.point_shape)
    u = np.zeros(fe.ndofs)
    record = PushRecord(bearing, fe, plate, fracture, erosion_steps, crush_jacobian)
    delta, h = 0.0, delta_end / steps
    while delta < delta_end * (1 - 1e-12):
        target = min(delta + h, delta_end)
        loose = record.loose(fixed)  # held, and out of the contact
        held = np.concatenate([fixed, loose])
        length = nodes.length
        if surface is not None and fe.retained is not None:
            length = surface.lengths(fe.retained)[keep]
            new = C.first_uncovered(length, nodes.length, uncovered)
            if new.any():  # first uncovered: the slider's penetration is their δ₀ (F68c)
                offset = offset.copy()
                offset[new] = C.overlap_gap(shape, mesh.p[:, nodes.nodes[new]]
                                            + u[node_dofs[:, new]], pose_at(delta))
        in_contact = dataclasses.replace(nodes, length=length * ~np.isin(node_dofs[0], loose))
        res = _newton(fe, steel, state, u, held, pose_at(target), shape, in_contact,
                      node_dofs, friction, offset, eps_n, tangential_ratio * eps_n)
        if res is None:  # cut the increment back
            h *= 0.5
            if h < 1e-6 * delta_end:
                if stop_short:
                    break
                raise RuntimeError(f"slider push: Newton did not converge beyond δ = "
                                   f"{delta:.4g} m even with increments of {h:.2g} m")
            continue
        delta, (u, ev, friction, slider_force) = target, res
        state = ev.state
        h = min(2.0 * h, delta_end / steps)
        force = -slider_force[0] * plate.depth  # the rim's push back on the slider, outward +
        if record.add(delta, force, u, state, ev.stress, ev.jacobian):
            break  # the rim is off
    return record.pushover("finite", u, state)


def _newton(fe, steel, state, u, fixed, pose, shape, nodes, node_dofs, friction, offset,
            eps_n, eps_t, rtol=1e-8, max_iter=15):
    """One increment: f_int(u) = f_contact(u) with the slider at ``pose`` and the dofs
    ``fixed`` held where they are; Newton with the consistent tangents of the plate and of
    the contact's node block (Eq. F18). Returns (u, the plate's evaluation
    (:class:`fem.finite_element.FiniteEvaluation`), friction history, slider force [N/m, N/m,
    N·m/m]) once converged, None if not."""
    from scipy.sparse.linalg import MatrixRankWarning
    from skfem import condense, solve

    from . import contact as C

    x0 = fe.basis.mesh.p[:, nodes.nodes]
    free = np.setdiff1d(np.arange(u.size), fixed)
    for _ in range(max_iter + 1):
        ev, f_int = fe.evaluate(steel, u, state)
        if not np.isfinite(f_int).all():
            return None
        con = C.evaluate(shape, nodes, x0 + u[node_dofs], pose, friction, offset, eps_n, eps_t)
        f_con = np.zeros_like(f_int)
        np.add.at(f_con, node_dofs.ravel(), con.node_force.ravel())
        r = f_con - f_int
        scale = max(np.linalg.norm(f_int), np.linalg.norm(f_con))
        if scale == 0.0 or np.linalg.norm(r[free]) <= rtol * scale:
            return u, ev, con.state, con.slider_force
        # only the nodes' block of the contact tangent: the slider's pose is prescribed
        K = fe.finite_stiffness(steel, ev) + _node_block(con.stiffness, node_dofs, u.size)
        with warnings.catch_warnings():  # a singular tangent fails the increment
            warnings.simplefilter("error", MatrixRankWarning)
            try:
                u = u + solve(*condense(K, r, D=fixed))
            except MatrixRankWarning:
                return None
    return None


def _node_block(stiffness, node_dofs, size):
    """The (x_i, z_i) block of the contact's local tangents scattered into a global matrix."""
    import scipy.sparse as sp

    n = node_dofs.shape[1]
    rows = np.broadcast_to(node_dofs[:, None, :], (2, 2, n)).ravel()
    cols = np.broadcast_to(node_dofs[None, :, :], (2, 2, n)).ravel()
    return sp.csr_matrix((stiffness[:2, :2].ravel(), (rows, cols)), shape=(size, size))
