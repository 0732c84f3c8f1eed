r"""Small-strain J2 plasticity in 3-D on 20-node serendipity hexahedra with 2 × 2 × 2 Gauss
points (the element CalculiX and Abaqus call C3D20R): strains in Mandel 6-vectors
``[xx, yy, zz, √2·yz, √2·xz, √2·xy]``, the radial return with capped linear hardening and its
consistent tangent (the 3-D form of docs/theory/finite-elements.md, Eqs. F4–F9), internal
forces and the tangent by batched products scattered into a CSR pattern computed once (Eq. F55).

:class:`Solid` holds the discretisation; :func:`return_map_3d` is the material point.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
import scipy.sparse as sp

from fem.material import Material

__all__ = ["Solid", "SolidState", "elastic_matrix", "return_map_3d", "von_mises_6"]

SQRT_2 = math.sqrt(2.0)
INTORDER = 3
IDENTITY_6 = np.array([1.0, 1.0, 1.0, 0.0, 0.0, 0.0])
DEVIATORIC_6 = np.eye(6) - np.outer(IDENTITY_6, IDENTITY_6) / 3.0


def elastic_matrix(material: Material) -> np.ndarray:
    """C = K 1⊗1 + 2G P_dev as a Mandel (6, 6) matrix [Pa] (Eq. F5)."""
    return (material.bulk_modulus * np.outer(IDENTITY_6, IDENTITY_6)
            + 2.0 * material.shear_modulus * DEVIATORIC_6)


def von_mises_6(stress: np.ndarray) -> np.ndarray:
    """Von Mises stress √(3/2)‖dev σ‖ [Pa] of Mandel 6-vectors (6, ...) [Pa]."""
    dev = np.array(stress, dtype=float)
    dev[:3] -= dev[:3].sum(axis=0) / 3.0
    return np.sqrt(1.5 * (dev * dev).sum(axis=0))


class SolidState(NamedTuple):
    """History at the quadrature points (never modified in place).

    Attributes
    ----------
    plastic_strain : ndarray, shape (6, nelems, nqp) [-]
        ε^p, Mandel.
    eq_plastic_strain : ndarray, shape (nelems, nqp) [-]
        p = ∫ √(2/3)‖dε^p‖.
    """

    plastic_strain: np.ndarray
    eq_plastic_strain: np.ndarray

    @classmethod
    def virgin(cls, shape) -> SolidState:
        """Zero plastic strain at points of shape ``(nelems, nqp)``."""
        return cls(np.zeros((6, *shape)), np.zeros(shape))


def return_map_3d(material: Material, strain: np.ndarray, state: SolidState):
    """Backward-Euler radial return of J2 with capped linear hardening (Eqs. F6–F8 in 3-D).

    Parameters
    ----------
    material : fem.Material
    strain : ndarray, shape (6, ...) [-]
        Total strain at the end of the increment (Mandel).
    state : SolidState
        The last converged history.

    Returns
    -------
    stress : ndarray, shape (6, ...) [Pa]
    tangent : ndarray, shape (6, 6, ...) [Pa]
        Consistent tangent dσ/dε (Eq. F9).
    state : SolidState
        The trial history (commit once the increment has converged).
    plastic : ndarray of bool, shape (...)
    """
    G, K = material.shear_modulus, material.bulk_modulus
    H, f_y, f_u = material.plastic_modulus, material.yield_stress, material.ultimate_stress
    p_u = material.ultimate_plastic_strain
    trial = strain - state.plastic_strain
    vol = trial[:3].sum(axis=0)
    dev = trial.copy()
    dev[:3] -= vol / 3.0
    s_tr = 2.0 * G * dev
    norm = np.sqrt((s_tr * s_tr).sum(axis=0))
    q = math.sqrt(1.5) * norm
    p_n = state.eq_plastic_strain
    f = q - np.minimum(f_y + H * p_n, f_u)
    plastic = f > 0.0
    dp = np.where(plastic, f / (3.0 * G + H), 0.0)
    flat = plastic & (p_n + dp > p_u)  # past the kink: the flat branch (Eq. F7)
    dp = np.where(flat, (q - f_u) / (3.0 * G), dp)
    safe = np.where(norm > 0, norm, 1.0)
    n_hat = s_tr / safe
    d_eps_p = math.sqrt(1.5) * dp * n_hat
    stress = s_tr - 2.0 * G * d_eps_p
    stress[:3] += K * vol
    new = SolidState(state.plastic_strain + d_eps_p, p_n + dp)
    extra = (1,) * (strain.ndim - 1)
    elastic = elastic_matrix(material).reshape(6, 6, *extra)
    tangent = np.array(np.broadcast_to(elastic, (6, 6, *strain.shape[1:])))
    if plastic.any():  # Eq. F9
        m = plastic
        ratio = dp[m] / q[m]
        h_alg = np.where(flat[m], 0.0, H)
        beta = 6.0 * G * G * (ratio - 1.0 / (3.0 * G + h_alg))
        nm = n_hat[:, m]
        tangent[:, :, m] = ((K * np.outer(IDENTITY_6, IDENTITY_6))[:, :, None]
                            + (2.0 * G * DEVIATORIC_6)[:, :, None] * (1.0 - 3.0 * G * ratio)
                            + beta * nm[:, None, :] * nm[None, :, :])
    return stress, tangent, new, plastic


class Solid:
    """The 3-D solid: a vector 20-node serendipity basis with 2 × 2 × 2 Gauss points, its
    strain–displacement array and the sparse pattern of its stiffness.

    Parameters
    ----------
    mesh : skfem.MeshHex1
        Coordinates [m].

    Attributes
    ----------
    basis : skfem.CellBasis
    B : ndarray, shape (6, 60, nelems, nqp) [1/m]
    weights : ndarray, shape (nelems, nqp) [m³]
    ndofs : int
    """

    def __init__(self, mesh):
        from skfem import Basis, ElementHexS2, ElementVector

        self.mesh = mesh
        self.basis = Basis(mesh, ElementVector(ElementHexS2()), intorder=INTORDER)
        grads = np.array([phi[0].grad for phi in self.basis.basis])  # (60, 3, 3, nel, nqp)
        B = np.empty((6, *grads.shape[:1], *grads.shape[3:]))
        B[0], B[1], B[2] = grads[:, 0, 0], grads[:, 1, 1], grads[:, 2, 2]
        B[3] = (grads[:, 1, 2] + grads[:, 2, 1]) / SQRT_2
        B[4] = (grads[:, 0, 2] + grads[:, 2, 0]) / SQRT_2
        B[5] = (grads[:, 0, 1] + grads[:, 1, 0]) / SQRT_2
        self.B = B
        self.weights = np.asarray(self.basis.dx)
        self.dofs = np.asarray(self.basis.element_dofs)  # (60, nel)
        self.ndofs = self.basis.N
        nb = self.dofs.shape[0]
        # element matrices in (e, a, b) order; the CSR slot of each entry
        rows = np.repeat(self.dofs.T[:, :, None], nb, axis=2).ravel()
        cols = np.repeat(self.dofs.T[:, None, :], nb, axis=1).ravel()
        key = rows.astype(np.int64) * self.ndofs + cols
        unique, self._slots = np.unique(key, return_inverse=True)
        indptr = np.concatenate([[0], np.cumsum(np.bincount(unique // self.ndofs,
                                                            minlength=self.ndofs))])
        self._indices = (unique % self.ndofs).astype(np.int32)
        self._indptr = indptr.astype(np.int64)
        self._Bt = np.ascontiguousarray(B.transpose(2, 3, 0, 1))  # (e, q, 6, 60)
        self._elastic = None

    @property
    def point_shape(self) -> tuple[int, int]:
        """(nelems, nqp)."""
        return self.weights.shape

    def strain(self, u: np.ndarray) -> np.ndarray:
        """Mandel strains (6, nelems, nqp) [-] of nodal displacements ``u`` [m]."""
        return np.einsum("iaeq,ae->ieq", self.B, u[self.dofs])

    def internal_force(self, stress: np.ndarray) -> np.ndarray:
        """∫ Bᵀσ dV assembled [N] from stresses (6, nelems, nqp) [Pa]."""
        fe = np.einsum("iaeq,ieq,eq->ae", self.B, stress, self.weights)
        return np.bincount(self.dofs.ravel(), fe.ravel(), minlength=self.ndofs)

    def element_matrices(self, tangent: np.ndarray, elements=slice(None)) -> np.ndarray:
        """∫ Bᵀ D B dV of the given elements, shape (nelems, 60, 60) [N/m], from tangents
        (6, 6, nelems, nqp) [Pa] of those elements."""
        Bt = self._Bt[elements]
        DB = np.matmul(np.ascontiguousarray(tangent.transpose(2, 3, 0, 1)), Bt)
        DB *= self.weights[elements][:, :, None, None]
        return np.matmul(Bt.transpose(0, 1, 3, 2), DB).sum(axis=1)

    def stiffness(self, tangent: np.ndarray, plastic: np.ndarray | None = None,
                  elastic: np.ndarray | None = None, extra=None) -> sp.csr_matrix:
        """∫ Bᵀ D B dV assembled [N/m] from tangents (6, 6, nelems, nqp) [Pa] (Eq. F55).

        With ``plastic`` (nelems, nqp) and the elastic matrix ``elastic`` (6, 6) [Pa], only
        the elements with a plastic point are integrated; the others take their elastic
        matrices, integrated once. ``extra`` = (elements, matrices (n, 60, 60) [N/m]) adds
        the matrices to those elements' (the contact's, Eq. F57). The sparsity pattern is
        the same at every call, explicit zeros kept, so a factorisation's analysis of it
        can be reused (:class:`fem.ring.linear.TangentSolver`)."""
        if plastic is None or elastic is None:
            ke = self.element_matrices(tangent)
        else:
            if self._elastic is None:
                C = np.broadcast_to(elastic[:, :, None, None], (6, 6, *self.point_shape))
                self._elastic = self.element_matrices(C)
            ke = self._elastic.copy()
            changed = np.flatnonzero(plastic.any(axis=1))
            if changed.size:
                ke[changed] = self.element_matrices(tangent[:, :, changed], changed)
        if extra is not None:
            np.add.at(ke, extra[0], extra[1])
        data = np.bincount(self._slots, ke.ravel(), minlength=self._indices.size)
        return sp.csr_matrix((data, self._indices, self._indptr),
                             shape=(self.ndofs, self.ndofs))
