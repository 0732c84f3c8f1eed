"""Figures of the rim-as-a-ring study (:mod:`validation.studies.rim3d`), from its CSVs:
``docs/rim-3d/pushes.png`` — the baseline rim's force against displacement under every load,
the plane-strain strip at today's depth πb/4 beside them, CalculiX's pushes as markers — and
``docs/rim-3d/effective_depth.png`` — d_eff at the hinge and at the limit load against the rim
thickness, per rim height and slider, with πb/4.

Run (seconds)::

    python -m validation.studies.rim3d_figures
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

from . import read_csv
from .rim3d import FOLDER


def _float(x: str) -> float:
    return float(x) if x not in ("", "nan") else math.nan


def pushes_figure(curves: list[dict], out: Path) -> None:
    """Force–displacement of the baseline rim (40 × 35 mm, b = 0.4 m, default mesh)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    base = [c for c in curves if c["rim_thickness_mm"] == "40" and c["rim_height_mm"] == "35"
            and _float(c["slider_diameter_m"]) == 0.4
            and (c["mesh"] == "default" or (c["mesh"] == "coarse" and c["load"] == "cylinder"))]
    series: dict[tuple, list] = {}
    for c in base:
        load = c["load"] + (", coarse mesh" if c["mesh"] == "coarse" else "")
        series.setdefault((c["model"], load), []).append(
            (_float(c["displacement_mm"]), _float(c["force_mn"])))
    fig, ax = plt.subplots(figsize=(8, 5), constrained_layout=True)
    styles = {"cylinder": ("k", "-", 2.2), "cylinder, coarse mesh": ("k", "--", 1.4)}
    for (model, load), pts in sorted(series.items()):
        d, f = zip(*pts, strict=True)
        if model.startswith("ccx"):
            ax.plot(d[::4], f[::4], "x" if "nlgeom" in model else "+", ms=6,
                    label=f"CalculiX{' NLGEOM' if 'nlgeom' in model else ''}: {load}")
            continue
        if model == "2d":
            ax.plot(d, f, color="tab:red", lw=2.2, ls="--",
                    label="plane strain × πb/4 (today's model)")
            continue
        color, ls, lw = styles.get(load, (None, "-" if load.startswith("punch") else ":", 1.4))
        ax.plot(d, f, color=color, ls=ls, lw=lw, label=f"3-D ring: {load}")
    ax.set_xlabel("push δ [mm]")
    ax.set_ylabel("rim force [MN]")
    ax.set_title("Baseline rim (40 × 35 mm, b = 0.4 m): 3-D ring against the plane-strain rim")
    ax.set_xlim(left=0)
    ax.set_ylim(bottom=0)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, ncol=2)
    fig.savefig(out, dpi=130)
    plt.close(fig)


def depth_figure(table: list[dict], out: Path) -> None:
    """d_eff at the hinge and the limit against rim thickness, one colour per rim height and
    slider: the slider (cylinder) on the default mesh (solid) and on the coarse one (thin,
    dotted), the πb/4 punch on the default mesh (dashed)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    series = {("cylinder", "default"): dict(marker="o", ls="-", lw=1.8, ms=5),
              ("cylinder", "coarse"): dict(marker=".", ls=":", lw=1.0, ms=4),
              ("punch", "default"): dict(marker="s", ls="--", lw=1.0, ms=4)}
    names = {("cylinder", "default"): "slider (cylinder)",
             ("cylinder", "coarse"): "slider, coarse mesh",
             ("punch", "default"): "punch πb/4"}
    rims = sorted({(r["rim_height_mm"], r["slider_diameter_m"]) for r in table},
                  key=lambda hb: (_float(hb[1]), _float(hb[0])))
    colour = {hb: f"C{i}" for i, hb in enumerate(rims)}
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.6), sharey=True, constrained_layout=True)
    for ax, point, title in ((axes[0], "hinge", "at the hinge"),
                             (axes[1], "limit", "at the limit load")):
        groups: dict[tuple, list] = {}
        for r in table:
            load = r["load"].split()[0]
            if r["model"] != "3d" or (load, r["mesh"]) not in series:
                continue
            if load == "punch" and not r["load"].startswith("punch " + str(round(
                    math.pi * _float(r["slider_diameter_m"]) / 4 * 1e3))):
                continue
            key = (load, r["mesh"], r["rim_height_mm"], r["slider_diameter_m"])
            groups.setdefault(key, []).append(
                (_float(r["rim_thickness_mm"]), _float(r[f"d_eff_{point}_m"])))
        for (load, mesh, h, b), pts in sorted(groups.items()):
            pts.sort()
            t, d = zip(*pts, strict=True)
            ax.plot(t, d, color=colour[(h, b)], **series[(load, mesh)],
                    label=f"{names[(load, mesh)]}: h_r = {h} mm, b = {b} m")
        for b, ls in ((0.4, "--"), (0.6, ":")):
            ax.axhline(math.pi * b / 4, color="grey", ls=ls, lw=1, label=f"πb/4, b = {b} m")
        ax.set_xscale("log", base=2)
        ax.set_xlim(30, 400)
        ax.set_xticks([40, 80, 160, 320], ["40", "80", "160", "320"])
        ax.set_xlabel("rim thickness t_r [mm]")
        ax.set_title(f"d_eff {title}")
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("effective depth d_eff = F_3D / f_2D [m]")
    axes[1].legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.02, 1.0))
    fig.savefig(out, dpi=130)
    plt.close(fig)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--folder", default=str(FOLDER))
    args = ap.parse_args()
    folder = Path(args.folder)
    pushes_figure(read_csv(folder / "curves.csv"), folder / "pushes.png")
    depth_figure(read_csv(folder / "pushes.csv"), folder / "effective_depth.png")
    print(f"wrote {folder / 'pushes.png'} and {folder / 'effective_depth.png'}")


if __name__ == "__main__":
    main()
