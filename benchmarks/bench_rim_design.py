"""CPU and wall time of the rim design space's cases (validation/studies/rim_design.py), by
part: with rigid rims (the ladder and the first-touch search, once per record and pressure)
and with yielding rims (the ladder run to containment, all three limit states, per rim); and
the sweep's time on two idle cores extrapolated from them.

A sample of records × thicknesses × pressures, no rung cache, one warm-up pass (Numba
compiles) then ``--repeats`` timed passes; the median pass is reported. Run from a checkout::

    python benchmarks/bench_rim_design.py [--records 0,9,18,27] [--thicknesses 40 160]
        [--repeats 3]
"""

from __future__ import annotations

import argparse
import os
import platform
import statistics
import time

import fem
import rigid
from rigid import DFPBearing
from validation.studies.rim_design import PRESSURES_MPA, STOP, THICKNESSES_MM
from validation.studies.rim_design_case import rigid_case, yielding_case


def _timed(func, *args):
    c0, w0 = time.process_time(), time.perf_counter()
    func(*args)
    return time.process_time() - c0, time.perf_counter() - w0


def one_pass(rigid_cases, yielding_cases) -> dict:
    """Seconds of CPU and wall per part: the rigid-rim cases [(bearing, motion)], once per
    record and pressure, and the yielding-rim cases [(bearing, law, motion)]."""
    cpu, wall = {}, {}
    for part, func, cases in (("rigid rims", rigid_case, rigid_cases),
                              ("yielding rims", yielding_case, yielding_cases)):
        c = w = 0.0
        for *args, motion in cases:
            dc, dw = _timed(func, args[0], motion, *args[1:], STOP, None)
            c, w = c + dc, w + dw
        cpu[part], wall[part] = c, w
    return {"cpu": cpu, "wall": wall}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--records", default="0,9,18,27",
                    help="comma-separated indices of near-field pulse components")
    ap.add_argument("--thicknesses", type=float, nargs="+", default=[40, 160],
                    help="rim thicknesses [mm]")
    ap.add_argument("--repeats", type=int, default=3)
    args = ap.parse_args()
    motions = rigid.fema_p695("nearfield_pulse")
    picked = [motions[int(i)] for i in args.records.split(",")]
    rigid_cases = [(DFPBearing(pressure=p * 1e6), m) for p in PRESSURES_MPA for m in picked]
    yielding_cases = []
    for t in args.thicknesses:
        for p in PRESSURES_MPA:
            bearing = DFPBearing(pressure=p * 1e6, rim_thickness=t * 1e-3)
            law = fem.rim_law(bearing)  # cached per rim: not the sweep's cost
            yielding_cases += [(bearing, law, m) for m in picked]
    one_pass(rigid_cases[:1], yielding_cases[:1])  # warm-up: compile
    passes = [one_pass(rigid_cases, yielding_cases) for _ in range(args.repeats)]
    totals = [sum(x["cpu"].values()) for x in passes]
    median = passes[totals.index(statistics.median_low(totals))]
    counts = {"rigid rims": len(rigid_cases), "yielding rims": len(yielding_cases)}
    print(f"{platform.processor() or platform.machine()}, {os.cpu_count()} cores; load "
          f"average {os.getloadavg()[0]:.1f} (1 min) at the end")
    print(f"{len(picked)} records x {len(PRESSURES_MPA)} pressures, yielding rims at "
          f"{len(args.thicknesses)} thicknesses; median of {args.repeats} passes:")
    for part, n in counts.items():
        print(f"  {part:14s} CPU {median['cpu'][part] / n:6.2f} s per case, wall "
              f"{median['wall'][part] / n:6.2f} s per case ({n} cases)")
    records = len(motions) * len(PRESSURES_MPA)
    cpu = (median["cpu"]["rigid rims"] / counts["rigid rims"] * records
           + median["cpu"]["yielding rims"] / counts["yielding rims"] * records
           * len(THICKNESSES_MM))
    print(f"  the sweep ({records} rigid-rim and {records * len(THICKNESSES_MM)} yielding-rim "
          f"cases): {cpu / 60:.0f} min of CPU, {cpu / 120:.1f} min on two idle cores")


if __name__ == "__main__":
    main()
