"""The loss of containment with rims that tear (issue #31, item 5): the rigid model's critical
SA with the law through tearing against the FE model's with tearing, on every case of the
containment validations with fracture, with the first touch beside each.

Reads ``fem_comparison.csv`` of ``docs/fem-validation-fracture`` (40 mm rims) and
``docs/fem-validation-fracture-rims80`` (80 mm), those that exist, or, of a run under way,
the finished searches of its ``status.csv`` (``python -m
validation.studies.fem_validation_status --limit-state containment --fem-fracture median
--fem-edge-radius 20 --out FOLDER``; marked ``run_finished`` False), and the first touch of
every record from the design space (``docs/rim-design/cases.csv``: the lowest 0.01 g rung at
which the rigid-rim model touches a rim). Writes to ``docs/results/``:

- ``containment_tearing.csv``: the validations' ``fem_comparison.csv`` columns plus
  ``rim_thickness_mm``, ``first_touch_sa_g`` and ``fem_over_first_touch``;
- ``containment_tearing_statistics.csv``: per thickness, the medians of FE/rigid and FE/first
  touch, how many cases are within ±20 % and ±35 % of each, and the issue's three targets:
  the median FE/rigid within ±15 %, at least 80 % of the cases within ±35 %, and more cases
  within ±20 % of the rigid model than of the first touch.

Run: ``python -m validation.studies.containment_tearing``.
"""

from __future__ import annotations

import argparse
import math
import statistics
from pathlib import Path

from rigid.collapse.comparison import write_csv

from . import DOCS, RESULTS, number
from .rim_design import OUT as DESIGN_SPACE
from .rim_design_fem import comparison

#: Rim thickness [mm] → the containment validation with tearing at it.
FOLDERS = {40.0: DOCS / "fem-validation-fracture", 80.0: DOCS / "fem-validation-fracture-rims80"}


def _within(ratios, band) -> int:
    return sum(abs(x - 1) <= band + 1e-9 for x in ratios)


def statistics_rows(rows: list[dict]) -> list[dict]:
    """Per thickness, containment only: the cases compared, the medians, the counts within
    the bands and the targets (module docstring)."""
    out = []
    for t in sorted({r["rim_thickness_mm"] for r in rows}):
        group = [r for r in rows
                 if r["rim_thickness_mm"] == t and r["limit_state"] == "containment"]
        some = [r for r in group if math.isfinite(number(r["fem_sa_g"]))
                and math.isfinite(number(r["yielding_sa_g"]))
                and math.isfinite(r["first_touch_sa_g"])]
        y = [number(r["fem_sa_g"]) / number(r["yielding_sa_g"]) for r in some]
        f = [r["fem_over_first_touch"] for r in some]
        median = statistics.median(y) if y else math.nan
        out.append({
            "rim_thickness_mm": t, "cases": len(group), "compared": len(some),
            "fem_uncertain": sum(str(r.get("uncertain")) == "True" for r in group),
            "numerical_runs": sum(int(r["numerical_runs"] or 0) for r in group),
            "median_fem_over_rigid": median,
            "median_fem_over_first_touch": statistics.median(f) if f else math.nan,
            "rigid_within_20": _within(y, 0.20), "first_touch_within_20": _within(f, 0.20),
            "rigid_within_35": _within(y, 0.35), "first_touch_within_35": _within(f, 0.35),
            "target_median": abs(median - 1) <= 0.15,
            "target_within_35": bool(y) and _within(y, 0.35) >= 0.8 * len(y),
            "target_beats_first_touch": _within(y, 0.20) > _within(f, 0.20),
        })
    return out


def main(argv=None) -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--out", type=Path, default=RESULTS)
    args = p.parse_args(argv)
    rows = []
    for t, folder in FOLDERS.items():
        if (folder / "fem_comparison.csv").exists():
            rows += [{**r, "run_finished": "True"}
                     for r in comparison(DESIGN_SPACE, {t: folder})]
        elif (folder / "status.csv").exists():  # a run under way: its finished searches
            rows += [{**r, "run_finished": "False"}
                     for r in comparison(DESIGN_SPACE, {t: folder}, "status.csv")
                     if r["finished"] == "True"]
    if not rows:
        raise SystemExit("no containment validation with tearing has a fem_comparison.csv "
                         "or a status.csv yet")
    write_csv(rows, args.out / "containment_tearing.csv")
    stats = statistics_rows(rows)
    write_csv(stats, args.out / "containment_tearing_statistics.csv")
    for s in stats:
        n = s["compared"]
        print(f"{s['rim_thickness_mm']:g} mm: {n} of {s['cases']} cases; median FE/rigid "
              f"{s['median_fem_over_rigid']:.2f}, FE/first touch "
              f"{s['median_fem_over_first_touch']:.2f}; within 20 %: rigid "
              f"{s['rigid_within_20']}, first touch {s['first_touch_within_20']}; within "
              f"35 %: rigid {s['rigid_within_35']}, first touch {s['first_touch_within_35']}")


if __name__ == "__main__":
    main()
