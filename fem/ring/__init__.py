"""The rim as a ring: 3-D static pushes of the bottom plate's circular rim, the plane-strain
strip of the same section, and the effective depth that turns one into the other
(docs/theory/finite-elements.md, "The rim as a ring", Eqs. F54–F58; docs/rim-3d/README.md).

* :mod:`fem.ring.mesh` — the cross-section (gmsh) swept into hexahedra: the half ring, the
  whole ring, a quarter of the free ring, or the one-layer plane-strain slab.
* :mod:`fem.ring.solid` — small-strain J2 on 20-node bricks with 2 × 2 × 2 Gauss points.
* :mod:`fem.ring.contact` — the slider as a rigid cylinder in penalty contact.
* :mod:`fem.ring.linear` — the tangent's factorisation (PARDISO or SuperLU).
* :mod:`fem.ring.push` — :func:`ring_push`: the push and its first yield, hinge, rupture and
  limit load.
* :mod:`fem.ring.ccx` — the same push as a CalculiX deck.

Needs the ``fem`` extra (scikit-fem, gmsh, meshio); ``pypardiso`` (the ``fast`` extra) makes
the factorisations several times faster.
"""

from .mesh import COARSE, DEFAULT, FINE, MESHES, MeshSizes, RingMesh, ring_mesh
from .push import Load, RingPush, load_patch_widths, ring_push

__all__ = ["COARSE", "DEFAULT", "FINE", "MESHES", "Load", "MeshSizes", "RingMesh", "RingPush",
           "load_patch_widths", "ring_mesh", "ring_push"]
