"""The 3-D mesh of the bottom plate's rim region: the plane cross-section (plate under the dish,
plate under the rim, rim) meshed in structured quadrilaterals by gmsh and swept into hexahedra,
either revolved about the bearing's axis over half a turn (the ring, by symmetry about the plane
of the push) or extruded straight by one layer (the plane-strain slab of the same section), for
the static rim pushes of :mod:`fem.ring.push` (docs/theory/finite-elements.md, "The rim as a
ring", Eqs. F54–F58).

Call :func:`ring_mesh`. Coordinates: x along the push, z up from the dish apex, y = 0 the plane
of symmetry; the section spans r ∈ [r_in − inner_width, r_in + t_r].
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import numpy as np

from rigid.bearing import DFPBearing

__all__ = ["MeshSizes", "RingMesh", "ring_mesh", "section_mesh"]


@dataclass(frozen=True)
class MeshSizes:
    """Element counts of the structured mesh.

    Parameters
    ----------
    rim_thickness : int
        Elements across the rim's thickness (and the plate under it).
    rim_height : int
        Elements up the rim's height (even: the pushed upper half starts on an element row).
    plate_depth : int
        Elements down the plate's depth under the dish and the rim.
    inner : int
        Elements across the plate strip under the dish.
    arc : float [m]
        Circumferential element length at the rim's inner face inside the widest load patch;
        beyond it the length grows geometrically by ``growth`` per element.
    growth : float [-]
        Ratio of successive circumferential element lengths beyond the patches.
    """

    rim_thickness: int = 4
    rim_height: int = 4
    plate_depth: int = 4
    inner: int = 4
    arc: float = 0.010
    growth: float = 1.3

    def __post_init__(self):
        for name in ("rim_thickness", "rim_height", "plate_depth", "inner"):
            value = getattr(self, name)
            if int(value) != value or value < 1:
                raise ValueError(f"MeshSizes.{name} must be a positive integer, got {value!r}")
        if self.rim_height % 2:
            raise ValueError(f"MeshSizes.rim_height must be even, got {self.rim_height!r}")
        if not (math.isfinite(self.arc) and self.arc > 0):
            raise ValueError(f"MeshSizes.arc must be a positive length [m], got {self.arc!r}")
        if not self.growth >= 1:
            raise ValueError(f"MeshSizes.growth must be at least 1, got {self.growth!r}")

    def refined(self, factor: int) -> MeshSizes:
        """Every count times ``factor`` and the arc length divided by it (growth kept)."""
        return MeshSizes(self.rim_thickness * factor, self.rim_height * factor,
                         self.plate_depth * factor, self.inner * factor, self.arc / factor,
                         self.growth ** (1.0 / factor))


#: The three meshes of the convergence study (docs/rim-3d/README.md): coarse, default, fine.
COARSE = MeshSizes(2, 2, 2, 2, 0.020, 1.6)
DEFAULT = MeshSizes()
FINE = DEFAULT.refined(2)
MESHES = {"coarse": COARSE, "default": DEFAULT, "fine": FINE}


@dataclass(frozen=True)
class RingMesh:
    """A swept hexahedral mesh of the rim region and its node and element sets.

    Attributes
    ----------
    points : ndarray, shape (3, npoints) [m]
        Vertex coordinates.
    hexes : ndarray of int, shape (8, nelems)
        Vertices of each hexahedron in VTK (= Abaqus C3D8) order.
    kind : {"ring", "slab"}
    angles : ndarray [rad] or [m]
        The sweep's stations: angles of the ring, or y of the slab.
    section_points : ndarray, shape (2, n2d) [m]
        (r, z) of the cross-section's vertices; vertex i of station k is ``k * n2d + i``.
    section_quads : ndarray of int, shape (4, nquads)
    rim_quads, root_quads : ndarray of int
        Section quads of the rim, and of the rim's first row above its root.
    bearing : DFPBearing
    sweep : {"half", "full", "quarter", "slab"}
    plate : bool
        Whether the plate is meshed (else the rim alone).
    """

    points: np.ndarray
    hexes: np.ndarray
    kind: str
    angles: np.ndarray
    section_points: np.ndarray
    section_quads: np.ndarray
    rim_quads: np.ndarray
    root_quads: np.ndarray
    bearing: DFPBearing
    sweep: str = "half"
    plate: bool = True

    @property
    def layers(self) -> int:
        """Number of element layers along the sweep."""
        return self.angles.size - 1

    def elements(self, quads, layers=None) -> np.ndarray:
        """Hexahedra swept from the given section quads, in the given layers (default all)."""
        layers = np.arange(self.layers) if layers is None else np.asarray(layers)
        nq = self.section_quads.shape[1]
        return (np.asarray(quads)[None, :] + nq * layers[:, None]).ravel()

    @property
    def load_layers(self) -> np.ndarray:
        """The element layers that touch the plane of the push (θ = 0): the first of a half or
        quarter ring, the two either side of it for the whole ring or the slab's one."""
        touching = (np.isclose(self.angles[:-1], 0.0, atol=1e-12)
                    | np.isclose(self.angles[1:], 0.0, atol=1e-12))
        return np.flatnonzero(touching) if self.kind == "ring" else np.array([0])

    def skfem(self):
        """The mesh as a :class:`skfem.MeshHex1` (element order as :attr:`hexes`)."""
        import meshio
        from skfem.io.meshio import from_meshio

        return from_meshio(meshio.Mesh(self.points.T, [("hexahedron", self.hexes.T)]))


def section_mesh(bearing: DFPBearing, sizes: MeshSizes, inner_width: float,
                 plate: bool = True):
    """The cross-section in structured quadrilaterals (gmsh): (r, z) points (2, n) [m], quads
    (4, m) counter-clockwise in (r, z), the rim's quads and its root row's; ``plate=False``
    keeps the rim alone (the free ring of the closed-form check)."""
    import gmsh

    r1, t, h = bearing.rim_radius, bearing.rim_thickness, bearing.rim_height
    r0, r2, zb = r1 - inner_width, r1 + t, -bearing.plate_thickness
    z0, z1 = bearing.dish_depth(r0), bearing.dish_depth(r1)
    initialised = gmsh.isInitialized()
    if not initialised:
        gmsh.initialize(readConfigFiles=False)
    gmsh.option.setNumber("General.Terminal", 0)
    try:
        gmsh.model.add("rim-section")
        geo = gmsh.model.geo
        pts = [geo.addPoint(r, z, 0.0) for r, z in
               [(r0, zb), (r1, zb), (r2, zb), (r0, z0), (r1, z1), (r2, z1), (r1, z1 + h),
                (r2, z1 + h)]]
        centre = geo.addPoint(0.0, bearing.radius, 0.0)  # the dish's centre of curvature
        a, b, c, d, e, f, g, k = pts

        def line(p, q):
            return geo.addLine(p, q)

        ab, bc, be, cf, ef, da, eg, fk, gk = (line(a, b), line(b, c), line(b, e), line(c, f),
                                              line(e, f), line(d, a), line(e, g), line(f, k),
                                              line(g, k))
        ed = geo.addCircleArc(e, centre, d)
        counts = {ab: sizes.inner, bc: sizes.rim_thickness, ef: sizes.rim_thickness,
                  gk: sizes.rim_thickness, ed: sizes.inner, be: sizes.plate_depth,
                  cf: sizes.plate_depth, da: sizes.plate_depth, eg: sizes.rim_height,
                  fk: sizes.rim_height}
        loops = {"inner": [ab, be, ed, da], "under": [bc, cf, -ef, -be],
                 "rim": [ef, fk, -gk, -eg]}
        surfaces = {name: geo.addPlaneSurface([geo.addCurveLoop(loop)])
                    for name, loop in loops.items()}
        geo.synchronize()
        for curve, n in counts.items():
            gmsh.model.mesh.setTransfiniteCurve(curve, n + 1)
        for s in surfaces.values():
            gmsh.model.mesh.setTransfiniteSurface(s)
            gmsh.model.mesh.setRecombine(2, s)
        gmsh.model.mesh.generate(2)
        tags, coords, _ = gmsh.model.mesh.getNodes()
        index = np.full(int(tags.max()) + 1, -1)
        index[tags.astype(int)] = np.arange(tags.size)
        points = coords.reshape(-1, 3)[:, :2].T.copy()
        quads, rim = [], []
        for name, s in surfaces.items():
            if not plate and name != "rim":
                continue
            _, _, nodes = gmsh.model.mesh.getElements(2, s)
            q = index[np.asarray(nodes[0], dtype=int)].reshape(-1, 4).T
            rim.append(np.full(q.shape[1], name == "rim"))
            quads.append(q)
    finally:
        gmsh.model.remove()
        if not initialised:
            gmsh.finalize()
    quads = np.concatenate(quads, axis=1)
    # drop unused nodes (the arc's centre), renumber
    used = np.unique(quads)
    renumber = np.full(points.shape[1], -1)
    renumber[used] = np.arange(used.size)
    points, quads = points[:, used], renumber[quads]
    # counter-clockwise in (r, z)
    r, z = points[0, quads], points[1, quads]
    area = 0.5 * ((r * np.roll(z, -1, axis=0)).sum(0) - (z * np.roll(r, -1, axis=0)).sum(0))
    quads[:, area < 0] = quads[::-1, area < 0]
    rim = np.flatnonzero(np.concatenate(rim))
    zc = points[1, quads[:, rim]].mean(axis=0)
    root = rim[zc < z1 + h / sizes.rim_height]
    return points, quads, rim, root


def _stations(bearing: DFPBearing, sizes: MeshSizes, patch_widths, end: float) -> np.ndarray:
    """Angles [rad] of the ring's element layers from 0 to ``end``: layer edges on every patch
    edge, elements of ``sizes.arc`` at the inner face inside the widest patch, growing by
    ``sizes.growth`` beyond it, at most :data:`MAX_ANGLE`."""
    r1 = bearing.rim_radius
    edges = sorted({0.5 * w / r1 for w in patch_widths} | {0.0})
    stations = [0.0]
    for lo, hi in itertools.pairwise(edges):
        n = max(1, math.ceil((hi - lo) * r1 / sizes.arc - 1e-9))
        stations.extend(np.linspace(lo, hi, n + 1)[1:])
    step = sizes.arc / r1
    while stations[-1] < end - 1e-12:
        step = min(step * sizes.growth, MAX_ANGLE)
        remaining = end - stations[-1]
        stations.append(end if remaining < 1.5 * step else stations[-1] + step)
    return np.array(stations)


#: The ring's largest element angle [rad] (15°: the faceted ring's circumference within 0.3 %,
#: where the ring is a quarter turn or more from the push).
MAX_ANGLE = math.radians(15.0)
#: The sweeps of a ring: half a turn with the plane of the push a plane of symmetry (the
#: study's), the whole turn (the symmetry check), a quarter turn (the free ring's closed form,
#: symmetric about both planes).
SWEEPS = {"half": math.pi, "full": 2 * math.pi, "quarter": math.pi / 2}


def ring_mesh(bearing: DFPBearing, *, sizes: MeshSizes = DEFAULT, kind: str = "ring",
              patch_widths=(), inner_width: float | None = None, slab_depth: float = 0.01,
              sweep: str = "half", plate: bool = True) -> RingMesh:
    """Mesh of the rim region: the section (:func:`section_mesh`) revolved over half a turn
    (``kind="ring"``) or extruded straight by one layer of ``slab_depth`` [m] (``"slab"``).

    Parameters
    ----------
    bearing : DFPBearing
        Rim radius, thickness and height, plate thickness, dish radius [m].
    sizes : MeshSizes
        Element counts; :data:`COARSE`, :data:`DEFAULT` and :data:`FINE` are the study's.
    kind : {"ring", "slab"}
    patch_widths : sequence of float [m]
        Arc lengths at the inner face of the load patches centred on y = 0: layer edges fall
        on their edges (ring only).
    inner_width : float [m], optional
        Radial width of the plate strip kept inside the rim; default twice the plate's depth
        at the rim (the plate's bottom is fixed, so the strip's stresses decay within it).
    slab_depth : float [m]
        Depth of the slab (its results are per unit depth).
    sweep : {"half", "full", "quarter"}
        The ring's extent (:data:`SWEEPS`); the whole turn is swept from −π to π.
    plate : bool
        False meshes the rim alone (no plate, no supports: the free ring).
    """
    if kind not in ("ring", "slab"):
        raise ValueError(f"kind must be 'ring' or 'slab', got {kind!r}")
    depth_at_rim = bearing.plate_thickness + bearing.dish_depth(bearing.rim_radius)
    inner_width = 2.0 * depth_at_rim if inner_width is None else float(inner_width)
    if not 0 < inner_width < bearing.rim_radius:
        raise ValueError(f"inner_width must lie in (0, rim radius {bearing.rim_radius:.3g} m), "
                         f"got {inner_width!r}")
    if sweep not in SWEEPS:
        raise ValueError(f"sweep must be one of {sorted(SWEEPS)}, got {sweep!r}")
    sec, quads, rim, root = section_mesh(bearing, sizes, inner_width, plate)
    n2d = sec.shape[1]
    if kind == "ring":
        if sweep == "full":
            half = _stations(bearing, sizes, patch_widths, math.pi)
            stations = np.concatenate([-half[:0:-1], half])
        else:
            stations = _stations(bearing, sizes, patch_widths, SWEEPS[sweep])
        c, s = np.cos(stations), np.sin(stations)
        points = np.stack([np.outer(c, sec[0]), np.outer(s, sec[0]),
                           np.broadcast_to(sec[1], (stations.size, n2d))]).reshape(3, -1)
    else:
        stations = np.array([0.0, float(slab_depth)])
        points = np.stack([np.broadcast_to(sec[0], (2, n2d)), np.outer(stations, np.ones(n2d)),
                           np.broadcast_to(sec[1], (2, n2d))]).reshape(3, -1)
    layers = np.arange(stations.size - 1)
    lo = quads[:, None, :] + n2d * layers[None, :, None]  # (4, layers, nquads)
    hexes = np.concatenate([lo, lo + n2d]).reshape(8, -1)
    if kind == "ring" and sweep == "full":  # the last station is the first: merge them
        last = n2d * (stations.size - 1)
        hexes = np.where(hexes >= last, hexes - last, hexes)
        points = points[:, :last]
    # VTK order needs the first face's normal towards the second face
    p = points[:, hexes]
    v = np.einsum("ij,ij->j", np.cross(p[:, 1] - p[:, 0], p[:, 3] - p[:, 0], axis=0),
                  p[:, 4] - p[:, 0])
    flip = v < 0
    hexes[:, flip] = hexes[[0, 3, 2, 1, 4, 7, 6, 5]][:, flip]
    return RingMesh(points, hexes, kind, stations, sec, quads, rim, root, bearing,
                    sweep if kind == "ring" else "slab", plate)
