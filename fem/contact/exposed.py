"""The rims' contact surface as their elements let go (docs/theory/finite-elements.md, Eq.
F68c): every vertex of a rim element is a contact node, and its tributary length is half of
each adjacent facet times how much of that facet is surface,

    original contact facet (dish, rim inner face, rim top) of element a:   w_a
    facet between elements a and b, one of them a rim element:             |w_a − w_b|

with w the fraction each element keeps (Eq. F68). Intact, only the original facets count, and
the lengths are those of :meth:`ContactNodes.from_mesh`; as a rim element crushes or tears,
the faces of the elements behind it become surface, so the slider meets what is left of the
rim instead of passing through it.

    nodes, surface = with_rim_vertices(mesh, nodes, boundaries, rim_friction)
    length = surface.lengths(retained)
    new = first_uncovered(length, nodes.length, uncovered)   # marks them in ``uncovered``
    offset[new] = overlap_gap(shape, positions[:, new], pose)
    nodes = dataclasses.replace(nodes, length=length)

A node uncovered for the first time inside the slider takes the slider's penetration there as
its gap adjustment δ₀ (:func:`fem.contact.initial_state`), so that it carries no force until the
slider moves further in.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from .nodes import ContactNodes
from .slider import SliderShape, body_coordinates, penetration

__all__ = ["ExposedSurface", "first_uncovered", "overlap_gap", "with_rim_vertices"]

#: The rims' subdomains of the bearing's mesh (``meshes/dfp.geo``).
RIM_SUBDOMAINS = ("bottom_rim", "top_rim")


@dataclasses.dataclass(frozen=True)
class ExposedSurface:
    """The facets that can carry contact and how to weigh them (module docstring).

    Attributes
    ----------
    ends : ndarray of int, shape (2, m)
        Each facet's two ends, as indices into the contact nodes.
    half_length : ndarray, shape (m,) [m]
    elements : ndarray of int, shape (2, m)
        The facet's elements; −1 in the second row for an original contact facet, whose
        weight is its element's w.
    size : int
        Number of contact nodes.
    """

    ends: np.ndarray
    half_length: np.ndarray
    elements: np.ndarray
    size: int

    def lengths(self, retained: np.ndarray) -> np.ndarray:
        """Tributary length [m] of every contact node for the elements' fractions ``retained``
        (nelems,) [-] (Eq. F68c)."""
        a, b = self.elements
        w = np.where(b < 0, retained[a], np.abs(retained[a] - retained[np.maximum(b, 0)]))
        length = np.zeros(self.size)
        for end in self.ends:
            np.add.at(length, end, w * self.half_length)
        return length


def with_rim_vertices(mesh, nodes: ContactNodes, boundaries, rim_friction: float):
    """The contact nodes ``nodes`` (from :meth:`ContactNodes.from_mesh` on ``boundaries``,
    names of the original contact facet sets) with every vertex of the rims' elements added
    (tributary length 0 until uncovered; friction ``rim_friction`` [-]; plate by subdomain),
    and their :class:`ExposedSurface`.

    Returns
    -------
    ContactNodes, ExposedSurface
    """
    if nodes.segments is not None:
        raise ValueError("uncovered rim faces need the node contact alone (no vertex contact)")
    rims = [s for s in RIM_SUBDOMAINS if s in mesh.subdomains]  # a push's plate: bottom only
    rim_elements = np.concatenate([mesh.subdomains[s] for s in rims])
    plate_of = np.zeros(mesh.p.shape[1], dtype=int)
    if "top_rim" in rims:
        plate_of[np.unique(mesh.t[:, mesh.subdomains["top_rim"]])] = 1
    extra = np.setdiff1d(np.unique(mesh.t[:, rim_elements]), nodes.nodes)
    grown = ContactNodes(
        np.concatenate([nodes.nodes, extra]),
        np.concatenate([nodes.length, np.zeros(extra.size)]),
        np.concatenate([nodes.friction, np.full(extra.size, float(rim_friction))]),
        np.concatenate([nodes.plate, plate_of[extra]]),
    )
    index = np.full(mesh.p.shape[1], -1)
    index[grown.nodes] = np.arange(grown.nodes.size)
    # the original contact facets, weighed by their element
    original = np.concatenate([mesh.boundaries[name] for name in boundaries])
    # the facets inside the mesh with a rim element on either side
    f2t = mesh.f2t
    is_rim = np.zeros(mesh.t.shape[1], dtype=bool)
    is_rim[rim_elements] = True
    inner = np.flatnonzero((f2t[1] >= 0) & (is_rim[f2t[0]] | is_rim[np.maximum(f2t[1], 0)]))
    facets = np.concatenate([original, inner])
    ends = mesh.facets[:, facets]
    seg = mesh.p[:, ends[1]] - mesh.p[:, ends[0]]
    elements = np.vstack([f2t[0, facets],
                          np.concatenate([np.full(original.size, -1), f2t[1, inner]])])
    surface = ExposedSurface(index[ends], 0.5 * np.hypot(seg[0], seg[1]), elements,
                             grown.nodes.size)
    return grown, surface


def first_uncovered(length: np.ndarray, intact: np.ndarray, uncovered: np.ndarray) -> np.ndarray:
    """Which contact nodes are uncovered for the first time (bool, (n,)): they carry a
    tributary length ``length`` (n,) [m] now, carried none intact (``intact`` (n,) [m]) and are
    not yet in ``uncovered`` (bool, (n,)), which is updated in place (Eq. F68c)."""
    new = (length > 0.0) & (intact == 0.0) & ~uncovered
    uncovered |= new
    return new


def overlap_gap(shape: SliderShape, positions: np.ndarray, pose) -> np.ndarray:
    """The gap adjustment δ₀ [m] of nodes uncovered at ``positions`` (2, k) [m]: the slider's
    penetration there with the slider at ``pose`` (X, Z, Θ) [m, m, rad], 0 outside it (Eq.
    F68c)."""
    return np.maximum(penetration(shape, body_coordinates(positions, pose))[0], 0.0)
