"""Frictionless penalty contact of the slider's four vertices with plate facets (the rims' inner
faces and tops), with the full second variation of the gap in the tangent (Wriggers 2006,
§9.1.1; docs/theory/finite-elements.md, "Contact"). Off by default
(``fem.simulate(vertex_contact=...)``)."""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from .nodes import ContactNodes, ContactResult
from .slider import SliderShape, rotation

__all__ = ["VertexContact", "add_vertices", "vertex_contact"]


class VertexContact(NamedTuple):
    """Contact of the slider's vertices with plate facets (:func:`vertex_contact`).

    Attributes
    ----------
    active : ndarray of bool, shape (4,)
    segment : ndarray of int, shape (4,)
        Facet index into ``ContactNodes.segments`` (−1 if open).
    normal : ndarray, shape (4,) [N/m]
        N = ε_N ℓ₀ δ.
    gap : ndarray, shape (4,) [m]
        Penetration δ (0 if open).
    force : ndarray, shape (7, 4)
        Generalised force −N∇δ on (x_a, z_a, x_b, z_b, X, Z, Θ).
    stiffness : ndarray, shape (7, 7, 4)
        K = ε_N ℓ₀ ∇δ∇δᵀ + N∇²δ.
    ends : ndarray of int, shape (2, 4)
        Slave-node indices of the facet ends (0 if open).
    """

    active: np.ndarray
    segment: np.ndarray
    normal: np.ndarray
    gap: np.ndarray
    force: np.ndarray
    stiffness: np.ndarray
    ends: np.ndarray


def vertex_contact(
    shape: SliderShape, nodes: ContactNodes, x: np.ndarray, pose, penalty: float,
    max_depth: float,
) -> VertexContact:
    """Frictionless penalty contact of the slider's four vertices with plate facets
    (docs/theory/finite-elements.md, Eq. F20).

    Parameters
    ----------
    shape : SliderShape
    nodes : ContactNodes
        With ``segments`` (see :meth:`ContactNodes.from_mesh`).
    x : ndarray, shape (2, n) [m]
        Deformed slave-node positions.
    pose : sequence of 3 floats [m, m, rad]
    penalty : float [N/m³]
        ε_N.
    max_depth : float [m]
        Largest penetration attributed to a facet (deeper points belong to no facet).

    Returns
    -------
    VertexContact
    """
    th = float(pose[2])
    Rm = rotation(th)
    v = shape.vertices
    u = Rm @ v  # R v
    w = np.array([-u[1], u[0]])  # ∂x_v/∂Θ = R' v
    xv = np.asarray(pose[:2], dtype=float)[:, None] + u  # (2, 4)
    out_active = np.zeros(4, dtype=bool)
    seg_of = np.full(4, -1)
    gap = np.zeros(4)
    nv = np.zeros((2, 4))
    xi_v = np.zeros(4)
    if nodes.segments is None or nodes.segments.size == 0:
        z = np.zeros(4)
        return VertexContact(out_active, seg_of, z, gap, np.zeros((7, 4)),
                             np.zeros((7, 7, 4)), np.zeros((2, 4), dtype=int))
    a = x[:, nodes.segments[:, 0]]
    b = x[:, nodes.segments[:, 1]]
    delta = b - a
    ell = np.hypot(delta[0], delta[1])
    t = delta / ell
    n = nodes.segment_sign * np.array([t[1], -t[0]])  # outward normal of the plate
    r = xv[:, :, None] - a[:, None, :]  # (2, 4, m)
    xi = (r * t[:, None, :]).sum(axis=0) / ell  # (4, m)
    depth = -(r * n[:, None, :]).sum(axis=0)
    ok = (xi >= 0.0) & (xi <= 1.0) & (depth > 0.0) & (depth <= max_depth)
    cand = np.where(ok, depth, np.inf)
    best = np.argmin(cand, axis=1)
    for k in range(4):
        if np.isfinite(cand[k, best[k]]):
            out_active[k] = True
            seg_of[k] = best[k]
            gap[k] = depth[k, best[k]]
            nv[:, k] = n[:, best[k]]
            xi_v[k] = xi[k, best[k]]
    ends = np.zeros((2, 4), dtype=int)
    force = np.zeros((7, 4))
    K = np.zeros((7, 7, 4))
    L0 = np.zeros(4)
    for k in np.flatnonzero(out_active):
        j = seg_of[k]
        ends[:, k] = nodes.segments[j]
        L0[k] = nodes.segment_length[j]
        force[:, k], K[:, :, k] = _vertex_terms(
            r[:, k, j], delta[:, j], nodes.segment_sign[j], w[:, k], u[:, k], penalty * L0[k]
        )
    N = penalty * L0 * gap
    return VertexContact(out_active, seg_of, N, gap, force, K, ends)


_Q = np.array([[0.0, 1.0], [-1.0, 0.0]])  # Q Δ = (Δz, −Δx)


def _vertex_terms(r, delta, sign, w, u, k_n):
    """Force −N∇δ and tangent k_n∇δ∇δᵀ + N∇²δ for δ = −sign·(rᵀQΔ)/ℓ, r = x_v − x_a,
    Δ = x_b − x_a, on d = (x_a, x_b, c, Θ); w = ∂x_v/∂Θ, u = R v (∂²x_v/∂Θ² = −u)."""
    ell = math.hypot(delta[0], delta[1])
    t = delta / ell
    phi = r @ _Q @ delta
    delta_gap = -sign * phi / ell
    g_r = -sign * (_Q @ delta) / ell  # ∂δ/∂r = −n
    g_d = -sign * ((_Q.T @ r) / ell - phi * t / ell**2)  # ∂δ/∂Δ
    h_rd = -sign * (_Q - np.outer(_Q @ delta, t) / ell) / ell  # ∂²δ/∂r∂Δ
    qr = _Q.T @ r
    h_dd = sign * (
        (np.outer(qr, t) + np.outer(t, qr)) / ell**2
        + phi * (np.eye(2) - 3.0 * np.outer(t, t)) / ell**3
    )  # ∂²δ/∂Δ²
    I2 = np.eye(2)
    A_r = np.zeros((2, 7))
    A_r[:, 0:2] = -I2
    A_r[:, 4:6] = I2
    A_r[:, 6] = w
    A_d = np.zeros((2, 7))
    A_d[:, 0:2] = -I2
    A_d[:, 2:4] = I2
    grad = A_r.T @ g_r + A_d.T @ g_d
    H = A_r.T @ h_rd @ A_d
    H = H + H.T + A_d.T @ h_dd @ A_d
    H[6, 6] += g_r @ (-u)  # ∂δ/∂r · ∂²r/∂Θ²
    N = k_n * delta_gap
    return -N * grad, k_n * np.outer(grad, grad) + N * H


def add_vertices(result: ContactResult, vc: VertexContact) -> ContactResult:
    """``result`` with the vertex contacts folded in: their forces on the facet-end nodes and
    the slider, each normal force shared by the two end nodes in proportion to their forces
    (for force resultants per rim), the end nodes marked active (so the rim counts as in
    contact) and the springs' energy added. The 7 × 7 tangents stay in ``vc``."""
    if not vc.active.any():
        return result
    node_force = result.node_force.copy()
    normal = result.normal.copy()
    active = result.active.copy()
    slider = result.slider_force.copy()
    for k in np.flatnonzero(vc.active):
        a, b = vc.ends[:, k]
        f = vc.force[:, k]
        node_force[:, a] += f[0:2]
        node_force[:, b] += f[2:4]
        slider += f[4:7]
        # nodal share of the normal force: |f| on each end along the facet normal
        fa, fb = math.hypot(*f[0:2]), math.hypot(*f[2:4])
        total = fa + fb
        if total > 0:
            normal[a] += vc.normal[k] * fa / total
            normal[b] += vc.normal[k] * fb / total
        active[a] = active[b] = True
    energy = result.normal_energy + float(0.5 * (vc.normal * vc.gap).sum())
    return result._replace(
        node_force=node_force, normal=normal, active=active, slider_force=slider,
        normal_energy=energy,
    )
