"""Speed of the signal tools: pulse extraction and response spectra (issue 3 targets).

Run: ``python benchmarks/bench_signals.py``. Prints the median of several runs after a
warm-up, for a synthetic 40 s record at dt = 0.005 s (8001 samples: band-limited noise plus
a Tp = 3 s antisymmetric Ricker pulse).

Targets: full extraction (2 kinds × 3 weightings × 2 sources) ≤ 0.5 s; spectrum at 500
periods ≤ 0.2 s.
"""

from __future__ import annotations

import argparse
import os
import platform
import statistics
import time

import numpy as np
from scipy.signal import butter, sosfiltfilt

import rigid
from rigid.motions.pulse_extraction import extract_pulses


def synthetic_record(duration: float = 40.0, dt: float = 0.005, seed: int = 0):
    rng = np.random.default_rng(seed)
    t = np.arange(round(duration / dt) + 1) * dt
    sos = butter(4, (0.2, 15.0), btype="band", fs=1 / dt, output="sos")
    noise = sosfiltfilt(sos, rng.normal(size=t.size))
    acc = 0.1 * rigid.G * noise / np.max(np.abs(noise))
    acc += rigid.ricker(t, 0.3 * rigid.G, 3.0, "antisymmetric", t0=12.0)
    return rigid.GroundMotion("benchmark", dt, acc)


def timed(fn, repeats: int, warmup: int = 1):
    for _ in range(warmup):
        fn()
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        fn()
        times.append(time.perf_counter() - start)
    return statistics.median(times), min(times), max(times)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=7, help="timed runs per case")
    args = parser.parse_args(argv)

    motion = synthetic_record()
    periods = np.geomspace(0.01, 10.0, 500)
    cases = [
        (
            "full extraction, 2 kinds x 3 weightings x 2 sources",
            lambda: extract_pulses(motion),
            0.5,
        ),
        (
            "extract_pulse (one source, one weighting, both kinds)",
            lambda: rigid.extract_pulse(motion, source="velocity"),
            None,
        ),
        (
            "best_pulse, criterion 4",
            lambda: rigid.best_pulse(motion, criterion=4),
            None,
        ),
        (
            "pseudo_acceleration at 500 periods",
            lambda: rigid.pseudo_acceleration(motion.acceleration, motion.dt, periods),
            0.2,
        ),
        (
            "pseudo_acceleration at T = 4.5 s",
            lambda: rigid.pseudo_acceleration(motion.acceleration, motion.dt, [4.5]),
            None,
        ),
    ]
    print(
        f"record: {motion.npts} samples, dt = {motion.dt} s; python {platform.python_version()}, "
        f"numpy {np.__version__}, {os.cpu_count()} CPUs; median of {args.repeats} after warm-up"
    )
    for label, fn, target in cases:
        median, low, high = timed(fn, args.repeats)
        verdict = "" if target is None else (" OK" if median <= target else " SLOW")
        goal = "" if target is None else f"  (target <= {target:.2f} s{verdict})"
        print(f"{label:<56s} {median:8.4f} s  [min {low:.4f}, max {high:.4f}]{goal}")


if __name__ == "__main__":
    main()
