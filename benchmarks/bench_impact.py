"""Wall time of the impact spectra sweeps (issue 4 targets: full region spectrum, both kinds,
100 × 100, one pressure ≤ 5 min; bisected boundaries alone ≤ 1 min, on 2 cores).

Every sweep starts from an empty cache in a temporary folder (so nothing is reused), runs on
all cores (spawned processes) and prints its wall time, its CPU time (this process and the
pool's workers; CPU/2 is the wall time on two idle cores, the honest figure when other jobs
share the machine), the cell count and the CPU time per cell.

1. one cell: median of 5 warm runs for representative pulses (no pool, no cache);
2. bisected boundaries, 100 periods (Tb/Tp 0.6 … 6), both kinds: impact boundary by
   continuation bisection, failure boundary (a) by the default upward scan in 0.05 g steps
   then bisection, (b) by plain bisection (``scan_step=None``);
3. a reduced region grid (``--periods`` × ``--amplitudes``, default 20 × 20, both kinds),
   extrapolated to 100 × 100 by the cell count (the reduced grid spans the same ranges, so
   its mean cost per cell is representative); ``--full`` runs the full grid instead.

Run: ``python benchmarks/bench_impact.py [--pressure 10e6] [--full]``.
"""

from __future__ import annotations

import argparse
import os
import platform
import resource
import statistics
import tempfile
import time
from pathlib import Path

from rigid import DFPBearing, G, impact_region_spectrum, region_boundaries
from rigid.impact import default_amplitudes, default_periods
from rigid.impact.sweep import SweepSettings, compute_cell


def one_cell(bearing):
    s = SweepSettings()
    for kind, tp, ap in (("symmetric", 1.0, 0.3), ("symmetric", 3.0, 0.5),
                         ("antisymmetric", 3.0, 0.8), ("antisymmetric", 7.5, 0.3)):
        compute_cell(bearing, kind, tp, ap * G, s)
        times = []
        for _ in range(5):
            t0 = time.perf_counter()
            c = compute_cell(bearing, kind, tp, ap * G, s)
            times.append(time.perf_counter() - t0)
        print(f"  cell {kind:13s} Tp = {tp:3.1f} s, Ap = {ap:.1f} g: median "
              f"{statistics.median(times) * 1e3:6.1f} ms  (region {c.region}, "
              f"{len(c.impact_times)} impacts, {c.simulated_time:.1f} s simulated)")


def cpu_seconds() -> float:
    """CPU time of this process and its finished children (the pool's workers) [s]."""
    own = resource.getrusage(resource.RUSAGE_SELF)
    kids = resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + kids.ru_utime + kids.ru_stime


def report(label, wall, cpu, cells, extrapolate=1.0):
    """Wall time, and CPU time / 2: the wall time on two otherwise idle cores."""
    print(f"  {label}: {wall:6.1f} s wall, {cpu:6.1f} s CPU (→ {cpu / 2:5.1f} s on 2 idle "
          f"cores), {cells} cells, {cpu / cells * 1e3:.0f} ms CPU/cell"
          + (f"; ×{extrapolate:.0f} → {wall * extrapolate / 60:.1f} min wall, "
             f"{cpu * extrapolate / 2 / 60:.1f} min on 2 idle cores" if extrapolate != 1 else ""))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pressure", type=float, default=10e6)
    parser.add_argument("--periods", type=int, default=20)
    parser.add_argument("--amplitudes", type=int, default=20)
    parser.add_argument("--full", action="store_true")
    parser.add_argument("--skip-grid", action="store_true")
    args = parser.parse_args()
    bearing = DFPBearing(pressure=args.pressure)
    print(f"machine: {platform.processor() or platform.machine()}, {os.cpu_count()} cores, "
          f"Python {platform.python_version()}, load average {os.getloadavg()[0]:.1f}")
    print(f"bearing: {args.pressure / 1e6:.0f} MPa")
    one_cell(bearing)
    periods = default_periods(bearing)
    with tempfile.TemporaryDirectory() as tmp:
        for label, scan in (("scan 0.05 g", 0.05 * G), ("plain bisection", None)):
            cache = Path(tmp) / f"bisect-{scan is None}.sqlite"
            t0, c0 = time.perf_counter(), cpu_seconds()
            cells = 0
            for kind in ("symmetric", "antisymmetric"):
                b = region_boundaries(bearing, kind, periods, scan_step=scan, cache=cache)
                cells += b.attrs["cells_computed"]
            report(f"boundaries, 100 periods × 2 kinds, failure by {label}",
                   time.perf_counter() - t0, cpu_seconds() - c0, cells)
        if args.skip_grid:
            return
        n_p, n_a = (100, 100) if args.full else (args.periods, args.amplitudes)
        cache = Path(tmp) / "grid.sqlite"
        t0, c0 = time.perf_counter(), cpu_seconds()
        cells = 0
        for kind in ("symmetric", "antisymmetric"):
            ds = impact_region_spectrum(bearing, kind, default_periods(bearing, n_p),
                                        default_amplitudes(n_a), cache=cache)
            cells += ds.attrs["cells_computed"]
        report(f"region grid {n_p} × {n_a} × 2 kinds", time.perf_counter() - t0,
               cpu_seconds() - c0, cells, extrapolate=2 * 100 * 100 / cells)
    print(f"load average at the end {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
