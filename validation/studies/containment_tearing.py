"""The loss of containment with rims that tear (issue #31, item 5): the rigid model's critical
SA with the law through tearing against the FE model's with tearing, on every case of the
containment validations with fracture, with the first touch beside each.

Reads ``fem_comparison.csv`` of ``docs/fem-validation-fracture`` (40 mm rims) and
``docs/fem-validation-fracture-rims80`` (80 mm), and of the same validations with crushing and
uncovered faces (``--fem-crush 0.1``, :data:`CRUSHED`: 40 and 80 mm and the design space's
120, 160 and 240 mm), those that exist, or, of a run under way,
the finished searches of its ``status.csv`` (``python -m
validation.studies.fem_validation_status --limit-state containment --fem-fracture median
--fem-edge-radius 20 --out FOLDER``; marked ``run_finished`` False), and the first touch of
every record from the design space (``docs/rim-design/cases.csv``: the lowest 0.01 g rung at
which the rigid-rim model touches a rim). Writes to ``docs/results/``:

- ``containment_tearing.csv``: the validations' ``fem_comparison.csv`` columns plus
  ``rim_thickness_mm``, ``crush_jacobian`` (blank without crushing), ``first_touch_sa_g`` and
  ``fem_over_first_touch``;
- ``containment_tearing_statistics.csv``: per validation (thickness and crushing), over all
  cases and over those where
  FE and first touch are more than 10 % apart, the statistics of ``rim_design_fem`` (the
  medians of FE/rigid and FE/first touch, the shares within ±20 % and ±35 % of each), the FE
  runs that ended numerically, and the issue's three targets: the median FE/rigid within
  ±15 %, at least 80 % of the cases within ±35 %, and more cases within ±20 % of the rigid
  model than of the first touch.

and draws ``docs/images/containment_tearing.png`` from them (beside the CSVs with ``--out``)
(:mod:`validation.studies.containment_tearing_figure`).

Run: ``python -m validation.studies.containment_tearing``.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from rigid.collapse.comparison import write_csv

from . import DOCS, RESULTS, validation_table
from .containment_tearing_figure import PNG, draw
from .rim_design import OUT as DESIGN_SPACE
from .rim_design_fem import comparison
from .rim_design_fem import statistics_rows as fem_statistics

#: Rim thickness [mm] → the containment validation with tearing at it.
FOLDERS = {40.0: DOCS / "fem-validation-fracture", 80.0: DOCS / "fem-validation-fracture-rims80"}
#: The crushing Jacobian of the validations with crushing and uncovered faces [-]
#: (docs/theory/finite-elements.md, Eqs. F67b, F68c).
CRUSH_JACOBIAN = 0.1
#: Rim thickness [mm] → the containment validation with tearing, crushing at
#: :data:`CRUSH_JACOBIAN` and uncovered faces at it.
CRUSHED = {40.0: DOCS / "fem-validation-fracture-crush",
           80.0: DOCS / "fem-validation-fracture-crush-rims80",
           **{t: DESIGN_SPACE / f"fem-{t:g}-containment" for t in (120.0, 160.0, 240.0)}}


def crushed_rims(thickness: float) -> list[str]:
    """The ``dfp validate`` arguments that set the rims, their crushing and the ladder of the
    validations with crushing at ``thickness`` [mm] (:data:`CRUSHED`; their fracture-constant
    runs too, :mod:`validation.studies.fracture_sensitivity`): the 40 mm rims' law pushed by
    the face, the others' by the slider; the design space's ladders up to 3 g, as its rupture
    validations."""
    rims = [] if thickness == 40 else ["--rim-thickness", f"{thickness:g}", "--rim-punch",
                                       "slider"]
    ladder = ["--stop", "3"] if thickness > 80 else []
    return [*rims, *ladder, "--fem-crush", f"{CRUSH_JACOBIAN:g}"]


def crushed_args(thickness: float) -> list[str]:
    """The ``dfp validate`` arguments (besides ``--out``) of the containment validation with
    crushing at ``thickness`` [mm] (:data:`CRUSHED`, :func:`crushed_rims`)."""
    return [*crushed_rims(thickness), "--limit-state", "containment", "--fem-fracture",
            "median", "--fem-edge-radius", "20"]


def statistics_rows(rows: list[dict]) -> list[dict]:
    """:func:`validation.studies.rim_design_fem.statistics_rows` of the containment rows of
    each validation (thickness and ``crush_jacobian``; all cases, and those where FE and first
    touch are apart), with the FE runs that ended numerically and the issue's three targets
    (module docstring)."""
    containment = [r for r in rows if r["limit_state"] == "containment"]
    validations = {}
    for r in containment:
        validations.setdefault(r.get("crush_jacobian", ""), []).append(r)
    out = []
    for crush, some in validations.items():
        for s in fem_statistics(some):
            group = [r for r in some if r["rim_thickness_mm"] == s["rim_thickness_mm"]]
            out.append({"crush_jacobian": crush, **_targets(s, group)})
    return out


def _targets(s: dict, group: list[dict]) -> dict:
    """One row of statistics ``s`` with the numerical runs of its cases ``group`` and the
    issue's three targets."""
    return {**s, "numerical_runs": sum(int(r["numerical_runs"] or 0) for r in group),
            "target_median": abs(s["median_fem_over_yielding"] - 1) <= 0.15,
            "target_within_35": s["yielding_within_35"] >= 0.8,
            "target_beats_first_touch": s["yielding_within_20"] > s["first_touch_within_20"]}


def main(argv=None) -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--out", type=Path, default=RESULTS)
    args = p.parse_args(argv)
    rows = []
    for crush, folders in (("", FOLDERS), (CRUSH_JACOBIAN, CRUSHED)):
        for t, folder in folders.items():
            table = validation_table(folder)
            if table is not None:
                name, finished = table
                rows += [{"crush_jacobian": crush,
                          **{k: v for k, v in r.items() if k != "finished"},
                          "run_finished": str(finished)}
                         for r in comparison(DESIGN_SPACE, {t: folder}, name)
                         if finished or r["finished"] == "True"]
    if not rows:
        raise SystemExit("no containment validation with tearing has a fem_comparison.csv "
                         "or a status.csv yet")
    write_csv(rows, args.out / "containment_tearing.csv")
    stats = statistics_rows(rows)
    write_csv(stats, args.out / "containment_tearing_statistics.csv")
    draw(args.out / "containment_tearing.csv",  # beside the CSVs when they go elsewhere
         PNG if args.out == RESULTS else args.out / "containment_tearing.png")
    for s in stats:
        crushed = f", crushing J_c {s['crush_jacobian']:g}" if s["crush_jacobian"] != "" else ""
        print(f"{s['rim_thickness_mm']:g} mm{crushed}, {s['cases']} cases: {s['n']} of {s['of']}; "
              f"median FE/rigid {s['median_fem_over_yielding']:.2f}, FE/first touch "
              f"{s['median_fem_over_first_touch']:.2f}; within 20 %: rigid "
              f"{s['yielding_within_20']:.0%}, first touch {s['first_touch_within_20']:.0%}; "
              f"within 35 %: rigid {s['yielding_within_35']:.0%}, first touch "
              f"{s['first_touch_within_35']:.0%}")


if __name__ == "__main__":
    main()
