r"""The coupled plate–slider system: internal forces, tangents, dof reduction, static Newton.

Full unknowns ``d = [u, q]``: the plate displacements ``u`` (scikit-fem's dof order of the
vector Q1 basis) followed by the slider's displacement ``q = (X, Z, Θ) − q₀`` from its initial
pose ``q₀``. Internal forces are ``f_int = f_mat(u) − F_c(d)`` (material, per unit depth, and
the contact force of :mod:`fem.contact`) with the tangent ``K = K_mat + K_c``.

Constraints are applied by a reduction ``d = P a`` (:class:`Reduction`): supported dofs
vanish and tied dofs (the superstructure block's top, rotation locked) share one master
column, so ``K_red = Pᵀ K P``, ``r_red = Pᵀ r`` and a lumped mass stays diagonal.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import spsolve

from fem import contact as C
from fem.assembly import PlaneStrainQ1
from fem.material import Material, MaterialState, ReturnMapResult, return_map


class Evaluation(NamedTuple):
    """Internal force and tangent at one iterate (full dofs, per unit depth)."""

    internal_force: np.ndarray
    stiffness: sp.csr_matrix
    material: ReturnMapResult
    contact: C.ContactResult
    material_force: np.ndarray


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
    """

    fe: PlaneStrainQ1
    material: Material
    shape: C.SliderShape
    nodes: C.ContactNodes
    pose: np.ndarray
    penalty: float
    tangential_penalty: float
    adjust: float = 1e-9

    def __post_init__(self):
        self.pose = np.asarray(self.pose, dtype=float)
        self.n_plate = self.fe.ndofs
        self.size = self.n_plate + 3
        self.slider_dofs = np.arange(self.n_plate, self.n_plate + 3)
        self.node_dofs = self.fe.basis.nodal_dofs[:, self.nodes.nodes]  # (2, n)
        self.reference = self.fe.mesh.p[:, self.nodes.nodes]
        cstate, self.offset = C.initial_state(
            self.shape, self.reference, self.pose, adjust=self.adjust
        )
        self.initial_contact = cstate

    def initial_state(self) -> State:
        """Virgin material and friction history."""
        return State(MaterialState.virgin(self.fe.point_shape), self.initial_contact)

    def slave_positions(self, d: np.ndarray) -> np.ndarray:
        """Deformed slave node positions (2, n) [m]."""
        return self.reference + d[self.node_dofs]

    def slider_pose(self, d: np.ndarray) -> np.ndarray:
        """Current slider pose (X, Z, Θ) [m, m, rad]."""
        return self.pose + d[self.slider_dofs]

    def evaluate(self, d: np.ndarray, state: State) -> Evaluation:
        """f_int and K at ``d`` from the converged history ``state`` (not modified)."""
        u = d[: self.n_plate]
        mat = return_map(self.material, self.fe.strain(u), state.material)
        f = np.zeros(self.size)
        f[: self.n_plate] = self.fe.internal_force(mat.stress)
        f_mat = f.copy()
        con = C.evaluate(
            self.shape,
            self.nodes,
            self.slave_positions(d),
            self.slider_pose(d),
            state.contact,
            self.offset,
            self.penalty,
            self.tangential_penalty,
        )
        np.add.at(f, self.node_dofs.ravel(), -con.node_force.ravel())
        f[self.slider_dofs] -= con.slider_force
        Km = self.fe.stiffness(mat.tangent)
        # pad the plate matrix with three empty rows/columns for the slider (no copy)
        indptr = np.concatenate([Km.indptr, np.full(3, Km.indptr[-1], dtype=Km.indptr.dtype)])
        Km = sp.csr_matrix((Km.data, Km.indices, indptr), shape=(self.size, self.size))
        K = Km + C.assemble(con.stiffness, self.node_dofs, self.slider_dofs, self.size)
        return Evaluation(f, K, mat, con, f_mat)


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
    Guards semi-smooth Newton against stick/slip and open/closed ping-pong (fem.md §4)."""
    s = 1.0
    for _ in range(halvings):
        trial = a + s * step
        ev = system.evaluate(reduction.expand(trial), state)
        r = f_ext - reduction.reduce(ev.internal_force)
        if np.isfinite(r).all() and np.linalg.norm(r[free]) / scale <= max(rel, 1e-300) * 1.0:
            return trial
        s *= 0.5
    return a + s * step
