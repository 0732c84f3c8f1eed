"""The slider's push through tearing with and without crushing (issue #31; docs/theory/
finite-elements.md, Eqs. F67b, F68c, F71): the push of the rigid model's law through tearing
(:func:`fem.slider_push.rim_slider_push`, increments of at most 0.25 mm, torn elements let go
over 10) on the rims whose push stops in Newton without crushing, the thick rims and the
80 mm rim with the steep constants, each with ``crush_jacobian`` None and 0.1. Writes
``docs/results/crushed_rim_push.csv``, a row per push: how far it went, its peak and last
force, where the rim first tore and whether it came off.

Run (about 10 minutes of CPU)::

    python -m validation.studies.crushed_rim_push
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from fem.slider_push import rim_slider_push
from rigid.bearing import DFPBearing
from rigid.collapse.comparison import write_csv
from rigid.rims import TEARING_PUSH

from . import RESULTS

#: (rim thickness [m], fracture set) of each push.
PUSHES = ((0.08, "median"), (0.08, "steep"), (0.12, "median"), (0.16, "median"),
          (0.24, "median"))

#: J_c of the crushing pushes (the thick rims' studies, docs/fe-companion.md).
CRUSH = 0.1


def push(thickness: float, fracture: str, crush: float | None) -> dict:
    """One push of the law through tearing, as :func:`fem.rim_law` makes it, and its row."""
    bearing = DFPBearing(rim_thickness=thickness)
    increment, steps = TEARING_PUSH
    reach = bearing.rim_thickness + bearing.rim_height
    start = time.process_time()
    p = rim_slider_push(bearing, displacement=reach, steps=round(reach / increment),
                        fracture=fracture, erosion_steps=steps, stop_short=True,
                        crush_jacobian=crush)
    tear = p.fracture_displacement
    return {"rim_thickness_mm": thickness * 1e3, "fracture": fracture,
            "crush_jacobian": "" if crush is None else crush,
            "reach_mm": reach * 1e3, "end_mm": p.displacement[-1] * 1e3,
            "peak_force_mn": p.force.max() / 1e6, "last_force_mn": p.force[-1] / 1e6,
            "first_tear_mm": "" if tear is None else tear * 1e3,
            "torn_elements": p.torn_elements, "off": bool(p.separated),
            "cpu_s": time.process_time() - start}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", default=str(RESULTS))
    args = ap.parse_args(argv)
    rows = []
    for thickness, fracture in PUSHES:
        for crush in (None, CRUSH):
            rows.append(push(thickness, fracture, crush))
            print(", ".join(f"{k} {v:.4g}" if isinstance(v, float) else f"{k} {v}"
                            for k, v in rows[-1].items()), flush=True)
    print(write_csv(rows, Path(args.out) / "crushed_rim_push.csv"))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
