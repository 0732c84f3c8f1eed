r"""The coupled plate–slider system: internal forces, tangents, dof reduction, static Newton.

Full unknowns ``d = [u, q]``: the plate displacements ``u`` (scikit-fem's dof order of the
vector Q1 basis) followed by the slider's displacement ``q = (X, Z, Θ) − q₀`` from its initial
pose ``q₀``. Internal forces are ``f_int = f_mat(u) − F_c(d)`` (material, per unit depth, and
the contact force of :mod:`fem.contact`) with the tangent ``K = K_mat + K_c``
(docs/theory/finite-elements.md, Eq. F21).

Constraints are applied by a reduction ``d = P a`` (:class:`Reduction`): supported dofs
vanish and tied dofs (the superstructure block's top, rotation locked) share one master
column, so ``K_red = Pᵀ K P``, ``r_red = Pᵀ r`` and a lumped mass stays diagonal (Eq. F22).
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import NamedTuple

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import spsolve

from fem import contact as C
from fem.assembly import PlaneStrainQ1
from fem.hencky import FiniteState
from fem.material import Material, MaterialState, return_map


class Evaluation:
    """Internal force at one iterate, and the tangent on demand (full dofs, per unit depth).

    Attributes
    ----------
    internal_force : ndarray, shape (size,) [N/m]
        f_int = f_mat − F_c.
    material : fem.material.ReturnMapResult
    contact : fem.contact.ContactResult
        Node contacts, with the slider-vertex contacts' forces folded in.
    material_force : ndarray, shape (size,) [N/m]
        f_mat alone.
    vertex : fem.contact.VertexContact or None
        The slider-vertex contacts (their 7 × 7 tangents).
    stiffness : scipy.sparse.csr_matrix, shape (size, size) [N/m²]
        K = K_mat + K_c, assembled at first access (a line search needs only forces).
    """

    __slots__ = ("_stiffness", "_system", "contact", "internal_force", "material",
                 "material_force", "vertex")

    def __init__(self, internal_force, material, contact, material_force, system, vertex=None):
        self.internal_force = internal_force
        self.material = material
        self.contact = contact
        self.material_force = material_force
        self.vertex = vertex  # fem.contact.VertexContact or None
        self._system = system
        self._stiffness = None

    @property
    def stiffness(self) -> sp.csr_matrix:
        if self._stiffness is None:
            self._stiffness = self._system.tangent(self)
        return self._stiffness


class State(NamedTuple):
    """Converged history: material and friction."""

    material: MaterialState
    contact: C.ContactState


@dataclass
class CoupledSystem:
    """Deformable plates in contact with a rigid slider.

    Parameters
    ----------
    fe : PlaneStrainQ1
        Plate discretisation (coordinates [m]).
    material : Material
        Plate steel (same everywhere).
    shape : contact.SliderShape
        Slider section.
    nodes : contact.ContactNodes
        Slave nodes.
    pose : sequence of 3 floats [m, m, rad]
        Initial slider pose q₀.
    penalty, tangential_penalty : float [N/m³]
        ε_N and ε_T.
    adjust : float [m]
        Gap adjustment tolerance (:func:`fem.contact.initial_state`).
    vertex_depth : float [m]
        Deepest penetration of a slider vertex attributed to a plate facet
        (:func:`fem.contact.vertex_contact`; used if ``nodes.segments`` is set).
    surface : fem.contact.ExposedSurface, optional
        With every rim vertex among ``nodes``: the contact lengths as elements let go (Eq.
        F68c; :meth:`erode`).
    carry_across_edges : bool
        Friction history kept across the rounded edges' tangent boundaries (Eq. F16a); the
        integrator turns it on when a step fails at its smallest size.
    """

    fe: PlaneStrainQ1
    material: Material
    shape: C.SliderShape
    nodes: C.ContactNodes
    pose: np.ndarray
    penalty: float
    tangential_penalty: float
    adjust: float = 1e-9
    vertex_depth: float = 0.02
    surface: C.ExposedSurface | None = None
    carry_across_edges: bool = False

    def __post_init__(self):
        self.pose = np.asarray(self.pose, dtype=float)
        self.finite = getattr(self.fe, "kinematics", "small") == "finite"
        self.n_plate = self.fe.ndofs
        self.size = self.n_plate + 3
        self.slider_dofs = np.arange(self.n_plate, self.n_plate + 3)
        self.node_dofs = self.fe.basis.nodal_dofs[:, self.nodes.nodes]  # (2, n)
        self.reference = self.fe.mesh.p[:, self.nodes.nodes]
        cstate, self.offset = C.initial_state(
            self.shape, self.reference, self.pose, adjust=self.adjust
        )
        self.initial_contact = cstate
        self._intact_nodes = self.nodes
        self._uncovered = np.zeros(len(self.nodes), dtype=bool)  # Eq. F68c

    def erode(self, retained: np.ndarray, d: np.ndarray | None = None) -> None:
        """Let the elements keep the fractions ``retained`` (nelems,) [-] of their stiffness
        and stress (Eq. F68, finite kinematics); a contact node keeps the largest fraction
        among its elements of its tributary length, so that a torn rim's surface leaves the
        contact (its nodes are gone when all their elements are), or, with :attr:`surface`,
        the faces that the elements letting go uncover become contact surface (Eq. F68c).
        A node uncovered there for the first time at the displacements ``d`` [m, rad] takes
        the slider's penetration there, if any, as its gap adjustment δ₀ (Eq. F68c). The plate
        dofs of the vertices that no element holds any more are kept in :attr:`loose_dofs`
        (Eq. F69b)."""
        if not self.finite:
            raise ValueError("erosion needs finite kinematics")
        retained = np.asarray(retained, dtype=float)
        self.fe.retained = retained
        t = self.fe.mesh.t
        keep = np.zeros(self.fe.mesh.p.shape[1])
        for corner in t:  # a vertex keeps the most that any of its elements keeps
            np.maximum.at(keep, corner, retained)
        nodes = self._intact_nodes
        if self.surface is None:
            length = nodes.length * keep[nodes.nodes]
        else:
            length = self.surface.lengths(retained)
            new = C.first_uncovered(length, nodes.length, self._uncovered)
            if new.any() and d is not None:
                self.offset = self.offset.copy()
                self.offset[new] = C.overlap_gap(self.shape, self.slave_positions(d)[:, new],
                                                 self.slider_pose(d))
        self.nodes = replace(nodes, length=length)
        # the dofs of the vertices no element holds any more: loose material (Eq. F69b)
        self.loose_dofs = self.fe.basis.nodal_dofs[:, keep == 0.0].ravel()

    def initial_state(self) -> State:
        """Virgin material and friction history."""
        virgin = FiniteState if self.finite else MaterialState
        return State(virgin.virgin(self.fe.point_shape), self.initial_contact)

    def slave_positions(self, d: np.ndarray) -> np.ndarray:
        """Deformed slave node positions (2, n) [m]."""
        return self.reference + d[self.node_dofs]

    def slider_pose(self, d: np.ndarray) -> np.ndarray:
        """Current slider pose (X, Z, Θ) [m, m, rad]."""
        return self.pose + d[self.slider_dofs]

    def evaluate(self, d: np.ndarray, state: State) -> Evaluation:
        """f_int and K at ``d`` from the converged history ``state`` (not modified)."""
        u = d[: self.n_plate]
        f = np.zeros(self.size)
        if self.finite:
            mat, f[: self.n_plate] = self.fe.evaluate(self.material, u, state.material)
        else:
            mat = return_map(self.material, self.fe.strain(u), state.material)
            f[: self.n_plate] = self.fe.internal_force(mat.stress)
        f_mat = f.copy()
        x = self.slave_positions(d)
        pose = self.slider_pose(d)
        con = C.evaluate(
            self.shape,
            self.nodes,
            x,
            pose,
            state.contact,
            self.offset,
            self.penalty,
            self.tangential_penalty,
            self.carry_across_edges,
        )
        vc = None
        if self.nodes.segments is not None:
            vc = C.vertex_contact(self.shape, self.nodes, x, pose, self.penalty,
                                  self.vertex_depth)
            con = C.add_vertices(con, vc)
        np.add.at(f, self.node_dofs.ravel(), -con.node_force.ravel())
        f[self.slider_dofs] -= con.slider_force
        return Evaluation(f, mat, con, f_mat, self, vc)

    def tangent(self, ev: Evaluation) -> sp.csr_matrix:
        """Full tangent K = K_mat + K_c of an evaluation [N/m²]."""
        if self.finite:
            Km = self.fe.finite_stiffness(self.material, ev.material)
        else:
            Km = self.fe.stiffness(ev.material.tangent)
        # pad the plate matrix with three empty rows/columns for the slider (no copy)
        indptr = np.concatenate([Km.indptr, np.full(3, Km.indptr[-1], dtype=Km.indptr.dtype)])
        Km = sp.csr_matrix((Km.data, Km.indices, indptr), shape=(self.size, self.size))
        K = Km + C.assemble(ev.contact.stiffness, self.node_dofs, self.slider_dofs, self.size)
        dofs, blocks = self.vertex_blocks(ev)
        if blocks.size:
            rows = np.broadcast_to(dofs[:, :, None], blocks.shape).ravel()
            cols = np.broadcast_to(dofs[:, None, :], blocks.shape).ravel()
            K = K + sp.csr_matrix((blocks.ravel(), (rows, cols)), shape=K.shape)
        return K

    def material_blocks(self, ev: Evaluation, skip=None, gradient: float | None = None):
        """The elements whose material tangent differs from the elastic small-strain stiffness
        K_el of :attr:`fe` (yielding, or, with finite kinematics, also noticeably deformed:
        :meth:`fem.finite_element.FiniteStrainQ1.active_elements`), and K_mat − K_el on them.

        Parameters
        ----------
        ev : Evaluation
        skip : ndarray of bool, shape (nelems,), optional
            Finite kinematics: elements left out unless a point of theirs yields
            (:class:`fem.linear.TangentSolver`'s frozen ones).
        gradient : float [-], optional
            Finite kinematics: the displacement gradient above which an element carries its
            exact tangent (default :data:`fem.finite_element.ACTIVE_GRADIENT`).

        Returns
        -------
        elements : ndarray of int, shape (m,)
        blocks : ndarray, shape (m, 8, 8) [N/m²]
        """
        fe, mat = self.fe, ev.material
        elastic = self.material.elastic_tangent()
        if self.finite:
            e = fe.active_elements(mat, gradient)
            if skip is not None:
                e = e[~skip[e] | mat.plastic[e].any(axis=1)]
            exact = fe.element_tangent(self.material, mat, e) if e.size else np.zeros((0, 8, 8))
        else:
            e = np.flatnonzero(mat.plastic.any(axis=1))
            exact = fe.element_stiffness(mat.tangent, e) if e.size else np.zeros((0, 8, 8))
        if not e.size:
            return e, exact
        return e, exact - fe.element_stiffness(elastic, e)

    def strain_energy(self, ev: Evaluation) -> float:
        """Elastic strain energy of the plates [J/m], per unit depth: ½∫σ:C⁻¹:σ dx (small
        strain) or the Hencky energy ½∫τ̄:C⁻¹:τ̄ dV₀ (finite)."""
        if self.finite:
            return self.fe.strain_energy(self.material, ev.material)
        compliance = np.linalg.inv(self.material.elastic_tangent())
        stress = ev.material.stress
        density = 0.5 * np.einsum("ieq,ij,jeq->eq", stress, compliance, stress)
        return float((density * self.fe.dx).sum())

    def vertex_blocks(self, ev: Evaluation):
        """Full dofs (m, 7) and tangents (m, 7, 7) of the active slider-vertex contacts."""
        vc = ev.vertex
        if vc is None or not vc.active.any():
            return np.zeros((0, 7), dtype=int), np.zeros((0, 7, 7))
        k = np.flatnonzero(vc.active)
        a, b = vc.ends[:, k]
        dofs = np.concatenate(
            [self.node_dofs[:, a].T, self.node_dofs[:, b].T,
             np.broadcast_to(self.slider_dofs, (k.size, 3))], axis=1,
        )
        return dofs, vc.stiffness[:, :, k].transpose(2, 0, 1)


class Reduction:
    """``d = P a``: drop fixed dofs, tie groups of dofs to one master each.

    Parameters
    ----------
    size : int
        Number of full dofs.
    fixed : array_like of int
        Full dofs held at zero (relative frame).
    ties : sequence of array_like of int
        Each group of full dofs moves as one reduced dof (its master), appended after the
        remaining free dofs in the given order.

    Attributes
    ----------
    P : scipy.sparse.csr_matrix, shape (size, nreduced)
    free : ndarray of int
        Full index of each untied, unfixed reduced dof (in order).
    masters : ndarray of int
        Reduced index of each tie group.
    """

    def __init__(self, size: int, fixed=(), ties=()):
        fixed = np.asarray(fixed, dtype=int)
        column = np.full(size, -1)
        tied = np.zeros(size, dtype=bool)
        for group in ties:
            tied[np.asarray(group, dtype=int)] = True
        keep = np.ones(size, dtype=bool)
        keep[fixed] = False
        keep &= ~tied
        self.free = np.flatnonzero(keep)
        column[self.free] = np.arange(self.free.size)
        n = self.free.size
        self.masters = np.arange(n, n + len(ties))
        for k, group in enumerate(ties):
            g = np.asarray(group, dtype=int)
            column[g[~np.isin(g, fixed)]] = n + k
        rows = np.flatnonzero(column >= 0)
        self.size = size
        self.nreduced = n + len(ties)
        self.P = sp.csr_matrix(
            (np.ones(rows.size), (rows, column[rows])), shape=(size, self.nreduced)
        )
        self.PT = self.P.T.tocsr()

    def expand(self, a: np.ndarray) -> np.ndarray:
        """Full vector from a reduced one."""
        return self.P @ a

    def reduce(self, f: np.ndarray) -> np.ndarray:
        """Pᵀ f (forces)."""
        return self.PT @ f

    def reduce_matrix(self, K) -> sp.csr_matrix:
        """Pᵀ K P."""
        return (self.PT @ K @ self.P).tocsr()

    def index(self, full_dof: int) -> int:
        """Reduced column of a full dof (−1 if fixed)."""
        row = self.P.getrow(full_dof)
        return int(row.indices[0]) if row.nnz else -1


class StaticResult(NamedTuple):
    """Outcome of :func:`solve_static`."""

    displacement: np.ndarray  # full d [m, rad]
    state: State  # trial history at the solution (commit if converged)
    evaluation: Evaluation
    converged: bool
    iterations: int
    residuals: tuple


def solve_static(
    system: CoupledSystem,
    reduction: Reduction,
    d: np.ndarray,
    state: State,
    external_force: np.ndarray,
    prescribed: dict | None = None,
    *,
    rtol: float = 1e-8,
    max_iter: int = 30,
) -> StaticResult:
    """Newton for ``Pᵀ(f_ext − f_int(P a)) = 0`` with some reduced dofs prescribed.

    Parameters
    ----------
    system : CoupledSystem
    reduction : Reduction
    d : ndarray [m, rad]
        Full displacement at the start (must satisfy the reduction).
    state : State
        Converged history.
    external_force : ndarray, shape (size,) [N/m]
        Full external load vector.
    prescribed : dict, optional
        Reduced dof → prescribed value (displacement control).
    rtol : float
        Convergence when ‖r_free‖ ≤ rtol·max(‖Pᵀ f_ext‖, ‖Pᵀ f_int‖).
    max_iter : int

    Returns
    -------
    StaticResult
    """
    prescribed = prescribed or {}
    a = reduction.PT @ d  # exact for a 0/1 map of free and tied dofs: d = P a
    counts = np.asarray(reduction.P.sum(axis=0)).ravel()
    a = a / np.maximum(counts, 1)
    fix = np.array(sorted(prescribed), dtype=int)
    jump = np.zeros(reduction.nreduced)
    for k in fix:
        jump[k] = prescribed[int(k)] - a[k]
    pending = bool(np.any(jump != 0.0))
    free = np.setdiff1d(np.arange(reduction.nreduced), fix)
    f_ext = reduction.reduce(external_force)
    residuals = []
    for it in range(max_iter + 1):
        d = reduction.expand(a)
        ev = system.evaluate(d, state)
        f_int = reduction.reduce(ev.internal_force)
        r = f_ext - f_int
        scale = max(np.linalg.norm(f_ext), np.linalg.norm(f_int), 1e-30)
        rel = float(np.linalg.norm(r[free]) / scale)
        residuals.append(rel)
        if (rel <= rtol and not pending) or not np.isfinite(rel) or it == max_iter:
            break
        K = reduction.reduce_matrix(ev.stiffness)
        rhs = r[free]
        if pending:  # consistent predictor: impose the prescribed increment through K
            rhs = rhs - K[free][:, fix] @ jump[fix]
            a[fix] += jump[fix]
            pending = False
        step = np.zeros_like(a)
        step[free] = spsolve(K[free][:, free].tocsc(), rhs)
        a = _line_search(system, reduction, state, a, step, f_ext, free, rel, scale)
    converged = bool(residuals[-1] <= rtol and not pending)
    trial = State(ev.material.state, ev.contact.state)
    return StaticResult(d, trial, ev, converged, it, tuple(residuals))


def _line_search(system, reduction, state, a, step, f_ext, free, rel, scale, halvings=5):
    """Backtracking on the residual norm: halve the Newton step while it increases the
    relative residual (at most ``halvings`` times; the last trial is taken regardless).
    Guards semi-smooth Newton against stick/slip and open/closed ping-pong
    (docs/theory/finite-elements.md, Eq. F27)."""
    s = 1.0
    for _ in range(halvings):
        trial = a + s * step
        ev = system.evaluate(reduction.expand(trial), state)
        r = f_ext - reduction.reduce(ev.internal_force)
        if np.isfinite(r).all() and np.linalg.norm(r[free]) / scale <= max(rel, 1e-300) * 1.0:
            return trial
        s *= 0.5
    return a + s * step
