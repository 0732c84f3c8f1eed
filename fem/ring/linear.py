"""The 3-D push's linear solves: a sparse factorisation of the symmetric tangent
(docs/theory/finite-elements.md, Eq. F55). The factorisation is MKL PARDISO's (``pypardiso``,
the ``fast`` extra) where it is installed, else SciPy's SuperLU in symmetric mode. PARDISO's
analysis of the sparsity pattern (its reordering) is done once per pattern and reused by every
later factorisation of a matrix of that pattern; Cholesky first, and where the tangent is not
positive definite (the contact's curvature term, Eq. F57, on a wild Newton iterate) PARDISO's
symmetric indefinite factorisation, then SuperLU.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

__all__ = ["BACKENDS", "TangentSolver", "default_backend"]

BACKENDS = ("pardiso", "superlu")
#: PARDISO's matrix types: real symmetric positive definite, real symmetric indefinite.
CHOLESKY, INDEFINITE = 2, -2
#: A factorisation is accepted when it solves A x = 1 to this relative residual.
ACCURACY = 1e-8


def default_backend() -> str:
    """``"pardiso"`` where ``pypardiso`` imports, else ``"superlu"``."""
    try:
        import pypardiso  # noqa: F401
    except ImportError:
        return "superlu"
    return "pardiso"


class _Pardiso:
    """One PARDISO solver of a matrix type, which analyses a sparsity pattern once (phase 11)
    and then factorises (phase 22) and solves (phase 33) matrices of that pattern. It drives
    ``pypardiso.PyPardisoSolver`` by its phases, which that class exposes through
    ``set_phase`` and ``_call_pardiso``."""

    def __init__(self, mtype: int):
        import pypardiso

        self.solver = pypardiso.PyPardisoSolver(mtype=mtype)  # searches for MKL: once
        self.error = pypardiso.pardiso_wrapper.PyPardisoError
        self.pattern = None
        self.upper = None

    def _phase(self, phase: int, b: np.ndarray) -> np.ndarray:
        self.solver.set_phase(phase)
        return self.solver._call_pardiso(self.upper, b)

    def factorize(self, upper: sp.csr_matrix) -> bool:
        """Factorise the upper triangle (CSR, sorted indices); False where PARDISO refuses."""
        self.solver._check_A(upper)
        zero = np.zeros((upper.shape[0], 1))
        same = (self.pattern is not None and np.array_equal(self.pattern[0], upper.indptr)
                and np.array_equal(self.pattern[1], upper.indices))
        self.upper = upper
        try:
            if not same:
                self.pattern = None
                self._phase(11, zero)
                self.pattern = (upper.indptr.copy(), upper.indices.copy())
            self._phase(22, zero)
        except self.error:
            return False
        return True

    def solve(self, b: np.ndarray) -> np.ndarray:
        """x with A x = b, A the last factorised matrix."""
        return self._phase(33, np.asfortranarray(b, dtype=float))


class TangentSolver:
    """Solves K x = b for a sequence of symmetric tangents K, most of one sparsity pattern.

    Parameters
    ----------
    backend : {"pardiso", "superlu"}, optional
        Default :func:`default_backend`.

    Attributes
    ----------
    factorizations : int
        Count of factorisations, the ones refused or rejected included.
    indefinite : int
        Solves that PARDISO's Cholesky did not take (its indefinite factorisation's or
        SuperLU's).
    """

    def __init__(self, backend: str | None = None):
        self.backend = default_backend() if backend is None else backend
        if self.backend not in BACKENDS:
            raise ValueError(f"backend must be one of {BACKENDS}, got {backend!r}")
        self._pardiso: dict[int, _Pardiso] = {}
        self._upper = None  # (indptr, indices, data positions) of the last pattern's triangle
        self.factorizations = 0
        self.indefinite = 0

    def _triangle(self, A: sp.csr_matrix) -> sp.csr_matrix:
        """The upper triangle of A, its positions in A.data found once per pattern."""
        cached = self._upper
        if cached is None or not (np.array_equal(cached[0], A.indptr)
                                  and np.array_equal(cached[1], A.indices)):
            marker = sp.csr_matrix((np.arange(1.0, A.nnz + 1), A.indices, A.indptr),
                                   shape=A.shape)
            upper = sp.triu(marker, format="csr")
            upper.sort_indices()
            cached = (A.indptr.copy(), A.indices.copy(), upper.indptr, upper.indices,
                      upper.data.astype(np.int64) - 1)
            self._upper = cached
        return sp.csr_matrix((A.data[cached[4]], cached[3], cached[2]), shape=A.shape)

    def _factorizations(self, A: sp.csr_matrix):
        """The factorisations to try, in order: (name, function b → x), each made on demand."""
        if self.backend == "pardiso":
            upper = self._triangle(A)
            for mtype, name in ((CHOLESKY, "cholesky"), (INDEFINITE, "indefinite")):
                if mtype not in self._pardiso:
                    self._pardiso[mtype] = _Pardiso(mtype)
                solver = self._pardiso[mtype]
                self.factorizations += 1
                if solver.factorize(upper):
                    yield name, solver.solve
        self.factorizations += 1
        lu = spla.splu(A.tocsc(), permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                       options={"SymmetricMode": True})
        yield "superlu", lu.solve

    def solve(self, A: sp.csr_matrix, b: np.ndarray) -> np.ndarray:
        """x with A x = b [units of b / units of A], by a new factorisation of A: the first
        of PARDISO's Cholesky, its indefinite factorisation and SuperLU whose x leaves a
        residual within :data:`ACCURACY` of b (PARDISO perturbs tiny pivots rather than
        fail); SuperLU's x in any case."""
        A = A.tocsr()
        A.sort_indices()
        b = np.asarray(b, dtype=float)
        for name, solve in self._factorizations(A):
            x = np.reshape(solve(b), b.shape)
            if name == "superlu" or (np.linalg.norm(A @ x - b)
                                     <= ACCURACY * np.linalg.norm(b)):
                self.indefinite += name != "cholesky"
                return x
