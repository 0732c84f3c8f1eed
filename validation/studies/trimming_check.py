"""Check the FE runs' trimming (rigid.collapse.trimming) with the rigid model: the critical SA
of every FEMA P695 near-field pulse component with and without trimming, both pressures.

    python -m validation.studies.trimming_check [--trim end|window] [--workers 2] [--records N]

For each record and pressure: rigid.critical_sa (fast search, 0.01 g, stop 1.5 g, untrimmed,
no cache) and rigid.collapse.critical_sa_trimmed (the same search, every rung run
from the strong-motion window's start and judged when the energy after its end is below the
reach energy). Reports per record: both critical SA, the rungs whose verdict differs, rim
impacts or failures after the trimmed end (the end argument says none), and the simulated
time saved. Writes docs/results/trimming_check_<trim>.csv.
"""

from __future__ import annotations

import argparse
import csv
import os
import resource
import time
from pathlib import Path

from rigid.tasks import Task, run_tasks

from . import RESULTS

STEP_G, STOP_G = 0.01, 1.5


def check(pressure: float, index: int, trim: str) -> dict:
    import rigid
    from rigid import DFPBearing, G
    from rigid.collapse.trimming import critical_sa_trimmed

    motion = rigid.fema_p695("nearfield_pulse")[index]
    bearing = DFPBearing(pressure=pressure)
    untrimmed = rigid.critical_sa(bearing, motion, STEP_G * G, stop=STOP_G * G, search="fast")
    trimmed = critical_sa_trimmed(bearing, motion, STEP_G * G, stop=STOP_G * G, search="fast",
                                  trim=trim)
    full = {r.index: r.failed for r in untrimmed.rungs}
    cut = {j: r["failed"] for j, r in trimmed["rungs"].items()}
    common = full.keys() & cut.keys()
    duration = (motion.acceleration.size - 1) * motion.dt
    runs = trimmed["rungs"].values()
    simulated = [r["stop"] - r["start"] for r in runs if r["start"] is not None]
    return {
        "pressure_mpa": pressure / 1e6,
        "index": index,
        "record": motion.name,
        "duration_s": duration,
        "untrimmed_sa_g": None if untrimmed.sa is None else round(untrimmed.sa / G, 6),
        "trimmed_sa_g": None if trimmed["sa"] is None else round(trimmed["sa"] / G, 6),
        "same": untrimmed.sa == trimmed["sa"],
        "rungs_untrimmed": len(full),
        "rungs_trimmed": len(cut),
        "verdicts_differ": sum(full[j] != cut[j] for j in common),
        "late_impacts": sum(r["late_impacts"] for r in runs),
        "late_failures": sum(r["late_failure"] for r in runs),
        "mean_start_s": sum(r["start"] or 0.0 for r in runs) / max(1, len(cut)),
        "mean_trimmed_s": sum(simulated) / max(1, len(simulated)),
    }


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--workers", type=int, default=len(os.sched_getaffinity(0)))
    parser.add_argument("--records", type=int, default=28)
    parser.add_argument("--pressures", type=float, nargs="+", default=[60.0, 10.0])
    parser.add_argument("--trim", choices=("end", "window"), default="end")
    parser.add_argument("--out", help="CSV (default docs/results/trimming_check_<trim>.csv)")
    args = parser.parse_args()
    args.out = args.out or RESULTS / f"trimming_check_{args.trim}.csv"
    tasks = [Task(f"{p}-{i}", "trimming-check", check,
                  {"pressure": p * 1e6, "index": i, "trim": args.trim})
             for p in args.pressures for i in range(args.records)]
    wall0 = time.perf_counter()
    results = run_tasks(tasks, None, workers=args.workers, progress=True, unit="record",
                        description="trimming check")
    rows = [results[t.key] for t in tasks]
    for r in rows:
        print(f"{r['pressure_mpa']:4g} MPa {r['record'][:40]:40s} "
              f"untrimmed {r['untrimmed_sa_g']} trimmed {r['trimmed_sa_g']} "
              f"{'same' if r['same'] else 'DIFFERENT'}; differing rungs "
              f"{r['verdicts_differ']}, late impacts {r['late_impacts']}")
    rows.sort(key=lambda r: (-r["pressure_mpa"], r["index"]))
    wall = time.perf_counter() - wall0
    usage = [resource.getrusage(w) for w in (resource.RUSAGE_SELF, resource.RUSAGE_CHILDREN)]
    cpu = sum(u.ru_utime + u.ru_stime for u in usage)
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    with open(args.out, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    same = sum(r["same"] for r in rows)
    print(f"\nsame critical SA: {same}/{len(rows)}; rungs with a different verdict: "
          f"{sum(r['verdicts_differ'] for r in rows)}; late impacts: "
          f"{sum(r['late_impacts'] for r in rows)}; late failures: "
          f"{sum(r['late_failures'] for r in rows)}")
    print(f"wall {wall:.0f} s, CPU {cpu:.0f} s, load {os.getloadavg()[0]:.1f}; -> {args.out}")


if __name__ == "__main__":
    main()
