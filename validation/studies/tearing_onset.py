"""Where the two models part on the loss of containment with rims that tear: the rim's first tear
(the rupture, Eqs. F67 and R56c) of the FE runs against the rigid model's law through tearing,
on every finished case of the containment validations with fracture (issue #31, item 5).

For each case the FE search's stored runs give the lowest SA at which an FE rim tore (an upper
bound of the FE model's rupture SA: the search probes near the containment SA, not below it)
and the highest SA below that at which none did, if a run was made there. Beside them:

- the rigid model's rupture SA with the run's own law (the store's), by the validation's ladder
  (0.01 g, the fast search) at the rupture limit state;
- one rigid run at the SA where the FE rim first tore: the largest rim set it reaches against
  the law's rupture set, and its largest uplift (Eq. R54).

With ``--pose RECORD:PRESSURE:SA ...`` (the start of a record's name, MPa, g; the 80 mm
validation's stored runs), those FE runs are made again, stopped at the first tear, and the
slider's pose there is set against its pendulum path, the path the law's push holds it to (Eq.
F71): its rotation less the path angle on each dish, its rise above the bottom dish's path,
and the largest rim force (``docs/results/tearing_onset_pose.csv``; a few minutes of CPU a run).

Writes ``docs/results/tearing_onset.csv`` and prints, per thickness and pressure, the cases where
the FE rim tore at least 10 % below the rigid model's rupture SA. Reads the stores of
:data:`validation.studies.containment_tearing.FOLDERS` (an unfinished run's finished searches,
as listed in its ``status.csv``); a few minutes of CPU.

Run: ``python -m validation.studies.tearing_onset``.
"""

from __future__ import annotations

import argparse
import math
from collections import defaultdict
from pathlib import Path

import numpy as np

from rigid import G, fema_p695, simulate
from rigid.collapse import critical_sa
from rigid.collapse.comparison import write_csv
from rigid.tasks import ResultStore
from validation.stored_rim_laws import stored_rim_law

from . import RESULTS, read_csv, validation_table
from .containment_tearing import FOLDERS
from .fem_validation_status import run_settings, stored_runs

#: Rim thickness [mm] → what pushed the rim for its law: the face (40 mm) or the slider with
#: 20 mm edges (80 mm), as the validations were run (their READMEs).
PUNCH = {40.0: ("face", None), 80.0: ("slider", 0.02)}
#: FE tearing this far below the rigid model's rupture SA counts as "earlier" [-].
EARLIER = 0.9


def fe_tearing(out: Path, settings, motions) -> dict:
    """(record name, pressure [MPa]) → the SAs [g] of the stored FE runs, each with whether a
    rim tore in it (its rupture time is set)."""
    runs = defaultdict(list)
    for result, kwargs, motion, sa in stored_runs(out, settings, motions):
        pressure = round(kwargs["bearing"]["pressure"] / 1e6)
        runs[(motion.name, pressure)].append((sa, result["limit_states"]["rupture"] is not None))
    return runs


def case_row(thickness, motion, pressure, runs, law, settings, table_row) -> dict:
    """The row of one case (module docstring)."""
    torn = [sa for sa, tore in runs if tore]
    tore_at = min(torn) if torn else math.nan
    intact_at = max((sa for sa, tore in runs if not tore and not sa > tore_at), default=math.nan)
    bearing = settings.bearing_at(pressure * 1e6)
    ladder = critical_sa(bearing, motion, step=settings.step, stop=settings.stop,
                         search=settings.search, rims="yielding", limit_state="rupture",
                         rim_law=law)
    row = {"rim_thickness_mm": thickness, "record": motion.name, "pressure_mpa": pressure,
           "fe_tore_at_g": tore_at, "fe_intact_at_g": intact_at,
           "rigid_rupture_sa_g": math.nan if ladder.sa is None else ladder.sa / G,
           "fe_containment_sa_g": float(table_row["fem_sa_g"]),
           "rigid_containment_sa_g": float(table_row["yielding_sa_g"]),
           "law_rupture_set_mm": law.rupture_set * 1e3}
    row["fe_tore_over_rigid_rupture"] = row["fe_tore_at_g"] / row["rigid_rupture_sa_g"]
    if torn:  # the rigid model at the SA where the FE rim first tore
        r = simulate(bearing, motion.acceleration * (tore_at * G / ladder.record_sa), motion.dt,
                     duration=(motion.acceleration.size - 1) * motion.dt + 20.0,
                     rims="yielding", limit_state="rupture", rim_law=law,
                     stop_when_quiet=True, on_instability="refine")
        row["rigid_max_set_mm_at_fe_tear"] = float(r.rim_set.max()) * 1e3
        row["rigid_max_uplift_mm_at_fe_tear"] = r.max_uplift * 1e3
    return row


def pose_at_tear(cases, motions) -> list[dict]:
    """The FE runs of the 80 mm validation named by ``cases`` ((record start, pressure [MPa],
    SA [g])) made again to their first tear: the slider's pose there against its path (module
    docstring)."""
    from threadpoolctl import threadpool_limits

    import fem
    from validation.fem_runs import fem_run

    thickness = 80.0
    settings = run_settings(["containment"], thickness, "median", 20.0, PUNCH[thickness][0])
    rows, made = [], []

    def keep(*args, **options):  # fem_run's stand-in for fem.simulate: keeps the result
        made.append(fem.simulate(*args, **options))
        return made[-1]

    for result, kwargs, motion, sa in stored_runs(FOLDERS[thickness], settings, motions):
        pressure = round(kwargs["bearing"]["pressure"] / 1e6)
        if not any(motion.name.startswith(name) and pressure == p and abs(sa - s) < 0.005
                   for name, p, s in cases) or result["limit_states"]["rupture"] is None:
            continue
        with threadpool_limits(1):  # as in a worker
            fem_run(**{**kwargs, "limit_state": "rupture"}, simulate=keep)
        r = made[-1]
        arm = r.bearing.radius - r.bearing.slider_height / 2  # the path's radius (Eq. F71)
        x, d, rotation = r.slider_displacement[-1], r.displacement[-1], r.slider_rotation[-1]
        bottom = math.asin(x / arm)  # concentric with the bottom dish; the top: x − d = −arm sin
        rows.append({"record": motion.name, "pressure_mpa": pressure, "sa_g": round(sa, 3),
                     "first_tear_s": next(iter(r.torn_elements.values()))[0],
                     "rim": next(iter(r.torn_elements.values()))[1],
                     "rotation_off_bottom_path_deg": math.degrees(rotation - bottom),
                     "rotation_off_top_path_deg": math.degrees(rotation + math.asin((x - d) / arm)),
                     "rise_above_bottom_path_mm": float(r.slider_rise[-1]
                                                   - arm * (1 - math.cos(bottom))) * 1e3,
                     "max_rim_force_mn": float(r.rim_force.max()) / 1e6})
        print(rows[-1], flush=True)
    return rows


def main(argv=None) -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--out", type=Path, default=RESULTS)
    p.add_argument("--pose", nargs="+", metavar="RECORD:PRESSURE:SA",
                   help="make these FE runs of the 80 mm validation again to their first tear")
    args = p.parse_args(argv)
    motions = fema_p695("nearfield_pulse")
    if args.pose:
        cases = [(c.split(":")[0], int(c.split(":")[1]), float(c.split(":")[2]))
                 for c in args.pose]
        write_csv(pose_at_tear(cases, motions), args.out / "tearing_onset_pose.csv")
        return
    rows = []
    for thickness, folder in FOLDERS.items():
        table = validation_table(folder)
        if table is None:
            continue
        punch, edge = PUNCH[thickness]
        settings = run_settings(["containment"], None if thickness == 40.0 else thickness,
                                "median", 20.0, punch)
        finished = {(r["record"], round(float(r["pressure_mpa"]))): r
                    for r in read_csv(folder / table[0])
                    if table[1] or r["finished"] == "True"}
        runs = fe_tearing(folder, settings, motions)
        with ResultStore(folder / "results.sqlite") as store:
            laws = {p: stored_rim_law(store, settings.bearing_at(p * 1e6), fracture="median",
                                      edge_radius=edge) for p in (60, 10)}
        for motion in motions:
            for pressure in (60, 10):
                if (motion.name, pressure) in finished:
                    rows.append(case_row(thickness, motion, pressure,
                                         runs[(motion.name, pressure)], laws[pressure],
                                         settings, finished[(motion.name, pressure)]))
    write_csv(rows, args.out / "tearing_onset.csv")
    for thickness in FOLDERS:
        for pressure in (60, 10):
            group = [r for r in rows if r["rim_thickness_mm"] == thickness
                     and r["pressure_mpa"] == pressure]
            if not group:
                continue
            ratio = [r["fe_tore_over_rigid_rupture"] for r in group]
            earlier = [r for r in group if r["fe_tore_over_rigid_rupture"] < EARLIER]
            print(f"{thickness:g} mm, {pressure} MPa, {len(group)} cases: FE tore at "
                  f"{np.nanmedian(ratio):.2f} of the rigid rupture SA (median), at least 10 % "
                  f"below it on {len(earlier)}"
                  + "".join(f"\n  {r['record']}: FE tore at {r['fe_tore_at_g']:.2f} g, rigid "
                            f"rupture {r['rigid_rupture_sa_g']:.2f} g (rigid set there "
                            f"{r['rigid_max_set_mm_at_fe_tear']:.1f} of "
                            f"{r['law_rupture_set_mm']:.1f} mm)" for r in earlier))


if __name__ == "__main__":
    main()
