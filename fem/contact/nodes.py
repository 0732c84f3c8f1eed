"""Node-to-surface penalty contact with Coulomb friction between the plates' boundary nodes and
the rigid slider: forces, the consistent tangent on the five local dofs (x_i, z_i, X, Z, Θ),
the friction history and its return map (docs/theory/finite-elements.md, "Contact";
Wriggers 2006)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from .slider import SliderShape, body_coordinates, penetration, rotation, tangent_continuous

__all__ = ["ContactNodes", "ContactResult", "ContactState", "assemble", "evaluate",
           "initial_state"]


@dataclass(frozen=True)
class ContactNodes:
    """Slave nodes of the plates with their tributary lengths and friction coefficients.

    Attributes
    ----------
    nodes : ndarray of int, shape (n,)
        Mesh vertex indices.
    length : ndarray, shape (n,) [m]
        Tributary length L (half of every adjacent facet of the contact boundaries).
    friction : ndarray, shape (n,) [-]
        Coulomb coefficient μ (length-weighted over the adjacent facets' boundaries).
    plate : ndarray of int, shape (n,)
        0 for nodes of the bottom plate, 1 for the top plate (for force resultants).
    """

    nodes: np.ndarray
    length: np.ndarray
    friction: np.ndarray
    plate: np.ndarray
    segments: np.ndarray | None = None
    segment_sign: np.ndarray | None = None
    segment_length: np.ndarray | None = None

    @classmethod
    def from_mesh(
        cls, mesh, boundaries: dict[str, float], plate_of=None, vertex_boundaries=()
    ) -> ContactNodes:
        """Collect the nodes of named facet sets.

        Parameters
        ----------
        mesh : skfem.Mesh
            Mesh with ``boundaries``.
        boundaries : dict
            Boundary name → friction coefficient μ [-] on it.
        plate_of : callable, optional
            Boundary name → 0/1 plate label; default: 1 if the name starts with ``"top"``.
        vertex_boundaries : sequence of str
            Boundaries (among ``boundaries``) whose facets the slider's vertices are checked
            against; they become ``segments`` (pairs of indices into ``nodes``),
            ``segment_sign`` (outward normal n = sign·(Δz, −Δx)/ℓ for Δ = x_b − x_a) and
            ``segment_length`` ℓ₀ [m].
        """
        plate_of = plate_of or (lambda name: int(name.startswith("top")))
        n = mesh.p.shape[1]
        length = np.zeros(n)
        mu_len = np.zeros(n)
        plate = np.zeros(n, dtype=int)
        for name, mu in boundaries.items():
            facets = mesh.facets[:, mesh.boundaries[name]]
            seg = mesh.p[:, facets[1]] - mesh.p[:, facets[0]]
            half = 0.5 * np.hypot(seg[0], seg[1])
            for end in facets:
                np.add.at(length, end, half)
                np.add.at(mu_len, end, mu * half)
            plate[np.unique(facets)] = plate_of(name)
        nodes = np.flatnonzero(length > 0)
        segs = signs = seg_len = None
        if vertex_boundaries:
            index = np.full(n, -1)
            index[nodes] = np.arange(nodes.size)
            fac = np.concatenate([mesh.boundaries[name] for name in vertex_boundaries])
            ends = mesh.facets[:, fac]
            delta = mesh.p[:, ends[1]] - mesh.p[:, ends[0]]
            mid = 0.5 * (mesh.p[:, ends[1]] + mesh.p[:, ends[0]])
            centroid = mesh.p[:, mesh.t[:, mesh.f2t[0, fac]]].mean(axis=1)
            qd = np.array([delta[1], -delta[0]])
            signs = np.sign(((mid - centroid) * qd).sum(axis=0))  # away from the element
            segs = index[ends].T
            seg_len = np.hypot(delta[0], delta[1])
        return cls(nodes, length[nodes], mu_len[nodes] / length[nodes], plate[nodes], segs,
                   signs, seg_len)

    def __len__(self) -> int:
        return self.nodes.size


class ContactState(NamedTuple):
    """Friction history per slave node, committed only at convergence.

    Attributes
    ----------
    xi : ndarray, shape (2, n) [m]
        Body-frame position of each node at the last converged state.
    traction : ndarray, shape (n,) [N/m]
        Tangential nodal force T along the face tangent τ (per unit depth).
    face : ndarray of int, shape (n,)
        Face in contact, −1 if open.
    """

    xi: np.ndarray
    traction: np.ndarray
    face: np.ndarray


class ContactResult(NamedTuple):
    """Output of :func:`evaluate` (all per unit depth).

    Attributes
    ----------
    normal, tangential : ndarray, shape (n,) [N/m]
        Nodal normal force N ≥ 0 and tangential force T.
    node_force : ndarray, shape (2, n) [N/m]
        Contact force on each slave node (global x, z).
    slider_force : ndarray, shape (3,) [N/m, N/m, N·m/m]
        Generalised contact force on the slider (F_X, F_Z, moment about the centroid).
    stiffness : ndarray, shape (5, 5, n)
        Local tangents ``K = −∂F/∂d``, d = (x_i, z_i, X, Z, Θ).
    state : ContactState
        Trial history.
    active, stick : ndarray of bool, shape (n,)
    gap : ndarray, shape (n,) [m]
        Adjusted penetration δ − δ₀ (positive when penetrating).
    slip : ndarray, shape (n,) [m]
        Slip ΔS since the last converged state (0 where open); friction dissipates −T·ΔS.
    normal_energy : float [J/m]
        Elastic energy of the normal penalty springs, Σ N (δ − δ₀)/2.
    """

    normal: np.ndarray
    tangential: np.ndarray
    node_force: np.ndarray
    slider_force: np.ndarray
    stiffness: np.ndarray
    state: ContactState
    active: np.ndarray
    stick: np.ndarray
    gap: np.ndarray
    slip: np.ndarray
    normal_energy: float


def initial_state(shape: SliderShape, x: np.ndarray, pose, adjust: float = 1e-9):
    """Virgin friction history and the gap adjustment δ₀ at the initial configuration
    (docs/theory/finite-elements.md, Eq. F15).

    Parameters
    ----------
    shape : SliderShape
    x : ndarray, shape (2, n) [m]
        Slave node positions.
    pose : sequence of 3 floats [m, m, rad]
    adjust : float [m]
        Nodes with |δ| ≤ ``adjust`` are moved onto the surface (their δ₀ = δ); others get 0.

    Returns
    -------
    state : ContactState
    offset : ndarray, shape (n,) [m]
    """
    xi = body_coordinates(x, pose)
    depth, _, _, _ = penetration(shape, xi)
    offset = np.where(np.abs(depth) <= adjust, depth, 0.0)
    n = x.shape[1]
    return ContactState(xi, np.zeros(n), np.full(n, -1)), offset


def evaluate(
    shape: SliderShape,
    nodes: ContactNodes,
    x: np.ndarray,
    pose,
    state: ContactState,
    offset: np.ndarray,
    penalty: float,
    tangential_penalty: float,
    carry_across_edges: bool = False,
) -> ContactResult:
    """Contact forces and tangents for slave positions ``x`` and slider pose ``pose``
    (docs/theory/finite-elements.md, Eqs. F15–F19).

    Parameters
    ----------
    shape : SliderShape
    nodes : ContactNodes
    x : ndarray, shape (2, n) [m]
        Current (deformed) positions of the slave nodes.
    pose : sequence of 3 floats [m, m, rad]
        Slider centroid and rotation.
    state : ContactState
        Last converged friction history.
    offset : ndarray, shape (n,) [m]
        Gap adjustment δ₀ from :func:`initial_state`.
    penalty : float [N/m³]
        Normal penalty ε_N (pressure per unit penetration).
    tangential_penalty : float [N/m³]
        Tangential (stick) penalty ε_T.
    carry_across_edges : bool
        A node that passes between a rounded edge and a face it joins with a common tangent
        keeps its friction history (Eq. F16a); False: only on the same face (Eq. F16).

    Returns
    -------
    ContactResult
    """
    th = float(pose[2])
    Rm = rotation(th)
    xi = body_coordinates(x, pose)
    depth, face, nu, rho = penetration(shape, xi)
    gap = depth - offset
    active = gap >= 0.0
    L = nodes.length
    N = np.where(active, penalty * L * gap, 0.0)  # Eq. F15

    n = Rm @ nu
    tau = np.array([-nu[1], nu[0]])
    t = Rm @ tau
    jxi = np.array([xi[1], -xi[0]])  # J ξ = ∂ξ/∂Θ
    grad_d = np.concatenate([-n, n, [-(nu * jxi).sum(axis=0)]])  # (5, n); Eq. F17
    grad_s = np.concatenate([t, -t, [(tau * jxi).sum(axis=0)]])

    # Friction: elastic predictor from the last converged state on the same face (Eq. F16), or
    # with carry_across_edges on one that meets it with a common tangent (Eq. F16a).
    if carry_across_edges:
        same = active & (state.face >= 0) & tangent_continuous(shape)[np.maximum(state.face, 0),
                                                                      face]
    else:
        same = active & (state.face == face)
    slip = (tau * (xi - state.xi)).sum(axis=0)
    t_old = np.where(same, state.traction, 0.0)
    trial = np.where(active, t_old - tangential_penalty * L * slip, 0.0)
    limit = nodes.friction * N
    stick = active & (np.abs(trial) <= limit) & (nodes.friction > 0)
    sign = np.sign(trial)
    T = np.where(stick, trial, sign * limit)
    T = np.where(active, T, 0.0)

    force = -N * grad_d + T * grad_s  # generalised force on (x_i, z_i, X, Z, Θ), Eq. F17
    node_force = force[:2]
    slider_force = force[2:].sum(axis=1)

    # Tangent K = −∂F/∂d (Eq. F18), with the curvature term N∇²δ (Eq. F19); zero where open
    K = np.zeros((5, 5, L.size))
    a = np.flatnonzero(active)
    if a.size:
        gd, gs, La = grad_d[:, a], grad_s[:, a], L[a]
        Ka = penalty * La * np.einsum("in,jn->ijn", gd, gd)
        Ka += N[a] * _depth_hessian(Rm, nu[:, a], xi[:, a], jxi[:, a], rho[a])
        kt = np.where(stick[a], tangential_penalty * La, 0.0)
        Ka += kt * np.einsum("in,jn->ijn", gs, gs)
        ks = np.where(stick[a], 0.0, -nodes.friction[a] * sign[a] * penalty * La)
        Ka += ks * np.einsum("in,jn->ijn", gs, gd)
        K[:, :, a] = Ka

    new_state = ContactState(xi, T, np.where(active, face, -1))
    energy = float(0.5 * (N * np.where(active, gap, 0.0)).sum())
    return ContactResult(
        N, T, node_force, slider_force, K, new_state, active, stick, gap,
        np.where(active, slip, 0.0), energy,
    )


def _depth_hessian(Rm, nu, xi, jxi, rho):
    """∇²δ over d = (x, z, X, Z, Θ) for each node, shape (5, 5, n) (Eq. F19).

    δ = R − |ξ − a| on an arc: ∇²_ξ δ = −(I − ν νᵀ)/ρ; with A = ∂ξ/∂d = [Rᵀ, −Rᵀ, Jξ] and the
    second derivatives of ξ(d) (∂²ξ/∂Θ∂x = J Rᵀ, ∂²ξ/∂Θ∂c = −J Rᵀ, ∂²ξ/∂Θ² = −ξ),
    ∇²δ = Aᵀ ∇²_ξ δ A + Σ_k (∂δ/∂ξ_k) ∂²ξ_k/∂d². Flat sides have ∇²_ξ δ = 0.
    """
    n = xi.shape[1]
    RT = Rm.T
    A = np.zeros((2, 5, n))
    A[:, 0:2, :] = RT[:, :, None]
    A[:, 2:4, :] = -RT[:, :, None]
    A[:, 4, :] = jxi
    curv = np.where(np.isfinite(rho), 1.0 / np.where(np.isfinite(rho), rho, 1.0), 0.0)
    hxi = -(np.eye(2)[:, :, None] - np.einsum("in,jn->ijn", nu, nu)) * curv  # (2, 2, n)
    H = np.einsum("kan,kln,lbn->abn", A, hxi, A)
    g = -nu  # ∂δ/∂ξ
    J = np.array([[0.0, 1.0], [-1.0, 0.0]])
    # cross terms (x, Θ) and (c, Θ): gᵀ J Rᵀ
    cross = np.einsum("kn,kl,lm->mn", g, J, RT)  # (2, n)
    H[0:2, 4] += cross
    H[4, 0:2] += cross
    H[2:4, 4] -= cross
    H[4, 2:4] -= cross
    H[4, 4] += -(g * xi).sum(axis=0)
    return H


def assemble(stiffness: np.ndarray, node_dofs: np.ndarray, slider_dofs, size: int):
    """Scatter local 5 × 5 tangents into a global sparse matrix.

    Parameters
    ----------
    stiffness : ndarray, shape (5, 5, n)
        From :attr:`ContactResult.stiffness`.
    node_dofs : ndarray of int, shape (2, n)
        Global x and z dofs of the slave nodes.
    slider_dofs : sequence of 3 int
        Global dofs of (X, Z, Θ).
    size : int
        Number of global dofs.

    Returns
    -------
    scipy.sparse.csr_matrix
    """
    import scipy.sparse as sp

    n = node_dofs.shape[1]
    dofs = np.concatenate([node_dofs, np.broadcast_to(np.asarray(slider_dofs)[:, None], (3, n))])
    rows = np.broadcast_to(dofs[:, None, :], (5, 5, n)).ravel()
    cols = np.broadcast_to(dofs[None, :, :], (5, 5, n)).ravel()
    return sp.csr_matrix((stiffness.ravel(), (rows, cols)), shape=(size, size))
