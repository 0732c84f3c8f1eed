"""2-D plane-strain finite-element companion of the rigid DFP model (scikit-fem + gmsh).

Modules (the ones needing the ``fem`` extra are imported on demand, not here):

* :mod:`fem.material` — J2 plasticity with capped linear hardening: radial return and the
  consistent tangent at quadrature points (numpy only).
* :mod:`fem.assembly` — plane-strain Q1 with B-bar, einsum assembly (scikit-fem).
* :mod:`fem.newton` — Newton iterations for one quasi-static increment (scikit-fem).
* :mod:`fem.geometry` — the bearing mesh from ``meshes/dfp.geo``, cached (gmsh, scikit-fem).

``fem`` depends on ``rigid`` (for :class:`rigid.DFPBearing`), never the other way.
"""

from .material import Material, MaterialState, ReturnMapResult, return_map, von_mises

__all__ = ["Material", "MaterialState", "ReturnMapResult", "return_map", "von_mises"]
