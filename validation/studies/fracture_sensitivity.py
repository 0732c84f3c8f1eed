"""The containment SA's sensitivity to the fracture constants (issue #31, item 4): the FE and
the rigid model's critical SA at the loss of containment with the steep, median and mild
sets of the ductile criterion (docs/theory/finite-elements.md, "Rim fracture"), on the first
8 records of the set at 60 MPa.

The steep and mild runs are containment validations of their own, made (or resumed) by this
study unless ``--tables-only``::

    dfp validate --records 8 --pressure 60 --limit-state containment --fem-fracture SET \\
        --fem-edge-radius 20 --out docs/fem-validation-fracture-sensitivity/SET

(``--rim-fracture`` follows ``--fem-fracture``: the rigid model's law through tearing is
pushed with the same set). The median runs are those of the full validation
(``docs/fem-validation-fracture``, its ``fem_comparison.csv``, or while it runs the finished
searches of its ``status.csv``). Writes ``docs/results/containment_fracture_sensitivity.csv``:
per record, each set's FE and rigid SA [g] and their ratios to the median's, and three last
rows with the median, smallest and largest of each ratio over the records.

With ``--rim-thickness 80`` the same for the 80 mm rims, whose law through tearing is the
slider's push (``--rim-thickness 80 --rim-punch slider`` added to the command above): the
folders ``docs/fem-validation-fracture-sensitivity-rims80/SET``, the median runs of
``docs/fem-validation-fracture-rims80``, the table ``containment_fracture_sensitivity_rims80.csv``.
With ``--rim-thickness 120``, ``160`` or ``240`` the same for the design space's rims, with
crushing as their containment validations (``validation.studies.containment_tearing.CRUSHED``):
the folders ``docs/rim-design/fem-T-containment-sensitivity/SET``, the table
``containment_fracture_sensitivity_rimsT.csv``.

Run: ``python -m validation.studies.fracture_sensitivity [--rim-thickness T] [--workers 2]
[--tables-only]``.
"""

from __future__ import annotations

import argparse
import statistics
from pathlib import Path

from rigid.collapse.comparison import write_csv

from . import DOCS, RESULTS, read_csv, validation_table
from .containment_tearing import CRUSHED, crushed_rims
from .rim_design import OUT as DESIGN_SPACE

SETS = ("steep", "median", "mild")
RECORDS = 8  # the first components of the set, in its order
PRESSURE = 60  # [MPa]
#: rim thickness [mm] → (the steep and mild sets' folder, the median set's validation, the
#: arguments of ``dfp validate`` that set the rims, the table's name)
RIMS = {
    40: (DOCS / "fem-validation-fracture-sensitivity", DOCS / "fem-validation-fracture", [],
         "containment_fracture_sensitivity.csv"),
    80: (DOCS / "fem-validation-fracture-sensitivity-rims80",
         DOCS / "fem-validation-fracture-rims80",
         ["--rim-thickness", "80", "--rim-punch", "slider"],
         "containment_fracture_sensitivity_rims80.csv"),
    # the design space's thicknesses, with crushing as their containment validations
    **{t: (DESIGN_SPACE / f"fem-{t}-containment-sensitivity", CRUSHED[t], crushed_rims(t),
           f"containment_fracture_sensitivity_rims{t}.csv") for t in (120, 160, 240)},
}


def validate_args(fracture: str, rims: list[str] = ()) -> list[str]:
    """``dfp validate`` arguments of one set's runs besides ``--out`` and ``--workers``
    (``rims``: those that set the rims, :data:`RIMS`); the committed stores' registry uses
    them too."""
    return ["--records", str(RECORDS), "--pressure", str(PRESSURE), "--limit-state",
            "containment", "--fem-fracture", fracture, "--fem-edge-radius", "20", *rims]


def command(fracture: str, out: Path, workers: int, rims: list[str] = ()) -> list[str]:
    """``dfp validate`` command line of one set's runs (``rims``: those that set the rims)."""
    return ["validate", *validate_args(fracture, rims), "--workers", str(workers),
            "--no-progress", "--out", str(out)]


def _finished(folder: Path) -> dict:
    """Record → its finished containment row at the study's pressure, from the folder's
    ``fem_comparison.csv`` or, of a run under way, its ``status.csv``."""
    name, finished = validation_table(folder)
    return {r["record"]: r for r in read_csv(folder / name)
            if (finished or r["finished"] == "True") and r["limit_state"] == "containment"
            and float(r["pressure_mpa"]) == PRESSURE}


def _sa(row: dict | None, column: str) -> float | None:
    return float(row[column]) if row is not None and row[column] else None


def table(folders: dict) -> list[dict]:
    """Rows of the study's CSV from the three sets' folders (module docstring)."""
    found = {s: _finished(f) for s, f in folders.items()}
    records = list(found["steep"])
    rows, ratios = [], {}
    for record in records:
        row = {"record": record, "pressure_mpa": PRESSURE}
        for model, column in (("fem", "fem_sa_g"), ("rigid", "yielding_sa_g")):
            median = _sa(found["median"].get(record), column)
            for s in SETS:
                sa = _sa(found[s].get(record), column)
                row[f"{model}_{s}_sa_g"] = sa
                if s != "median":
                    ratio = sa / median if sa and median else None
                    row[f"{model}_{s}_over_median"] = ratio
                    if ratio is not None:
                        ratios.setdefault((model, s), []).append(ratio)
        rows.append(row)
    for name, stat in (("median", statistics.median), ("min", min), ("max", max)):
        rows.append({"record": f"{name} over the records", **{
            f"{model}_{s}_over_median": stat(r) for (model, s), r in ratios.items()}})
    return rows


def main(argv=None) -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--workers", type=int, default=2)
    p.add_argument("--tables-only", action="store_true",
                   help="only write the table from the folders as they are")
    p.add_argument("--rim-thickness", type=int, choices=sorted(RIMS), default=40,
                   help="[mm]")
    p.add_argument("--out", type=Path, default=RESULTS)
    args = p.parse_args(argv)
    out, median, rims, name = RIMS[args.rim_thickness]
    folders = {"steep": out / "steep", "median": median, "mild": out / "mild"}
    if not args.tables_only:
        from validation import cli

        for s in ("steep", "mild"):
            cli.main(command(s, folders[s], args.workers, rims))
    rows = table(folders)
    write_csv(rows, args.out / name)
    for r in rows[-3:]:
        print(r)


if __name__ == "__main__":
    main()
