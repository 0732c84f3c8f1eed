"""The rigid slider's section in its body frame: its faces (two spherical arcs of radius R and
two flat sides, the rigid model's slider, with optionally rounded edges), the exact rotation
between body and global frames, and the depth of a point inside the section with the closest
face's normal (the gap of the contact law; docs/theory/finite-elements.md, "Contact")."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:  # pragma: no cover - typing only
    from rigid.bearing import DFPBearing

__all__ = ["BOTTOM", "EDGES", "LEFT", "RIGHT", "TOP", "SliderShape", "body_coordinates",
           "penetration", "rotation"]

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
        :data:`BOTTOM`, :data:`TOP`, :data:`LEFT` or :data:`RIGHT`.
    normal : ndarray, shape (2, n) [-]
        Outward unit normal ν of that face at the closest point (body frame).
    radius : ndarray, shape (n,) [m]
        Distance ρ from the face circle's centre (inf for the flat sides), for the curvature.
    """
    xi = np.asarray(xi, dtype=float)
    R = shape.radius
    cb, ct = shape.centres
    rb = xi - cb[:, None]
    rt = xi - ct[:, None]
    lb = np.hypot(rb[0], rb[1])
    lt = np.hypot(rt[0], rt[1])
    depths = np.stack([R - lb, R - lt, shape.half_width + xi[0], shape.half_width - xi[0]])
    face = np.argmin(depths, axis=0)
    depth = depths[face, np.arange(xi.shape[1])]
    normal = np.zeros_like(xi)
    radius = np.full(xi.shape[1], np.inf)
    for f, r, length in ((BOTTOM, rb, lb), (TOP, rt, lt)):
        m = face == f
        normal[:, m] = r[:, m] / length[m]
        radius[m] = length[m]
    normal[0, face == LEFT] = -1.0
    normal[0, face == RIGHT] = 1.0
    if shape.edge_radius > 0.0:
        _round_edges(shape, xi, depth, face, normal, radius)
    return depth, face, normal, radius


def _round_edges(shape: SliderShape, xi, depth, face, normal, radius) -> None:
    """Overwrite, in place, the points whose closest face is a rounded edge: those in the
    wedge between the edge's two end normals (the side's and the spherical face's, both
    through the edge centre f), where δ = r − |ξ − f| (Eq. F14a)."""
    r = shape.edge_radius
    centres = shape.edge_centres
    for k, (side, sphere) in enumerate(((LEFT, BOTTOM), (RIGHT, BOTTOM), (LEFT, TOP),
                                        (RIGHT, TOP))):
        f = centres[:, k]
        n_side = np.array([-1.0 if side == LEFT else 1.0, 0.0])
        n_face = f - shape.centres[sphere]
        n_face /= np.linalg.norm(n_face)
        d = xi - f[:, None]
        # d = α n_side + β n_face with α, β ≥ 0: inside the wedge
        det = n_side[0] * n_face[1] - n_side[1] * n_face[0]
        alpha = (d[0] * n_face[1] - d[1] * n_face[0]) / det
        beta = (n_side[0] * d[1] - n_side[1] * d[0]) / det
        m = (alpha >= 0.0) & (beta >= 0.0)
        if not m.any():
            continue
        length = np.hypot(d[0, m], d[1, m])
        depth[m] = r - length
        face[m] = EDGES[k]
        normal[:, m] = d[:, m] / length
        radius[m] = length


def body_coordinates(x: np.ndarray, pose) -> np.ndarray:
    """ξ = Rᵀ(Θ)(x − c) for global points x (2, n) [m] and pose (X, Z, Θ) (Eq. F13)."""
    c, s = math.cos(pose[2]), math.sin(pose[2])
    dx = x[0] - pose[0]
    dz = x[1] - pose[1]
    return np.array([c * dx + s * dz, -s * dx + c * dz])
