"""Does the rim lift the slider? The rigid model's law through tearing comes from a push that
holds the slider on its pendulum path (:func:`fem.slider_push.rim_slider_push`, Eq. F71), so
the rim may push it up with any force. In the bearing what holds it down is the supported
weight W = p·πd²/4. This study takes the law's own push (median criterion, crushing at
J_c = 0.1, 20 mm edges, its increments) at each rim thickness and sets the rim's vertical
force on the slider against W at 60 and 10 MPa: the set at which it first exceeds W (from
there a slider held down by W alone would leave its path and climb the rim), and its largest
value, beside where the push first tears the rim.

Writes ``docs/results/slider_lift.csv`` (a row per thickness and pressure) and
``slider_lift_curves.csv`` (the push's horizontal and vertical force on the slider against its
set). Run (a few minutes of CPU)::

    python -m validation.studies.slider_lift [--thicknesses 80 120 160 240]
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path
from unittest import mock

from fem import slider_push
from fem.pushover import PushRecord
from rigid.bearing import DFPBearing
from rigid.collapse.comparison import write_csv
from rigid.rims import TEARING_PUSH

from . import RESULTS
from .containment_tearing import CRUSH_JACOBIAN

PRESSURES = (60.0, 10.0)  # [MPa]


def lift_curve(thickness: float) -> tuple[list[dict], object]:
    """The law's push through tearing of the ``thickness`` [mm] rim with crushing
    (:func:`fem.rim_law`'s, ``punch="slider"``): per accepted increment the set δ [mm] and the
    rim's horizontal (outward +) and vertical (upward +) force on the slider [MN] (times the
    model's depth); and the push (:class:`fem.pushover.Pushover`)."""
    bearing = DFPBearing(rim_thickness=thickness / 1e3)
    depth = slider_push.bottom_plate(bearing).depth
    last, rows = {}, []
    newton, add = slider_push._newton, PushRecord.add

    def solved(*args, **kwargs):  # the converged increment's force on the slider
        res = newton(*args, **kwargs)
        if res is not None:
            last["force"] = res[3]
        return res

    def recorded(self, delta, force, *args, **kwargs):
        rows.append({"rim_thickness_mm": thickness, "set_mm": delta * 1e3,
                     "horizontal_mn": force / 1e6,
                     "vertical_mn": float(last["force"][1]) * depth / 1e6})
        return add(self, delta, force, *args, **kwargs)

    increment, erosion_steps = TEARING_PUSH
    reach = bearing.rim_thickness + bearing.rim_height
    with mock.patch.object(slider_push, "_newton", solved), \
            mock.patch.object(PushRecord, "add", recorded):
        push = slider_push.rim_slider_push(
            bearing, displacement=reach, steps=round(reach / increment), fracture="median",
            erosion_steps=erosion_steps, stop_short=True, crush_jacobian=CRUSH_JACOBIAN)
    return rows, push


def lift_rows(curve: list[dict], push, pressures=PRESSURES) -> list[dict]:
    """Per pressure [MPa]: the weight W [MN], the first set [mm] at which the rim's upward
    force on the slider reaches it (blank: never), the largest upward force and its set, and
    the push's first tear and end [mm]."""
    top = max(curve, key=lambda r: r["vertical_mn"])
    tear = push.fracture_displacement
    out = []
    for p in pressures:
        weight = p * math.pi * DFPBearing.slider_diameter ** 2 / 4  # [MN]: MPa × m²
        lift = next((r["set_mm"] for r in curve if r["vertical_mn"] >= weight), "")
        out.append({"rim_thickness_mm": curve[0]["rim_thickness_mm"], "pressure_mpa": p,
                    "weight_mn": weight, "lifted_from_mm": lift,
                    "largest_upward_mn": top["vertical_mn"], "largest_at_mm": top["set_mm"],
                    "first_tear_mm": "" if tear is None else tear * 1e3,
                    "push_end_mm": curve[-1]["set_mm"]})
    return out


def main(argv=None) -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--thicknesses", type=float, nargs="+", default=[80, 120, 160, 240],
                   help="rim thicknesses [mm]")
    p.add_argument("--out", type=Path, default=RESULTS)
    args = p.parse_args(argv)
    curves, rows = [], []
    for t in args.thicknesses:
        curve, push = lift_curve(t)
        curves += curve
        rows += lift_rows(curve, push)
        for r in rows[-len(PRESSURES):]:
            print({k: round(v, 3) if isinstance(v, float) else v for k, v in r.items()},
                  flush=True)
    write_csv(rows, args.out / "slider_lift.csv")
    write_csv(curves, args.out / "slider_lift_curves.csv")


if __name__ == "__main__":
    main()
