"""The rigid slider's section in its body frame: its faces (two spherical arcs of radius R and
two flat sides, the rigid model's slider, with optionally rounded edges), the exact rotation
between body and global frames, and the depth of a point inside the section with the closest
face's normal (the gap of the contact law; docs/theory/finite-elements.md, "Contact")."""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numba import njit

if TYPE_CHECKING:  # pragma: no cover - typing only
    from rigid.bearing import DFPBearing

__all__ = ["BOTTOM", "EDGES", "LEFT", "RIGHT", "TOP", "SliderShape", "body_coordinates",
           "penetration", "rotation", "tangent_continuous"]

#: Face labels returned by :func:`penetration`; the rounded edges (if any) are EDGES[k], k in
#: the order of :attr:`SliderShape.vertices`.
BOTTOM, TOP, LEFT, RIGHT = 0, 1, 2, 3
EDGES = (4, 5, 6, 7)


def rotation(theta: float) -> np.ndarray:
    """Rotation matrix R(Θ), counter-clockwise, body to global."""
    c, s = math.cos(theta), math.sin(theta)
    return np.array([[c, -s], [s, c]])


@dataclass(frozen=True)
class SliderShape:
    """Section of the rigid slider in its body frame (origin at the centroid).

    Parameters
    ----------
    radius : float [m]
        Radius R of both spherical faces.
    half_width : float [m]
        Half the slider diameter, b/2.
    half_height : float [m]
        Half the height on the axis, h/2 (face apex to centroid).
    edge_radius : float [m]
        Radius r of the rounded edges between the spherical faces and the flat sides (0: sharp
        edges, the rigid model's slider); each is an arc tangent to both faces
        (docs/theory/finite-elements.md, Eq. F14a).
    """

    radius: float
    half_width: float
    half_height: float
    edge_radius: float = 0.0

    def __post_init__(self):
        if not (self.radius > 0 and self.half_width > 0 and self.half_height > 0):
            raise ValueError("SliderShape dimensions must be positive")
        if self.half_width >= self.radius:
            raise ValueError("SliderShape.half_width must be smaller than the radius")
        if self.half_height <= self.sag:
            raise ValueError("SliderShape.half_height must exceed the face sag")
        if not 0.0 <= self.edge_radius < min(self.half_width, self.half_height - self.sag):
            raise ValueError(
                "SliderShape.edge_radius must be ≥ 0 and smaller than both b/2 and half the "
                f"height of the flat sides, got {self.edge_radius!r} m")

    @classmethod
    def from_bearing(cls, bearing: DFPBearing, edge_radius: float = 0.0) -> SliderShape:
        """The slider of a :class:`rigid.DFPBearing` (R, b/2, h/2), with rounded edges of
        ``edge_radius`` [m] (0: sharp)."""
        return cls(bearing.radius, bearing.slider_diameter / 2, bearing.slider_height / 2,
                   edge_radius)

    @property
    def sag(self) -> float:
        """Bulge of a face over its chord, R − √(R² − (b/2)²) [m]."""
        return self.radius - math.sqrt(self.radius**2 - self.half_width**2)

    @property
    def centres(self) -> np.ndarray:
        """Body-frame centres of the bottom and top face circles, shape (2, 2) [m]."""
        return np.array(
            [[0.0, self.radius - self.half_height], [0.0, self.half_height - self.radius]]
        )

    @property
    def vertices(self) -> np.ndarray:
        """Body-frame corners (bottom-left, bottom-right, top-left, top-right), (2, 4) [m]: those
        of the sharp section (with rounded edges, just outside the section)."""
        he = self.half_height - self.sag
        hw = self.half_width
        return np.array([[-hw, hw, -hw, hw], [-he, -he, he, he]])

    @property
    def edge_centres(self) -> np.ndarray:
        """Body-frame centres of the rounded edges, in the order of :attr:`vertices`, (2, 4)
        [m]: at b/2 − r from the axis and R − r from the face circle's centre (Eq. F14a)."""
        r = self.edge_radius
        x = self.half_width - r
        (_, zb), (_, zt) = self.centres
        dz = math.sqrt((self.radius - r) ** 2 - x**2)
        return np.array([[-x, x, -x, x], [zb - dz, zb - dz, zt + dz, zt + dz]])


#: The faces each rounded edge joins, in the order of :data:`EDGES` (side, spherical face).
EDGE_FACES = ((LEFT, BOTTOM), (RIGHT, BOTTOM), (LEFT, TOP), (RIGHT, TOP))


@functools.lru_cache(maxsize=16)
def tangent_continuous(shape: SliderShape) -> np.ndarray:
    """Which faces meet with a common tangent, (8, 8) bool indexed by face label: a face with
    itself, and each rounded edge with the side and the spherical face it joins (Eq. F14a).
    Across such a boundary a node's tangential force keeps its direction, so its friction
    history carries over (Eq. F16). Cached per shape, not to be modified."""
    smooth = np.eye(len(EDGES) + 4, dtype=bool)
    if shape.edge_radius > 0.0:
        for edge, faces in zip(EDGES, EDGE_FACES, strict=True):
            for f in faces:
                smooth[edge, f] = smooth[f, edge] = True
    smooth.flags.writeable = False
    return smooth


def penetration(shape: SliderShape, xi: np.ndarray):
    """Depth of body-frame points inside the slider section and the closest face (Eq. F14).

    Parameters
    ----------
    shape : SliderShape
    xi : ndarray, shape (2, n) [m]
        Points in the slider's body frame.

    Returns
    -------
    depth : ndarray, shape (n,) [m]
        Smallest face depth; positive inside the section.
    face : ndarray of int, shape (n,)
        :data:`BOTTOM`, :data:`TOP`, :data:`LEFT` or :data:`RIGHT`, or one of :data:`EDGES`.
    normal : ndarray, shape (2, n) [-]
        Outward unit normal ν of that face at the closest point (body frame).
    radius : ndarray, shape (n,) [m]
        Distance ρ from the face circle's centre (inf for the flat sides), for the curvature.
    """
    xi = np.ascontiguousarray(xi, dtype=float)
    n = xi.shape[1]
    depth, radius = np.empty(n), np.empty(n)
    face = np.empty(n, dtype=np.intp)
    normal = np.empty((2, n))
    _penetration_points(xi, shape.radius, shape.half_width, shape.centres, _edges(shape),
                        shape.edge_radius, depth, face, normal, radius)
    return depth, face, normal, radius


@functools.lru_cache(maxsize=16)
def _edges(shape: SliderShape) -> np.ndarray:
    """Per rounded edge k (rows, none if the edges are sharp): its centre f, its two end
    normals (the side's n_s, the spherical face's n_f, both through f) and det[n_s n_f],
    (k, 7): f_x, f_z, n_s,x, n_s,z, n_f,x, n_f,z, det (Eq. F14a); cached per shape, not to be
    modified."""
    if shape.edge_radius <= 0.0:
        return np.zeros((0, 7))
    centres = shape.edge_centres
    rows = []
    for k, (side, sphere) in enumerate(EDGE_FACES):
        f = centres[:, k]
        n_side = np.array([-1.0 if side == LEFT else 1.0, 0.0])
        n_face = f - shape.centres[sphere]
        n_face /= np.linalg.norm(n_face)
        det = n_side[0] * n_face[1] - n_side[1] * n_face[0]
        rows.append([f[0], f[1], n_side[0], n_side[1], n_face[0], n_face[1], det])
    return np.array(rows)


@njit(cache=True)
def _penetration_points(xi, R, half_width, centres, edges, edge_radius, depth, face, normal,
                        radius):
    """:func:`penetration` point by point (columns of xi), into the output arrays. The closest
    of the four faces is the first smallest depth (NaN first, as ``np.argmin``); a point in
    the wedge of a rounded edge (d = α n_s + β n_f, α, β ≥ 0, d = ξ − f) then takes that edge,
    the later edge winning (Eq. F14a)."""
    depths = np.empty(4)
    for i in range(xi.shape[1]):
        x0, x1 = xi[0, i], xi[1, i]
        rb0, rb1 = x0 - centres[0, 0], x1 - centres[0, 1]
        rt0, rt1 = x0 - centres[1, 0], x1 - centres[1, 1]
        lb, lt = math.hypot(rb0, rb1), math.hypot(rt0, rt1)
        depths[0], depths[1] = R - lb, R - lt
        depths[2], depths[3] = half_width + x0, half_width - x0
        best = 0
        if not math.isnan(depths[0]):
            for f in range(1, 4):
                if math.isnan(depths[f]):
                    best = f
                    break
                if depths[f] < depths[best]:
                    best = f
        face[i] = best
        depth[i] = depths[best]
        if best == BOTTOM:
            normal[0, i], normal[1, i], radius[i] = rb0 / lb, rb1 / lb, lb
        elif best == TOP:
            normal[0, i], normal[1, i], radius[i] = rt0 / lt, rt1 / lt, lt
        else:
            normal[0, i] = -1.0 if best == LEFT else 1.0
            normal[1, i], radius[i] = 0.0, np.inf
        for k in range(edges.shape[0]):
            d0, d1 = x0 - edges[k, 0], x1 - edges[k, 1]
            ns0, ns1, nf0, nf1, det = edges[k, 2:7]
            alpha = (d0 * nf1 - d1 * nf0) / det
            beta = (ns0 * d1 - ns1 * d0) / det
            if alpha >= 0.0 and beta >= 0.0:
                length = math.hypot(d0, d1)
                depth[i] = edge_radius - length
                face[i] = EDGES[0] + k
                normal[0, i], normal[1, i], radius[i] = d0 / length, d1 / length, length


def body_coordinates(x: np.ndarray, pose) -> np.ndarray:
    """ξ = Rᵀ(Θ)(x − c) for global points x (2, n) [m] and pose (X, Z, Θ) (Eq. F13)."""
    c, s = math.cos(pose[2]), math.sin(pose[2])
    dx = x[0] - pose[0]
    dz = x[1] - pose[1]
    return np.array([c * dx + s * dz, -s * dx + c * dz])
