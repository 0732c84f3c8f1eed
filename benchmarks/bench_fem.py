"""Speed of the FE model (fem.simulate) and the cost of one Newton iteration against mesh size.

1. One FE run of a symmetric Ricker pulse, Tp = 2 s, 10 s of input (dt = 5 ms), on the default
   mesh, for the 60 MPa bearing: a 0.2 g pulse that stays off the rims (whole 10 s) and a 0.3 g
   pulse that drives the slider into the rims (stops at failure). Prints wall time, steps,
   Newton iterations, rejected steps and dofs.
2. Time per Newton iteration (material return map + contact + assembly + reduction + sparse
   LU solve) at the gravity equilibrium, for meshes from coarse to fine.

Run: ``python benchmarks/bench_fem.py`` (about 10 minutes on 2 cores). ``--quick`` skips the
0.3 g run.
"""

from __future__ import annotations

import platform
import sys
import tempfile
import time

import numpy as np

import fem
from rigid import DFPBearing, G, ricker_record

MESHES = {
    "coarse (rim 20 mm, far 60 mm)": {"rim_size": 0.02, "contact_size": 0.03, "coarse_size": 0.06},
    "medium (rim 10 mm, far 40 mm)": {"rim_size": 0.01, "coarse_size": 0.04},
    "default (rim 5 mm, dish 10 mm, far 30 mm)": {},
    "fine (rim 2.5 mm, dish 5 mm, far 15 mm)": {"rim_size": 0.0025, "coarse_size": 0.015},
}


def newton_iteration_cost(options: dict, cache: str, repeat: int = 5):
    """Median wall time [s] of one full Newton iteration at the gravity state, and dofs."""
    from scipy.sparse import diags
    from scipy.sparse.linalg import spsolve

    from fem.dfp import build_system
    from fem.dynamics import Integrator

    model = build_system(DFPBearing(), mesh_options=options, cache_dir=cache)
    integ = Integrator(model, lambda t: 0.0)
    a, state, _ = integ.gravity_step()
    d = model.reduction.expand(a)
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        ev = model.system.evaluate(d, state)
        r = model.reduction.reduce(ev.internal_force)
        K = model.reduction.reduce_matrix(ev.stiffness) + diags(model.mass * 1e4)
        spsolve(K.tocsc(), r)
        times.append(time.perf_counter() - t0)
    return float(np.median(times)), model.reduction.nreduced


def run(amplitude_g: float, cache: str):
    _, a = ricker_record(amplitude_g * G, 2.0, dt=0.005, duration=10.0)
    t0 = time.perf_counter()
    res = fem.simulate(DFPBearing(), a, 0.005, cache_dir=cache)
    return res, time.perf_counter() - t0


def main() -> None:
    quick = "--quick" in sys.argv
    print(f"python {platform.python_version()}, {platform.machine()}, numpy {np.__version__}")
    with tempfile.TemporaryDirectory() as cache:
        print("\nTime per Newton iteration at the gravity equilibrium (median of 5):")
        print(f"{'mesh':45s} {'dofs':>7s} {'ms/iteration':>13s}")
        for name, options in MESHES.items():
            cost, dofs = newton_iteration_cost(options, cache)
            print(f"{name:45s} {dofs:7d} {cost * 1e3:13.1f}")
        print("\nRicker pulse, Tp = 2 s, 10 s of input, 60 MPa bearing, default mesh:")
        for amplitude in (0.2,) if quick else (0.2, 0.3):
            res, wall = run(amplitude, cache)
            end = res.time[-1]
            per_iter = wall / max(res.newton_iterations, 1)
            print(
                f"  Ap = {amplitude} g: wall {wall:.1f} s for {end:.2f} s simulated, "
                f"{res.steps} steps, {res.newton_iterations} Newton iterations "
                f"({res.newton_iterations / max(res.steps, 1):.2f}/step, {per_iter * 1e3:.0f} ms "
                f"each incl. overhead), {res.rejected_steps} rejected steps, {res.dofs} dofs; "
                + (f"failed by {res.failure_mode} at {res.failure_time:.3f} s"
                   if res.failed else "no failure")
            )


if __name__ == "__main__":
    main()
