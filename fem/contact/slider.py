"""The rigid slider's section in its body frame: its faces (two spherical arcs of radius R and
two flat sides, the rigid model's slider), the exact rotation between body and global frames,
and the depth of a point inside the section with the closest face's normal (the gap of the
contact law; docs/theory/finite-elements.md, "Contact")."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:  # pragma: no cover - typing only
    from rigid.bearing import DFPBearing

__all__ = ["BOTTOM", "LEFT", "RIGHT", "TOP", "SliderShape", "body_coordinates", "penetration",
           "rotation"]

#: Face labels returned by :func:`penetration`.
BOTTOM, TOP, LEFT, RIGHT = 0, 1, 2, 3


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
    """

    radius: float
    half_width: float
    half_height: float

    def __post_init__(self):
        if not (self.radius > 0 and self.half_width > 0 and self.half_height > 0):
            raise ValueError("SliderShape dimensions must be positive")
        if self.half_width >= self.radius:
            raise ValueError("SliderShape.half_width must be smaller than the radius")
        if self.half_height <= self.sag:
            raise ValueError("SliderShape.half_height must exceed the face sag")

    @classmethod
    def from_bearing(cls, bearing: DFPBearing) -> SliderShape:
        """The slider of a :class:`rigid.DFPBearing` (R, b/2, h/2)."""
        return cls(bearing.radius, bearing.slider_diameter / 2, bearing.slider_height / 2)

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
        """Body-frame corners (bottom-left, bottom-right, top-left, top-right), (2, 4) [m]."""
        he = self.half_height - self.sag
        hw = self.half_width
        return np.array([[-hw, hw, -hw, hw], [-he, -he, he, he]])


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
    return depth, face, normal, radius


def body_coordinates(x: np.ndarray, pose) -> np.ndarray:
    """ξ = Rᵀ(Θ)(x − c) for global points x (2, n) [m] and pose (X, Z, Θ) (Eq. F13)."""
    c, s = math.cos(pose[2]), math.sin(pose[2])
    dx = x[0] - pose[0]
    dz = x[1] - pose[1]
    return np.array([c * dx + s * dz, -s * dx + c * dz])
