"""The FE runs' end trimming checked by the FE model itself: for the searches of a validation
run that found an answer, the highest surviving rung below it (the run whose verdict a
trimmed end could have changed; failing runs are identical up to their failure) is run again
untrimmed, the record plus the free time (``trim="none"``), and the two verdicts compared.
The cases taken are the ones whose trimmed run stopped earliest before the record's end plus
the free time.

Run: ``python -m validation.studies.fem_trimming_check [--out docs/fem-validation]
[--cases 6] [--workers 2]`` with the validation run's settings (``--limit-state``,
``--rim-thickness``, ``--fem-fracture``, ``--fem-edge-radius``, ``--rim-punch``); the
untrimmed runs are stored tasks in ``docs/results/<name>/results.sqlite`` (resumable), the
table goes to ``docs/results/<name>.csv`` (``--name``, default ``fem_trimming_check``). The
rigid model's check of the same trimming on all 56 cases is
``validation.studies.trimming_check``.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from fem.fracture import FRACTURE_SETS
from rigid import G, fema_p695
from rigid.collapse.comparison import write_csv
from rigid.tasks import ResultStore, Task, run_tasks, task_key
from validation.fem_runs import fem_run
from validation.fem_search import failed_under
from validation.studies import FEM_VALIDATION, RESULTS
from validation.studies.fem_validation_status import replayed, run_settings


def surviving_runs(out: Path, limit_states, motions, rim_thickness_mm=None,
                   **tearing) -> list[dict]:
    """Every finished search's highest surviving run below its answer: the search's record,
    pressure, limit state, SA [m/s²], the trimmed run's result and the run's keyword
    arguments; ``limit_states`` those of the validation run (its ``--limit-state``);
    ``tearing``: the run's ``fracture``, ``edge_radius_mm`` and ``rim_punch``
    (:func:`validation.studies.fem_validation_status.run_settings`)."""
    settings = run_settings(tuple(limit_states), rim_thickness_mm, **tearing)
    searches, owners = replayed(out, settings, motions)
    found = searches.results()
    rows = []
    for k, r in enumerate(found):
        if not searches.searches[k].done or r.sa is None or r.survived_below is None:
            continue
        probe = next(p for p in r.probes if abs(p["sa"] - r.survived_below) < 1e-9)
        j = round((probe["sa"] - searches.start) / searches.step)
        _, kwargs = searches.run_key(k // len(searches.limit_states), j)
        pressure, i = owners[k // len(searches.limit_states)]
        rows.append({"record": motions[i], "pressure": pressure,
                     "limit_state": r.limit_state, "sa": probe["sa"],
                     "trimmed": probe, "kwargs": kwargs, "models": searches.models})
    return rows


def _untrimmed(args, motions) -> tuple[list[dict], list[Task]]:
    """The ``args.cases`` surviving runs cut shortest (a run that survived under two limit
    states counts once per limit state), and their untrimmed runs as tasks, one per run."""
    rows = surviving_runs(args.out, args.limit_state, motions, args.rim_thickness,
                          fracture=args.fem_fracture, edge_radius_mm=args.fem_edge_radius,
                          rim_punch=args.rim_punch)
    if not rows:
        raise SystemExit(f"no finished FE search with a surviving run in {args.out} under "
                         "these settings (they must be the validation run's)")
    for r in rows:
        m = r["record"]
        r["cut_s"] = (m.npts - 1) * m.dt + r["kwargs"]["free"] - r["trimmed"]["end"]
    rows = sorted(rows, key=lambda r: -r["cut_s"])[:args.cases]
    tasks = {}
    for r in rows:
        kwargs = {**r["kwargs"], "trim": "none"}
        r["key"] = task_key("fem-run", r["models"], runner=None, **kwargs)
        tasks[r["key"]] = Task(r["key"], "fem-run", fem_run, kwargs)
    return rows, list(tasks.values())


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--out", type=Path, default=FEM_VALIDATION,
                   help="the validation run's folder (its results.sqlite)")
    p.add_argument("--limit-state", nargs="+", default=["hinge"],
                   help="the run's --limit-state (all of them)")
    p.add_argument("--rim-thickness", type=float, help="the run's --rim-thickness [mm]")
    p.add_argument("--fem-fracture", choices=sorted(FRACTURE_SETS),
                   help="the run's --fem-fracture")
    p.add_argument("--fem-edge-radius", type=float, default=0.0,
                   help="the run's --fem-edge-radius [mm]")
    p.add_argument("--rim-punch", choices=("face", "slider"), default="face",
                   help="the run's --rim-punch")
    p.add_argument("--cases", type=int, default=6)
    p.add_argument("--workers", type=int, default=None)
    p.add_argument("--name", default="fem_trimming_check",
                   help="the store's folder and the table's name under docs/results")
    p.add_argument("--rekey-from", metavar="REVISION",
                   help="first carry the untrimmed runs that REVISION's code stored over to "
                   "today's keys, once the shortest two rerun equal (rigid.tasks.rekey)")
    args = p.parse_args()
    motions = fema_p695("nearfield_pulse")
    folder = RESULTS / args.name
    folder.mkdir(parents=True, exist_ok=True)
    if args.rekey_from:
        from rigid.tasks.rekey import rekey

        def replay(seen):
            run_tasks(_untrimmed(args, motions)[1], store, progress=False, replay=True,
                      seen=seen)

        with ResultStore(folder / "results.sqlite") as store:
            carried = rekey(store, replay, args.rekey_from)
        print(f"--rekey-from {args.rekey_from}: {carried.describe()}")
    rows, tasks = _untrimmed(args, motions)
    with ResultStore(folder / "results.sqlite") as store:
        results = run_tasks(tasks, store, workers=args.workers, description="untrimmed FE runs",
                            log=folder / "progress.log")
    table = []
    for r in rows:
        full, trimmed = results[r["key"]], r["trimmed"]
        table.append({
            "record": r["record"].name, "pressure_mpa": r["pressure"] / 1e6,
            "limit_state": r["limit_state"], "sa_g": r["sa"] / G,
            "trimmed_end_s": trimmed["end"], "untrimmed_end_s": full["end"],
            "trimmed_failed": bool(trimmed["failed"]),
            "untrimmed_failed": failed_under(full, r["limit_state"]),
            "untrimmed_failure_mode": full["failure_mode"] or "none",
            "trimmed_max_rim_force_mn": trimmed["max_rim_force"] / 1e6,
            "untrimmed_max_rim_force_mn": full["max_rim_force"] / 1e6,
            "trimmed_cpu_s": trimmed["cpu_seconds"], "untrimmed_cpu_s": full["cpu_seconds"],
        })
    path = RESULTS / f"{args.name}.csv"
    write_csv(table, path)
    same = sum(t["trimmed_failed"] == t["untrimmed_failed"] for t in table)
    print(f"the same verdict on {same} of {len(table)} surviving runs; {path}")


if __name__ == "__main__":
    main()
