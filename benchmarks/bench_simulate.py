"""Wall time of rigid.simulate on 40 s of input at the default accuracy.

Prints the first call in a fresh interpreter (JIT compile, or load from Numba's cache) and
the median of 5 warm calls for three inputs: rest, a pulse below the rims and a pulse with
rim impacts: wall and CPU time (the CPU time is the honest figure when other jobs share the
cores), and the integration steps taken. Run: ``python benchmarks/bench_simulate.py
[--rims yielding]`` (yielding rims, failure criterion "containment"; a fourth input, a pulse
that bends the heavy bearing's rims without losing containment, compares the two rim models
where both run to the end).
"""

from __future__ import annotations

import argparse
import os
import platform
import statistics
import subprocess
import sys
import time

import numpy as np

from rigid import DFPBearing, G, ricker_record, simulate

DT = 0.005
DURATION = 40.0

FIRST_CALL = """
import time, numpy as np
t0 = time.perf_counter()
from rigid import DFPBearing, simulate
simulate(DFPBearing(), np.zeros(11), 0.005)
print(time.perf_counter() - t0)
"""


def cases():
    n = int(DURATION / DT) + 1
    _, small = ricker_record(0.1 * G, 2.0, dt=DT, duration=DURATION)
    _, strong = ricker_record(0.4 * G, 3.0, "antisymmetric", dt=DT, duration=DURATION)
    _, bent = ricker_record(0.16 * G, 3.0, "antisymmetric", dt=DT, duration=DURATION)
    return {"rest": np.zeros(n), "pulse 0.1 g, 2 s": small, "pulse 0.4 g, 3 s, impacts": strong,
            "pulse 0.16 g, 3 s, impacts": bent}


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--rims", choices=("rigid", "yielding"), default="rigid",
                    help="the rim model (yielding: limit state containment, a fourth input)")
    options = ({"rims": "yielding", "limit_state": "containment"}
               if ap.parse_args(argv).rims == "yielding" else {})
    first = float(subprocess.check_output([sys.executable, "-c", FIRST_CALL], text=True))
    machine = platform.processor() or platform.machine()
    print(f"machine: {machine}, Python {platform.python_version()}")
    print(f"first call (import + compile or cache load): {first:.2f} s; rims: "
          f"{options.get('rims', 'rigid')}")
    for pressure in (60e6, 10e6):
        bearing = DFPBearing(pressure=pressure)
        if options.get("rims") == "yielding":
            from fem import rim_law  # the rims' law: FE pushes of the rim, cached

            options["rim_law"] = rim_law(bearing)
        for name, acceleration in cases().items():
            simulate(bearing, acceleration, DT, **options)  # warm-up
            times, cpu = [], []
            for _ in range(5):
                t0, c0 = time.perf_counter(), time.process_time()
                result = simulate(bearing, acceleration, DT, **options)
                times.append(time.perf_counter() - t0)
                cpu.append(time.process_time() - c0)
            print(
                f"{pressure / 1e6:4.0f} MPa  {name:28s} median {statistics.median(times):.3f} s "
                f"wall, {statistics.median(cpu):.3f} s CPU per {DURATION:.0f} s  "
                f"({result.steps_taken} steps, {len(result.impacts)} impacts, "
                f"failed={result.failed}, max rim set "
                f"{max(result.rim_sets) * 1e3:.2f} mm)"
            )
    print(f"load average {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
