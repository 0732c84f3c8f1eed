"""The rim design space (issue #29): the critical SA(4.5 s) and the failure mode of every
near-field pulse component against rim thickness, with rigid and with yielding rims.

For each rim thickness (``--thicknesses``, mm) and pressure (``--pressures``, MPa) and each of
the 28 components of FEMA P695's near-field pulse set:

- the rigid-rim ladder (the paper's model; loss of containment, always by uplift), once per
  record and pressure (the rigid-rim model does not see the rim's thickness);
- the yielding-rim ladders at the hinge, the rupture and the loss of containment, from one
  set of rungs run to containment (:func:`rigid.collapse.critical_sa_by_limit_state`), the
  rims' law from the FE push of that rim (``fem.rim_law``, cached per geometry; ``--rim-model
  ring`` takes the 3-D ring's instead), and how each fails (the rim, or uplift first);
- the first touch: the lowest 0.01 g rung at which the rigid-rim model touches a rim (the
  trivial predictor of a rim that fails at its first touch).

Every case is a stored task (``<out>/store/results.sqlite``): an interrupted study resumes.
Writes to ``--out`` (default ``docs/rim-design``): ``cases.csv`` (every case),
``failure_mode_map.csv`` and ``failure_mode_map.png`` (the share of records per failure mode,
thickness and pressure), ``design_charts.csv`` and ``design_charts.png`` (median and 16/84 %
critical SA against thickness per limit state and pressure, the rigid-rim model beside),
``rim_capacity.csv`` (the rim's capacity from its push beside the closed forms). How to read
them: docs/rim-design/README.md.

Run: ``python -m validation.studies.rim_design [--workers 2] [--thicknesses 20 40 ...]``.
"""

from __future__ import annotations

import argparse
import math
import time
from pathlib import Path

import numpy as np

import fem
import rigid
from rigid import DFPBearing, G
from rigid.collapse.comparison import write_csv
from rigid.collapse.record_set import pool_context
from rigid.limit_states import LIMIT_STATES
from rigid.tasks import ResultStore, Task, cache_root, run_tasks, task_key

from . import DOCS
from .rim_design_case import CASE_CODE, MODES, rigid_case, yielding_case

OUT = DOCS / "rim-design"
#: Rim thicknesses [mm]: the issue's seven, from a rim that hinges at once to one the slider
#: cannot hinge (docs/rim-design/README.md).
THICKNESSES_MM = (20, 40, 80, 120, 160, 240, 320)
PRESSURES_MPA = (60, 10)
#: Top of every ladder [m/s²]: a case without failure up to it is censored there.
STOP = 3.0 * G


def tasks(thicknesses_mm, pressures_mpa, motions, rim_model: str, stop: float, cache,
          rim_height: float = DFPBearing.rim_height):
    """The stored tasks of the study and what each is: one with rigid rims per pressure ×
    record (at the baseline's thickness: the rigid-rim model does not see it;
    :func:`.rim_design_case.rigid_case`), one with yielding rims per thickness × pressure ×
    record;
    ``what`` maps a task's key to ("rigid", pressure [MPa], record) or ("yielding", thickness
    [mm], pressure, record)."""
    out, what = [], {}

    def add(kind, func, args, label):
        inputs = {k: v for k, v in args.items() if k not in ("motion", "cache")}
        key = task_key(kind, CASE_CODE, **inputs, motion=args["motion"].acceleration,
                       dt=args["motion"].dt)
        out.append(Task(key, kind, func, {**args, "cache": cache}, leads=False))
        what[key] = label

    for p in pressures_mpa:
        bearing = DFPBearing(pressure=p * 1e6, rim_height=rim_height)
        for m in motions:
            add("rim-design-rigid", rigid_case, {"bearing": bearing, "motion": m, "stop": stop},
                ("rigid", p, m.name))
    for t in thicknesses_mm:
        for p in pressures_mpa:
            bearing = DFPBearing(pressure=p * 1e6, rim_thickness=t * 1e-3,
                                 rim_height=rim_height)
            law = fem.rim_law(bearing, model=rim_model)
            for m in motions:
                add("rim-design-yielding", yielding_case,
                    {"bearing": bearing, "motion": m, "rim_law": law, "stop": stop},
                    ("yielding", t, p, m.name))
    return out, what


def cases(thicknesses_mm, pressures_mpa, out: Path, *, rim_model="plane-strain",
          workers=2, records=None, cache=None,
          rim_height: float = DFPBearing.rim_height, replay: bool = False,
          seen: dict | None = None) -> list[dict]:
    """Run (or read) every case; one row per thickness × pressure × record (``rim_height``
    [m]); ``replay``: run nothing (:func:`rigid.tasks.run_tasks`, which fills ``seen`` with
    the tasks found), the rims' laws from the store too."""
    from ..stored_rim_laws import keep_rim_laws

    motions = rigid.fema_p695("nearfield_pulse")[:records]
    cache = cache_root() / "ladders" if cache is None else cache
    (out / "store").mkdir(parents=True, exist_ok=True)
    with ResultStore(out / "store" / "results.sqlite") as store:
        for t in thicknesses_mm:
            keep_rim_laws(store, DFPBearing(rim_thickness=t * 1e-3, rim_height=rim_height),
                          [rim_model], replay=replay)
        todo, what = tasks(thicknesses_mm, pressures_mpa, motions, rim_model, STOP, cache,
                           rim_height)
        results = run_tasks(todo, store, workers=workers, description="rim design cases",
                            unit="case", start_method=pool_context().get_start_method(),
                            log=None if replay else out / "store" / "progress.log",
                            replay=replay, seen=seen)
    rigid_rims = {label[1:]: results[key] for key, label in what.items() if label[0] == "rigid"}
    return [{"rim_thickness_mm": t, "rim_height_mm": rim_height * 1e3, "pressure_mpa": p,
             "record": name, "rim_model": rim_model, **rigid_rims[p, name], **results[key]}
            for key, (kind, *label) in what.items() if kind == "yielding"
            for t, p, name in [label]]


def capacity_rows(thicknesses_mm, rim_height: float, rim_model: str) -> list[dict]:
    """The rim's lateral capacity per thickness [MN]: from its law (the FE push: first yield,
    hinge, force at the end of the push to half the height) beside the closed forms of
    docs/theory/finite-elements.md (root shear F40, root moment F41 at the lever 0.75 h_r,
    face crushing F60, all times the depth D = πb/4) and the tipping force W b/h (F39) of each
    pressure."""
    rows = []
    for t in thicknesses_mm:
        b = DFPBearing(rim_thickness=t * 1e-3, rim_height=rim_height)
        law = fem.rim_law(b, model=rim_model)
        depth, k = math.pi * b.slider_diameter / 4, b.yield_stress / math.sqrt(3)
        row = {"rim_thickness_mm": t, "rim_height_mm": rim_height * 1e3,
               "first_yield_MN": law.first_yield_force / 1e6,
               "hinge_MN": law.hinge_force / 1e6,
               "push_end_MN": float(law.push_force[-1]) / 1e6,
               "root_shear_F40_MN": k * b.rim_thickness * depth / 1e6,
               "root_moment_F41_MN": 2 * k * b.rim_thickness**2 / 4 / (0.75 * rim_height)
               * depth / 1e6,
               "face_F60_MN": (2 + math.pi) * k * rim_height / 2 * depth / 1e6}
        for p in PRESSURES_MPA:
            w = DFPBearing(pressure=p * 1e6).weight
            row[f"tipping_F39_{p:g}MPa_MN"] = w * b.slider_diameter / b.slider_height / 1e6
        rows.append(row)
    return rows


def mode_map(rows: list[dict]) -> list[dict]:
    """Share of records per governing mode and per limit state's mode, per thickness and
    pressure."""
    out = []
    for (t, p), group in _groups(rows).items():
        n = len(group)
        row = {"rim_thickness_mm": t, "rim_height_mm": group[0].get("rim_height_mm", 35.0),
               "pressure_mpa": p, "records": n}
        for mode in MODES:
            row[f"share_{mode}"] = round(sum(r["governing_mode"] == mode for r in group) / n, 4)
        for state in LIMIT_STATES:
            for mode in ("rim", "uplift"):
                row[f"{state}_by_{mode}"] = round(
                    sum(r[f"{state}_mode"] == mode for r in group) / n, 4)
        out.append(row)
    return out


def design_chart(rows: list[dict]) -> list[dict]:
    """Median and 16/84 % critical SA [g] per thickness, pressure and limit state (yielding
    rims), and of the rigid-rim model and the first touch. A case without failure up to the
    ladder's top counts as above it (a percentile that lands there is inf); one whose answer
    depends on numerical rungs (``*_uncertain``) is left out and counted as unknown, and with
    half the records or more unknown the percentiles are NaN; so are the hinge's of a rim
    that hinges on no record (its "hinge" is then the loss of containment)."""
    out = []
    for (t, p), group in _groups(rows).items():
        columns = {f"yielding_{s}": (f"{s}_sa_g", f"{s}_uncertain") for s in LIMIT_STATES}
        columns |= {"rigid_rims": ("rigid_sa_g", "rigid_uncertain"),
                    "first_touch": ("first_touch_sa_g", None)}
        for model, (column, uncertain) in columns.items():
            unknown = [r[column] is None and bool(uncertain and r[uncertain])
                       for r in group]
            v = np.array([math.inf if r[column] is None else r[column]
                          for r, u in zip(group, unknown, strict=True) if not u])
            if 2 * sum(unknown) >= len(group) or (model == "yielding_hinge"
                                                   and not any(map(_hinged, group))):
                q16 = q50 = q84 = math.nan
            else:
                q16, q50, q84 = (float(np.percentile(v, q, method="inverted_cdf"))
                                 for q in (16, 50, 84))
            out.append({"rim_thickness_mm": t, "pressure_mpa": p, "model": model,
                        "median_g": q50, "p16_g": q16, "p84_g": q84,
                        "no_failure": int(np.isinf(v).sum()), "unknown": sum(unknown),
                        "records": len(group)})
    return out


def _hinged(row) -> bool:
    """The rim hinged before the slider got out: the hinge came first, or below the loss of
    containment."""
    hinge, lost = row["hinge_sa_g"], row["containment_sa_g"]
    return row["governing_mode"] == "hinge" or (
        hinge is not None and (lost is None or float(hinge) < float(lost)))


def _groups(rows):
    groups = {}
    for r in rows:
        groups.setdefault((r["rim_thickness_mm"], r["pressure_mpa"]), []).append(r)
    return groups


def _rekey(args) -> None:
    """``--rekey-from``: :func:`rigid.tasks.rekey.rekey` of the study's store, replaying
    :func:`cases` with the arguments given, once the rims' laws are stored under today's
    keys (carried over once today's push agrees, or kept with ``--keep-stored-laws``;
    pushed where the store lacks them)."""
    from rigid.tasks.rekey import rekey

    from ..stored_rim_laws import carry_rim_laws, keep_rim_laws

    with ResultStore(args.out / "store" / "results.sqlite") as store:
        for t in args.thicknesses:
            bearing = DFPBearing(rim_thickness=t * 1e-3, rim_height=args.rim_height * 1e-3)
            for line in carry_rim_laws(store, bearing, [args.rim_model], args.rekey_from,
                                       keep_differing=args.keep_stored_laws):
                print(f"--rekey-from {args.rekey_from}: {t:g} mm: {line}")
            keep_rim_laws(store, bearing, [args.rim_model])

    def replay(seen):
        cases(args.thicknesses, args.pressures, args.out, rim_model=args.rim_model,
              records=args.records, rim_height=args.rim_height * 1e-3, replay=True,
              seen=seen)

    with ResultStore(args.out / "store" / "results.sqlite") as store:
        carried = rekey(store, replay, args.rekey_from)
    print(f"--rekey-from {args.rekey_from}: {carried.describe()}")


def main(argv=None) -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--thicknesses", type=float, nargs="+", default=THICKNESSES_MM,
                   help="rim thicknesses [mm]")
    p.add_argument("--pressures", type=float, nargs="+", default=PRESSURES_MPA,
                   help="slider pressures [MPa]")
    p.add_argument("--rim-model", choices=("plane-strain", "ring"), default="plane-strain",
                   help="where the yielding rims' law comes from (fem.rim_law)")
    p.add_argument("--rim-height", type=float, default=DFPBearing.rim_height * 1e3,
                   help="the rims' height [mm] (default 35; the geometry holds up to about "
                   "47 mm: DFPBearing.rim_clearance)")
    p.add_argument("--records", type=int, help="only the first N components")
    p.add_argument("--workers", type=int, default=2)
    p.add_argument("--out", type=Path, default=OUT)
    p.add_argument("--replay", action="store_true",
                   help="run nothing: every case and rim law from the store")
    p.add_argument("--rekey-from", metavar="REVISION",
                   help="first carry the cases that REVISION's code stored over to today's "
                   "keys, once the shortest two of each kind rerun equal "
                   "(rigid.tasks.rekey.rekey)")
    p.add_argument("--keep-stored-laws", action="store_true",
                   help="with --rekey-from: carry the store's rim laws over even where "
                   "today's push differs (a push takes other increments on another machine); "
                   "the differences are printed")
    args = p.parse_args(argv)
    if args.keep_stored_laws and not args.rekey_from:
        p.error("--keep-stored-laws needs --rekey-from")
    t0 = time.perf_counter()
    if args.rekey_from:
        from rigid.tasks.rekey import RekeyError

        try:
            _rekey(args)
        except RekeyError as exc:
            raise SystemExit(f"--rekey-from {args.rekey_from}: {exc}") from None
    rows = cases(args.thicknesses, args.pressures, args.out, rim_model=args.rim_model,
                 workers=args.workers, records=args.records,
                 rim_height=args.rim_height * 1e-3, replay=args.replay)
    wall = time.perf_counter() - t0
    write_csv(rows, args.out / "cases.csv")
    write_csv(mode_map(rows), args.out / "failure_mode_map.csv")
    write_csv(design_chart(rows), args.out / "design_charts.csv")
    write_csv(capacity_rows(args.thicknesses, args.rim_height * 1e-3, args.rim_model),
              args.out / "rim_capacity.csv")
    from .rim_design_figures import draw

    draw(args.out)
    cpu = sum(r["yielding_cpu_s"] for r in rows) + sum(
        {(r["pressure_mpa"], r["record"]): r["rigid_cpu_s"] for r in rows}.values())
    print(f"{len(rows)} cases in {wall:.0f} s wall ({cpu:.0f} s CPU of the cases computed "
          f"now or before); {args.out}")


if __name__ == "__main__":
    main()
