"""The 40 mm validation with the rims as rings against the plane-strain one (issue #30 item
4; docs/fem_validation.md, "The rims as rings").

Reads the FE comparisons of the ring runs (``dfp validate --rim-model ring --limit-state S``,
one folder per limit state under ``docs/fem-validation-ring/``), of the plane-strain run
(``docs/fem-validation/fem_comparison.csv``) and the first SA at which the rigid-rim model
touches a rim (``docs/results/hinge_vs_first_impact.csv``, the trivial predictor), and writes
``docs/fem-validation-ring/ring_vs_plane_strain.csv`` (one row per record × pressure × limit
state) and ``ring_statistics.csv`` (per limit state: medians and shares within ±20 %).

Run: ``python -m validation.studies.ring_validation``.
"""

from __future__ import annotations

import argparse
import math
import statistics
from pathlib import Path

from rigid.collapse.comparison import write_csv

from . import DOCS, RESULTS, number, read_csv

RING = DOCS / "fem-validation-ring"
PLANE = DOCS / "fem-validation" / "fem_comparison.csv"
FIRST_TOUCH = RESULTS / "hinge_vs_first_impact.csv"


def rows(ring_folder: Path = RING) -> list[dict]:
    """One row per record, pressure and limit state run with the ring."""
    plane = {(r["record"], r["pressure_mpa"], r["limit_state"]): r for r in read_csv(PLANE)}
    touch = {(r["record"], r["pressure_mpa"]): number(r["first_impact_sa_g"])
             for r in read_csv(FIRST_TOUCH)}
    out = []
    for path in sorted(ring_folder.glob("*/fem_comparison.csv")):
        for r in read_csv(path):
            key = (r["record"], r["pressure_mpa"], r["limit_state"])
            p = plane.get(key, {})
            fe, y = number(r["fem_sa_g"]), number(r["yielding_sa_g"])
            first = touch.get(key[:2], math.nan)
            out.append({
                "record": r["record"], "pressure_mpa": r["pressure_mpa"],
                "limit_state": r["limit_state"],
                "first_touch_sa_g": first,
                "fem_ring_sa_g": fe, "fem_plane_sa_g": number(p.get("fem_sa_g")),
                "yielding_ring_sa_g": y, "yielding_plane_sa_g": number(p.get("yielding_sa_g")),
                "rigid_sa_g": number(r["rigid_sa_g"]),
                "fem_ring_mode": r["fem_failure_mode"], "fem_plane_mode": p.get("fem_failure_mode"),
                "fem_ring_uncertain": r["uncertain"] == "True",
                "fem_over_yielding_ring": fe / y if y > 0 else math.nan,
                "fem_over_first_touch": fe / first if first > 0 else math.nan,
            })
    return out


def _share(ratios, band) -> str:
    ok = [x for x in ratios if math.isfinite(x)]
    return f"{sum(abs(x - 1) <= band + 1e-12 for x in ok)}/{len(ok)}"


def statistics_rows(table: list[dict]) -> list[dict]:
    """Per limit state and pressure: medians of the four critical SAs, the FE ring/plane
    ratio and the two predictors' ratios with their shares within ±20 % and ±35 %."""
    out = []
    keys = sorted({(r["limit_state"], r["pressure_mpa"]) for r in table})
    for state, mpa in keys:
        sel = [r for r in table if r["limit_state"] == state and r["pressure_mpa"] == mpa]

        def med(name, sel=sel):
            vals = [r[name] for r in sel if math.isfinite(r[name])]
            return statistics.median(vals) if vals else math.nan

        moved = [r["fem_ring_sa_g"] / r["fem_plane_sa_g"] for r in sel
                 if r["fem_plane_sa_g"] > 0 and math.isfinite(r["fem_ring_sa_g"])]
        out.append({
            "limit_state": state, "pressure_mpa": mpa, "cases": len(sel),
            "uncertain": sum(r["fem_ring_uncertain"] for r in sel),
            "median_fem_ring_g": med("fem_ring_sa_g"), "median_fem_plane_g": med("fem_plane_sa_g"),
            "median_yielding_ring_g": med("yielding_ring_sa_g"),
            "median_yielding_plane_g": med("yielding_plane_sa_g"),
            "median_first_touch_g": med("first_touch_sa_g"),
            "fem_ring_equal_plane": sum(abs(x - 1) < 1e-9 for x in moved),
            "fem_ring_below_plane": sum(x < 1 - 1e-9 for x in moved),
            "fem_ring_above_plane": sum(x > 1 + 1e-9 for x in moved),
            "median_fem_over_yielding": med("fem_over_yielding_ring"),
            "yielding_within_20": _share([r["fem_over_yielding_ring"] for r in sel], 0.2),
            "yielding_within_35": _share([r["fem_over_yielding_ring"] for r in sel], 0.35),
            "median_fem_over_first_touch": med("fem_over_first_touch"),
            "first_touch_within_20": _share([r["fem_over_first_touch"] for r in sel], 0.2),
            "first_touch_within_35": _share([r["fem_over_first_touch"] for r in sel], 0.35),
        })
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--ring", default=str(RING), help="folder of the ring runs")
    args = ap.parse_args()
    folder = Path(args.ring)
    table = rows(folder)
    stats = statistics_rows(table)
    write_csv(table, folder / "ring_vs_plane_strain.csv")
    write_csv(stats, folder / "ring_statistics.csv")
    for s in stats:
        print(", ".join(f"{k} {v:.3g}" if isinstance(v, float) else f"{k} {v}"
                        for k, v in s.items()))


if __name__ == "__main__":
    main()
