"""Mesh dependence of the rim's push and of the rupture measure, on meshes of a few element
sizes at the rim (docs/theory/finite-elements.md, Eqs. F51–F52).

- The face push (:func:`fem.rim_pushover`, finite deformation, to half the rim height; Newton
  failing ends it short): its force at 5 and 10 mm and at its end, the largest local
  equivalent plastic strain against the largest one averaged over a gauge of the rim
  thickness.
- With ``--slider``, also the slider's push through tearing (:func:`fem.slider_push.
  rim_slider_push`, 20 mm edges, median fracture constants, as for the rigid model's law
  through tearing, Eq. F71): how far it gets, its force at 10 and 25 mm, and the pushed rim's
  largest damage and gauge triaxiality at its end, with its first tear if any.

Writes ``docs/results/rupture_mesh.csv`` (the 40 mm rim) or ``rupture_mesh_T.csv`` (a rim T mm
thick, ``--rim-thickness T``).

Run (about two minutes of CPU at 40 mm; sixteen for the 160 mm rim with ``--slider``)::

    python -m validation.studies.rupture_mesh [--rim-thickness 160 --rim-sizes 20 10 5 --slider]
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

from fem.limit_states import rim_gauge_average
from fem.pushover import rim_pushover
from rigid import DFPBearing
from rigid.collapse.comparison import write_csv
from rigid.rims import TEARING_PUSH

from . import RESULTS

#: Rim element sizes [m]: 2, 4, 8 and 16 elements across the 40 mm rim (8: the default mesh).
RIM_SIZES = (0.02, 0.01, 0.005, 0.0025)


def regularised_peak(push, bearing: DFPBearing) -> float:
    """Largest plastic strain of the pushed (+x) rim averaged over a disc of diameter t_r
    (Eq. F52)."""
    from fem.assembly import PlaneStrainQ1

    mesh = push.plate.mesh
    elems, operator = rim_gauge_average(PlaneStrainQ1(mesh), mesh, "bottom +x",
                                        bearing.rim_thickness)
    return float((operator @ push.final_plastic_strain[elems].ravel()).max())


def force_at(push, delta: float) -> float:
    """The push's force [MN] at its advance ``delta`` [m]; NaN if it stopped short of it."""
    d = push.displacement
    return float(np.interp(delta, d, push.force)) / 1e6 if d[-1] >= delta else float("nan")


def face_row(bearing: DFPBearing, size: float) -> dict:
    """The face push on rim elements of ``size`` [m]: one CSV row."""
    t0 = time.process_time()
    push = rim_pushover(bearing, mesh_options={"rim_size": size}, stop_short=True)
    return {
        "rim_size_mm": size * 1e3,
        "elements_across_rim": round(bearing.rim_thickness / size),
        "elements_up_rim": round(bearing.rim_height / size, 1),
        "dofs": push.dofs,
        "reach_mm": push.displacement[-1] * 1e3,
        "force_5mm_mn": force_at(push, 0.005),
        "force_10mm_mn": force_at(push, 0.010),
        "force_mn": push.force[-1] / 1e6,
        "local_peak_plastic_strain": float(push.final_plastic_strain.max()),
        "regularised_peak_plastic_strain": regularised_peak(push, bearing),
        "cpu_s": time.process_time() - t0,
    }


def slider_row(bearing: DFPBearing, size: float) -> dict:
    """The slider's push through tearing on rim elements of ``size`` [m], as
    :func:`fem.rim_law` makes it for a law through tearing: the CSV row's slider columns."""
    from fem.slider_push import rim_slider_push

    t0 = time.process_time()
    increment, erosion_steps = TEARING_PUSH
    reach = bearing.rim_thickness + bearing.rim_height
    push = rim_slider_push(bearing, displacement=reach, steps=round(reach / increment),
                           fracture="median", erosion_steps=erosion_steps, stop_short=True,
                           mesh_options={"rim_size": size})
    return {
        "slider_reach_mm": push.displacement[-1] * 1e3,
        "slider_force_10mm_mn": force_at(push, 0.010),
        "slider_force_25mm_mn": force_at(push, 0.025),
        "slider_peak_force_mn": float(push.force.max()) / 1e6,
        "slider_first_tear_mm": (push.fracture_displacement or float("nan")) * 1e3,
        "slider_damage_at_end": float(push.damage[-1]),
        "slider_gauge_triaxiality_at_end": float(push.triaxiality[-1]),
        "slider_local_peak_plastic_strain": float(push.max_plastic_strain[-1]),
        "slider_cpu_s": time.process_time() - t0,
    }


def main() -> None:
    baseline = DFPBearing().rim_thickness * 1e3  # [mm]
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rim-thickness", type=float, default=baseline, help="rim thickness [mm]")
    ap.add_argument("--rim-sizes", type=float, nargs="+", help="element sizes at the rim "
                    "[mm]; default 20, 10, 5 and 2.5")
    ap.add_argument("--slider", action="store_true", help="also the slider's push through "
                    "tearing on each mesh")
    ap.add_argument("--out", default=str(RESULTS))
    args = ap.parse_args()
    bearing = DFPBearing(rim_thickness=args.rim_thickness / 1e3)
    sizes = RIM_SIZES if args.rim_sizes is None else [s / 1e3 for s in args.rim_sizes]
    rows = []
    for size in sizes:
        row = face_row(bearing, size)
        if args.slider:
            row.update(slider_row(bearing, size))
        rows.append(row)
        print(rows[-1], flush=True)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    name = ("rupture_mesh.csv" if args.rim_thickness == baseline
            else f"rupture_mesh_{args.rim_thickness:g}.csv")
    write_csv(rows, out / name)
    print(f"wrote {out / name}")


if __name__ == "__main__":
    main()
