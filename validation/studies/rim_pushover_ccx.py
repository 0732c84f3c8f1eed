"""The rim push of the FE companion (fem.rim_pushover) against CalculiX, an independent FE
program, on the same mesh, with geometric nonlinearity.

The bottom plate of the bearing's default mesh, its back face fixed, the upper half of the +x
rim's inner face pushed outward by a prescribed horizontal displacement to half the rim height
(17.5 mm). Ours: finite deformation (mean-dilatation Q1, Hencky J2) and small strain (Q1 B-bar).
CalculiX (``ccx``, Debian's ``calculix-ccx``): the same nodes and elements written as an Abaqus
deck, ``*STEP, NLGEOM``, J2 with the same bilinear capped hardening (``*PLASTIC``: 345 MPa at
0, 450 MPa at (450 − 345)/H), the same boundary conditions, with several element types because
CalculiX has no mean-dilatation quadrilateral: CPE8R (the same quadrilaterals with mid-side
nodes, reduced integration), C3D8I (one layer of incompatible-mode bricks, plane strain by
u_z = 0) and CPE4 (full integration, which locks in plastic flow; shown as the bound). Writes
``docs/results/rim_pushover.csv`` (δ [mm] against the horizontal force [MN] of each) and
``docs/images/rim_pushover.png``, and prints the largest difference between ours and each
CalculiX curve beyond the elastic range.

Run: ``python -m validation.studies.rim_pushover_ccx`` (needs ``ccx`` on the PATH; about a
minute).
"""

from __future__ import annotations

import argparse
import csv
import os
import re
import shutil
import subprocess
import tempfile
import time
from pathlib import Path

import numpy as np

from fem.pushover import bottom_plate, rim_pushover
from rigid import DFPBearing

from . import IMAGES, RESULTS

ELEMENTS = ("CPE8R", "C3D8I", "CPE4")


def _num(x: float) -> str:
    """A number CalculiX reads whole (it reads at most 20 characters per field)."""
    return f"{x:.12g}"


def write_deck(path: Path, plate, bearing: DFPBearing, element: str, delta: float) -> None:
    """An Abaqus/CalculiX deck of the push on ``plate``'s mesh with ``element`` [m, N, Pa]."""
    mesh = plate.mesh
    p, t = mesh.p, mesh.t.copy()
    # counter-clockwise node order (CalculiX needs it; scikit-fem accepts either)
    x, y = p[0, t], p[1, t]
    area = 0.5 * ((x * np.roll(y, -1, axis=0)).sum(0) - (y * np.roll(x, -1, axis=0)).sum(0))
    t[:, area < 0] = t[::-1, area < 0]
    nodes = {i + 1: (p[0, i], p[1, i], 0.0) for i in range(p.shape[1])}
    extra = {}
    if element == "CPE8R":  # mid-side nodes of the same quadrilaterals
        mids, conn = {}, []
        for e in t.T:
            row = [int(k) + 1 for k in e]
            for a, b in zip(e, np.roll(e, -1), strict=True):
                key = (min(a, b), max(a, b))
                if key not in mids:
                    mids[key] = len(nodes) + len(mids) + 1
                    extra[mids[key]] = (*(0.5 * (p[:, a] + p[:, b])), 0.0)
                row.append(mids[key])
            conn.append(row)
        nodes.update(extra)
    elif element == "C3D8I":  # one layer of bricks, 1 m thick
        n0 = p.shape[1]
        for i in range(n0):
            nodes[n0 + i + 1] = (p[0, i], p[1, i], 1.0)
        conn = [[int(k) + 1 for k in e] + [int(k) + 1 + n0 for k in e] for e in t.T]
    else:
        conn = [[int(k) + 1 for k in e] for e in t.T]

    def node_set(ids):
        ids = sorted(ids)
        return "\n".join(", ".join(str(i) for i in ids[k:k + 8]) for k in range(0, len(ids), 8))

    n0 = p.shape[1]
    support = [int(i) + 1 for i in plate.support]
    face = [int(i) + 1 for i in plate.face]
    if element == "CPE8R":  # the mid-side nodes on the fixed and pushed edges belong too
        z = {k: v[1] for k, v in nodes.items()}
        xs = {k: v[0] for k, v in nodes.items()}
        z_lo = min(nodes[i][1] for i in face) - 1e-9
        x_f = nodes[face[0]][0]
        face += [k for k in extra if abs(xs[k] - x_f) < 1e-9 and z[k] > z_lo]
        support += [k for k in extra if abs(z[k] + bearing.plate_thickness) < 1e-9]
    if element == "C3D8I":
        support += [i + n0 for i in support]
        face += [i + n0 for i in face]
    h = bearing.youngs_modulus * bearing.hardening_ratio / (1 - bearing.hardening_ratio)
    p_u = (bearing.ultimate_stress - bearing.yield_stress) / h
    lines = ["*HEADING", f"rim push, {element}", "*NODE"]
    lines += [f"{k}, {_num(v[0])}, {_num(v[1])}, {_num(v[2])}" for k, v in sorted(nodes.items())]
    lines += [f"*ELEMENT, TYPE={element}, ELSET=PLATE"]
    lines += [f"{k}, " + ", ".join(str(n) for n in c) for k, c in enumerate(conn, 1)]
    lines += ["*NSET, NSET=SUPPORT", node_set(support), "*NSET, NSET=FACE", node_set(face),
              "*NSET, NSET=ALL", node_set(nodes),
              "*MATERIAL, NAME=STEEL", "*ELASTIC",
              f"{_num(bearing.youngs_modulus)}, {_num(bearing.poisson_ratio)}", "*PLASTIC",
              f"{_num(bearing.yield_stress)}, 0.", f"{_num(bearing.ultimate_stress)}, {_num(p_u)}",
              f"{_num(bearing.ultimate_stress)}, 100."]
    lines += ["*SOLID SECTION, ELSET=PLATE, MATERIAL=STEEL"] + (["1."] if element != "C3D8I"
                                                                 else [])
    lines += ["*BOUNDARY", "SUPPORT, 1, 2, 0."]
    if element == "C3D8I":
        lines += ["ALL, 3, 3, 0."]
    lines += ["*STEP, NLGEOM, INC=10000", "*STATIC", "0.005, 1., 1e-7, 0.02", "*BOUNDARY",
              f"FACE, 1, 1, {_num(delta)}", "*NODE PRINT, NSET=FACE, TOTALS=ONLY", "RF",
              "*END STEP"]
    path.write_text("\n".join(lines) + "\n")


def run_ccx(deck: Path) -> tuple[np.ndarray, np.ndarray]:
    """Run CalculiX on ``deck`` (a ``.inp``); the step times and total horizontal reactions
    [N per metre of thickness] of the set FACE."""
    env = {**os.environ, "OMP_NUM_THREADS": "1"}
    proc = subprocess.run(["ccx", "-i", deck.stem], cwd=deck.parent, capture_output=True,
                          text=True, env=env, timeout=1800)
    dat = deck.with_suffix(".dat")
    if proc.returncode != 0 or not dat.exists():
        raise RuntimeError(f"ccx failed on {deck.name}: {proc.stdout[-2000:]}")
    times, forces = [0.0], [0.0]
    text = dat.read_text()
    for m in re.finditer(r"total force \(fx,fy,fz\) for set FACE and time\s+(\S+)\s*\n\s*"
                         r"(\S+)\s+(\S+)\s+(\S+)", text):
        times.append(float(m.group(1)))
        forces.append(float(m.group(2)))
    if len(times) < 3:
        raise RuntimeError(f"no reactions in {dat.name}; last output: {proc.stdout[-1500:]}")
    return np.array(times), np.array(forces)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=RESULTS / "rim_pushover.csv")
    parser.add_argument("--figure", type=Path, default=IMAGES / "rim_pushover.png")
    parser.add_argument("--elements", nargs="+", default=list(ELEMENTS))
    args = parser.parse_args()
    if shutil.which("ccx") is None:
        raise SystemExit("ccx (CalculiX) is not on the PATH: apt-get install calculix-ccx")
    bearing = DFPBearing()
    delta = 0.5 * bearing.rim_height
    plate = bottom_plate(bearing)
    curves = {}
    for kinematics in ("finite", "small"):
        t0 = time.process_time()
        res = rim_pushover(bearing, kinematics=kinematics, displacement=delta)
        curves[f"ours_{kinematics}"] = (res.displacement, res.force)
        print(f"ours, {kinematics}: hinge at δ = {res.hinge_displacement * 1e3:.2f} mm, "
              f"{res.hinge_force / 1e6:.3f} MN; at 17.5 mm {res.force[-1] / 1e6:.3f} MN "
              f"({res.dofs} dofs, {time.process_time() - t0:.1f} s CPU)", flush=True)
    with tempfile.TemporaryDirectory() as tmp:
        for element in args.elements:
            deck = Path(tmp) / f"push_{element.lower()}.inp"
            write_deck(deck, plate, bearing, element, delta)
            t0 = time.perf_counter()
            times, force = run_ccx(deck)
            curves[f"ccx_{element}"] = (times * delta, force * plate.depth)
            print(f"CalculiX {element}: at 17.5 mm {force[-1] * plate.depth / 1e6:.3f} MN "
                  f"({times.size - 1} increments, {time.perf_counter() - t0:.0f} s)", flush=True)
    grid = np.linspace(0.0, delta, 71)
    table = {name: np.interp(grid, d, f) for name, (d, f) in curves.items()}
    ours = table["ours_finite"]
    beyond = grid >= 2e-3  # past the hinge (0.75 mm) and the knee of the curves
    for name, values in table.items():
        if name.startswith("ccx"):
            diff = np.max(np.abs(ours[beyond] / values[beyond] - 1))
            print(f"ours (finite) against {name}: largest difference {100 * diff:.1f} % for "
                  f"δ ≥ 2 mm")
    args.out.parent.mkdir(parents=True, exist_ok=True)
    with open(args.out, "w", newline="") as fh:
        writer = csv.writer(fh)
        writer.writerow(["displacement_mm", *(f"force_MN_{n}" for n in table)])
        for k, d in enumerate(grid):
            writer.writerow([f"{d * 1e3:.4f}", *(f"{table[n][k] / 1e6:.6f}" for n in table)])
    print(f"-> {args.out}")
    _figure(grid, table, args.figure)


def _figure(grid, table, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.4, 4.2), constrained_layout=True)
    style = {"ours_finite": ("k-", "ours, finite deformation"),
             "ours_small": ("k--", "ours, small strain"),
             "ccx_CPE8R": ("C0-", "CalculiX CPE8R, NLGEOM"),
             "ccx_C3D8I": ("C1-", "CalculiX C3D8I, NLGEOM"),
             "ccx_CPE4": ("C2:", "CalculiX CPE4 (locks), NLGEOM")}
    for name, values in table.items():
        fmt, label = style.get(name, ("C3-", name))
        ax.plot(grid * 1e3, values / 1e6, fmt, label=label, lw=1.4)
    ax.set_xlabel("horizontal displacement of the rim face δ [mm]")
    ax.set_ylabel("horizontal force on the rim [MN]")
    ax.set_title("Push of a 40 mm rim (bottom plate, default mesh)", fontsize=10)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=130)
    plt.close(fig)
    print(f"-> {path}")


if __name__ == "__main__":
    main()
