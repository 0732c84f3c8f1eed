"""What crushing and the uncovered faces (docs/theory/finite-elements.md, Eqs. F67b, F68c)
change in a containment validation with tearing, or another crushing Jacobian J_c in one made
with them: the two runs that decide each case named (the lowest failing rung and the survival
one rung below it, from the folder's ``fem_comparison.csv`` and ``fem_runs.csv``) run again
with each ``--crush`` J_c, their verdicts beside the stored ones. Writes
``docs/results/TABLE`` (default ``uncovered_faces_check.csv``).

Run (a minute or two of CPU a run)::

    python -m validation.studies.uncovered_faces_check \
        --folder docs/fem-validation-fracture-rims80 --rim-thickness 80 \
        --cases B-PTS_037@60 ERZ_032@60 B-PTS_037@10 PET_260@10

    python -m validation.studies.uncovered_faces_check \
        --folder docs/rim-design/fem-120-containment --rim-thickness 120 --records 8 \
        --pressure 60 --crush 0.05 0.2 --table crush_sensitivity_rims120.csv
"""

from __future__ import annotations

import argparse
import csv
import dataclasses
import time
from pathlib import Path

from threadpoolctl import threadpool_limits

from rigid import DFPBearing, fema_p695
from rigid.collapse.comparison import write_csv
from validation.fem_runs import fem_run
from validation.fem_search import FESettings

from . import RESULTS


def first_cases(folder: Path, records: int, pressure: float) -> list[str]:
    """``NAME@MPA`` of the first ``records`` records of ``folder``'s ``fem_comparison.csv`` at
    ``pressure`` [MPa] whose FE search found an answer."""
    with open(folder / "fem_comparison.csv") as fh:
        rows = [r for r in csv.DictReader(fh)
                if float(r["pressure_mpa"]) == pressure and r["fem_sa_g"]]
    return [f"{r['record']}@{pressure:g}" for r in rows[:records]]


def deciding_runs(folder: Path, case: str):
    """The stored rows (``fem_runs.csv``) of the two runs that decide ``case``, a part of a
    record's name and its pressure, ``NAME@MPA``."""
    name, pressure = case.rsplit("@", 1)
    with open(folder / "fem_comparison.csv") as fh:
        row = next(r for r in csv.DictReader(fh)
                   if name in r["record"] and float(r["pressure_mpa"]) == float(pressure))
    with open(folder / "fem_runs.csv") as fh:
        runs = [r for r in csv.DictReader(fh)
                if r["record"] == row["record"] and r["pressure_mpa"] == row["pressure_mpa"]]
    for sa in (row["fem_sa_g"], row["survived_below_g"]):
        yield next(r for r in runs if abs(float(r["sa_g"]) - float(sa)) < 1e-9)


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--folder", type=Path, required=True,
                   help="a containment validation with --fem-fracture median and 20 mm edges")
    p.add_argument("--rim-thickness", type=float, default=40.0, help="its rims [mm]")
    which = p.add_mutually_exclusive_group(required=True)
    which.add_argument("--cases", nargs="+", help="NAME@MPA each")
    which.add_argument("--records", type=int, help="the first N records at --pressure")
    p.add_argument("--pressure", type=float, default=60.0, help="with --records [MPa]")
    p.add_argument("--crush", type=float, nargs="+", default=[0.1], help="J_c [-], each")
    p.add_argument("--table", default="uncovered_faces_check.csv",
                   help="the CSV's name under docs/results")
    args = p.parse_args(argv)
    motions = {m.name: m for m in fema_p695("nearfield_pulse")}
    cases = args.cases or first_cases(args.folder, args.records, args.pressure)
    rows = []
    for case, crush in ((c, j) for c in cases for j in args.crush):
        options = FESettings(limit_states=("containment",), fracture="median",
                             edge_radius=0.02, crush_jacobian=crush).run_options()
        for stored in deciding_runs(args.folder, case):
            bearing = DFPBearing(pressure=float(stored["pressure_mpa"]) * 1e6,
                                 rim_thickness=args.rim_thickness / 1e3)
            motion = motions[stored["record"]]
            start = time.process_time()
            with threadpool_limits(1):
                out = fem_run(dataclasses.asdict(bearing), motion.acceleration, motion.dt,
                              float(stored["scale"]), **options)
            rows.append({
                "record": stored["record"], "pressure_mpa": stored["pressure_mpa"],
                "sa_g": stored["sa_g"], "stored_failed": stored["failed"],
                "stored_failure_time_s": stored["failure_time_s"],
                "failed": out["failed"], "failure_time_s": out["failure_time"] or "",
                "numerical": out["numerical_failure"], "torn": out["torn_elements"],
                "crushed": out["crushed_elements"], "crush_jacobian": crush,
                "cpu_s": time.process_time() - start})
            print(rows[-1], flush=True)
    print(write_csv(rows, RESULTS / args.table))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
