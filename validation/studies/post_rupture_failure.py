"""Why FE runs end numerically after a rim's rupture: the stored runs that ended with "Newton
did not converge", rerun with the element Jacobians watched.

For each run: whether the rerun reproduces the stored one (same end time and message), the
smallest J = det F over the elements at the last accepted step and where that element lies,
and over the Newton attempts of the failing step (all its step halvings) how many iterates
had an inverted element (J ≤ 0, which :meth:`fem.finite_element.FiniteStrainQ1.evaluate`
marks invalid, so that Newton gives up; docs/theory/finite-elements.md, "Finite deformation").

Run: ``python -m validation.studies.post_rupture_failure [--out docs/fem-validation-rims80]
[--rim-thickness 80] [--limit-state hinge rupture containment] [--runs 3]`` with the
settings of the validation run; writes ``docs/results/post_rupture_failure.csv`` and, for the
first run, ``docs/images/post_rupture_failure.png`` (the last accepted state at the rim).
Runs the shortest of the numerical runs first, each with one BLAS thread as in a worker (so
that it repeats the stored run's end).
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
from threadpoolctl import threadpool_limits

from fem.dynamics import Integrator
from fem.finite_element import FiniteStrainQ1
from rigid import fema_p695
from rigid.collapse.comparison import write_csv
from validation.fem_runs import fem_run

from . import DOCS, IMAGES, RESULTS
from .fem_validation_status import run_settings, stored_runs


class JacobianWatch:
    """Wraps :meth:`FiniteStrainQ1.evaluate` and :meth:`Integrator.step` while active: the
    smallest element Jacobian of every evaluation, grouped by step attempt."""

    def __init__(self):
        self.attempts = []  # (t [s], h [s], accepted, [(min J, element), ...])
        self._evaluate, self._step = FiniteStrainQ1.evaluate, Integrator.step

    def __enter__(self):
        watch = self

        def evaluate(disc, material, u, state):
            ev, force = watch._evaluate(disc, material, u, state)
            _, jac, _ = disc.deformation(u)
            e = int(np.argmin(jac.min(axis=1)))
            if watch.attempts:
                watch.attempts[-1][3].append((float(jac[e].min()), e))
            return ev, force

        def step(integrator, t, h, *args):
            watch.attempts.append((t, h, False, []))
            out = watch._step(integrator, t, h, *args)
            watch.attempts[-1] = (t, h, out is not None, watch.attempts[-1][3])
            return out

        FiniteStrainQ1.evaluate, Integrator.step = evaluate, step
        return self

    def __exit__(self, *exc):
        FiniteStrainQ1.evaluate, Integrator.step = self._evaluate, self._step


def numerical_runs(out: Path, settings, motions) -> list:
    """The stored FE runs of a validation run that ended numerically: (stored result,
    keyword arguments of :func:`fem_run`, record name, SA [g]), shortest first."""
    found = [(result, kwargs, motion.name, sa)
             for result, kwargs, motion, sa in stored_runs(out, settings, motions)
             if result["numerical_failure"]]
    return sorted(found, key=lambda f: f[0]["wall_seconds"])


def locate(mesh, bearing, element: int) -> str:
    """Where an element lies: its subdomain and its centroid's position [mm] from the rim
    root corner of that plate (x past the rim radius, z above the root)."""
    sub = next((name for name, elems in mesh.subdomains.items() if element in elems), "?")
    cx, cz = mesh.p[:, mesh.t[:, element]].mean(axis=1)
    z_root = bearing.dish_depth(bearing.rim_radius)
    dz = cz - z_root if sub.startswith("bottom") else bearing.slider_height - z_root - cz
    return (f"{sub}, {1e3 * (abs(cx) - bearing.rim_radius):+.1f} mm radially from the rim's "
            f"inner face, {1e3 * dz:+.1f} mm from its root")


def diagnose(result: dict, kwargs: dict):
    """Rerun one stored run under a :class:`JacobianWatch`: the row of the CSV and the rerun's
    last :class:`fem.FEMResult`."""
    from fem import simulate

    keep = []

    def kept(*args, **kw):
        keep.append(simulate(*args, **kw))
        return keep[-1]

    with JacobianWatch() as watch, threadpool_limits(1):  # one BLAS thread, as in a worker
        again = fem_run(**kwargs, simulate=kept)
    accepted = [a for a in watch.attempts if a[2]]
    failing = [a for a in watch.attempts if a[0] == watch.attempts[-1][0] and not a[2]]
    last_j, last_e = min(accepted[-1][3])
    evaluations = [j for a in failing for j, _ in a[3]]
    res = keep[-1]
    return res, {
        "reproduced": again["detail"] == result["detail"] and again["end"] == result["end"],
        "stored_end_s": result["end"], "end_s": again["end"],
        "max_plastic_strain": again["max_plastic_strain"],
        "min_J_last_accepted": last_j, "element": locate(res.mesh, res.bearing, last_e),
        "failing_attempts": len(failing), "failing_evaluations": len(evaluations),
        "inverted_evaluations": sum(j <= 0.0 for j in evaluations),
        "min_J_failing": min(evaluations), "smallest_step_s": failing[-1][1],
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=DOCS / "fem-validation-rims80")
    parser.add_argument("--rim-thickness", type=float, default=80.0, help="[mm]")
    parser.add_argument("--limit-state", nargs="+", default=["hinge", "rupture",
                                                             "containment"])
    parser.add_argument("--runs", type=int, default=3)
    args = parser.parse_args()
    settings = run_settings(args.limit_state, args.rim_thickness)
    motions = fema_p695("nearfield_pulse")
    found = numerical_runs(args.out, settings, motions)
    print(f"{len(found)} numerical runs stored; rerunning the {min(args.runs, len(found))} "
          "shortest", flush=True)
    rows = []
    for n, (result, kwargs, name, sa) in enumerate(found[: args.runs]):
        res, found_row = diagnose(result, kwargs)
        row = {"record": name, "pressure_mpa": kwargs["bearing"]["pressure"] / 1e6,
               "sa_g": round(sa, 4), **found_row}
        rows.append(row)
        print(", ".join(f"{k} {v:.4g}" if isinstance(v, float) else f"{k} {v}"
                        for k, v in row.items()), flush=True)
        if n == 0:
            from fem.output import render_result

            b = res.bearing
            side = 1.0 if res.final_displacement[-3] > 0 else -1.0
            render_result(IMAGES / "post_rupture_failure.png", res,
                          title=f"{name}, {row['pressure_mpa']:g} MPa, SA {sa:.2f} g: last "
                                f"accepted state (t = {row['end_s']:.4f} s)",
                          focus=(side * b.rim_radius, b.dish_depth(b.rim_radius), 0.08))
    write_csv(rows, RESULTS / "post_rupture_failure.csv")
    print(f"wrote {RESULTS / 'post_rupture_failure.csv'}")


if __name__ == "__main__":
    main()
