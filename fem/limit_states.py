"""The three limit states of the FE model, watched after every accepted step of a run: the first
rim hinge, rupture of a rim, and loss of containment, with the failure mode decided from the
deformed geometry (docs/theory/finite-elements.md, "Limit states", Eqs. F36–F38, F51–F53).
:class:`LimitStates` is driven by :func:`fem.simulate`.
"""

from __future__ import annotations

import math

import numpy as np
import scipy.sparse as sp

from rigid.limit_states import LIMIT_STATES

__all__ = ["LIMIT_STATES", "RIMS", "LimitStates", "rim_gauge_average", "rim_overshoots",
           "slider_vertex_positions"]

RIMS = ("bottom -x", "bottom +x", "top -x", "top +x")


def _nearest_vertices(mesh, bearing, r: float, z: float) -> dict:
    """Mesh vertex nearest (±r, z) on the bottom plate and (±r, h − z) on the top, per rim."""
    h = bearing.slider_height
    targets = {"bottom -x": (-r, z), "bottom +x": (r, z), "top -x": (-r, h - z),
               "top +x": (r, h - z)}
    return {k: int(np.argmin(np.hypot(mesh.p[0] - x, mesh.p[1] - zk)))
            for k, (x, zk) in targets.items()}


def corner_nodes(mesh, bearing) -> dict:
    """Mesh vertex at each rim's inner top corner, per rim."""
    return _nearest_vertices(mesh, bearing, bearing.rim_radius, bearing.rim_top)


def root_nodes(mesh, bearing) -> dict:
    """Mesh vertex at the middle of each rim's root section, per rim: it carries the plate's
    rigid motion, against which a rim's bending is measured (Eq. F53)."""
    return _nearest_vertices(mesh, bearing, bearing.rim_radius + 0.5 * bearing.rim_thickness,
                             bearing.dish_depth(bearing.rim_radius))


def inner_root_nodes(mesh, bearing) -> dict:
    """Mesh vertex where each rim's inner face meets the dish: the corner of a rim that is
    gone (Eq. F68b)."""
    return _nearest_vertices(mesh, bearing, bearing.rim_radius,
                             bearing.dish_depth(bearing.rim_radius))


def averaging_operator(points: np.ndarray, weights: np.ndarray, radius: float) -> sp.csr_matrix:
    """Row-normalised top-hat average over a disc of the given radius [m] (Eq. F52): row i holds
    w_j / Σ w_j for the points j within ``radius`` of point i (reference positions (2, n) [m],
    quadrature weights (n,) [m²])."""
    d = np.hypot(points[0][:, None] - points[0][None, :], points[1][:, None] - points[1][None, :])
    w = np.where(d <= radius, weights[None, :], 0.0)
    return sp.csr_matrix(w / w.sum(axis=1, keepdims=True))


def rim_gauge_average(fe, mesh, rim: str, gauge: float) -> tuple[np.ndarray, sp.csr_matrix]:
    """The elements of one rim (``"bottom +x"`` …; the mesh's ``<plate>_rim`` subdomain on that
    side) and the operator that averages a quadrature-point field of them over a disc of
    diameter ``gauge`` [m] (Eq. F52): ``operator @ field[elements].ravel()``. ``fe`` is the
    element of the mesh (:class:`fem.assembly.PlaneStrainQ1`), for its points and weights."""
    plate, side = rim.split()
    elems = mesh.subdomains[f"{plate}_rim"]
    centroid_x = mesh.p[0, mesh.t[:, elems]].mean(axis=0)
    elems = elems[np.sign(centroid_x) == (1.0 if side == "+x" else -1.0)]
    points = np.asarray(fe.basis.global_coordinates())[:, elems].reshape(2, -1)
    return elems, averaging_operator(points, fe.basis.dx[elems].ravel(), 0.5 * gauge)  # geometric


def slider_vertex_positions(vertices: np.ndarray, pose) -> tuple[np.ndarray, np.ndarray]:
    """x and z [m] of the slider's corners ``vertices`` (body frame, (2, 4) [m], in the order of
    :attr:`fem.contact.slider.SliderShape.vertices`) at the pose (X [m], Z [m], Θ [rad])."""
    c, s = math.cos(pose[2]), math.sin(pose[2])
    return (pose[0] + c * vertices[0] - s * vertices[1],
            pose[1] + s * vertices[0] + c * vertices[1])


def rim_overshoots(rim: str, corner, vx: np.ndarray, vz: np.ndarray):
    """For each slider vertex that faces ``rim`` (the bottom ones for a bottom rim, the top ones
    for a top rim; positions ``vx``, ``vz`` [m]): (vertex index, how far [m] it lies
    horizontally beyond the rim's deformed inner corner ``corner`` (x, z) [m], the height [m]
    it still has to go to get past that corner vertically). Eq. F37 calls the vertex past the
    rim when the first is positive and the second negative. The side σ of Eq. F37 is the rim's
    own (+1 for a +x rim, −1 for a −x rim), whatever the plate's displacement: a top plate
    displaced further than the rim radius carries its −x rim's corner to x > 0."""
    side = 1.0 if rim.endswith("+x") else -1.0
    top = rim.startswith("top")
    cx, cz = corner
    for j in ((2, 3) if top else (0, 1)):
        yield j, side * (vx[j] - cx), (vz[j] - cz) if top else (cz - vz[j])


class LimitStates:
    """Hinge, rupture and containment of one FE run (module docstring).

    Parameters
    ----------
    bearing : rigid.DFPBearing
        Geometry, ``rupture_strain`` and ``rim_thickness`` (the averaging gauge).
    model : fem.dfp.DFPSystem
        Mesh, system and the rim-root rows.
    fracture : fem.fracture.RimFracture, optional
        Rupture is then the first element it tears (Eq. F67) instead of the gauge strain's
        reaching the rupture strain (Eq. F51).

    Attributes
    ----------
    times : dict
        Limit state → time [s] it was first reached, or None.
    hinge_times : dict
        Rim → time [s] its root section became fully plastic (rims that did).
    mode, detail : str or None
        At containment: "yielding" (the rim let go) or "uplift" (the slider climbed over a rim
        that held), and what happened.
    """

    def __init__(self, bearing, model, fracture=None):
        self.bearing = bearing
        self.fracture = fracture
        self.system = model.system
        mesh = model.mesh
        self.roots = [model.rim_roots[k] for k in RIMS]
        self.corners = corner_nodes(mesh, bearing)
        self.root_nodes = root_nodes(mesh, bearing)
        self.inner_roots = inner_root_nodes(mesh, bearing)
        self.nd = self.system.fe.basis.nodal_dofs
        self.vertices = self.system.shape.vertices
        self.mesh = mesh
        # rupture: rim points and their averaging operators (reference configuration)
        self.rim_points, self.rim_average = zip(*(
            rim_gauge_average(self.system.fe, mesh, name, bearing.rim_thickness)
            for name in RIMS), strict=True)
        self.times: dict = dict.fromkeys(LIMIT_STATES)
        self.hinge_times: dict = {}
        self.mode: str | None = None
        self.detail: str | None = None
        self.rupture_rim: str | None = None
        self.hinge_rim: str | None = None

    def root_yielding(self, p: np.ndarray):
        """Largest plastic strain and yielded fraction of each rim's root row (Eq. F36)."""
        peak = [float(p[e].max()) if e.size else 0.0 for e in self.roots]
        frac = [float((p[e] > 0).mean()) if e.size else 0.0 for e in self.roots]
        return peak, frac

    def regularised_strain(self, p: np.ndarray) -> list[float]:
        """Largest gauge-averaged equivalent plastic strain of each rim (Eq. F52)."""
        return [float((A @ p[e].ravel()).max()) for A, e in
                zip(self.rim_average, self.rim_points, strict=True)]

    def update(self, t: float, d: np.ndarray, pose, p: np.ndarray) -> tuple[list, list, list]:
        """Record the state after an accepted step at time t [s]: d the full dofs, pose the
        slider's (X, Z, Θ), p the equivalent plastic strain (nelems, nqp). Returns the root rows'
        peak strains and yielded fractions and the rims' regularised strains."""
        peak, frac = self.root_yielding(p)
        for k, f in enumerate(frac):
            if f >= 1.0 and RIMS[k] not in self.hinge_times:
                self.hinge_times[RIMS[k]] = t
                if self.times["hinge"] is None:
                    self.times["hinge"], self.hinge_rim = t, RIMS[k]
        regular = self.regularised_strain(p)
        if self.times["rupture"] is None:
            if self.fracture is not None:
                if self.fracture.first_tear is not None:
                    self.times["rupture"], self.rupture_rim = self.fracture.first_tear
            else:
                k = int(np.argmax(regular))
                if regular[k] >= self.bearing.rupture_strain:
                    self.times["rupture"], self.rupture_rim = t, RIMS[k]
        if self.times["containment"] is None:
            mode, detail = self._containment(d, pose)
            if mode is not None:
                self.times["containment"], self.mode, self.detail = t, mode, detail
        return peak, frac, regular

    def _containment(self, d, pose):
        """(mode, detail) if the slider has got past a rim or overturned (Eq. F37, F53)."""
        vx, vz = slider_vertex_positions(self.vertices, pose)
        p = self.mesh.p
        nd = self.nd
        corners = self.corners if self.fracture is None else self._standing_corners()
        for name in RIMS:
            node = corners[name]
            corner = (p[0, node] + d[nd[0, node]], p[1, node] + d[nd[1, node]])
            top = name.startswith("top")
            for j, overshoot, climb_left in rim_overshoots(name, corner, vx, vz):
                if overshoot > 0 and climb_left < 0:
                    # past where the corner would be had the rim not bent (its reference
                    # position moved with the rim's root): it climbed over a rim that held
                    z0 = p[1, node] + d[nd[1, self.root_nodes[name]]]
                    torn = node != self.corners[name]
                    climbed = not torn and ((vz[j] < z0) if top else (vz[j] > z0))
                    which = "top" if top else "bottom"
                    how = ("climbed over it" if climbed else "through its tear" if torn
                           else "passed through it, bent out of the way")
                    return ("uplift" if climbed else "yielding",
                            f"a {which} slider vertex got past the {name} rim ({how})")
        r_in = self.bearing.rim_radius
        x_top = float(np.mean(d[nd[0, corners["top -x"]]]))
        if abs(pose[0]) > r_in or abs(pose[0] - x_top) > r_in:
            mode = "yielding" if self.hinge_times else "uplift"
            return mode, "the slider's centroid passed a rim"
        if abs(pose[2]) > 0.25 * math.pi:
            return "uplift", "the slider overturned (|θ| > 45°)"
        return None, None

    def _standing_corners(self) -> dict:
        """Each rim's corner node, or, once no element that keeps some stiffness holds it, the
        rim's node nearest to it (reference configuration) that one still holds: the corner
        of what is left of the rim (where its inner face met the dish when nothing is; Eq.
        F68b)."""
        retained = self.fracture.retained
        if (retained == 1.0).all():
            return self.corners
        t = self.mesh.t
        corners = {}
        for name, elems in zip(RIMS, self.rim_points, strict=True):
            node = self.corners[name]
            held = np.unique(t[:, elems[retained[elems] > 0.0]])
            if node in held or not held.size:
                corners[name] = node if node in held else self.inner_roots[name]
                continue
            p = self.mesh.p
            corners[name] = int(held[np.argmin(np.hypot(p[0, held] - p[0, node],
                                                         p[1, held] - p[1, node]))])
        return corners

    def verdict(self, limit_state: str):
        """(failed, time [s], mode, detail) under ``limit_state``: the first of that limit
        state and containment (an escape is failure whatever the limit state)."""
        t_c = self.times["containment"]
        t = self.times[limit_state]
        if t is None and t_c is None:
            return False, None, None, None
        if t_c is not None and (t is None or t_c <= t):
            return True, t_c, self.mode, self.detail
        if limit_state == "hinge":
            return True, t, "yielding", f"plastic hinge across the root of the {self.hinge_rim} rim"
        if self.fracture is not None:
            return True, t, "yielding", (
                f"the {self.rupture_rim} rim tore: the ductile damage of an element (exponent "
                f"c = {self.fracture.criterion.exponent:g}) reached 1")
        return True, t, "yielding", (
            f"the {self.rupture_rim} rim ruptured: its plastic strain over a gauge of the rim "
            f"thickness reached {self.bearing.rupture_strain:.3g}")
