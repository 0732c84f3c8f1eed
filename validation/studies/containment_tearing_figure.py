"""The loss of containment with rims that tear, at a glance: per containment validation with
tearing (rim thickness, crushing), the FE critical SA against the rigid model's with the law
through tearing and against the first touch, the simplest predictor, on log axes with the
±20 % band about equality. Read from ``docs/results/containment_tearing.csv``
(:mod:`validation.studies.containment_tearing`, which draws it after writing the CSV).

Run: ``python -m validation.studies.containment_tearing_figure [--csv ...] [--png ...]``;
writes ``docs/images/containment_tearing.png``.
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

import matplotlib
import matplotlib.ticker

matplotlib.use("Agg")
import matplotlib.pyplot as plt

from validation.report.write import save_figure

from . import DOCS, RESULTS, read_csv
from .rim_design_fem import _share

PNG = DOCS / "images" / "containment_tearing.png"
#: The predictors set against the FE answer: column, label, marker, colour.
PREDICTORS = (("yielding_sa_g", "rigid model, law through tearing", "o", "#7a1f5c"),
              ("first_touch_sa_g", "first touch of a rim (rigid rims)", "x", "#777777"))
BAND = 0.2  # the ±20 % band drawn about equality [-]
TICKS = (0.1, 0.15, 0.2, 0.3, 0.5, 0.7, 1.0, 1.5, 2.0, 3.0)  # [g]


def panels(rows: list[dict]) -> dict:
    """The containment rows by validation, ``(thickness [mm], crushing J_c or "")``, in
    order of thickness, uncrushed first."""
    groups: dict = {}
    for r in rows:
        if r["limit_state"] == "containment" and r["fem_sa_g"] and r["yielding_sa_g"]:
            groups.setdefault((float(r["rim_thickness_mm"]), r["crush_jacobian"]), []).append(r)
    return dict(sorted(groups.items(), key=lambda g: (g[0][0], g[0][1] != "")))


def _within(rows: list[dict], column: str) -> int:
    """How many of ``rows`` have FE/``column`` within ±:data:`BAND`, counted as the
    statistics count them (:func:`validation.studies.rim_design_fem._share`)."""
    ratios = [float(r["fem_sa_g"]) / float(r[column]) for r in rows if r[column]]
    return round(_share(ratios, BAND) * len(ratios)) if ratios else 0


def draw(csv_path: Path = RESULTS / "containment_tearing.csv", png: Path = PNG) -> Path:
    """Draw one panel per validation of ``csv_path`` into ``png``; returns ``png``."""
    groups = panels(read_csv(csv_path))
    if not groups:
        raise SystemExit(f"{csv_path}: no containment case with both answers")
    columns = min(3, len(groups))
    fig, axes = plt.subplots(math.ceil(len(groups) / columns), columns, squeeze=False,
                             figsize=(4.2 * columns, 4.0 * math.ceil(len(groups) / columns)))
    values = [float(r[c]) for rows in groups.values() for r in rows
              for c in ("fem_sa_g", *(p[0] for p in PREDICTORS)) if r[c]]
    low, high = min(values) / 1.15, max(values) * 1.15
    line = [low, high]
    for ax, ((thickness, crush), rows) in zip(axes.flat, groups.items(), strict=False):
        ax.fill_between(line, [v * (1 - BAND) for v in line], [v * (1 + BAND) for v in line],
                        color="#e8e8e8", label="±20 %")
        ax.plot(line, line, color="black", linewidth=0.8)
        for column, label, marker, colour in PREDICTORS:
            some = [r for r in rows if r[column]]
            ax.scatter([float(r[column]) for r in some], [float(r["fem_sa_g"]) for r in some],
                       marker=marker, s=22, color=colour,
                       facecolors="none" if marker == "o" else colour,
                       label=f"{label}: {_within(some, column)} within 20 %")
        finished = all(r["run_finished"] == "True" for r in rows)
        state = "" if finished else " (run under way)"
        crushed = f", crushing J_c {float(crush):g}" if crush != "" else ""
        ax.set_title(f"{thickness:g} mm rims{crushed}: {len(rows)} cases{state}", fontsize=9)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlim(low, high)
        ax.set_ylim(low, high)
        for axis in (ax.xaxis, ax.yaxis):
            axis.set_major_locator(matplotlib.ticker.FixedLocator(TICKS))
            axis.set_major_formatter(matplotlib.ticker.FormatStrFormatter("%g"))
            axis.set_minor_formatter(matplotlib.ticker.NullFormatter())
        ax.set_xlabel("predicted critical SA [g]")
        ax.set_ylabel("FE critical SA, loss of containment [g]")
        ax.legend(fontsize=7, loc="upper left")
    for ax in list(axes.flat)[len(groups):]:
        ax.set_visible(False)
    fig.tight_layout()
    png.parent.mkdir(parents=True, exist_ok=True)
    return save_figure(fig, png)


def main(argv=None) -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--csv", type=Path, default=RESULTS / "containment_tearing.csv")
    p.add_argument("--png", type=Path, default=PNG)
    args = p.parse_args(argv)
    print(draw(args.csv, args.png))


if __name__ == "__main__":
    main()
