"""Figures of the rim design space from its CSVs (``validation.studies.rim_design``): the
failure-mode map and the design charts.

Run: ``python -m validation.studies.rim_design_figures [--out docs/rim-design]``.
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

import matplotlib
import matplotlib.ticker

matplotlib.use("Agg")
import matplotlib.pyplot as plt

from . import read_csv
from .rim_design import OUT
from .rim_design_case import MODES

COLOURS = {"hinge": "#f0a830", "rupture": "#d2452d", "containment": "#7a1f5c",
           "uplift": "#3a7bbf", "none": "#c8c8c8"}
LABELS = {"hinge": "rim hinges", "rupture": "rim ruptures",
          "containment": "rim lets the slider through", "uplift": "uplift over the rim",
          "none": "no failure up to 3 g"}
CHARTS = {"yielding_hinge": ("yielding rims, hinge", "#f0a830"),
          "yielding_rupture": ("yielding rims, rupture", "#d2452d"),
          "yielding_containment": ("yielding rims, containment", "#7a1f5c"),
          "rigid_rims": ("rigid rims (the paper's model)", "#3a7bbf"),
          "first_touch": ("first touch of a rim", "#777777")}


def draw_map(out: Path) -> Path:
    """``failure_mode_map.png``: per pressure, the share of records by governing mode against
    rim thickness (stacked bars)."""
    rows = read_csv(out / "failure_mode_map.csv")
    pressures = sorted({float(r["pressure_mpa"]) for r in rows}, reverse=True)
    fig, axes = plt.subplots(1, len(pressures), figsize=(5.2 * len(pressures), 4.0),
                             sharey=True, squeeze=False)
    for ax, p in zip(axes[0], pressures, strict=True):
        some = sorted((r for r in rows if float(r["pressure_mpa"]) == p),
                      key=lambda r: float(r["rim_thickness_mm"]))
        labels = [f"{float(r['rim_thickness_mm']):g}" for r in some]
        bottom = [0.0] * len(some)
        for mode in MODES:
            share = [100 * float(r[f"share_{mode}"]) for r in some]
            ax.bar(labels, share, bottom=bottom, color=COLOURS[mode], label=LABELS[mode],
                   edgecolor="white", linewidth=0.5)
            bottom = [b + s for b, s in zip(bottom, share, strict=True)]
        ax.set_title(f"{p:g} MPa ({some[0]['records']} records)")
        ax.set_xlabel("rim thickness [mm]")
    axes[0][0].set_ylabel("records [%] by what fails first")
    axes[0][-1].legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), frameon=False)
    height = float(rows[0].get("rim_height_mm") or 35.0)
    fig.suptitle(f"What fails first as SA(4.5 s) rises: yielding rims {height:g} mm high")
    fig.tight_layout()
    path = out / "failure_mode_map.png"
    fig.savefig(path, dpi=130)
    plt.close(fig)
    return path


def draw_charts(out: Path) -> Path:
    """``design_charts.png``: per pressure, median critical SA and its 16–84 % band against
    rim thickness, per limit state with yielding rims, with rigid rims and the first touch."""
    rows = read_csv(out / "design_charts.csv")
    pressures = sorted({float(r["pressure_mpa"]) for r in rows}, reverse=True)
    fig, axes = plt.subplots(1, len(pressures), figsize=(5.8 * len(pressures), 4.4),
                             sharey=True, squeeze=False)
    top = 3.0
    highest = max((float(r["p84_g"]) for r in rows if math.isfinite(float(r["p84_g"]))),
                  default=top)
    for ax, p in zip(axes[0], pressures, strict=True):
        for model, (label, colour) in CHARTS.items():
            some = sorted((r for r in rows if float(r["pressure_mpa"]) == p
                           and r["model"] == model), key=lambda r: float(r["rim_thickness_mm"]))
            t = [float(r["rim_thickness_mm"]) for r in some]

            def col(name, some=some):  # above the top: drawn at it; unknown (NaN): a gap
                return [top if float(r[name]) == math.inf else float(r[name]) for r in some]

            style = "--" if model in ("rigid_rims", "first_touch") else "-"
            ax.plot(t, col("median_g"), style, marker="o", ms=3, color=colour, label=label)
            if model.startswith("yielding") or model == "rigid_rims":
                ax.fill_between(t, col("p16_g"), col("p84_g"), color=colour, alpha=0.12)
        ax.set_xscale("log")
        ax.set_xticks([20, 40, 80, 160, 320], labels=["20", "40", "80", "160", "320"])
        ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
        ax.set_ylim(0, 1.1 * highest)
        ax.set_title(f"{p:g} MPa")
        ax.set_xlabel("rim thickness [mm]")
        ax.grid(alpha=0.3)
    axes[0][0].set_ylabel("critical SA(4.5 s) [g]: median, 16–84 % band")
    axes[0][-1].legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), frameon=False)
    fig.suptitle("Rim design chart, 28 near-field pulse components (a gap: half the records "
                 "or more numerical)")
    fig.tight_layout()
    path = out / "design_charts.png"
    fig.savefig(path, dpi=130)
    plt.close(fig)
    return path


def draw(out: Path = OUT) -> list[Path]:
    """Both figures from the CSVs in ``out``."""
    return [draw_map(out), draw_charts(out)]


def main(argv=None) -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--out", type=Path, default=OUT)
    for path in draw(p.parse_args(argv).out):
        print(path)


if __name__ == "__main__":
    main()
