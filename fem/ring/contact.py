r"""The slider's side as a rigid vertical cylinder of diameter b in frictionless penalty contact
with the rim's inner face, integrated at the face's Gauss points (docs/theory/finite-elements.md,
Eqs. F56–F57): the gap g = ρ − b/2, ρ the horizontal distance of a face point from the
cylinder's axis; the pressure k⟨−g⟩ pushes the face away from the axis.

:class:`CylinderContact` gives the contact's force vector, tangent and resultant.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

__all__ = ["CylinderContact"]


class CylinderContact:
    """Penalty contact of a rigid vertical cylinder with a set of boundary facets.

    Parameters
    ----------
    solid : fem.ring.solid.Solid
    facets : ndarray of int
        The facets the cylinder may touch (the rim's inner face).
    radius : float [m]
        Cylinder radius b/2.
    penalty : float [Pa/m]
        Pressure per unit penetration.
    z_range : (float, float) [m]
        Heights of the cylinder's side that push: face points outside carry no pressure (the
        2-D push's upper half of the rim's inner face, Eq. F57).
    """

    def __init__(self, solid, facets, radius: float, penalty: float, z_range):
        from skfem import FacetBasis

        self.solid = solid
        self.radius = float(radius)
        self.penalty = float(penalty)
        fb = FacetBasis(solid.mesh, solid.basis.elem, facets=facets, intorder=5)
        self.N = np.array([np.asarray(phi[0]) for phi in fb.basis])  # (60, 3, nfacets, nqp)
        self.X = np.asarray(fb.global_coordinates())  # (3, nfacets, nqp)
        self.weights = np.asarray(fb.dx)
        self.dofs = np.asarray(fb.element_dofs)
        self.elements = np.asarray(fb.tind)  # the element each facet belongs to
        zmin, zmax = z_range
        self.active_height = (self.X[2] > zmin - 1e-9) & (self.X[2] < zmax + 1e-9)

    def _kinematics(self, u, centre):
        x = self.X + np.einsum("aieq,ae->ieq", self.N, u[self.dofs])
        dx, dy = x[0] - centre, x[1]
        rho = np.hypot(dx, dy)
        n = np.stack([dx, dy, np.zeros_like(dx)]) / np.where(rho > 0, rho, 1.0)
        pressure = self.penalty * np.maximum(self.radius - rho, 0.0) * self.active_height
        return rho, n, pressure

    def force(self, u: np.ndarray, centre: float):
        """The contact's nodal forces on the solid [N] and their resultant along x [N], for
        the cylinder's axis at x = ``centre`` [m], y = 0."""
        _, n, pressure = self._kinematics(u, centre)
        traction = n * pressure * self.weights  # (3, nf, nq) [N]
        fe = np.einsum("aieq,ieq->ae", self.N, traction)
        f = np.bincount(self.dofs.ravel(), fe.ravel(), minlength=self.solid.ndofs)
        return f, float(traction[0].sum())

    def element_matrices(self, u: np.ndarray, centre: float):
        """−∂(contact force)/∂u [N/m] as the pressed facets' elements and their (n, 60, 60)
        matrices: k n⊗n − (p/ρ)(P_h − n⊗n) at each pressed point (Eq. F57)."""
        rho, n, pressure = self._kinematics(u, centre)
        on = pressure > 0
        facets = np.flatnonzero(on.any(axis=1))
        horizontal = np.diag([1.0, 1.0, 0.0])
        n, rho, pressure = n[:, facets], rho[facets], pressure[facets]
        nn = n[:, None] * n[None, :]
        k = (self.penalty * nn - (pressure / np.where(rho > 0, rho, 1.0))
             * (horizontal[:, :, None, None] - nn)) * (on[facets] * self.weights[facets])
        Nf = self.N[:, :, facets]
        ke = np.einsum("aieq,ijeq,bjeq->eab", Nf, k, Nf, optimize=True)
        return self.elements[facets], ke

    def stiffness(self, u: np.ndarray, centre: float) -> sp.csr_matrix:
        """The tangent of :meth:`element_matrices` assembled [N/m]."""
        elements, ke = self.element_matrices(u, centre)
        dofs = self.solid.dofs[:, elements]
        nb = dofs.shape[0]
        rows = np.repeat(dofs.T[:, :, None], nb, axis=2).ravel()
        cols = np.repeat(dofs.T[:, None, :], nb, axis=1).ravel()
        return sp.csr_matrix((ke.ravel(), (rows, cols)),
                             shape=(self.solid.ndofs, self.solid.ndofs))
