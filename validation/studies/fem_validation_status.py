"""Where a long validation run stands, read from its store without running anything: every
FE search replayed from the stored runs (the searches are pure functions of their outcomes,
:class:`validation.fem_search.BracketBisect`), finished ones with their answer, unfinished
ones with the runs they have made; the rigid critical SA with rigid and with yielding rims
beside them.

Run: ``python -m validation.studies.fem_validation_status [--out docs/fem-validation]
[--limit-state hinge] [--rim-thickness MM] [--fem-fracture SET --fem-edge-radius MM]`` with
the settings of the run (those of
``dfp validate`` without ``--quick``: the FEMA P695 near-field pulse set, 60 and 10 MPa,
coarse mesh, 0.005 s steps, finite deformation); writes ``OUT/status.csv`` (every search
started), ``OUT/status_statistics.csv`` and ``OUT/status_fig4.png`` (the report's Fig. 4 and
its statistics over the finished searches) and prints a summary. A setting that differs
from the run's finds nothing stored: the keys include every setting.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from fem.fracture import FRACTURE_SETS
from rigid import G, fema_p695
from rigid.collapse.comparison import write_csv
from rigid.tasks import MissingResultsError, ResultStore
from validation.fem_search import FESearches, FESettings
from validation.report.write import (
    claim_verdicts,
    fem_rows,
    fem_statistics,
    plot_fem_vs_rigid,
    save_figure,
)
from validation.run import Settings, critical_from_json, rigid_tasks
from validation.stored_rim_laws import keep_rim_laws

from . import FEM_VALIDATION


def run_settings(limit_states=("hinge",), rim_thickness_mm=None, fracture=None,
                 edge_radius_mm=0.0, rim_punch="face", crush=None, stop_g=None) -> Settings:
    """The settings of ``dfp validate`` without ``--quick`` (FE steps 0.005 s), with
    ``--rim-thickness``, ``--fem-fracture`` (and so the rigid model's law through tearing),
    ``--fem-edge-radius``, ``--rim-punch``, ``--fem-crush`` and ``--stop`` [g] when given."""
    from fem.slider_push import EDGE_RADIUS

    bearing = () if rim_thickness_mm is None else (("rim_thickness", rim_thickness_mm / 1e3),)
    punch = {} if rim_punch == "face" else {
        "rim_punch": rim_punch, "rim_edge_radius": edge_radius_mm / 1e3 or EDGE_RADIUS,
        "rim_crush": crush}
    return Settings(fem=FESettings(max_step=0.005, limit_states=tuple(limit_states),
                                   fracture=fracture, edge_radius=edge_radius_mm / 1e3,
                                   crush_jacobian=crush),
                    rims=("rigid", "yielding"), bearing=bearing, rim_fracture=fracture,
                    **punch, **({} if stop_g is None else {"stop": stop_g * G}))


def replayed(out: Path, settings: Settings, motions) -> tuple[FESearches, list]:
    """The run's FE searches replayed from its store: the searches and their owners
    (pressure, record index), one per record in the order the searches were added. The
    yielding rims' law is the store's (planted in the cache: a law pushed on this machine
    differs in its last digits, and the rigid records key on its numbers)."""
    owners = []
    with ResultStore(out / "results.sqlite") as store:
        if settings.ladder_states():
            keep_rim_laws(store, settings.bearing_at(settings.pressures[0]),
                          [settings.rim_model], replay=True, fracture=settings.rim_fracture,
                          edge_radius=(settings.rim_edge_radius
                                       if settings.rim_punch == "slider" else None),
                          crush_jacobian=settings.rim_crush)
        tasks, index = rigid_tasks(motions, settings, out)
        searches = FESearches(settings.fem, step=settings.step, start=settings.step,
                              stop=settings.stop, stored=store.get)
        for task in tasks:
            pressure, i = index[task.key]
            result = store.get(task.key)
            if result is None:
                continue
            yielding = {s: critical_from_json(c) for s, c in result["yielding"].items()}
            pending = list(searches.add(settings.bearing_at(pressure), motions[i],
                                        critical_from_json(result["actual"]), yielding))
            owners.append((pressure, i))
            while pending:
                task = pending.pop()
                stored = store.get(task.key)
                if stored is not None:
                    pending += searches.follow_up(task, stored)
    return searches, owners


def stored_runs(out: Path, settings: Settings, motions):
    """Every FE run of the run's searches that its store holds: (stored result, keyword
    arguments of :func:`validation.fem_runs.fem_run`, the record's motion, SA [g])."""
    searches, _ = replayed(out, settings, motions)
    with ResultStore(out / "results.sqlite") as store:
        for key, (i, j) in searches.by_key.items():
            result = store.get(key)
            if result is not None:
                _, kwargs = searches.run_key(i, j)
                yield (result, kwargs, searches.targets[i][1],
                       (searches.start + j * searches.step) / G)


def replay(out: Path, settings: Settings, motions) -> list[dict]:
    """One row per (pressure, record, limit state): the report's FE comparison row
    (:func:`validation.report.write.fem_rows`) of the stored answers so far, and whether the
    search has finished."""
    searches, owners = replayed(out, settings, motions)
    per = len(settings.fem.limit_states)
    return [{"finished": search.done, **fem_rows({owners[k // per][0]: [r]})[0]}
            for k, (search, r) in enumerate(zip(searches.searches, searches.results(),
                                                strict=True))]


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--out", type=Path, default=FEM_VALIDATION)
    p.add_argument("--limit-state", nargs="+", default=["hinge"])
    p.add_argument("--rim-thickness", type=float, help="the run's --rim-thickness [mm]")
    p.add_argument("--fem-fracture", choices=FRACTURE_SETS, help="the run's --fem-fracture")
    p.add_argument("--fem-edge-radius", type=float, default=0.0,
                   help="the run's --fem-edge-radius [mm]")
    p.add_argument("--rim-punch", choices=("face", "slider"), default="face",
                   help="the run's --rim-punch")
    p.add_argument("--fem-crush", type=float, default=None, help="the run's --fem-crush")
    p.add_argument("--stop", type=float, default=None, help="the run's --stop [g]")
    args = p.parse_args()
    motions = fema_p695("nearfield_pulse")
    settings = run_settings(args.limit_state, args.rim_thickness, args.fem_fracture,
                            args.fem_edge_radius, args.rim_punch, args.fem_crush, args.stop)
    try:
        rows = replay(args.out, settings, motions)
    except MissingResultsError as exc:  # the rim law of other settings
        raise SystemExit(str(exc)) from None
    if not rows:
        raise SystemExit(f"no FE search of these settings in {args.out / 'results.sqlite'} "
                         "(other settings than the run's find nothing: the keys include them)")
    write_csv(rows, args.out / "status.csv")
    done = [r for r in rows if r["finished"]]
    print(f"{len(rows)} searches started, {len(done)} finished of "
          f"{2 * len(motions) * len(args.limit_state)}; FE probes (a run shared by searches "
          f"counts once per search): {sum(r['fem_runs'] for r in rows)}")
    written = ["status.csv"]
    if done:  # the report's Fig. 4 and its statistics, of the finished searches
        stats = fem_statistics(done)
        write_csv(stats, args.out / "status_statistics.csv")
        save_figure(plot_fem_vs_rigid(done, settings.stop / G), args.out / "status_fig4.png")
        for line in claim_verdicts(stats):
            print(f"  {line}")
        written += ["status_statistics.csv", "status_fig4.png"]
    for name in written:
        print(args.out / name)


if __name__ == "__main__":
    main()
