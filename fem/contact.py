r"""Penalty contact with Coulomb friction between plate nodes and a rigid slider.

The slider is a rigid body with pose ``q = (X, Z, Θ)`` (centroid [m], counter-clockwise rotation
[rad]) and *exact* rotation ``ξ = Rᵀ(Θ)(x − c)`` between global points ``x`` and body-frame
points ``ξ``. Its section (the same as the rigid model's, ``rigid/bearing.py``) is the convex
intersection of

* the bottom spherical face: inside the circle of radius R about ``(0, −h/2 + R)``,
* the top spherical face: inside the circle of radius R about ``(0, h/2 − R)``,
* the two flat sides ``|ξ_x| ≤ b/2``.

Contact is node-to-analytic-surface (fem.md §7.1): every plate boundary node that may touch the
slider (dish faces, rim inner faces, rim tops, hence the rims' corners) is a slave; its
penetration δ is its depth inside the section, the smallest of the three face depths (the
closest face), with the outward body normal ν of that face. Each node carries a tributary
length L (half of each adjacent boundary facet), so with the normal penalty ε_N [N/m³]

    N = ε_N L ⟨δ − δ₀⟩                                   (penalty, Wriggers 2006, Eq. 2.5)

per unit depth, δ₀ being the node's initial penetration when it is within ``adjust`` of the
surface ("adjust" to zero initial gaps, fem.md §3.5). Friction is Coulomb with a tangential
penalty ε_T and an elastic-predictor/return map on the nodal tangential force T
(Wriggers 2006, §5.2, Eqs. 5.49–5.53; Laursen 2002, §4.2)::

    T_trial = T_n − ε_T L ΔS,   ΔS = τ·(ξ − ξ_n),   T = T_trial             if |T_trial| ≤ μN
                                                     T = μN sign(T_trial)    otherwise,

where ξ_n is the node's body-frame position at the last converged step, so ΔS is exactly the
slip of the node relative to the slider's material along the face tangent τ = (−ν_z, ν_x).

Generalised forces on the five local dofs ``d = (x_i, z_i, X, Z, Θ)`` follow from virtual work,
``F = −N ∇δ + T ∇ΔS`` with (using ∂ξ/∂x = Rᵀ, ∂ξ/∂c = −Rᵀ, ∂ξ/∂Θ = J ξ, J = [[0, 1], [−1, 0]])::

    ∇δ  = (−n, n, −ν·Jξ),      n = R ν  (global outward normal of the slider)
    ∇ΔS = ( t, −t, τ·Jξ),      t = R τ

and the tangent ``K = −∂F/∂d`` is

    K = ε_N L ∇δ ∇δᵀ + N ∇²δ + { ε_T L ∇ΔS ∇ΔSᵀ          (stick)
                                 −μ σ ε_N L ∇ΔS ∇δᵀ      (slip, σ = sign T; unsymmetric)

The curvature term N ∇²δ (exact for the arcs, zero for the flat sides) carries the pendulum's
geometric stiffness; the analogous terms of the friction force (T times the change of τ) are
of relative size μ δ/R and left out, which only slows Newton down negligibly.

The slider's four vertices can be slaves too, against the plate facets listed in
``ContactNodes.segments`` (the rims' inner faces and tops; ``fem.simulate(...,
vertex_contact=True)``, off by default, see :mod:`fem.model` for why): without them a vertex of
a tilted slider pressed into a rim face finds no rim node in its way and sinks between two of
them by up to about tan θ times the rim node spacing. Vertex-to-segment contact (Wriggers 2006,
§9.1.1, frictionless) uses the gap δ = −(x_v − x_a)·n of the vertex x_v = c + R(Θ)v below the
deformed facet (a, b) of outward normal n, with the facet's reference length ℓ₀ as tributary
length, N = ε_N ℓ₀ δ on the seven dofs (x_a, z_a, x_b, z_b, X, Z, Θ) and the full second
variation of δ in the tangent. A vertex contacts the facet that it projects onto (0 ≤ ξ ≤ 1) and
penetrates least, to at most ``vertex_depth``. Friction is not modelled at these corner contacts
(rim friction is 0.05). They are not used on the dish, whose chords lie above the arc by ℓ²/(8R)
(5 µm on the default mesh): a vertex sliding on the dish would be pushed up and down by that
sag; there a tilted slider's corner can still sink ≈ h_dish·tan θ (1 mm at 10 mm facets and θ =
0.1) before the next dish node meets its face.

Units: SI; forces are per unit out-of-plane depth ([N/m]), moments [N·m/m].
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, NamedTuple

import numpy as np

if TYPE_CHECKING:  # pragma: no cover - typing only
    from rigid.bearing import DFPBearing

#: Face labels returned by :func:`penetration`.
BOTTOM, TOP, LEFT, RIGHT = 0, 1, 2, 3


def rotation(theta: float) -> np.ndarray:
    """Rotation matrix R(Θ), counter-clockwise, body to global."""
    c, s = math.cos(theta), math.sin(theta)
    return np.array([[c, -s], [s, c]])


@dataclass(frozen=True)
class SliderShape:
    """Section of the rigid slider in its body frame (origin at the centroid).

    Parameters
    ----------
    radius : float [m]
        Radius R of both spherical faces.
    half_width : float [m]
        Half the slider diameter, b/2.
    half_height : float [m]
        Half the height on the axis, h/2 (face apex to centroid).
    """

    radius: float
    half_width: float
    half_height: float

    def __post_init__(self):
        if not (self.radius > 0 and self.half_width > 0 and self.half_height > 0):
            raise ValueError("SliderShape dimensions must be positive")
        if self.half_width >= self.radius:
            raise ValueError("SliderShape.half_width must be smaller than the radius")
        if self.half_height <= self.sag:
            raise ValueError("SliderShape.half_height must exceed the face sag")

    @classmethod
    def from_bearing(cls, bearing: DFPBearing) -> SliderShape:
        """The slider of a :class:`rigid.DFPBearing` (R, b/2, h/2)."""
        return cls(bearing.radius, bearing.slider_diameter / 2, bearing.slider_height / 2)

    @property
    def sag(self) -> float:
        """Bulge of a face over its chord, R − √(R² − (b/2)²) [m]."""
        return self.radius - math.sqrt(self.radius**2 - self.half_width**2)

    @property
    def centres(self) -> np.ndarray:
        """Body-frame centres of the bottom and top face circles, shape (2, 2) [m]."""
        return np.array(
            [[0.0, self.radius - self.half_height], [0.0, self.half_height - self.radius]]
        )

    @property
    def vertices(self) -> np.ndarray:
        """Body-frame corners (bottom-left, bottom-right, top-left, top-right), (2, 4) [m]."""
        he = self.half_height - self.sag
        hw = self.half_width
        return np.array([[-hw, hw, -hw, hw], [-he, -he, he, he]])


def penetration(shape: SliderShape, xi: np.ndarray):
    """Depth of body-frame points inside the slider section and the closest face.

    Parameters
    ----------
    shape : SliderShape
    xi : ndarray, shape (2, n) [m]
        Points in the slider's body frame.

    Returns
    -------
    depth : ndarray, shape (n,) [m]
        Smallest face depth; positive inside the section.
    face : ndarray of int, shape (n,)
        :data:`BOTTOM`, :data:`TOP`, :data:`LEFT` or :data:`RIGHT`.
    normal : ndarray, shape (2, n) [-]
        Outward unit normal ν of that face at the closest point (body frame).
    radius : ndarray, shape (n,) [m]
        Distance ρ from the face circle's centre (inf for the flat sides), for the curvature.
    """
    xi = np.asarray(xi, dtype=float)
    R = shape.radius
    cb, ct = shape.centres
    rb = xi - cb[:, None]
    rt = xi - ct[:, None]
    lb = np.hypot(rb[0], rb[1])
    lt = np.hypot(rt[0], rt[1])
    depths = np.stack([R - lb, R - lt, shape.half_width + xi[0], shape.half_width - xi[0]])
    face = np.argmin(depths, axis=0)
    depth = depths[face, np.arange(xi.shape[1])]
    normal = np.zeros_like(xi)
    radius = np.full(xi.shape[1], np.inf)
    for f, r, length in ((BOTTOM, rb, lb), (TOP, rt, lt)):
        m = face == f
        normal[:, m] = r[:, m] / length[m]
        radius[m] = length[m]
    normal[0, face == LEFT] = -1.0
    normal[0, face == RIGHT] = 1.0
    return depth, face, normal, radius


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


def body_coordinates(x: np.ndarray, pose) -> np.ndarray:
    """ξ = Rᵀ(Θ)(x − c) for global points x (2, n) [m] and pose (X, Z, Θ)."""
    c, s = math.cos(pose[2]), math.sin(pose[2])
    dx = x[0] - pose[0]
    dz = x[1] - pose[1]
    return np.array([c * dx + s * dz, -s * dx + c * dz])


def initial_state(shape: SliderShape, x: np.ndarray, pose, adjust: float = 1e-9):
    """Virgin friction history and the gap adjustment δ₀ at the initial configuration.

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
) -> ContactResult:
    """Contact forces and tangents for slave positions ``x`` and slider pose ``pose``.

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
    N = np.where(active, penalty * L * gap, 0.0)

    n = Rm @ nu
    tau = np.array([-nu[1], nu[0]])
    t = Rm @ tau
    jxi = np.array([xi[1], -xi[0]])  # J ξ = ∂ξ/∂Θ
    grad_d = np.concatenate([-n, n, [-(nu * jxi).sum(axis=0)]])  # (5, n)
    grad_s = np.concatenate([t, -t, [(tau * jxi).sum(axis=0)]])

    # Friction: elastic predictor from the last converged state on the same face.
    same = active & (state.face == face)
    slip = (tau * (xi - state.xi)).sum(axis=0)
    t_old = np.where(same, state.traction, 0.0)
    trial = np.where(active, t_old - tangential_penalty * L * slip, 0.0)
    limit = nodes.friction * N
    stick = active & (np.abs(trial) <= limit) & (nodes.friction > 0)
    sign = np.sign(trial)
    T = np.where(stick, trial, sign * limit)
    T = np.where(active, T, 0.0)

    force = -N * grad_d + T * grad_s  # generalised force on (x_i, z_i, X, Z, Θ)
    node_force = force[:2]
    slider_force = force[2:].sum(axis=1)

    # Tangent K = −∂F/∂d.
    kn = np.where(active, penalty * L, 0.0)
    K = kn * np.einsum("in,jn->ijn", grad_d, grad_d)
    K += N * _depth_hessian(Rm, nu, xi, jxi, rho)
    kt = np.where(stick, tangential_penalty * L, 0.0)
    K += kt * np.einsum("in,jn->ijn", grad_s, grad_s)
    ks = np.where(active & ~stick, -nodes.friction * sign * penalty * L, 0.0)
    K += ks * np.einsum("in,jn->ijn", grad_s, grad_d)

    new_state = ContactState(xi, T, np.where(active, face, -1))
    energy = float(0.5 * (N * np.where(active, gap, 0.0)).sum())
    return ContactResult(
        N, T, node_force, slider_force, K, new_state, active, stick, gap,
        np.where(active, slip, 0.0), energy,
    )


def _depth_hessian(Rm, nu, xi, jxi, rho):
    """∇²δ over d = (x, z, X, Z, Θ) for each node, shape (5, 5, n).

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
    """Frictionless penalty contact of the slider's four vertices with plate facets.

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
