"""Where a bent rim's inner top corner goes, in the FE model and in the rigid model's yielding
rims: why the rigid model loses containment early (docs/fe-companion.md, "Yielding rims in the
rigid model").

The rigid model turns a rim with set u_p about its root as a link of lever L (Eq. R55 of
docs/theory/rigid-body.md): its corner drops by h_r(1 − cos φ), sin φ = u_p/L, and the rim lies
flat at u_p = L. This script follows the FE model's corners instead: a Ricker pulse run to the
loss of containment with snapshots, the corner of every rim measured from the middle of its
root section (which carries the plate's own motion, Eq. F53), at the lowest amplitude that loses
containment and one grid step below; and the static push of the rim (face held vertical) to
half and to the whole rim height.

Run: ``python -m validation.studies.rim_corner_path`` (about 1.5 min of CPU); writes
``docs/results/rim_corner_path.csv`` and ``docs/images/rim_corner_path.png``.
"""

from __future__ import annotations

import argparse
import csv
from pathlib import Path

import numpy as np

from rigid import DFPBearing, G
from rigid.rims import LEVER_FRACTION

from . import IMAGES, RESULTS

#: The case: heavy bearing, symmetric pulse, Tp = 2 s; FE containment lost at 0.45 g, held at
#: 0.40 g (docs/results/yielding_rims_vs_fe.csv); the rigid model loses it at 0.35 g.
CASE = {"pressure": 60e6, "tp": 2.0, "kind": "symmetric", "amplitudes_g": (0.40, 0.45)}
SNAPSHOT_EVERY = 5  # accepted FE steps between snapshots


def corner_motion(mesh, bearing: DFPBearing, d, rim: str) -> tuple[float, float]:
    """(outward, drop) [m] of a rim's inner top corner relative to the middle of its root,
    for the mesh's displacements ``d`` (outward: away from the bearing's axis; drop: towards
    the rim's own plate)."""
    from fem.limit_states import corner_nodes, root_nodes
    from fem.output import nodal_displacement

    u = nodal_displacement(mesh, d)
    rel = u[:, corner_nodes(mesh, bearing)[rim]] - u[:, root_nodes(mesh, bearing)[rim]]
    side = 1.0 if rim.endswith("+x") else -1.0
    towards_plate = 1.0 if rim.startswith("top") else -1.0
    return float(side * rel[0]), float(towards_plate * rel[1])


def fe_corner_paths(bearing: DFPBearing, tp: float, kind: str, amplitude: float) -> tuple:
    """FE run of the study's pulse at ``amplitude`` [m/s²] to the loss of containment: its
    result and, per rim, rows (t [s], outward [m], drop [m]) of :func:`corner_motion`."""
    from fem import simulate
    from fem.geometry import COARSE_MESH
    from fem.limit_states import RIMS

    from .yielding_rims import pulse_motion

    motion = pulse_motion(tp, kind)
    res = simulate(bearing, amplitude * motion.acceleration, motion.dt,
                   mesh_options=COARSE_MESH, max_step=5e-3, impact_step=5e-4,
                   kinematics="finite", limit_state="containment",
                   snapshot_every=SNAPSHOT_EVERY)
    return res, {name: [(t, *corner_motion(res.mesh, bearing, d, name))
                        for t, d, _, _ in res.snapshots] for name in RIMS}


def push_corner(bearing: DFPBearing, displacement: float, steps: int) -> tuple[float, float]:
    """:func:`corner_motion` of the pushed rim at the end of a push to ``displacement`` [m]
    (:func:`fem.rim_pushover`, default mesh, finite deformation)."""
    from fem import rim_pushover

    push = rim_pushover(bearing, displacement=displacement, steps=steps)
    return corner_motion(push.plate.mesh, bearing, push.final_displacement, "bottom +x")


def link_corner(bearing: DFPBearing, plastic_set) -> np.ndarray:
    """Corner drop [m] of the rigid model's rim at sets ``plastic_set`` [m] (Eq. R55)."""
    lever = LEVER_FRACTION * bearing.rim_height
    sin = np.minimum(1.0, np.asarray(plastic_set) / lever)
    return bearing.rim_height * (1.0 - np.sqrt(1.0 - sin**2))


def main(argv=None) -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--csv", type=Path, default=RESULTS / "rim_corner_path.csv")
    p.add_argument("--figure", type=Path, default=IMAGES / "rim_corner_path.png")
    p.add_argument("--plot-only", action="store_true", help="redraw the figure from the CSV")
    args = p.parse_args(argv)
    bearing = DFPBearing(pressure=CASE["pressure"])
    if args.plot_only:
        with open(args.csv, newline="") as f:
            rows = [{**r, "containment_lost": r["containment_lost"] == "True"}
                    for r in csv.DictReader(f)]
        plot(bearing, rows, args.figure)
        return
    rows = []
    for amp_g in CASE["amplitudes_g"]:
        res, paths = fe_corner_paths(bearing, CASE["tp"], CASE["kind"], amp_g * G)
        lost = res.limit_states["containment"]
        print(f"FE {amp_g:.2f} g: limit states {res.limit_states}; {res.failure_detail or 'held'}")
        # the rim whose corner went furthest is the one the slider got past
        furthest = max(paths, key=lambda name: max(x for _, x, _ in paths[name]))
        for name, path in paths.items():
            a = np.array(path)
            if np.abs(a[:, 1]).max() < 1e-3:  # a rim the slider never bent
                continue
            k = int(np.argmax(a[:, 1]))
            print(f"  {name}: corner {a[k, 1] * 1e3:.1f} mm outward, {a[k, 2] * 1e3:.1f} mm "
                  f"lower (t = {a[k, 0]:.2f} s)")
            # a run that loses containment stops there: its last snapshot is the loss
            rows += [{"source": f"FE {amp_g:.2f} g", "rim": name, "time_s": f"{t:.4f}",
                      "outward_mm": f"{x * 1e3:.3f}", "drop_mm": f"{z * 1e3:.3f}",
                      "containment_lost": (lost is not None and name == furthest
                                           and i == len(path) - 1)}
                     for i, (t, x, z) in enumerate(path)]
    for reach, steps in ((0.5 * bearing.rim_height, 40), (bearing.rim_height, 80)):
        x, z = push_corner(bearing, reach, steps)
        print(f"push to {reach * 1e3:.1f} mm: corner {x * 1e3:.1f} mm outward, "
              f"{z * 1e3:.1f} mm lower")
        rows.append({"source": f"push to {reach * 1e3:.1f} mm", "rim": "bottom +x",
                     "time_s": "", "outward_mm": f"{x * 1e3:.3f}", "drop_mm": f"{z * 1e3:.3f}",
                     "containment_lost": ""})
    args.csv.parent.mkdir(parents=True, exist_ok=True)
    with open(args.csv, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    plot(bearing, rows, args.figure)
    print(args.csv, args.figure, sep="\n")


def plot(bearing: DFPBearing, rows: list, path: Path) -> None:
    """Corner drop against outward motion: the FE paths, the push's ends, Eq. R55."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(10, 4.5))
    for source in dict.fromkeys(r["source"] for r in rows if r["source"].startswith("FE")):
        for rim in dict.fromkeys(r["rim"] for r in rows if r["source"] == source):
            sel = [r for r in rows if r["source"] == source and r["rim"] == rim]
            x = [float(r["outward_mm"]) for r in sel]
            z = [float(r["drop_mm"]) for r in sel]
            line, = ax.plot(x, z, label=f"{source}, {rim} rim")
            lost = [i for i, r in enumerate(sel) if r["containment_lost"]]
            if lost:
                ax.plot(x[lost[0]], z[lost[0]], "x", color=line.get_color(), ms=9,
                        label=f"{source}: containment lost (slider past the rim)")
    pushes = [r for r in rows if r["source"].startswith("push")]
    ax.plot([float(r["outward_mm"]) for r in pushes], [float(r["drop_mm"]) for r in pushes],
            "ks", label="static push (face held vertical)")
    lever = LEVER_FRACTION * bearing.rim_height
    up = np.linspace(0.0, lever, 100)
    ax.plot(up * 1e3, link_corner(bearing, up) * 1e3, "k--",
            label="rigid model, Eq. R55 (flat at $u_p$ = L)")
    ax.axhline(bearing.rim_height * 1e3, color="0.6", lw=0.8)
    ax.text(1, bearing.rim_height * 1e3 + 0.5, "rim height", color="0.4", fontsize=8)
    ax.set_xlabel("inner corner moved outward [mm] (rigid model: set $u_p$)")
    ax.set_ylabel("inner corner moved towards its plate [mm]")
    ax.set_title("Bent rims' inner corners: FE model (heavy bearing, symmetric Ricker pulse, "
                 "Tp = 2 s) and rigid model", fontsize=10)
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    ax.grid(alpha=0.3)
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=130)
    plt.close(fig)


if __name__ == "__main__":
    main()
