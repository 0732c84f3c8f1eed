r"""The finite-deformation counterpart of the B-bar quadrilateral: total-Lagrangian Q1 with the
element's mean dilatation (F̄ = (J̄/J)^{1/3} F), its internal force and consistent element
tangent, and which elements need their exact tangent in Newton's solves
(docs/theory/finite-elements.md, Eqs. F43, F47, F49).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
import scipy.sparse as sp

from . import hencky
from .assembly import PlaneStrainQ1
from .material import Material

__all__ = ["FiniteEvaluation", "FiniteStrainQ1"]

#: Elements whose displacement gradient stays below this norm [-] (and that do not yield)
#: are given the small-strain elastic stiffness in Newton's solves (:mod:`fem.linear`); their
#: exact tangent differs from it by about this fraction, which can only slow Newton's
#: convergence, never change the solution (docs/fe-companion.md: the same iteration counts
#: as with 1e-3, for a third less time), except near a tear
#: (:data:`fem.linear.TORN_ACTIVE_GRADIENT`).
ACTIVE_GRADIENT = 1e-2


class FiniteEvaluation(NamedTuple):
    """The material part of an evaluation with finite kinematics (what
    :class:`fem.system.CoupledSystem` needs from it).

    Attributes
    ----------
    stress : ndarray, shape (4, nelems, nqp) [Pa]
        Cauchy stress σ̄ (Mandel, zz included), for output.
    kirchhoff : ndarray, shape (4, nelems, nqp) [Pa]
        Kirchhoff stress τ̄ (Mandel).
    state : fem.hencky.FiniteState
        Trial history.
    plastic : ndarray of bool, shape (nelems, nqp)
    gradient : ndarray, shape (2, 2, nelems, nqp) [-]
        F.
    jacobian : ndarray, shape (nelems, nqp) [-]
        det F (1 in the elements gone, which are evaluated undeformed).
    mean_dilatation : ndarray, shape (nelems, nqp) [-]
        J̄ of each point's element.
    start : fem.hencky.FiniteState
        The converged history the update started from (the tangent needs it).
    weights : ndarray, shape (nelems, nqp) [m²]
        The integration weights used: ``dx`` times what each element retains (Eq. F68).
    """

    stress: np.ndarray
    kirchhoff: np.ndarray
    state: hencky.FiniteState
    plastic: np.ndarray
    gradient: np.ndarray
    jacobian: np.ndarray
    mean_dilatation: np.ndarray
    start: hencky.FiniteState
    weights: np.ndarray


class FiniteStrainQ1(PlaneStrainQ1):
    """Plane-strain Q1 for finite deformation with a mean dilatation (module docstring).

    It keeps the small-strain B-bar arrays of :class:`fem.assembly.PlaneStrainQ1` (the elastic
    stiffness that Newton's solves start from) and adds the reference gradient operator.

    Parameters
    ----------
    mesh : skfem.MeshQuad1
        Reference mesh, coordinates [m].
    intorder : int
        Quadrature order (2: the 2 × 2 Gauss rule).
    thickness : array_like, optional
        Relative thickness of each element (:class:`fem.assembly.PlaneStrainQ1`).
    """

    kinematics = "finite"
    #: Fraction of its stiffness and stress each element keeps (nelems,), or None: all of
    #: them (torn rim elements let go: :class:`fem.fracture.RimFracture`, Eq. F68).
    retained = None

    def __init__(self, mesh, intorder: int = 2, thickness=None):
        super().__init__(mesh, bbar=True, intorder=intorder, thickness=thickness)
        grads = np.array([phi[0].grad for phi in self.basis.basis])  # (8, 2, 2, nel, nqp)
        nbf = grads.shape[0]
        G = grads.transpose(1, 2, 0, 3, 4).reshape(4, nbf, *grads.shape[3:])  # rows iJ
        self.G = G
        self._Gt = np.ascontiguousarray(G.transpose(2, 3, 0, 1))  # (nel, nqp, 4, 8)
        nel, nqp = self.dx.shape
        rows = np.broadcast_to(np.arange(4 * nel * nqp).reshape(4, 1, nel, nqp), G.shape)
        cols = np.broadcast_to(self.element_dofs[None, :, :, None], G.shape)
        self._Gmat = sp.csr_matrix((G.ravel(), (rows.ravel(), cols.ravel())),
                                   shape=(4 * nel * nqp, self.ndofs))
        self._GmatT = self._Gmat.T.tocsr()
        self.volume = self.dx.sum(axis=1)  # V_e [m² per unit depth]

    def deformation(self, u: np.ndarray):
        """F (2, 2, nelems, nqp), J = det F (nelems, nqp) and the element means J̄ broadcast
        to the points (nelems, nqp), for a displacement vector u [m]."""
        H = (self._Gmat @ u).reshape(2, 2, *self.dx.shape)
        F = H + np.eye(2)[:, :, None, None]
        J = F[0, 0] * F[1, 1] - F[0, 1] * F[1, 0]
        jbar = (J * self.dx).sum(axis=1) / self.volume
        return F, J, np.broadcast_to(jbar[:, None], J.shape)

    def evaluate(self, material: Material, u: np.ndarray, state: hencky.FiniteState):
        """Material response at displacement u [m] from the converged history ``state``.

        Returns
        -------
        FiniteEvaluation, ndarray
            The evaluation and the internal force f = ∫ Ĝᵀ P* dV₀ [N/m], per unit depth (NaN
            if any element is inverted, J ≤ 0, which Newton treats as divergence).
        """
        F, J, jbar = self.deformation(u)
        weights = self.dx
        inverted = (J <= 0.0).any(axis=1)
        if self.retained is not None:
            # an element letting go (Eq. F68) may invert: it is then gone, as is one that has
            # let go altogether; both are evaluated undeformed (finite numbers), with no weight
            letting_go = self.retained < 1.0
            gone = (letting_go & inverted) | (self.retained == 0.0)
            weights = self.dx * np.where(gone, 0.0, self.retained)[:, None]
            if gone.any():
                F[:, :, gone] = np.eye(2)[:, :, None, None]
                J[gone] = 1.0
                jbar = np.array(jbar)
                jbar[gone] = 1.0
            inverted &= ~letting_go
        res = hencky.update(material, F, jbar, state)
        force = self._GmatT @ (res.first_piola.reshape(4, *self.dx.shape) * weights).ravel()
        if inverted.any():  # an inverted element is no deformation: mark the iterate
            force[:] = np.nan  # invalid, so that Newton rejects it (and the step is cut)
        ev = FiniteEvaluation(res.cauchy, res.kirchhoff, res.state, res.plastic, F, J, jbar,
                              state, weights)
        return ev, force

    def active_elements(self, ev: FiniteEvaluation, gradient: float | None = None) -> np.ndarray:
        """Elements whose tangent is not the small-strain elastic one: any point yields, the
        displacement gradient exceeds ``gradient`` [-] (default :data:`ACTIVE_GRADIENT`), or
        the element lets go (Eq. F68)."""
        gradient = ACTIVE_GRADIENT if gradient is None else gradient
        H = ev.gradient - np.eye(2)[:, :, None, None]
        big = np.sqrt((H * H).sum(axis=(0, 1))).max(axis=1) > gradient
        if self.retained is not None:
            big |= self.retained < 1.0
        return np.flatnonzero(big | ev.plastic.any(axis=1))

    def element_tangent(self, material: Material, ev: FiniteEvaluation,
                        elements: np.ndarray) -> np.ndarray:
        """Consistent element tangents K_e of some elements (module docstring).

        Returns
        -------
        ndarray, shape (m, 8, 8) [N/m²]
            Rows and columns in the order of ``element_dofs[:, e]``.
        """
        e = np.asarray(elements, dtype=np.int64)
        F = ev.gradient[:, :, e]
        jbar = ev.mean_dilatation[e]
        start = hencky.FiniteState(ev.start.elastic_inverse[:, e], ev.start.eq_plastic_strain[e])
        A, AJ = hencky.tangent(material, F, jbar, start)  # (4, 4, m, nqp), (4, m, nqp)
        w = ev.weights[e]  # (m, nqp)
        Gt = self._Gt[e]  # (m, nqp, 4, 8)
        AG = np.matmul(A.transpose(2, 3, 0, 1), Gt)  # (m, nqp, 4, 8)
        K = np.einsum("mqia,mqib,mq->mab", Gt, AG, w)
        p_j = np.einsum("mqia,imq,mq->ma", Gt, AJ, w)
        Finv_T = np.stack([F[1, 1], -F[1, 0], -F[0, 1], F[0, 0]])  # J F⁻ᵀ, order [11 12 21 22]
        # ∂J̄/∂u: J̄ is a mean over the element's whole volume, whatever it retains
        g_j = np.einsum("mqia,imq,mq->ma", Gt, Finv_T, self.dx[e]) / self.volume[e][:, None]
        return K + p_j[:, :, None] * g_j[:, None, :]

    def finite_stiffness(self, material: Material, ev: FiniteEvaluation) -> sp.csr_matrix:
        """The full consistent tangent K = Σ_e K_e [N/m²], per unit depth."""
        ke = self.element_tangent(material, ev, np.arange(self.dx.shape[0]))
        data = np.bincount(self._scatter, ke.transpose(1, 2, 0).ravel(), minlength=self._nnz)
        return sp.csr_matrix((data, self._indices, self._indptr), shape=(self.ndofs,) * 2)

    def strain_energy(self, material: Material, ev: FiniteEvaluation) -> float:
        """Elastic (Hencky) energy ∫ ½ τ̄ : C⁻¹ : τ̄ dV₀ [J/m], per unit depth."""
        compliance = np.linalg.inv(material.elastic_tangent())
        tau = ev.kirchhoff
        density = 0.5 * np.einsum("ieq,ij,jeq->eq", tau, compliance, tau)
        return float((density * ev.weights).sum())
