"""Speed of the FE model (fem.simulate) and the cost of one Newton iteration against mesh size.

1. Time per Newton iteration at the gravity equilibrium, for meshes from coarse to fine: one
   evaluation (return map, contact, internal forces) plus the linear solve, (a) as fem.dynamics
   does it (fem.linear.TangentSolver: cached elastic LU + low-rank update, after its
   factorization and columns are cached) and (b) the former direct sparse LU of the assembled
   tangent.
2. One FE run of a symmetric Ricker pulse, Tp = 2 s, 10 s of input (dt = 5 ms), on the default
   mesh, for the 60 MPa bearing: a 0.2 g pulse that stays off the rims (whole 10 s) and a 0.3 g
   pulse that drives the slider into the rims (stops at failure). Prints wall and CPU time
   (median of ``--repeat`` runs after a short warm-up run), steps, Newton iterations, rejected
   steps and dofs.

3. Finite deformation against small strain on the same runs (``--kinematics``): the 0.3 g run
   above (to the first hinge), and on the coarse mesh the 10 MPa bearing under a symmetric
   Ricker pulse, Tp = 2 s, 0.4 g, run past the hinge to the loss of containment
   (``limit_state="containment"``, 18 s), the regime where small strain is meaningless.

4. The threshold of the low-rank set (``--active-gradient G [G ...]``): the past-hinge run of
   part 3 at finite deformation with ``fem.finite_element.ACTIVE_GRADIENT`` set to each G [-]
   (elements below it are solved with the small-strain elastic stiffness), beside the
   small-strain run.

5. Finite against small strain over a set of runs past the hinge (``--past-hinge-set``): the
   eight Ricker pulses of ``validation/studies/fem_uplift.py`` on the light bearing, coarse
   mesh, run to the loss of containment, once each at both kinematics; the ratio of the
   summed CPU times (one run's count of Newton iterations moves by about 10 % on round-off
   alone, BENCHMARKS.md, so a set says more than one run).

6. Rims that tear (``--tearing``): the heavy bearing's one-second sine pulse of 3 m/s² (as
   tests/test_erosion.py), coarse mesh, steps of at most 20 ms, run to 2 s or the loss of
   containment, without fracture and with the median criterion, with sharp slider edges and
   with edges of 20 mm (the validation's with tearing).

Run: ``OMP_NUM_THREADS=1 python benchmarks/bench_fem.py [--quick] [--repeat N] [--kinematics |
--active-gradient G ... | --past-hinge-set | --tearing]`` (about 10 minutes on 2 cores with
the default 3 repeats; ``--kinematics`` alone runs only part 3, about 8 minutes; part 4
about 1 minute per value; part 5 about 5 minutes; part 6 about 5 minutes per repeat).
``--quick`` skips the 0.3 g run.
"""

from __future__ import annotations

import argparse
import os
import platform
import tempfile
import time

import numpy as np

import fem
import fem.finite_element
from fem.geometry import COARSE_MESH
from rigid import DFPBearing, G, ricker_record

MESHES = {
    "coarse (rim 20 mm, far 60 mm)": COARSE_MESH,
    "medium (rim 10 mm, far 40 mm)": {"rim_size": 0.01, "coarse_size": 0.04},
    "default (rim 5 mm, dish 10 mm, far 30 mm)": {},
    "fine (rim 2.5 mm, dish 5 mm, far 15 mm)": {"rim_size": 0.0025, "coarse_size": 0.015},
}


def newton_iteration_cost(options: dict, cache: str, repeat: int = 7):
    """Median CPU time [s] of one Newton iteration (evaluation + solve) at the gravity state,
    with the production solver and with a direct sparse LU; and the dofs."""
    from scipy.sparse import diags
    from scipy.sparse.linalg import spsolve

    from fem.dfp import build_system
    from fem.dynamics import Integrator

    model = build_system(DFPBearing(), mesh_options=options, cache_dir=cache)
    integ = Integrator(model, lambda t: 0.0)
    a, state, _ = integ.gravity_step()
    d = model.reduction.expand(a)
    h = integ.control.max_step
    c0, s = 1.0 / (integ.hht.beta * h * h), 1.0 + integ.hht.alpha
    solver = integ.solver
    ev = model.system.evaluate(d, state)
    solver.solve(ev, c0, s, model.reduction.reduce(ev.internal_force))  # factorize, cache
    fast, direct = [], []
    for _ in range(repeat):
        t0 = time.process_time()
        ev = model.system.evaluate(d, state)
        solver.solve(ev, c0, s, model.reduction.reduce(ev.internal_force))
        fast.append(time.process_time() - t0)
        t0 = time.process_time()
        ev = model.system.evaluate(d, state)
        r = model.reduction.reduce(ev.internal_force)
        K = model.reduction.reduce_matrix(ev.stiffness) * s + diags(c0 * model.mass)
        spsolve(K.tocsc(), r)
        direct.append(time.process_time() - t0)
    return float(np.median(fast)), float(np.median(direct)), model.reduction.nreduced


def run(amplitude_g: float, cache: str, duration=None, **options):
    """One run on the default mesh; returns the result, wall and CPU time [s]."""
    _, a = ricker_record(amplitude_g * G, 2.0, dt=0.005, duration=10.0)
    t0, c0 = time.perf_counter(), time.process_time()
    res = fem.simulate(DFPBearing(), a, 0.005, duration=duration, cache_dir=cache, **options)
    return res, time.perf_counter() - t0, time.process_time() - c0


def post_hinge_run(cache: str, **options):
    """The 10 MPa bearing past the hinge on the coarse mesh (module docstring, part 3)."""
    _, a = ricker_record(0.4 * G, 2.0, dt=0.005, duration=18.0)
    t0, c0 = time.perf_counter(), time.process_time()
    res = fem.simulate(DFPBearing(pressure=10e6), a, 0.005, mesh_options=COARSE_MESH,
                       max_step=0.01, limit_state="containment", cache_dir=cache,
                       **options)
    return res, time.perf_counter() - t0, time.process_time() - c0


def tearing_run(cache: str, **options):
    """The heavy bearing's sine pulse to 2 s or the loss of containment (module docstring,
    part 6)."""
    t = np.arange(0.0, 2.0 + 0.005, 0.01)
    a = np.where(t < 1.0, 3.0 * np.sin(np.pi * t), 0.0)
    t0, c0 = time.perf_counter(), time.process_time()
    res = fem.simulate(DFPBearing(pressure=60e6), a, 0.01, max_step=0.02,
                       mesh_options=COARSE_MESH, limit_state="containment", cache_dir=cache,
                       **options)
    return res, time.perf_counter() - t0, time.process_time() - c0


def tearing_comparison(cache: str, repeat: int) -> None:
    print(f"\nRims that tear: sine pulse, heavy bearing, coarse mesh (median of {repeat}):")
    for radius in (0.0, 0.02):
        for fracture in (None, "median"):
            runs = [tearing_run(cache, fracture=fracture, edge_radius=radius)
                    for _ in range(repeat)]
            torn = len(runs[0][0].torn_elements)
            report(f"edges {radius * 1e3:g} mm, fracture {fracture}, {torn} torn", runs)


def report(label: str, runs) -> None:
    """One line: medians of wall and CPU, the machine's load, the run's counts and outcome."""
    res = runs[0][0]
    wall = float(np.median([w for _, w, _ in runs]))
    cpu = float(np.median([c for _, _, c in runs]))
    print(
        f"  {label}: wall {wall:.1f} s, CPU {cpu:.1f} s "
        f"(runs: {', '.join(f'{w:.0f}/{c:.0f}' for _, w, c in runs)} s wall/CPU; "
        f"load {os.getloadavg()[0]:.1f}) for {res.time[-1]:.2f} s simulated, {res.steps} "
        f"steps, {res.newton_iterations} Newton iterations "
        f"({cpu / max(res.newton_iterations, 1) * 1e3:.1f} ms CPU each incl. overhead), "
        f"{res.rejected_steps} rejected steps, {res.dofs} dofs; "
        + (f"failed by {res.failure_mode} at {res.failure_time:.3f} s" if res.failed
           else "no failure")
        + "; limit states " + ", ".join(f"{k} {'-' if v is None else f'{v:.3f} s'}"
                                        for k, v in res.limit_states.items())
    )


def kinematics_comparison(cache: str, repeat: int) -> None:
    """Part 3 of the module docstring."""
    print(f"\nFinite deformation against small strain (median of {repeat}):")
    post_hinge_run(cache, duration=0.1)
    for kinematics in ("small", "finite"):
        report(f"0.3 g, default mesh, {kinematics}",
               [run(0.3, cache, kinematics=kinematics) for _ in range(repeat)])
    for kinematics in ("small", "finite"):
        report(f"10 MPa past the hinge, coarse mesh, {kinematics}",
               [post_hinge_run(cache, kinematics=kinematics) for _ in range(repeat)])


def threshold_comparison(cache: str, repeat: int, thresholds: list[float]) -> None:
    """Part 4 of the module docstring."""
    print(f"\nThreshold of the low-rank set, past the hinge, coarse mesh (median of {repeat}):")
    post_hinge_run(cache, duration=0.1)
    report("small strain", [post_hinge_run(cache, kinematics="small") for _ in range(repeat)])
    default = fem.finite_element.ACTIVE_GRADIENT
    try:
        for g in thresholds:
            fem.finite_element.ACTIVE_GRADIENT = g
            report(f"finite, ACTIVE_GRADIENT = {g:g}",
                   [post_hinge_run(cache, kinematics="finite") for _ in range(repeat)])
    finally:
        fem.finite_element.ACTIVE_GRADIENT = default


def past_hinge_set(cache: str) -> None:
    """Part 5 of the module docstring."""
    from validation.studies.fem_uplift import DEFAULT, FE_OPTIONS, parse_case, pulse

    print("\nFinite against small strain, eight pulses past the hinge (light bearing, coarse "
          "mesh):")
    post_hinge_run(cache, duration=0.1)
    total = {"small": 0.0, "finite": 0.0}
    for case in DEFAULT:
        tp, ap, kind = parse_case(case)
        a = pulse(tp, ap, kind)
        line = f"  {kind[:4]} Tp {tp:g} s, {ap:g} g:"
        for kinematics in ("small", "finite"):
            c0 = time.process_time()
            res = fem.simulate(DFPBearing(pressure=10e6), a, 0.005, **FE_OPTIONS,
                               kinematics=kinematics, cache_dir=cache)
            cpu = time.process_time() - c0
            total[kinematics] += cpu
            line += (f" {kinematics} {cpu:.1f} s CPU, {res.newton_iterations} iterations, "
                     f"{'failed by ' + res.failure_mode if res.failed else 'no failure'};")
        print(line, flush=True)
    print(f"  sum: small {total['small']:.1f} s, finite {total['finite']:.1f} s, ratio "
          f"{total['finite'] / total['small']:.2f} (load {os.getloadavg()[0]:.1f})")


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true", help="skip the 0.3 g run")
    ap.add_argument("--repeat", type=int, default=3, help="timed runs of each case")
    part = ap.add_mutually_exclusive_group()
    part.add_argument("--kinematics", action="store_true", help="part 3 alone")
    part.add_argument("--tearing", action="store_true", help="part 6 alone")
    part.add_argument("--past-hinge-set", action="store_true", help="part 5 alone")
    part.add_argument("--active-gradient", type=float, nargs="+", metavar="G",
                      help="part 4 alone, at these thresholds [-]")
    args = ap.parse_args(argv)
    quick, repeat = args.quick, args.repeat
    print(f"python {platform.python_version()}, {platform.machine()}, numpy {np.__version__}, "
          f"{os.cpu_count()} cores, OMP_NUM_THREADS={os.environ.get('OMP_NUM_THREADS')}")
    with tempfile.TemporaryDirectory() as cache:
        if args.kinematics:
            kinematics_comparison(cache, repeat)
            return
        if args.tearing:
            tearing_comparison(cache, repeat)
            return
        if args.past_hinge_set:
            past_hinge_set(cache)
            return
        if args.active_gradient:
            threshold_comparison(cache, repeat, args.active_gradient)
            return
        print("\nCPU time per Newton iteration at the gravity equilibrium (median of 7):")
        print(f"{'mesh':45s} {'dofs':>7s} {'ms (solver)':>12s} {'ms (direct LU)':>15s}")
        for name, options in MESHES.items():
            fast, direct, dofs = newton_iteration_cost(options, cache)
            print(f"{name:45s} {dofs:7d} {fast * 1e3:12.1f} {direct * 1e3:15.1f}")
        print("\nRicker pulse, Tp = 2 s, 10 s of input, 60 MPa bearing, default mesh "
              f"(median of {repeat} after a 0.1 s warm-up run):")
        run(0.2, cache, duration=0.1)
        for amplitude in (0.2,) if quick else (0.2, 0.3):
            report(f"Ap = {amplitude} g", [run(amplitude, cache) for _ in range(repeat)])
        kinematics_comparison(cache, repeat)


if __name__ == "__main__":
    main()
