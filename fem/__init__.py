"""2-D plane-strain finite-element companion of the rigid DFP model (scikit-fem + gmsh).

Modules (the ones needing the ``fem`` extra are imported on demand, not here):

* :mod:`fem.material` — J2 plasticity with capped linear hardening: radial return and the
  consistent tangent at quadrature points (numpy only).
* :mod:`fem.assembly` — plane-strain Q1 with B-bar, einsum assembly (scikit-fem).
* :mod:`fem.hencky`, :mod:`fem.finite_element` — finite deformation: Hencky J2 plasticity
  with the exponential map, mean-dilatation Q1, complex-step tangents.
* :mod:`fem.newton` — Newton iterations for one quasi-static increment (scikit-fem).
* :mod:`fem.geometry` — the bearing mesh from ``meshes/dfp.geo``, cached (gmsh, scikit-fem).
* :mod:`fem.contact` — the rigid slider: its section and exact rotation, node-to-analytic-
  surface penalty contact with Coulomb friction and its coupled tangent, optional
  vertex-to-facet contact (numpy only).
* :mod:`fem.system` — plates + slider: internal forces, tangent, constraints, static Newton.
* :mod:`fem.dfp` — the bearing as a plane-strain system (depth, masses, ties, loads).
* :mod:`fem.linear` — Newton's linear solves: cached elastic LU + low-rank (Woodbury) update.
* :mod:`fem.dynamics` — HHT-α with Newton, step cutback and an energy balance.
* :mod:`fem.model` — :func:`simulate`, :class:`FEMResult` and :class:`fem.model.FEEnergy`.
* :mod:`fem.observer` — what a run records after every step: histories, snapshots, verdict.
* :mod:`fem.limit_states` — hinge, rupture and containment, watched during a run.
* :mod:`fem.pushover` — :func:`rim_pushover`, the static push of a rim.
* :mod:`fem.rim_laws` — :func:`rim_law`, the yielding rims' law from pushes of the rim, the
  data :func:`rigid.simulate` takes with ``rims="yielding"`` (cached per rim geometry and
  model, plane strain or the ring), and :func:`effective_rim_depth`, the depth that gives the
  plane-strain rim the ring's force at a limit state (``simulate(rim_depth=…)``).
* :mod:`fem.output` — VTU files and pictures (meshio, pyvista).
* :mod:`fem.ring` — the rim as a ring: 3-D static pushes of the rim and the effective depth
  of the plane-strain rim (imported on its own: ``from fem.ring import ring_push``).

``fem`` depends on ``rigid`` (the bearing, records, pulses, the rim law's data class), never
the other way, and never on ``validation`` (docs/architecture.md).
"""

from rigid.reprs import install as _short_reprs

from .limit_states import LIMIT_STATES
from .material import Material, MaterialState, ReturnMapResult, return_map, von_mises
from .model import FEMResult, simulate
from .pushover import rim_pushover
from .rim_laws import effective_rim_depth, rim_law

_short_reprs(FEMResult)

__all__ = [
    "LIMIT_STATES",
    "FEMResult",
    "Material",
    "MaterialState",
    "ReturnMapResult",
    "effective_rim_depth",
    "return_map",
    "rim_law",
    "rim_pushover",
    "simulate",
    "von_mises",
]
