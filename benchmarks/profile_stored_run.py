"""Where one FE run of a validation store spends its time: the run, found in the store by its
record and SA, is made again with today's code under cProfile (one BLAS thread, as in a
worker), its result checked against the stored one, and the functions that took the most
time printed, by own time and by cumulative time.

Run, from a checkout (it reads the store through ``validation.studies``)::

    OMP_NUM_THREADS=1 python benchmarks/profile_stored_run.py \\
        --out docs/fem-validation-fracture-rims80 --limit-state containment \\
        --rim-thickness 80 --fem-fracture median --fem-edge-radius 20 --rim-punch slider \\
        --record nearfield_pulse-2a --sa 0.24 [--top 25] [--save run.pstats]

(the run's stored CPU time and about half as much again for the profiler). With
``--no-profile`` the run is only timed (CPU, wall and the machine's load), to compare two
checkouts' code on the same stored run.
"""

from __future__ import annotations

import argparse
import cProfile
import os
import pstats
import time
from pathlib import Path

from threadpoolctl import threadpool_limits

from rigid import fema_p695
from validation.fem_runs import fem_run
from validation.studies.fem_validation_status import run_settings, stored_runs
from validation.studies.stored_runs_check import FIELDS


def main(argv=None) -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--out", type=Path, required=True, help="the validation folder")
    p.add_argument("--limit-state", nargs="+", default=["containment"])
    p.add_argument("--rim-thickness", type=float, default=None, help="[mm]")
    p.add_argument("--fem-fracture", default=None)
    p.add_argument("--fem-edge-radius", type=float, default=0.0, help="[mm]")
    p.add_argument("--rim-punch", default="face")
    p.add_argument("--record", required=True, help="the start of the record's name")
    p.add_argument("--sa", type=float, required=True, help="the run's SA [g], to 0.005 g")
    p.add_argument("--top", type=int, default=25)
    p.add_argument("--save", type=Path, default=None, help="write the profile here")
    p.add_argument("--no-profile", dest="profile", action="store_false",
                   help="time the run without the profiler")
    args = p.parse_args(argv)
    settings = run_settings(args.limit_state, args.rim_thickness, args.fem_fracture,
                            args.fem_edge_radius, args.rim_punch)
    motions = fema_p695("nearfield_pulse")
    found = [(result, kwargs) for result, kwargs, motion, sa in
             stored_runs(args.out, settings, motions)
             if motion.name.startswith(args.record) and abs(sa - args.sa) < 0.005]
    if not found:
        raise SystemExit(f"{args.out}: no stored run of {args.record}* at {args.sa:g} g")
    stored, kwargs = found[0]
    profile = cProfile.Profile()
    cpu, wall = time.process_time(), time.perf_counter()
    with threadpool_limits(1):
        if args.profile:
            profile.enable()
        again = fem_run(**kwargs)
        profile.disable()
    cpu, wall = time.process_time() - cpu, time.perf_counter() - wall
    differ = [f for f in FIELDS if stored[f] != again[f]]
    print(f"{args.record} at {args.sa:g} g: {again['steps']} steps, "
          f"{again['newton_iterations']} Newton iterations, {again['dofs']} dofs; "
          f"{cpu:.1f} s of CPU{' profiled' if args.profile else ''} ({wall:.1f} s wall, "
          f"load {os.getloadavg()[0]:.1f}) against {stored['cpu_seconds']:.1f} s stored; "
          + ("the same result as stored" if not differ else
             f"differs from the stored result in {', '.join(differ)}"))
    if not args.profile:
        return
    if args.save:
        profile.dump_stats(args.save)
    stats = pstats.Stats(profile).strip_dirs()
    for order in ("tottime", "cumulative"):
        stats.sort_stats(order).print_stats(args.top)


if __name__ == "__main__":
    main()
