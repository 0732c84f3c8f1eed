"""The rim torn off in a static push: the force through the tear, from its first element to
the rim's separation (issue #31 item 5; docs/theory/finite-elements.md, Eqs. F66–F68, F70): the
rim push (:func:`fem.rim_pushover`, finite deformation) with ``fracture=`` and
``erosion_steps=``, the torn elements let go over N accepted increments of at most 0.25 mm,
until the force is below 2 % of its peak or Newton stops. On the 40 mm rim: four meshes with
the median criterion, the three criteria and N = 1 and 10 on the default mesh; on the 80 mm
rim the median criterion on the coarse and default meshes. Writes
``docs/results/rim_tearing_push.csv`` (a row per push), ``rim_tearing_curves.csv`` (the
force–displacement curves, with the rim's inner top corner: how far it has moved out and
its height above the root) and ``docs/images/rim_tearing_push.png``.

Run (about 4 minutes of CPU)::

    python -m validation.studies.rim_tearing_push
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from fem.pushover import rim_pushover
from rigid import DFPBearing
from rigid.collapse.comparison import write_csv
from rigid.rims import TEARING_PUSH

from . import IMAGES, RESULTS
from .rim_fracture_push import MESHES

#: The largest push increment [m] and N, as the law through tearing's push (``fem.rim_law``):
#: N increments are how far a torn element lets go.
INCREMENT, N = TEARING_PUSH
#: (rim thickness [m], mesh, criterion, N, reach [m]) of each push.
PUSHES = (
    *((0.04, mesh, "median", N, 0.045) for mesh in MESHES),
    (0.04, "default", "steep", N, 0.045),
    (0.04, "default", "mild", N, 0.045),
    (0.04, "default", "median", 1, 0.045),
    (0.08, "coarse", "median", N, 0.04),
    (0.08, "default", "median", N, 0.04),
)


def push(thickness: float, mesh: str, fracture: str, erosion_steps: int, reach: float):
    """One push with erosion (its :class:`fem.pushover.Pushover`) and its row."""
    t0 = time.process_time()
    p = rim_pushover(DFPBearing(rim_thickness=thickness), fracture=fracture,
                     erosion_steps=erosion_steps, displacement=reach,
                     steps=round(reach / INCREMENT), mesh_options=MESHES[mesh],
                     stop_short=True)
    torn = p.fracture_displacement is not None
    row = {
        "rim_thickness_mm": round(thickness * 1e3),
        "mesh": mesh,
        "dofs": p.dofs,
        "fracture_set": fracture,
        "erosion_steps": erosion_steps,
        "peak_force_mn": p.force.max() / 1e6,
        "peak_displacement_mm": p.displacement[p.force.argmax()] * 1e3,
        "tear_displacement_mm": p.fracture_displacement * 1e3 if torn else "",
        "tear_force_mn": p.fracture_force / 1e6 if torn else "",
        "separation_displacement_mm": p.displacement[-1] * 1e3 if p.separated else "",
        "pushed_to_mm": p.displacement[-1] * 1e3,
        "end": ("separated" if p.separated
                else "reach" if p.displacement[-1] >= reach * (1 - 1e-9) else "newton"),
        "torn_elements": p.torn_elements,
        "largest_damage": float(p.damage.max()),
        "cpu_s": round(time.process_time() - t0, 1),
    }
    return p, row


def plot(curves: list[dict], path: Path) -> None:
    """Force against push displacement of the 40 mm rim: the meshes (left), the criteria and
    N (right)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(10, 4), sharey=True)
    for c in curves:
        if c["rim_thickness_mm"] != 40:
            continue
        if c["fracture_set"] == "median" and c["erosion_steps"] == N:
            axes[0].plot(c["d"] * 1e3, c["f"] / 1e6, label=f"{c['mesh']} ({c['dofs']} dofs)")
        if c["mesh"] == "default":
            axes[1].plot(c["d"] * 1e3, c["f"] / 1e6,
                         label=f"{c['fracture_set']}, N = {c['erosion_steps']}")
    axes[0].set_title(f"40 mm rim, median criterion, N = {N}: meshes")
    axes[1].set_title("40 mm rim, default mesh: criteria and N")
    for ax in axes:
        ax.set_xlabel("push displacement of the face [mm]")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    axes[0].set_ylabel("force on the face [MN]")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=str(RESULTS))
    ap.add_argument("--images", default=str(IMAGES))
    args = ap.parse_args()
    rows, curves, points = [], [], []
    for spec in PUSHES:
        p, row = push(*spec)
        rows.append(row)
        curves.append({**row, "d": p.displacement, "f": p.force})
        bearing = DFPBearing(rim_thickness=spec[0])
        root = bearing.dish_depth(bearing.rim_radius)
        points += [{"rim_thickness_mm": row["rim_thickness_mm"], "mesh": row["mesh"],
                    "fracture_set": row["fracture_set"], "erosion_steps": row["erosion_steps"],
                    "displacement_mm": d * 1e3, "force_mn": f / 1e6, "damage": D,
                    "corner_outward_mm": (k[0] - bearing.rim_radius) * 1e3,
                    "corner_height_mm": (k[1] - root) * 1e3}
                   for d, f, D, k in zip(p.displacement, p.force, p.damage, p.corner,
                                         strict=True)]
        print(row, flush=True)
    out, images = Path(args.out), Path(args.images)
    out.mkdir(parents=True, exist_ok=True)
    images.mkdir(parents=True, exist_ok=True)
    write_csv(rows, out / "rim_tearing_push.csv")
    write_csv(points, out / "rim_tearing_curves.csv")
    plot(curves, images / "rim_tearing_push.png")
    print(f"wrote {out / 'rim_tearing_push.csv'}, rim_tearing_curves.csv and "
          f"{images / 'rim_tearing_push.png'}")


if __name__ == "__main__":
    main()
