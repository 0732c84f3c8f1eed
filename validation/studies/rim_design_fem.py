"""The FE validation across rim thicknesses (issue #29, items 3–4): one table of every FE
search with the rim's thickness and the trivial predictor beside it, and its statistics.

Reads the FE comparisons of the validation runs (``dfp validate --rim-thickness T --out
docs/rim-design/fem-<T>``, plus the 40 and 80 mm runs in ``docs/fem-validation`` and
``docs/fem-validation-rims80``) and the first touch of every record from the design space
(``docs/rim-design/cases.csv``: the lowest 0.01 g rung at which the rigid-rim model touches a
rim). Writes to ``docs/rim-design/``:

- ``fem_comparison.csv``: the validation's ``fem_comparison.csv`` columns plus
  ``rim_thickness_mm``, ``first_touch_sa_g`` and ``fem_over_first_touch``;
- ``fem_statistics.csv``: per thickness and limit state, over all cases and over the
  discriminating ones (FE and first touch more than 10 % apart): the medians of FE/yielding
  and FE/first touch, the shares within ±20 % and ±35 %, and how many FE answers are
  uncertain (their search met a numerical run below the answer).

Run: ``python -m validation.studies.rim_design_fem``.
"""

from __future__ import annotations

import argparse
import math
import statistics
from pathlib import Path

from rigid.collapse.comparison import write_csv

from . import DOCS, number, read_csv
from .rim_design import OUT

#: The validation runs at the baseline's two earlier thicknesses [mm] → their folders.
EARLIER = {40.0: DOCS / "fem-validation", 80.0: DOCS / "fem-validation-rims80"}
#: FE and first touch further apart than this make a case discriminating.
APART = 0.10


def runs(out: Path = OUT) -> dict[float, Path]:
    """Thickness [mm] → the folder of its FE validation run (those that exist)."""
    found = {t: d for t, d in EARLIER.items() if (d / "fem_comparison.csv").exists()}
    for d in sorted(out.glob("fem-*")):
        if d.name.removeprefix("fem-").isdigit() and (d / "fem_comparison.csv").exists():
            found[float(d.name.removeprefix("fem-"))] = d
    return dict(sorted(found.items()))


def comparison(out: Path = OUT, folders: dict[float, Path] | None = None,
               table: str = "fem_comparison.csv") -> list[dict]:
    """Every FE search of every thickness, with the first touch (from ``out``'s design space)
    beside it; ``folders``: thickness [mm] → validation folder (default :func:`runs`), whose
    ``table`` is read."""
    touch = {(float(r["rim_thickness_mm"]), float(r["pressure_mpa"]), r["record"]):
             number(r["first_touch_sa_g"]) for r in read_csv(out / "cases.csv")}
    rows = []
    for t, folder in (runs(out) if folders is None else folders).items():
        for r in read_csv(folder / table):
            first = touch.get((t, float(r["pressure_mpa"]), r["record"]), math.nan)
            fe = number(r["fem_sa_g"])
            rows.append({"rim_thickness_mm": t, **r, "first_touch_sa_g": first,
                         "fem_over_first_touch": fe / first if first > 0 else math.nan})
    return rows


def _share(ratios, band):
    return sum(abs(x - 1) <= band + 1e-9 for x in ratios) / len(ratios) if ratios else math.nan


def statistics_rows(rows: list[dict]) -> list[dict]:
    """Per thickness and limit state: medians and shares, all and discriminating cases."""
    out = []
    groups = {}
    for r in rows:
        groups.setdefault((r["rim_thickness_mm"], r["limit_state"]), []).append(r)
    for (t, state), group in groups.items():
        for subset in ("all", "discriminating"):
            some = [r for r in group if math.isfinite(number(r["fem_sa_g"]))
                    and math.isfinite(number(r["yielding_sa_g"]))
                    and math.isfinite(r["first_touch_sa_g"])]
            if subset == "discriminating":
                some = [r for r in some
                        if abs(r["fem_over_first_touch"] - 1) > APART]
            y = [number(r["fem_sa_g"]) / number(r["yielding_sa_g"]) for r in some]
            f = [r["fem_over_first_touch"] for r in some]
            out.append({
                "rim_thickness_mm": t, "limit_state": state, "cases": subset,
                "n": len(some), "of": len(group),
                "fem_uncertain": sum(str(r.get("uncertain")) == "True" for r in some),
                "median_fem_over_yielding": statistics.median(y) if y else math.nan,
                "median_fem_over_first_touch": statistics.median(f) if f else math.nan,
                "yielding_within_20": _share(y, 0.20), "first_touch_within_20": _share(f, 0.20),
                "yielding_within_35": _share(y, 0.35), "first_touch_within_35": _share(f, 0.35),
            })
    return out


def main(argv=None) -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--out", type=Path, default=OUT)
    args = p.parse_args(argv)
    rows = comparison(args.out)
    write_csv(rows, args.out / "fem_comparison.csv")
    stats = statistics_rows(rows)
    write_csv(stats, args.out / "fem_statistics.csv")
    for s in stats:
        print(f"{s['rim_thickness_mm']:5g} mm {s['limit_state']:11s} {s['cases']:14s} "
              f"n {s['n']:2d}/{s['of']}: median FE/yielding {s['median_fem_over_yielding']:.2f},"
              f" FE/first touch {s['median_fem_over_first_touch']:.2f}; within 20 %: "
              f"yielding {s['yielding_within_20']:.0%}, first touch "
              f"{s['first_touch_within_20']:.0%}")


if __name__ == "__main__":
    main()
