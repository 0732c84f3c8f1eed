r"""The rims tear: damage per rim after every accepted step of an FE run, and the erosion of
the elements it tears (docs/theory/finite-elements.md, "Rim fracture", Eqs. F66–F68).

    fracture = RimFracture(criterion, fe, mesh, gauge=bearing.rim_thickness, steps=10)
    if fracture.update(t, plastic_strain, stress):          # after an accepted step
        system.erode(fracture.retained)                     # fem.system.CoupledSystem
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components

from .criterion import StressModifiedStrain
from .gauge import GaugeDamage

__all__ = ["RimFracture"]


class RimFracture:
    """Ductile damage of the four rims and the erosion of their torn elements.

    Each rim's damage is accumulated over a gauge of the rim thickness (Eq. F66) at its
    quadrature points; an element tears when the largest damage of its points reaches 1
    (Eq. F67) and then keeps 1 − k/N of its stiffness and stress k accepted steps later, N =
    ``steps``, until none is left (Eq. F68). Torn elements add no strain to the gauges. Rim
    elements that the gone ones leave joined to no plate (across element edges) are a loose
    fragment and let go in the same way (Eq. F68b). With ``crush_jacobian``, a whole rim element
    whose deformation gradient's determinant at any of its points falls below it is crushed
    and lets go as a torn one does (Eq. F67b).

    Parameters
    ----------
    criterion : StressModifiedStrain
    fe : fem.assembly.PlaneStrainQ1
        The plates' element (its quadrature points and weights).
    mesh : skfem.MeshQuad1
        With the ``bottom_rim`` and ``top_rim`` subdomains.
    gauge : float [m]
        Diameter of the averaging disc: the rim thickness (Eq. F52).
    steps : int
        N, the accepted steps over which a torn element lets go; 0 tracks the damage and
        tears nothing (static comparisons, today's runs).
    rims : sequence of str, optional
        The rims watched (default all four, ``fem.limit_states.RIMS``; the static rim push
        watches ``("bottom +x",)``).
    crush_jacobian : float [-], optional
        J_c of Eq. F67b, in (0, 1); default None: nothing is crushed.

    Attributes
    ----------
    retained : ndarray, shape (nelems,) [-]
        Fraction of its stiffness and stress each element keeps.
    torn : dict
        Element → (time [s], rim) at which it tore, in the order they tore (crushed ones
        included).
    crushed : dict
        Element → (time [s], rim) of the torn elements that were crushed (Eq. F67b).
    loose : dict
        Element → (time [s], rim) at which it was cut off in a loose fragment (Eq. F68b).
    rim_damage : list of float
        Largest element damage of each watched rim (in ``rims``' order) after the last
        update.
    rim_triaxiality : list of float
        T̄ (Eq. F66) at the most damaged point of each watched rim in the last step in which
        it strained.
    """

    def __init__(self, criterion: StressModifiedStrain, fe, mesh, gauge: float,
                 steps: int = 10, rims=None, crush_jacobian: float | None = None):
        from fem.limit_states import RIMS, rim_gauge_average

        if int(steps) != steps or steps < 0:
            raise ValueError(f"steps must be a non-negative integer, got {steps!r}")
        if crush_jacobian is not None and not 0.0 < crush_jacobian < 1.0:
            raise ValueError(f"crush_jacobian must lie in (0, 1), got {crush_jacobian!r}")
        self.crush_jacobian = crush_jacobian
        self.criterion = criterion
        self.steps = int(steps)
        self.rims = tuple(RIMS if rims is None else rims)
        self.nqp = fe.dx.shape[1]
        self.elements, self.gauges = [], []
        for name in self.rims:
            elems, operator = rim_gauge_average(fe, mesh, name, gauge)
            self.elements.append(elems)
            self.gauges.append(GaugeDamage(criterion, operator))
        self.retained = np.ones(fe.dx.shape[0])
        self.torn: dict = {}
        self.crushed: dict = {}
        self.loose: dict = {}
        self._edges = _edge_adjacency(mesh)
        self._anchored = np.ones(self.retained.size, dtype=bool)  # plates: never torn
        for elems in self.elements:
            self._anchored[elems] = False
        self.rim_damage = [0.0] * len(self.rims)
        self.rim_triaxiality = [0.0] * len(self.rims)

    @property
    def first_tear(self):
        """(time [s], rim) of the first element that tore, or None."""
        return next(iter(self.torn.values()), None)

    def update(self, t: float, plastic_strain: np.ndarray, stress: np.ndarray,
               jacobian: np.ndarray | None = None) -> bool:
        """Add an accepted step at time t [s]: equivalent plastic strain (nelems, nqp) [-],
        Mandel stress (4, nelems, nqp) [Pa] and, for Eq. F67b, det F (nelems, nqp) [-].
        Returns whether :attr:`retained` changed."""
        before = self.retained.copy()
        if self.steps:  # the elements already letting go lose another 1/N (Eq. F68)
            going = self.retained < 1.0
            self.retained[going] = np.maximum(self.retained[going] - 1.0 / self.steps, 0.0)
        for k, (elems, gauge) in enumerate(zip(self.elements, self.gauges, strict=True)):
            whole = before[elems] == 1.0  # neither torn nor letting go before this step
            intact = np.repeat(whole, self.nqp)
            points = (plastic_strain[elems].ravel(),
                      stress[:, elems].reshape(4, -1).T)
            damage = gauge.update(*points, intact=intact)
            if damage.size:
                self.rim_triaxiality[k] = float(gauge.triaxiality[np.argmax(damage)])
            element = damage.reshape(elems.size, self.nqp).max(axis=1)  # Eq. F67
            self.rim_damage[k] = float(element.max()) if element.size else 0.0
            torn = (element >= 1.0) & whole
            crushed = np.zeros_like(torn)
            if self.crush_jacobian is not None and jacobian is not None:  # Eq. F67b
                crushed = (jacobian[elems].min(axis=1) < self.crush_jacobian) & whole & ~torn
            for e in elems[torn | crushed]:
                self.torn.setdefault(int(e), (t, self.rims[k]))
                if self.steps:
                    self.retained[e] = 1.0 - 1.0 / self.steps
            for e in elems[crushed]:
                self.crushed.setdefault(int(e), (t, self.rims[k]))
        if self.steps and ((self.retained == 0.0) & (before > 0.0)).any():
            self._let_loose_go(t)
        return bool((self.retained != before).any())

    def _let_loose_go(self, t: float) -> None:
        """Start letting go the whole elements that no longer reach a plate through elements
        that keep some stiffness (Eq. F68b)."""
        alive = np.flatnonzero(self.retained > 0.0)
        n, label = connected_components(self._edges[alive][:, alive], directed=False)
        held = np.zeros(n, dtype=bool)
        held[label[self._anchored[alive]]] = True
        cut = alive[~held[label]]
        for k, elems in enumerate(self.elements):
            for e in np.intersect1d(cut, elems):
                if self.retained[e] == 1.0:
                    self.loose[int(e)] = (t, self.rims[k])
                    self.retained[e] = 1.0 - 1.0 / self.steps


def _edge_adjacency(mesh) -> sp.csr_matrix:
    """Elements × elements, nonzero where two elements share an edge."""
    pair = mesh.f2t[:, (mesh.f2t >= 0).all(axis=0)]
    n = mesh.t.shape[1]
    a = sp.coo_matrix((np.ones(pair.shape[1]), (pair[0], pair[1])), shape=(n, n))
    return (a + a.T).tocsr()
