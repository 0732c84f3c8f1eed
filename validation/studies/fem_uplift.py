"""Does the light bearing (10 MPa) of the FE model ever fail by uplift? A sweep of Ricker pulses.

For each Ricker pulse (Tp, Ap, symmetric or antisymmetric) the script runs the rigid model and
the FE model (coarse mesh, finite deformation, ``limit_state="containment"`` so the run
goes on past the first rim hinge until the slider gets past a rim) and prints the outcome of
both, the FE limit states and hinge times, and the quantities that decide between tipping and
rim yielding: the largest slider rotation and rise, and the largest rim force against the
tipping force F_tip = W b/h (the rim couple that lifts the supported load W over the slider's
edge) and the rim root's plastic shear capacities V_p = t f_y/√3 and V_u = t f_u/√3 (times the
model depth).

Run: ``OMP_NUM_THREADS=1 python -m validation.studies.fem_uplift [Tp:Ap_g[:a] ...]`` (``:a`` for
an antisymmetric pulse; ``--small`` for small strain; ``--vertices`` makes the slider's vertices
contact points; ``--yield-scale K`` multiplies the steel's f_y and f_u by K and
``--rim-thickness T`` [m] sets the rims' thickness, variants of the assumed rims). The findings
are summarised in ``docs/fe-companion.md`` and the README.
"""

from __future__ import annotations

import math
import sys
import tempfile
import time
from dataclasses import replace

import numpy as np

import fem
import rigid
from fem.dfp import out_of_plane_depth
from fem.geometry import COARSE_MESH
from rigid import DFPBearing, G, ricker_record

#: ``--small`` runs the FE model at small strain (the study's first version).
KINEMATICS = "small" if "--small" in sys.argv else "finite"
DEFAULT = ["2:0.8", "1:2.0", "0.5:3.0", "3:0.8", "1:1.0", "2:1.5", "2:1.0:a", "1:2.0:a"]
#: The FE runs' settings besides the kinematics: coarse mesh, run to the loss of containment.
FE_OPTIONS = {"mesh_options": COARSE_MESH, "max_step": 0.01, "limit_state": "containment"}


def parse_case(case: str) -> tuple[float, float, str]:
    """Tp [s], Ap [g] and kind of a case written ``Tp:Ap_g`` or ``Tp:Ap_g:a`` (antisymmetric)."""
    parts = case.split(":")
    return float(parts[0]), float(parts[1]), ("antisymmetric" if parts[2:] == ["a"]
                                              else "symmetric")


def pulse(tp: float, ap_g: float, kind: str) -> np.ndarray:
    """The Ricker pulse's ground acceleration [m/s²], every 0.005 s, 3 s of rest after it."""
    return ricker_record(ap_g * G, tp, kind, dt=0.005, free=3.0)[1]


def one(bearing, tp, ap_g, cache, kind="symmetric", vertices=False):
    """Rigid and FE outcome of one pulse; returns a printable line."""
    a = pulse(tp, ap_g, kind)
    rb = rigid.simulate(bearing, a, 0.005)
    v_imp = max((abs(i.velocity) for i in rb.impacts), default=0.0)
    c0 = time.process_time()
    res = fem.simulate(bearing, a, 0.005, **FE_OPTIONS, vertex_contact=vertices,
                       kinematics=KINEMATICS, cache_dir=cache)
    cpu = time.process_time() - c0
    W = bearing.weight
    f_tip = W * bearing.slider_diameter / bearing.slider_height
    v_p = bearing.rim_thickness * bearing.yield_stress / math.sqrt(3) * res.depth
    first_hinge = min(res.hinge_times.values()) if res.hinge_times else None
    at_hinge = ""
    if first_hinge is not None:
        k = int(np.searchsorted(res.time, first_hinge))
        at_hinge = (f" (rim force then {res.rim_force[: k + 1].max() / 1e6:.2f} MN, |θ| "
                    f"{np.abs(res.slider_rotation[: k + 1]).max():.3f} rad)")
    states = ", ".join(f"{k} {'-' if v is None else f'{v:.3f} s'}"
                       for k, v in res.limit_states.items())
    fe = (f"{res.failure_mode} at {res.failure_time:.3f} s ({res.failure_detail}; {states})"
          if res.failed
          else ("NUMERICAL: " + str(res.failure_detail)) if res.numerical_failure
          else "no failure")
    return (
        f"{kind[:4]} Tp {tp:4.1f} s Ap {ap_g:4.1f} g | rigid: "
        + (f"{rb.failure_mode} at {rb.failure_time:.2f} s" if rb.failed else "no failure")
        + f", impact {v_imp:.2f} m/s | FE: {fe}; first hinge "
        + (f"{first_hinge:.3f} s{at_hinge}" if first_hinge is not None else "none")
        + f"; max |θ| {np.abs(res.slider_rotation).max():.3f} rad, max rise "
        f"{res.slider_rise.max() * 1e3:.1f} mm, max rim force {res.rim_force.max() / 1e6:.2f} MN"
        f" = {res.rim_force.max() / f_tip:.2f} F_tip = {res.rim_force.max() / v_p:.2f} V_p; "
        f"max plastic strain {res.max_plastic_strain:.3f}; {res.time[-1]:.2f} s simulated, "
        f"CPU {cpu:.0f} s"
    )


def _option(name, default):
    """The value after ``name`` on the command line, or ``default``."""
    return sys.argv[sys.argv.index(name) + 1] if name in sys.argv else default


def main() -> None:
    cases = [arg for arg in sys.argv[1:] if ":" in arg] or DEFAULT
    bearing = DFPBearing(pressure=10e6)
    scale = float(_option("--yield-scale", 1.0))
    bearing = replace(
        bearing, yield_stress=scale * bearing.yield_stress,
        ultimate_stress=scale * bearing.ultimate_stress,
        rim_thickness=float(_option("--rim-thickness", bearing.rim_thickness)),
    )
    W = bearing.weight
    depth = out_of_plane_depth(bearing)
    t = bearing.rim_thickness
    print(f"light bearing: W = {W / 1e6:.3f} MN, F_tip = W b/h = "
          f"{W * bearing.slider_diameter / bearing.slider_height / 1e6:.2f} MN, "
          f"V_p = {t * bearing.yield_stress / math.sqrt(3) * depth / 1e6:.2f} MN, "
          f"V_u = {t * bearing.ultimate_stress / math.sqrt(3) * depth / 1e6:.2f} MN")
    with tempfile.TemporaryDirectory() as cache:
        for case in cases:
            tp, ap_g, kind = parse_case(case)
            print(one(bearing, tp, ap_g, cache, kind, "--vertices" in sys.argv), flush=True)


if __name__ == "__main__":
    main()
