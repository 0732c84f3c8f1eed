"""What the FE model does when a thick rim (120–240 mm) is driven to the loss of containment:
single FE runs with the containment validations' settings (rims that tear, the median fracture
set, 20 mm slider edges), one record scaled to SAs above its FE rupture, each run's end and the
slider's pose there against the rims' corners (the test of Eq. F37 in
docs/theory/finite-elements.md).

Run: ``OMP_NUM_THREADS=1 python -m validation.studies.thick_rim_containment [--thicknesses
120 160 240] [--sa 0.22 0.34] [--pressure 60] [--record B-PTS_037] [--crush J_C ...]``;
writes ``docs/results/thick_rim_containment.csv`` and, for the first run, the deformed bearing
at its end (``docs/images/thick_rim_containment.png``); with ``--crush``, the rims' elements
are also crushed below each J_c given (Eq. F67b), into ``thick_rim_containment_crush.csv``
and ``thick_rim_containment_crush.png``. Under a minute of CPU a run.
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import time

from threadpoolctl import threadpool_limits

import fem
from fem.contact import SliderShape
from fem.limit_states import corner_nodes, rim_overshoots, slider_vertex_positions
from fem.output import final_pose, nodal_displacement, render_result
from fem.slider_push import EDGE_RADIUS  # 20 mm, the validations' --fem-edge-radius
from rigid import DFPBearing, G, fema_p695, scale_factor
from rigid.collapse.comparison import write_csv
from validation.fem_runs import fem_run

from . import IMAGES, RESULTS


def closest_rim(result) -> dict:
    """The rim a slider vertex is furthest beyond horizontally at the run's end, with that
    vertex's overshoot past the rim's inner corner and the height it still has to climb to get
    over it [mm] (Eq. F37 calls the slider past a rim once the overshoot is positive and the
    climb left negative), in the deformed configuration. The corner is the rim's corner node:
    once that node's elements have torn off, it went with them, and the run's ``detail`` says
    what the containment test saw (it follows what is left of the rim, Eq. F68b)."""
    b = result.bearing
    d = result.final_displacement
    vx, vz = slider_vertex_positions(SliderShape.from_bearing(b, result.edge_radius).vertices,
                                     final_pose(result))
    u = nodal_displacement(result.mesh, d)
    best = (-math.inf, None, None)  # (overshoot [m], rim, climb left [m])
    for name, node in corner_nodes(result.mesh, b).items():
        corner = result.mesh.p[:, node] + u[:, node]
        for _, over, left in rim_overshoots(name, corner, vx, vz):
            best = max(best, (over, name, left), key=lambda candidate: candidate[0])
    over, name, left = best
    return {"rim": name, "overshoot_mm": over * 1e3, "climb_left_mm": left * 1e3}


def render_end(path, result, title: str):
    """The run's final state around the slider (:func:`fem.output.render_result`)."""
    pose = final_pose(result)
    return render_result(path, result, title=title, focus=(pose[0], pose[1], 0.35))


def run(thickness: float, pressure: float, motion, sa_g: float,
        crush_jacobian: float | None = None) -> tuple[dict, object]:
    """One FE containment run of ``motion`` scaled to ``sa_g`` [g] with rims ``thickness``
    [m] thick under ``pressure`` [Pa], rim elements crushed below ``crush_jacobian`` (Eq.
    F67b; default none): (row of the CSV, the FE result)."""
    bearing = DFPBearing(pressure=pressure, rim_thickness=thickness)
    # the record scaled to SA(Tb) with 5 % damping, as the ladders scale records (Eq. M15)
    scale = scale_factor(motion.acceleration, motion.dt, sa_g * G, bearing.design_period)
    captured = {}

    def simulate(*args, **kwargs):
        captured["result"] = fem.simulate(*args, **kwargs)
        return captured["result"]

    start = time.process_time()
    with threadpool_limits(1):
        out = fem_run(dataclasses.asdict(bearing), motion.acceleration, motion.dt,
                      scale, limit_state="containment", fracture="median",
                      edge_radius=EDGE_RADIUS, crush_jacobian=crush_jacobian,
                      simulate=simulate)
    r = captured["result"]
    outcome = ("numerical" if out["numerical_failure"] else out["failure_mode"] or "contained")
    row = {"rim_thickness_mm": thickness * 1e3, "pressure_mpa": pressure / 1e6,
           "record": motion.name, "sa_g": sa_g, "outcome": outcome, "end_s": out["end"],
           "detail": out["detail"] or "", "torn_elements": out["torn_elements"],
           **({} if crush_jacobian is None else
              {"crush_jacobian": crush_jacobian, "crushed_elements": out["crushed_elements"]}),
           "max_plastic_strain": out["max_plastic_strain"],
           "max_rim_force_mn": out["max_rim_force"] / 1e6,
           "slider_x_mm": r.slider_displacement[-1] * 1e3,
           "slider_rise_mm": r.slider_rise[-1] * 1e3,
           "slider_rotation_deg": math.degrees(r.slider_rotation[-1]),
           "top_plate_rise_mm": r.top_plate_rise[-1] * 1e3,
           **closest_rim(r), "cpu_s": time.process_time() - start}
    return row, r


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--thicknesses", type=float, nargs="+", default=[120, 160, 240],
                   help="rim thicknesses [mm]")
    p.add_argument("--sa", type=float, nargs="+", default=[0.22, 0.34],
                   help="SA(4.5 s) of the scaled record [g]")
    p.add_argument("--pressure", type=float, default=60, help="bearing pressure [MPa]")
    p.add_argument("--record", default="B-PTS_037",
                   help="a near-field pulse component, by a part of its name")
    p.add_argument("--crush", type=float, nargs="+", default=None, metavar="J_C",
                   help="crush rim elements below each of these det F (Eq. F67b)")
    args = p.parse_args(argv)
    motion = next((m for m in fema_p695("nearfield_pulse") if args.record in m.name), None)
    if motion is None:
        p.error(f"no near-field pulse component named like {args.record!r}")
    rows = []
    suffix = "" if args.crush is None else "_crush"
    for crush in [None] if args.crush is None else args.crush:
        for thickness in args.thicknesses:
            for sa in args.sa:
                row, result = run(thickness / 1e3, args.pressure * 1e6, motion, sa, crush)
                rows.append(row)
                print(", ".join(f"{k} {v:.4g}" if isinstance(v, float) else f"{k} {v}"
                                for k, v in row.items()), flush=True)
                if len(rows) == 1:
                    render_end(IMAGES / f"thick_rim_containment{suffix}.png", result,
                               f"{thickness:.0f} mm rims, {sa} g: the run's end")
    print(write_csv(rows, RESULTS / f"thick_rim_containment{suffix}.csv"))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
