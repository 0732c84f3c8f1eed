"""2-D plane-strain finite-element companion of the rigid DFP model (scikit-fem + gmsh).

Modules (the ones needing the ``fem`` extra are imported on demand, not here):

* :mod:`fem.material` — J2 plasticity with capped linear hardening: radial return and the
  consistent tangent at quadrature points (numpy only).
* :mod:`fem.assembly` — plane-strain Q1 with B-bar, einsum assembly (scikit-fem).
* :mod:`fem.newton` — Newton iterations for one quasi-static increment (scikit-fem).
* :mod:`fem.geometry` — the bearing mesh from ``meshes/dfp.geo``, cached (gmsh, scikit-fem).
* :mod:`fem.contact` — the rigid slider: its section and exact rotation, node-to-analytic-
  surface penalty contact with Coulomb friction and its coupled tangent, optional
  vertex-to-facet contact (numpy only).
* :mod:`fem.system` — plates + slider: internal forces, tangent, constraints, static Newton.
* :mod:`fem.dfp` — the bearing as a plane-strain system (depth, masses, ties, loads).
* :mod:`fem.linear` — Newton's linear solves: cached elastic LU + low-rank (Woodbury) update.
* :mod:`fem.dynamics` — HHT-α with Newton, step cutback and an energy balance.
* :mod:`fem.model` — :func:`simulate` and :class:`FEMResult`, failure detection.
* :mod:`fem.output` — VTU files and pictures (meshio, pyvista).

``fem`` depends on ``rigid`` (for :class:`rigid.DFPBearing`), never the other way.
"""

from .material import Material, MaterialState, ReturnMapResult, return_map, von_mises
from .model import FEMResult, simulate

__all__ = [
    "FEMResult",
    "Material",
    "MaterialState",
    "ReturnMapResult",
    "return_map",
    "simulate",
    "von_mises",
]
