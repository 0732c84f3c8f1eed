r"""Plane-strain bilinear quadrilaterals (Q1) with the B-bar (mean dilatation) strain: the
strain–displacement array ``B`` in Mandel rows ``[ε_xx, ε_yy, ε_zz, √2 ε_xy]`` computed once from
a scikit-fem basis, strains, internal forces and the tangent by batched products scattered into
a CSR pattern computed once (docs/theory/finite-elements.md, Eqs. F10–F12).
"""

from __future__ import annotations

import math

import numpy as np
import scipy.sparse as sp
from skfem import Basis, ElementQuad1, ElementVector, Mesh

SQRT_2 = math.sqrt(2.0)


def strain_displacement(basis: Basis, bbar: bool = True) -> np.ndarray:
    """Strain–displacement array of a 2-D vector basis, Mandel rows.

    Parameters
    ----------
    basis : skfem.CellBasis
        A 2-D vector basis (e.g. ``ElementVector(ElementQuad1())``).
    bbar : bool
        Replace the dilatation by its element mean (B-bar).

    Returns
    -------
    ndarray, shape (4, nbfun, nelems, nqp) [1/m]
        ``B[:, a]`` is the strain of the a-th local basis function.
    """
    grads = np.array([phi[0].grad for phi in basis.basis])  # (nbfun, 2, 2, nel, nqp)
    B = np.zeros((4, *grads.shape[:1], *grads.shape[3:]))
    B[0] = grads[:, 0, 0]
    B[1] = grads[:, 1, 1]
    B[3] = (grads[:, 0, 1] + grads[:, 1, 0]) / SQRT_2  # √2 ε_xy with ε_xy = (u_x,y + u_y,x)/2
    if bbar:  # Eq. F11 (mean dilatation)
        theta = grads[:, 0, 0] + grads[:, 1, 1]
        dx = basis.dx
        theta_mean = (theta * dx).sum(axis=-1, keepdims=True) / dx.sum(axis=-1, keepdims=True)
        correction = (theta_mean - theta) / 3.0
        B[:3] += correction
    return B


class PlaneStrainQ1:
    """Q1 (B-bar by default) plane-strain discretisation with einsum assembly.

    Parameters
    ----------
    mesh : skfem.MeshQuad1
        Quadrilateral mesh, coordinates in [m].
    bbar : bool
        Use the mean-dilatation B-bar strain (recommended for plasticity).
    intorder : int
        Quadrature order; 2 gives the 2 × 2 Gauss rule.
    thickness : array_like, shape (nelems,), optional
        Out-of-plane thickness of each element relative to the model's depth [-] (default
        1): it multiplies the element's stiffness, forces and strain energy (Eq. F59).

    Attributes
    ----------
    basis : skfem.CellBasis
        The vector Q1 basis (reusable for post-processing and facet loads).
    B : ndarray, shape (4, 8, nelems, nqp) [1/m]
        Strain–displacement array.
    dx : ndarray, shape (nelems, nqp) [m²]
        Quadrature weights times Jacobians (per unit depth), times the element's relative
        thickness.
    """

    def __init__(self, mesh: Mesh, bbar: bool = True, intorder: int = 2, thickness=None):
        self.mesh = mesh
        self.bbar = bbar
        self.basis = Basis(mesh, ElementVector(ElementQuad1()), intorder=intorder)
        self.B = strain_displacement(self.basis, bbar=bbar)
        self.dx = self.basis.dx
        if thickness is not None:
            thickness = np.asarray(thickness, dtype=float)
            if thickness.shape != (self.dx.shape[0],) or not np.all(thickness > 0):
                raise ValueError("thickness must hold one positive factor per element")
            self.dx = self.dx * thickness[:, None]
        self.element_dofs = self.basis.element_dofs  # (8, nelems)
        self.ndofs = self.basis.N
        # Batched-matmul layout for the tangent: B as (nel, nqp, 4, 8), and Bᵀ·dx stacked over
        # the quadrature points as (nel, 8, nqp·4), so ke = (Bᵀdx) @ (D B) is one matmul.
        self._Bt = np.ascontiguousarray(self.B.transpose(2, 3, 0, 1))
        nel = self._Bt.shape[0]
        weighted = self._Bt * self.dx[:, :, None, None]
        weighted = weighted.reshape(nel, -1, self._Bt.shape[-1])
        self._BwT = np.ascontiguousarray(weighted.transpose(0, 2, 1))
        self._pattern()
        # B as one sparse matrix (rows: component, element, point): strains and forces by
        # sparse products, faster than the einsum over the gathered element dofs (BENCHMARKS.md,
        # "FE model").
        nel, nqp = self.dx.shape
        rows = np.broadcast_to(np.arange(4 * nel * nqp).reshape(4, 1, nel, nqp), self.B.shape)
        cols = np.broadcast_to(self.element_dofs[None, :, :, None], self.B.shape)
        self._Bmat = sp.csr_matrix(
            (self.B.ravel(), (rows.ravel(), cols.ravel())), shape=(4 * nel * nqp, self.ndofs)
        )
        self._BmatT = self._Bmat.T.tocsr()

    @property
    def point_shape(self) -> tuple[int, int]:
        """Shape ``(nelems, nqp)`` of quadrature-point arrays."""
        return self.dx.shape

    def _pattern(self):
        """CSR sparsity and the scatter map from element entries to CSR data (computed once)."""
        dofs = self.element_dofs
        rows = np.broadcast_to(dofs[:, None, :], (dofs.shape[0], *dofs.shape)).ravel()
        cols = np.broadcast_to(dofs[None, :, :], (dofs.shape[0], *dofs.shape)).ravel()
        keys, self._scatter = np.unique(rows * self.ndofs + cols, return_inverse=True)
        self._indices = (keys % self.ndofs).astype(np.int32)
        counts = np.bincount(keys // self.ndofs, minlength=self.ndofs)
        self._indptr = np.concatenate(([0], np.cumsum(counts))).astype(np.int32)
        self._nnz = keys.size

    def element_stiffness(self, tangent: np.ndarray, elements: np.ndarray) -> np.ndarray:
        """Element matrices ke = ∫ Bᵀ D B dx of some elements, per unit thickness.

        Parameters
        ----------
        tangent : ndarray, shape (4, 4, nelems, nqp) or (4, 4) [Pa]
            Material tangent of *all* elements (Mandel), or one matrix for every point.
        elements : ndarray of int, shape (m,)
            Element indices.

        Returns
        -------
        ndarray, shape (m, 8, 8) [N/m²]
            Rows and columns in the order of ``element_dofs[:, e]``.
        """
        elements = np.asarray(elements, dtype=np.int64)
        D = tangent if tangent.ndim == 2 else tangent[:, :, elements].transpose(2, 3, 0, 1)
        DB = np.matmul(D, self._Bt[elements])
        m = DB.shape[0]
        return np.matmul(self._BwT[elements], DB.reshape(m, -1, DB.shape[-1]))

    def strain(self, u: np.ndarray) -> np.ndarray:
        """Mandel strain of a displacement vector at the quadrature points.

        Parameters
        ----------
        u : ndarray, shape (ndofs,) [m]

        Returns
        -------
        ndarray, shape (4, nelems, nqp) [-]
        """
        return (self._Bmat @ u).reshape(4, *self.dx.shape)

    def internal_force(self, stress: np.ndarray) -> np.ndarray:
        """f_int = Σ_e ∫ Bᵀσ dx, per unit thickness (Eq. F12).

        Parameters
        ----------
        stress : ndarray, shape (4, nelems, nqp) [Pa]

        Returns
        -------
        ndarray, shape (ndofs,) [N/m]
        """
        return self._BmatT @ (stress * self.dx).ravel()

    def stiffness(self, tangent: np.ndarray) -> sp.csr_matrix:
        """K = Σ_e ∫ Bᵀ D B dx, per unit thickness (Eq. F12).

        Parameters
        ----------
        tangent : ndarray, shape (4, 4, nelems, nqp) or (4, 4) [Pa]
            Material tangent in Mandel form; a (4, 4) matrix is used at every point.

        Returns
        -------
        scipy.sparse.csr_matrix, shape (ndofs, ndofs) [N/m²]
        """
        D = tangent if tangent.ndim == 2 else tangent.transpose(2, 3, 0, 1)
        DB = np.matmul(D, self._Bt)  # (nel, nqp, 4, 8)
        nel = DB.shape[0]
        ke = np.matmul(self._BwT, DB.reshape(nel, -1, DB.shape[-1]))  # (nel, 8, 8)
        data = np.bincount(self._scatter, ke.transpose(1, 2, 0).ravel(), minlength=self._nnz)
        return sp.csr_matrix(
            (data, self._indices, self._indptr), shape=(self.ndofs, self.ndofs)
        )
