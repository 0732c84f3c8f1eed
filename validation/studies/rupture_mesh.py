"""Mesh dependence of the rupture measure: the rim push (:func:`fem.rim_pushover`, finite
deformation, to half the rim height) on meshes of 2 to 16 elements across the rim, the largest
local equivalent plastic strain against the largest one averaged over a gauge of the rim
thickness (docs/theory/finite-elements.md, Eqs. F51–F52). Writes
``docs/results/rupture_mesh.csv``.

Run (about two minutes)::

    python -m validation.studies.rupture_mesh
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from fem.limit_states import rim_gauge_average
from fem.pushover import rim_pushover
from rigid import DFPBearing
from rigid.collapse.comparison import write_csv

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


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=str(RESULTS))
    args = ap.parse_args()
    bearing = DFPBearing()
    rows = []
    for size in RIM_SIZES:
        t0 = time.process_time()
        push = rim_pushover(bearing, mesh_options={"rim_size": size})
        rows.append({
            "rim_size_mm": size * 1e3,
            "elements_across_rim": round(bearing.rim_thickness / size),
            "dofs": push.dofs,
            "force_mn": push.force[-1] / 1e6,
            "local_peak_plastic_strain": float(push.final_plastic_strain.max()),
            "regularised_peak_plastic_strain": regularised_peak(push, bearing),
            "cpu_s": time.process_time() - t0,
        })
        print(rows[-1], flush=True)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    write_csv(rows, out / "rupture_mesh.csv")
    print(f"wrote {out / 'rupture_mesh.csv'}")


if __name__ == "__main__":
    main()
