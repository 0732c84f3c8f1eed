"""How far past the rupture each model keeps the slider: per record and pressure, the critical
SA under the rupture and under containment from the FE model and from the rigid model with
yielding rims, the margins between the two limit states, and the median of each per pressure.

It answers why the containment gap between the models is wider for the light bearing
(docs/fem_validation.md, "Results: the containment limit state"): both models agree at the
rupture, so the FE/rigid ratio under containment is set by the two margins past it.

Run: ``python -m validation.studies.containment_margin [--comparison CSV] [--out CSV]``; reads
a validation run's ``fem_comparison.csv`` (or the status script's ``status.csv``, whose
unfinished searches are skipped) with the rupture and containment limit states, writes the
table (default ``docs/results/containment_margin.csv``) and prints the medians.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import pandas as pd

from . import FEM_VALIDATION, RESULTS


def margins(comparison: pd.DataFrame) -> pd.DataFrame:
    """One row per record and pressure with both limit states answered by both models.

    Parameters
    ----------
    comparison : DataFrame
        Rows of ``fem_comparison.csv``: ``record``, ``pressure_mpa``, ``limit_state``,
        ``fem_sa_g`` and ``yielding_sa_g`` [g]; an optional ``finished`` column selects rows.

    Returns
    -------
    DataFrame
        ``fem_rupture_g``, ``fem_containment_g``, ``yielding_rupture_g``,
        ``yielding_containment_g`` [g]; ``fem_margin_g`` and ``yielding_margin_g``
        (containment − rupture) [g]; ``rupture_ratio`` and ``containment_ratio`` (FE / yielding
        rims) [-].
    """
    rows = comparison
    if "finished" in rows:
        rows = rows[rows["finished"].astype(bool)]
    rows = rows[rows["limit_state"].isin(("rupture", "containment"))]
    wide = rows.pivot_table(index=["record", "pressure_mpa"], columns="limit_state",
                            values=["fem_sa_g", "yielding_sa_g"])
    out = pd.DataFrame({
        "fem_rupture_g": wide["fem_sa_g", "rupture"],
        "fem_containment_g": wide["fem_sa_g", "containment"],
        "yielding_rupture_g": wide["yielding_sa_g", "rupture"],
        "yielding_containment_g": wide["yielding_sa_g", "containment"],
    }).dropna()
    out["fem_margin_g"] = out.fem_containment_g - out.fem_rupture_g
    out["yielding_margin_g"] = out.yielding_containment_g - out.yielding_rupture_g
    out["rupture_ratio"] = out.fem_rupture_g / out.yielding_rupture_g
    out["containment_ratio"] = out.fem_containment_g / out.yielding_containment_g
    return out.round(4).reset_index()


def summary(table: pd.DataFrame) -> pd.DataFrame:
    """Medians per pressure of :func:`margins`' columns, the number of cases, and the median
    ratio of the rigid model's margin to the FE model's [-]."""
    by = table.groupby("pressure_mpa")
    out = by[["fem_margin_g", "yielding_margin_g", "rupture_ratio",
              "containment_ratio"]].median()
    ratio = table.yielding_margin_g / table.fem_margin_g.where(table.fem_margin_g > 0)
    out["margin_ratio"] = ratio.groupby(table.pressure_mpa).median()
    out["cases"] = by.size()
    return out.round(3)


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--comparison", type=Path,
                   default=FEM_VALIDATION / "fem_comparison.csv")
    p.add_argument("--out", type=Path, default=RESULTS / "containment_margin.csv")
    args = p.parse_args()
    table = margins(pd.read_csv(args.comparison))
    if table.empty:
        raise SystemExit(f"{args.comparison}: no case with both rupture and containment")
    args.out.parent.mkdir(parents=True, exist_ok=True)
    table.to_csv(args.out, index=False)
    print(summary(table).to_string())
    print(args.out)


if __name__ == "__main__":
    main()
