"""Contact between the plates and the rigid slider: the slider's section and exact rotation
(:mod:`fem.contact.slider`), penalty contact with Coulomb friction at the plates' boundary
nodes (:mod:`fem.contact.nodes`) and, optionally, at the slider's vertices
(:mod:`fem.contact.vertices`). Forces are per unit out-of-plane depth [N/m], moments [N·m/m];
the formulation is in ``docs/theory/finite-elements.md``, "Contact"."""

from .exposed import ExposedSurface, first_uncovered, overlap_gap, with_rim_vertices
from .nodes import ContactNodes, ContactResult, ContactState, assemble, evaluate, initial_state
from .slider import (
    BOTTOM,
    EDGES,
    LEFT,
    RIGHT,
    TOP,
    SliderShape,
    body_coordinates,
    penetration,
    rotation,
    tangent_continuous,
)
from .vertices import VertexContact, add_vertices, vertex_contact

__all__ = [
    "BOTTOM",
    "EDGES",
    "LEFT",
    "RIGHT",
    "TOP",
    "ContactNodes",
    "ContactResult",
    "ContactState",
    "ExposedSurface",
    "SliderShape",
    "VertexContact",
    "add_vertices",
    "assemble",
    "body_coordinates",
    "evaluate",
    "first_uncovered",
    "initial_state",
    "overlap_gap",
    "penetration",
    "rotation",
    "tangent_continuous",
    "vertex_contact",
    "with_rim_vertices",
]
