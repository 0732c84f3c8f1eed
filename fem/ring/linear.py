"""The 3-D push's linear solves: a sparse factorisation of the symmetric tangent, reused as the
preconditioner of conjugate gradients until they need more than :data:`MAX_CG` iterations, then
refactorised (docs/theory/finite-elements.md, Eq. F55). The factorisation is MKL PARDISO's
Cholesky (``pypardiso``, the ``fast`` extra) where it is installed and the matrix is positive
definite, else SciPy's SuperLU in symmetric mode.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

__all__ = ["BACKENDS", "TangentSolver", "default_backend"]

#: CG iterations with a stale factor before a new one is cheaper.
MAX_CG = 6
BACKENDS = ("pardiso", "superlu")


def default_backend() -> str:
    """``"pardiso"`` where ``pypardiso`` imports, else ``"superlu"``."""
    try:
        import pypardiso  # noqa: F401
    except ImportError:
        return "superlu"
    return "pardiso"


class TangentSolver:
    """Solves K x = b for a sequence of symmetric tangents K of one sparsity pattern.

    Parameters
    ----------
    backend : {"pardiso", "superlu"}, optional
        Default :func:`default_backend`.
    reuse : bool
        Try CG preconditioned by the last factor before factorising anew.

    Attributes
    ----------
    factorizations, cg_solves : int
        Counts of new factorisations and of solves done by preconditioned CG alone.
    """

    def __init__(self, backend: str | None = None, reuse: bool = False):
        self.backend = default_backend() if backend is None else backend
        if self.backend not in BACKENDS:
            raise ValueError(f"backend must be one of {BACKENDS}, got {backend!r}")
        self._solve = None
        self._pardiso = None
        self.reuse = reuse
        self.factorizations = 0
        self.cg_solves = 0

    def _factorize(self, A: sp.csr_matrix):
        self.factorizations += 1
        if self.backend == "pardiso":
            import pypardiso

            if self._pardiso is None:  # its constructor searches for MKL: once per solver
                self._pardiso = pypardiso.PyPardisoSolver(mtype=2)  # symmetric pos. definite
            solver = self._pardiso
            upper = sp.triu(A, format="csr")
            try:
                solver.factorize(upper)

                def solve(b, solver=solver, upper=upper):
                    return solver.solve(upper, np.ascontiguousarray(b, dtype=float))

                ones = np.ones(A.shape[0])
                x = solve(ones)
                # not positive definite: PARDISO's Cholesky perturbs pivots; SuperLU then
                if np.linalg.norm(A @ x - ones) <= 1e-8 * np.linalg.norm(ones):
                    self._solve = solve
                    return
            except pypardiso.pardiso_wrapper.PyPardisoError:
                pass
        lu = spla.splu(A.tocsc(), permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                       options={"SymmetricMode": True})
        self._solve = lu.solve

    def solve(self, A: sp.csr_matrix, b: np.ndarray) -> np.ndarray:
        """x with A x = b [units of b / units of A]: CG preconditioned by the last factor (at
        most :data:`MAX_CG` iterations; ``reuse=False`` skips it) or a new factorisation."""
        if self._solve is not None and self.reuse:
            M = spla.LinearOperator(A.shape, self._solve, dtype=float)
            x, info = spla.cg(A, b, M=M, rtol=1e-9, atol=0.0, maxiter=MAX_CG)
            if info == 0:
                self.cg_solves += 1
                return x
        self._factorize(A.tocsr())
        return self._solve(b)
