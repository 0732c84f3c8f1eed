"""Does today's FE code reproduce a validation run's stored FE runs? An audit in two steps,
for when the code of ``fem/`` has changed since the store was made (every FE run is keyed by
that code, so a replay with the new code finds none of them).

1. ``collect``, run with the code that made the store (for example in a ``git worktree`` of
   that commit, with this file copied into its ``validation/studies``): replays the store's
   FE searches and writes a sample of its FE runs, their arguments and stored results, to a
   JSON file: per pressure the ``--per-pressure`` − 1 shortest runs and the run of median
   length.
2. ``rerun``, with today's code: reruns every sampled run with one BLAS thread (as in a
   worker) and writes one CSV row per run: the stored and the new end time, failure, limit
   states, steps, Newton iterations and largest plastic strain; whether all of them are
   identical, whether the verdict (failed, mode, numerical end) is the same, and the largest
   change of a limit-state or end time.

Run::

    python -m validation.studies.stored_runs_check collect --out docs/fem-validation \\
        --limit-state hinge rupture containment --to sample.json
    python -m validation.studies.stored_runs_check rerun sample.json \\
        [--csv docs/results/stored_runs_check.csv]

(a few minutes per sampled run on the coarse mesh).
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from threadpoolctl import threadpool_limits

from rigid import fema_p695
from rigid.collapse.comparison import write_csv
from validation.fem_runs import fem_run

from . import FEM_VALIDATION, RESULTS
from .fem_validation_status import run_settings, stored_runs

#: The stored fields compared (those of :func:`validation.fem_runs.fem_run`'s result).
FIELDS = ("failed", "failure_mode", "failure_time", "numerical_failure", "detail",
          "limit_states", "end", "steps", "newton_iterations", "max_plastic_strain")
#: The fields of the verdict.
VERDICT = ("failed", "failure_mode", "numerical_failure")


def collect(out: Path, settings, motions, per_pressure: int) -> list[dict]:
    """The sample of stored runs (module docstring, step 1): record name, SA [g], the
    arguments of :func:`fem_run` without the acceleration, and the stored result."""
    runs = {}
    for result, kwargs, motion, sa in stored_runs(out, settings, motions):
        args = {k: v for k, v in kwargs.items() if k != "acceleration"}
        runs.setdefault(args["bearing"]["pressure"], []).append({
            "record": motion.name, "sa_g": sa, "arguments": args, "stored": result})
    sample = []
    for pressure in sorted(runs):
        found = sorted(runs[pressure], key=lambda r: r["stored"]["wall_seconds"])
        sample += [*found[: per_pressure - 1], found[len(found) // 2]]
    return sample


def rerun(sample: list[dict], motions) -> list[dict]:
    """Rerun every sampled run with today's code (module docstring, step 2)."""
    by_name = {m.name: m for m in motions}
    rows = []
    for entry in sample:
        with threadpool_limits(1):
            again = fem_run(acceleration=by_name[entry["record"]].acceleration,
                            **entry["arguments"])
        stored = entry["stored"]
        times = [(stored["end"], again["end"])] + [
            (stored["limit_states"][k], again["limit_states"][k]) for k in stored["limit_states"]]
        row = {"record": entry["record"],
               "pressure_mpa": entry["arguments"]["bearing"]["pressure"] / 1e6,
               "sa_g": round(entry["sa_g"], 4),
               "identical": all(stored[f] == again[f] for f in FIELDS),
               "same_verdict": all(stored[f] == again[f] for f in VERDICT),
               "largest_time_change_s": max(
                   (abs(a - b) if a is not None and b is not None
                    else (0.0 if a is b else float("inf")) for a, b in times))}
        for f in ("end", "failure_mode", "steps", "newton_iterations", "max_plastic_strain"):
            row[f"stored_{f}"], row[f"new_{f}"] = stored[f], again[f]
        for state in stored["limit_states"]:
            row[f"stored_{state}_s"] = stored["limit_states"][state]
            row[f"new_{state}_s"] = again["limit_states"][state]
        rows.append(row)
        print(", ".join(f"{k} {v}" for k, v in row.items()), flush=True)
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="step", required=True)
    c = sub.add_parser("collect")
    c.add_argument("--out", type=Path, default=FEM_VALIDATION)
    c.add_argument("--limit-state", nargs="+", default=["hinge", "rupture", "containment"])
    c.add_argument("--rim-thickness", type=float, default=None, help="[mm]")
    c.add_argument("--per-pressure", type=int, default=3)
    c.add_argument("--to", type=Path, required=True, help="JSON file to write")
    r = sub.add_parser("rerun")
    r.add_argument("sample", type=Path, help="JSON file of the collect step")
    r.add_argument("--csv", type=Path, default=RESULTS / "stored_runs_check.csv")
    args = parser.parse_args()
    motions = fema_p695("nearfield_pulse")
    if args.step == "collect":
        settings = run_settings(args.limit_state, args.rim_thickness)
        sample = collect(args.out, settings, motions, args.per_pressure)
        args.to.write_text(json.dumps(sample, indent=1))
        print(f"wrote {len(sample)} runs to {args.to}")
    else:
        rows = rerun(json.loads(args.sample.read_text()), motions)
        write_csv(rows, args.csv)
        print(f"{sum(r['identical'] for r in rows)} of {len(rows)} identical, "
              f"{sum(r['same_verdict'] for r in rows)} with the same verdict, largest time "
              f"change {max(r['largest_time_change_s'] for r in rows):.3g} s; wrote {args.csv}")


if __name__ == "__main__":
    main()
