"""Where the rim begins to tear in a static push, on four meshes and with the three sets of
the fracture criterion (issue #31 item 3; docs/theory/finite-elements.md, Eqs. F62–F67): the
rim push (:func:`fem.rim_pushover`, finite deformation) with ``fracture=``, the displacement
and force at which the first element's damage reaches 1, and the gauge's triaxiality there.
Writes ``docs/results/rim_fracture_push.csv``.

Run (about six minutes)::

    python -m validation.studies.rim_fracture_push
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from fem.geometry import COARSE_MESH
from fem.pushover import rim_pushover
from rigid import DFPBearing
from rigid.collapse.comparison import write_csv

from . import RESULTS

#: The meshes: the validation's coarse one (20 mm at the rims), 10 mm, the default (5 mm)
#: and a fine one (2.5 mm): 2 to 16 elements across a 40 mm rim.
MESHES = {"coarse": COARSE_MESH, "10 mm": {"rim_size": 0.01}, "default": {},
          "fine": {"rim_size": 0.0025}}
#: Rim thicknesses [m] and how far each is pushed [m]: past the 40 mm rim's tear, and on the
#: 80 mm one as far as Newton converges (near 21 mm; 6.6 mm on the fine mesh).
PUSHES = {0.04: 0.016, 0.08: 0.02}
SETS = ("steep", "median", "mild")


def push_row(bearing: DFPBearing, mesh: str, fracture: str, reach: float) -> dict:
    """One push and where it tore (empty fields: it did not within ``reach`` [m])."""
    t0 = time.process_time()
    push = rim_pushover(bearing, fracture=fracture, displacement=reach, steps=60,
                        mesh_options=MESHES[mesh], stop_short=True)
    torn = push.fracture_displacement is not None
    k = int(push.damage.argmax()) if not torn else int(
        (push.displacement >= push.fracture_displacement).argmax())
    return {
        "rim_thickness_mm": round(bearing.rim_thickness * 1e3),
        "mesh": mesh,
        "dofs": push.dofs,
        "fracture_set": fracture,
        "pushed_to_mm": round(push.displacement[-1] * 1e3, 3),
        "tear_displacement_mm": push.fracture_displacement * 1e3 if torn else "",
        "tear_force_mn": push.fracture_force / 1e6 if torn else "",
        "hinge_displacement_mm": (push.hinge_displacement * 1e3
                                  if push.hinge_displacement is not None else ""),
        "largest_damage": float(push.damage.max()),
        "gauge_triaxiality": float(push.triaxiality[k]),
        "cpu_s": round(time.process_time() - t0, 1),
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=str(RESULTS))
    args = ap.parse_args()
    rows = []
    for thickness, reach in PUSHES.items():
        bearing = DFPBearing(rim_thickness=thickness)
        for mesh in MESHES:
            for fracture in SETS:
                rows.append(push_row(bearing, mesh, fracture, reach))
                print(rows[-1], flush=True)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    write_csv(rows, out / "rim_fracture_push.csv")
    print(f"wrote {out / 'rim_fracture_push.csv'}")


if __name__ == "__main__":
    main()
