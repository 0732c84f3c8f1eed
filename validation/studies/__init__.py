"""Studies that produce the documented results: each module writes what ``docs/`` shows (CSV
tables in ``docs/results/``, figures in ``docs/images/``) and is run as
``python -m validation.studies.<name> --help``. Speed measurements are in ``benchmarks/``."""

from pathlib import Path

#: Where the studies write by default: the repository's documentation.
DOCS = Path(__file__).resolve().parents[2] / "docs"
RESULTS = DOCS / "results"
IMAGES = DOCS / "images"
