"""Studies that produce the documented results: each module writes what ``docs/`` shows (CSV
tables in ``docs/results/``, figures in ``docs/images/``) and is run from a checkout of the
repository as ``python -m validation.studies.<name> --help``. Speed measurements are in
``benchmarks/``.

The studies are not part of the installed library (``pyproject.toml`` leaves
``validation.studies`` out of the wheel); what they need beyond the library is the ``studies``
extra (``pip install -e ".[studies]"``). Every path they read or write by default comes from
here.
"""

import csv
import math
from pathlib import Path

#: The repository's root (the checkout the studies run from).
ROOT = Path(__file__).resolve().parents[2]
#: Where the studies write by default: the repository's documentation.
DOCS = ROOT / "docs"
RESULTS = DOCS / "results"
IMAGES = DOCS / "images"
#: The FE validation runs' folder (its store, comparison table and report).
FEM_VALIDATION = DOCS / "fem-validation"


def read_csv(path: Path) -> list[dict]:
    """The rows of a CSV table the studies wrote, as dicts of text."""
    with open(path, newline="") as fh:
        return list(csv.DictReader(fh))


def number(text) -> float:
    """A table's cell as a float; NaN for an empty or missing one."""
    try:
        return float(text)
    except (TypeError, ValueError):
        return math.nan


def validation_table(folder: Path) -> tuple[str, bool] | None:
    """The table of a ``dfp validate`` folder to read its searches from: ``("fem_comparison.csv",
    True)`` once the run has finished, ``("status.csv", False)`` while it is under way (written
    by ``validation.studies.fem_validation_status``; keep its rows whose ``finished`` is
    "True"), None with neither."""
    for name, finished in (("fem_comparison.csv", True), ("status.csv", False)):
        if (folder / name).exists():
            return name, finished
    return None
