r"""Newton's linear solves for the HHT-α iteration, (c₀M + sK)x = r: a sparse LU of the elastic
matrix cached per step size, plus a low-rank (Woodbury) update for the few degrees of freedom
that contact, plasticity or finite deformation touch, polished by iterative refinement against
the exact matrix and backed by a direct sparse solve (docs/theory/finite-elements.md, Eqs.
F32–F35). At small strain the linear systems are those of a direct solve; with finite
deformation elastic elements may carry a frozen tangent (Eq. F35a).
"""

from __future__ import annotations

from collections import OrderedDict

import numpy as np
import scipy.linalg as la
import scipy.sparse as sp
from scipy.sparse.linalg import splu, spsolve

#: Relative residual ‖r − K x‖/‖r‖ accepted from the Woodbury solve (Eq. F35), near what a
#: direct sparse LU of these matrices reaches (measured: docs/theory/finite-elements.md,
#: "Linear solves"); more is refined, and what cannot be refined is solved directly.
REFINE_TOL = 1e-12

#: With finite kinematics, the number of elastic elements carrying their own tangent in the
#: low-rank update beyond which the LU is refactored with their tangents in it, frozen
#: (Eq. F35a; measured: BENCHMARKS.md, "Finite deformation against small strain").
FREEZE_AFTER = 24

#: Once elements have torn (Eq. F35b), the displacement gradient [-] above which an element
#: carries its exact tangent in the assembled matrix; those below keep the small-strain
#: elastic one. Ten times finer than :data:`fem.finite_element.ACTIVE_GRADIENT`: near a tear
#: that threshold multiplied Newton's iterations (measured: docs/theory/finite-elements.md,
#: Eq. F35b).
TORN_ACTIVE_GRADIENT = 1e-3


def factorize(A: sp.spmatrix):
    """Sparse LU of a (nearly) symmetric matrix: minimum degree on Aᵀ + A, diagonal pivots
    preferred (SuperLU's symmetric mode, chosen for speed: docs/theory/finite-elements.md,
    "Linear solves")."""
    return splu(
        sp.csc_matrix(A), permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.1,
        options={"SymmetricMode": True},
    )


class _Base:
    """LU of A = c₀M + s(K_el + Σ D_e) for one (c₀, s), D_e the frozen elastic elements'
    K_e − K_el,e (none at first; Eq. F35a), and the cached columns A⁻¹ e_j."""

    def __init__(self, A, n, capacity, frozen=None, blocks=None):
        self.lu = factorize(A)
        self.A = A
        self.frozen = frozen  # bool per element, or None
        self.blocks = blocks  # D_e of the frozen elements, (m, 8, 8) in element order
        self.stale = False  # refreeze at the next solve (TangentSolver.thaw)
        if frozen is not None:
            self.slot = np.cumsum(frozen) - 1
        self.last = (None, None, None)  # S, C = A⁻¹E_S (contiguous), G = Eᵀ C
        self.where = np.full(n, -1)  # reduced dof → column slot
        self.cols = np.empty((n, capacity), order="F")
        self.count = 0

    def columns(self, dofs: np.ndarray) -> np.ndarray:
        """Slots of A⁻¹ e_j for the reduced dofs ``dofs``, computing the missing ones."""
        missing = dofs[self.where[dofs] < 0]
        if missing.size:
            if self.count + missing.size > self.cols.shape[1]:
                self.where[:] = -1  # full: start over (the needed ones are recomputed)
                self.count = 0
                missing = dofs
            E = np.zeros((self.cols.shape[0], missing.size))
            E[missing, np.arange(missing.size)] = 1.0
            slots = np.arange(self.count, self.count + missing.size)
            self.cols[:, slots] = self.lu.solve(E)
            self.where[missing] = slots
            self.count += missing.size
        return self.where[dofs]


class TangentSolver:
    """Solves (c₀ M + s K) x = r for an evaluation of a :class:`fem.system.CoupledSystem`.

    Parameters
    ----------
    system : fem.system.CoupledSystem
    reduction : fem.system.Reduction
    mass : ndarray, shape (nreduced,) [kg/m, kg·m²/m]
        Lumped reduced mass.
    keep : int
        Factorizations kept, one per distinct (c₀, s) (time steps recur after impacts).
    capacity : int
        Cached columns per factorization before the cache starts over; also the largest
        modified set S solved by the low-rank update (a larger one is solved directly).

    Attributes
    ----------
    factorizations, fallbacks, solves, freezes : int
        Counters (fallbacks: direct sparse solves after a failed refinement; freezes:
        factorizations with frozen element tangents, Eq. F35a).
    """

    def __init__(self, system, reduction, mass, *, keep: int = 4, capacity: int = 1200):
        self.system = system
        self.red = reduction
        self.M = np.asarray(mass, dtype=float)
        n = reduction.nreduced
        self.n = n
        self.keep = keep
        self.capacity = min(capacity, n)
        P = reduction.P.tocsr()
        col = np.full(reduction.size, -1)
        has = np.diff(P.indptr) > 0
        col[has] = P.indices[P.indptr[:-1][has]]
        self._col = col
        fe = system.fe
        self._C = system.material.elastic_tangent()
        Pp = P[: system.n_plate]
        self.K_el = (Pp.T @ fe.stiffness(self._C) @ Pp).tocsr()
        self._elem = col[fe.element_dofs].T  # (nel, 8) reduced dofs, −1 fixed
        self._node = col[system.node_dofs].T  # (n, 2)
        self._slider = col[system.slider_dofs]
        self._bases: OrderedDict = OrderedDict()
        self._elastic: OrderedDict = OrderedDict()  # c₀M + sK_el per (c₀, s), torn solves
        self.factorizations = self.fallbacks = self.solves = self.freezes = 0

    def _base(self, c0: float, s: float) -> _Base:
        key = (c0, s)
        base = self._bases.get(key)
        if base is None:
            A = (sp.diags(c0 * self.M) + s * self.K_el).tocsc()
            base = _Base(A, self.n, self.capacity)
            self.factorizations += 1
            self._bases[key] = base
            while len(self._bases) > self.keep:
                self._bases.popitem(last=False)
        else:
            self._bases.move_to_end(key)
        return base

    def modification(self, ev, s: float, base: _Base | None = None,
                     gradient: float | None = None):
        """The reduced dofs S, the dense block W = s(ΔK_mat + K_c) on them (ΔK_mat taken
        against ``base``'s frozen elements, which are left out while elastic; ``gradient``:
        :meth:`fem.system.CoupledSystem.material_blocks`'), and the number of elastic elements
        in it."""
        S, flat, values, elastic = self._scattered(ev, s, base, gradient)
        W = np.bincount(flat, values, minlength=S.size * S.size).reshape(S.size, S.size)
        return S, W, elastic

    def sparse_modification(self, ev, s: float, gradient: float | None = None):
        """S and the nonzero entries of :meth:`modification`'s W as rows, columns (reduced
        dofs) and values, row by row: the same sums without forming the dense |S| × |S| block
        (the torn solves' S spans most of a rim)."""
        S, flat, values, _ = self._scattered(ev, s, None, gradient)
        entries, which = np.unique(flat, return_inverse=True)
        sums = np.bincount(which, values, minlength=entries.size)  # in the order of W's sums
        nonzero = sums != 0.0
        entries, sums = entries[nonzero], sums[nonzero]
        return S, S[entries // max(S.size, 1)], S[entries % max(S.size, 1)], sums

    def _scattered(self, ev, s: float, base: _Base | None, gradient: float | None):
        """S, and W's contributions as positions in the row-major |S| × |S| block with their
        values (summed in this order), and the number of elastic elements."""
        blocks, dofs = [], []
        con = ev.contact
        active = np.flatnonzero(con.active)
        if active.size:
            blocks.append(con.stiffness[:, :, active].transpose(2, 0, 1))
            dofs.append(np.concatenate(
                [self._node[active], np.broadcast_to(self._slider, (active.size, 3))], axis=1
            ))
        vdofs, vblocks = self.system.vertex_blocks(ev)
        if vblocks.size:
            blocks.append(vblocks)
            dofs.append(self._col[vdofs])
        frozen = base.frozen if base is not None else None
        elements, material = self.system.material_blocks(ev, frozen, gradient)
        elastic = int((~ev.material.plastic[elements].any(axis=1)).sum())
        if frozen is not None and elements.size:
            hit = frozen[elements]  # frozen but yielding now: against their frozen block
            material[hit] -= base.blocks[base.slot[elements[hit]]]
        if elements.size:
            blocks.append(material)
            dofs.append(self._elem[elements])
        if not blocks:
            return np.zeros(0, dtype=int), np.zeros(0, dtype=int), np.zeros(0), elastic
        # pad every block to 8 × 8 so that all can be scattered at once
        kk, dd = [], []
        for b, d in zip(blocks, dofs, strict=True):
            m, k = d.shape
            bb = np.zeros((m, 8, 8))
            bb[:, :k, :k] = b
            di = np.full((m, 8), -1)
            di[:, :k] = d
            kk.append(bb)
            dd.append(di)
        B = np.concatenate(kk)
        D = np.concatenate(dd)
        S = np.unique(D[D >= 0])
        loc = np.where(D >= 0, np.searchsorted(S, np.maximum(D, 0)), -1)
        keep = (loc[:, :, None] >= 0) & (loc[:, None, :] >= 0)
        flat = (loc[:, :, None] * S.size + loc[:, None, :])[keep]
        return S, flat, s * B[keep], elastic

    def thaw(self) -> None:
        """Make every factorization with frozen tangents refreeze them at its next solve (after
        a step Newton could not do: the frozen tangents may have drifted too far; Eq. F35a)."""
        for base in self._bases.values():
            base.stale = True

    def _freeze(self, ev, c0: float, s: float) -> _Base:
        """Refactor the (c₀, s) base with the current tangents of every elastic element that
        carries its own (Eq. F35a)."""
        sysm = self.system
        fe, mat = sysm.fe, ev.material
        e = fe.active_elements(mat)
        e = e[~mat.plastic[e].any(axis=1)]
        D = (fe.element_tangent(sysm.material, mat, e)
             - fe.element_stiffness(sysm.material.elastic_tangent(), e)) if e.size else (
            np.zeros((0, 8, 8)))
        dofs = self._elem[e]  # (m, 8), −1 fixed
        keep = (dofs[:, :, None] >= 0) & (dofs[:, None, :] >= 0)
        rows = np.broadcast_to(dofs[:, :, None], keep.shape)[keep]
        cols = np.broadcast_to(dofs[:, None, :], keep.shape)[keep]
        extra = sp.csr_matrix((s * D[keep], (rows, cols)), shape=(self.n, self.n))
        A = (sp.diags(c0 * self.M) + s * self.K_el + extra).tocsc()
        frozen = np.zeros(fe.element_dofs.shape[1], dtype=bool)
        frozen[e] = True
        base = _Base(A, self.n, self.capacity, frozen, D)
        self.factorizations += 1
        self.freezes += 1
        self._bases[(c0, s)] = base
        return base

    def solve(self, ev, c0: float, s: float, rhs: np.ndarray) -> np.ndarray:
        """x with (c₀ M + s K(ev)) x = rhs, to a relative residual ≤ :data:`REFINE_TOL`
        (Eqs. F32–F35), K with the frozen elastic tangents of Eq. F35a if any.

        Parameters
        ----------
        ev : fem.system.Evaluation
        c0 : float [1/s²]
            Mass coefficient 1/(βΔt²).
        s : float [-]
            Stiffness coefficient 1 + α.
        rhs : ndarray, shape (nreduced,) [N/m]
        """
        self.solves += 1
        retained = getattr(self.system.fe, "retained", None)
        if retained is not None and (retained < 1.0).any():
            # torn elements let go (Eq. F68): the update of the intact elastic matrix would
            # span them and cancel their stiffness, ill-conditioned; solve the matrix itself
            return self._torn(ev, c0, s, rhs)
        base = self._base(c0, s)
        if base.frozen is not None and base.stale:
            base = self._freeze(ev, c0, s)
        S, W, elastic = self.modification(ev, s, base)
        if self.system.finite and elastic > FREEZE_AFTER:
            base = self._freeze(ev, c0, s)
            S, W, elastic = self.modification(ev, s, base)
        if S.size > self.capacity:  # too much yields or touches for a low-rank update
            return self._direct(ev, c0, s, rhs)
        S_last, Cs, Gs = base.last
        if S_last is None or not np.array_equal(S, S_last):  # else the active set is unchanged
            Cs = base.cols[:, base.columns(S)]
            Gs = Cs[S]
            base.last = (S, Cs, Gs)
        # The slider's dofs are decoupled in A (diagonal c₀m, K_el has no slider entries), so
        # their diagonal in A can be changed per solve at no cost: move W's slider diagonal into
        # A (d = c₀m + W_ii) and out of W, which keeps the small matrix below well conditioned
        # (docs/theory/finite-elements.md, "Linear solves").
        sl = self._slider
        pos = np.searchsorted(S, sl)
        ok = pos < S.size
        ok[ok] = S[pos[ok]] == sl[ok]
        sl, pos = sl[ok], pos[ok]
        Ws = W
        d = None
        if sl.size:
            shift = np.maximum(np.diag(W)[pos], 0.0)
            d = c0 * self.M[sl] + shift
            Ws = W.copy()
            Ws[pos, pos] -= shift
            Cs[sl, pos] = 1.0 / d  # the cached slider columns are rewritten on every solve
            Gs[pos, pos] = 1.0 / d
        if S.size:  # Woodbury, Eq. F34
            lu_small = la.lu_factor(np.eye(S.size) + Ws @ Gs)

        def apply(r):
            y = base.lu.solve(r)
            if d is not None:
                y[sl] = r[sl] / d
            if S.size:
                y -= Cs @ la.lu_solve(lu_small, Ws @ y[S])
            return y

        def residual(x):
            out = rhs - base.A @ x
            if S.size:
                out[S] -= W @ x[S]
            return out

        scale = float(np.linalg.norm(rhs))
        x = apply(rhs)
        r = residual(x)
        norm = float(np.linalg.norm(r))
        for _ in range(3):  # iterative refinement, Eq. F35
            if not np.isfinite(norm) or norm <= REFINE_TOL * scale:
                break
            x += apply(r)
            r = residual(x)
            new = float(np.linalg.norm(r))
            if not new < 0.5 * norm:
                norm = new
                break
            norm = new
        if np.isfinite(norm) and norm <= REFINE_TOL * scale:
            return x
        return self._direct(ev, c0, s, rhs)

    def _direct(self, ev, c0, s, rhs):
        """Direct sparse LU of the assembled matrix (the fallback)."""
        self.fallbacks += 1
        return self._assembled(ev, c0, s, rhs)

    def _torn(self, ev, c0, s, rhs):
        """x from a sparse LU of c₀M + s(K_el + W), W the exact tangent less K_el on the
        elements past :data:`TORN_ACTIVE_GRADIENT` and the contacts (Eq. F35b)."""
        S, rows, cols, values = self.sparse_modification(ev, s, gradient=TORN_ACTIVE_GRADIENT)
        A = self._elastic.get((c0, s))
        if A is None:
            A = self._elastic[(c0, s)] = sp.diags(c0 * self.M) + s * self.K_el
            while len(self._elastic) > self.keep:
                self._elastic.popitem(last=False)
        if S.size:
            A = A + sp.csr_matrix((values, (rows, cols)), shape=A.shape)
        return factorize(A).solve(rhs)

    def _assembled(self, ev, c0, s, rhs):
        """x from a sparse LU of the assembled (c₀ M + s K(ev))."""
        K = self.red.reduce_matrix(ev.stiffness) * s + sp.diags(c0 * self.M)
        return spsolve(K.tocsc(), rhs)
