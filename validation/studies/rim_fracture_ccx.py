"""Where the rim begins to tear in the static push, ours against CalculiX (issue #31 item 3):
the same push as ``rim_pushover_ccx`` (C3D8I bricks, NLGEOM, the same mesh and steel), its
equivalent plastic strain (PEEQ), stresses and integration-point coordinates printed at every
increment, and the damage of the median criterion accumulated from them exactly as an FE run
of ours accumulates it (:class:`fem.fracture.GaugeDamage` over a disc of the rim thickness,
docs/theory/finite-elements.md, Eqs. F62–F67). Writes ``docs/results/rim_fracture_ccx.csv``
(the largest damage and the triaxiality there against the push displacement, both programs)
and prints the displacement at which each reaches D = 1.

Run: ``python -m validation.studies.rim_fracture_ccx`` (needs ``ccx``; about two minutes).
"""

from __future__ import annotations

import argparse
import re
import shutil
import tempfile
from pathlib import Path

import numpy as np

from fem.assembly import PlaneStrainQ1
from fem.fracture import FRACTURE_SETS, GaugeDamage
from fem.limit_states import averaging_operator, rim_gauge_average
from fem.pushover import bottom_plate, rim_pushover
from rigid import DFPBearing
from rigid.collapse.comparison import write_csv

from . import RESULTS
from .rim_pushover_ccx import run_ccx, write_deck

#: How far the rim is pushed [m]: past the tear of the 40 mm rim (about 10.7 mm).
REACH = 0.014
#: Our push's increments: 0.1 mm, finer than CalculiX's largest (2 % of the reach).
STEPS = 140


def _blocks(text: str, title: str) -> dict:
    """{time: {(element, point): values}} of every block of the .dat with ``title``."""
    out = {}
    pattern = re.escape(title) + r"[^\n]*for set RIM and time\s+(\S+)\s*\n\s*\n(.*?)(?=\n\s*\n|\Z)"
    for m in re.finditer(pattern, text, flags=re.S):
        rows = {}
        for line in m.group(2).strip().splitlines():
            f = line.split()
            rows[(int(f[0]), int(f[1]))] = np.array([float(v) for v in f[2:]])
        out[float(m.group(1))] = rows
    return out


def calculix_damage(bearing: DFPBearing, plate, fe, elements, criterion, tmp: Path):
    """CalculiX's push on ``plate`` (``fe``: its element, for the areas) and the damage
    accumulated from its points: (δ [m], largest D, T̄ there) per increment."""
    deck = tmp / "fracture_push.inp"
    write_deck(deck, plate, bearing, "C3D8I", REACH)
    ids = sorted(int(e) + 1 for e in elements)
    text = deck.read_text()
    eset = "*ELSET, ELSET=RIM\n" + "\n".join(
        ", ".join(map(str, ids[k:k + 8])) for k in range(0, len(ids), 8)) + "\n"
    text = text.replace("*STEP", eset + "*STEP", 1).replace(
        "*END STEP", "*EL PRINT, ELSET=RIM\nS, PEEQ, COORD\n*END STEP")
    deck.write_text(text)
    run_ccx(deck)
    dat = deck.with_suffix(".dat").read_text()
    stress = _blocks(dat, "stresses (elem, integ.pnt.")
    peeq = _blocks(dat, "equivalent plastic strain (elem, integ.pnt.")
    coord = _blocks(dat, "global coordinates (elem, integ.pnt.")
    times = sorted(stress)
    keys = sorted(coord[times[0]])  # (element, point): 8 bricks' points, two layers alike
    points = np.array([coord[times[0]][k][:2] for k in keys]).T
    area = fe.basis.dx.sum(axis=1)
    weights = np.array([area[e - 1] / 8.0 for e, _ in keys])
    gauge = GaugeDamage(criterion, averaging_operator(points, weights,
                                                      0.5 * bearing.rim_thickness))
    rows = [(0.0, 0.0, 0.0)]
    for t in times:
        s = np.array([stress[t][k] for k in keys])  # sxx, syy(z), szz(out of plane), sxy
        mandel = np.column_stack([s[:, 0], s[:, 1], s[:, 2], np.sqrt(2.0) * s[:, 3]])
        p = np.array([peeq[t][k][0] for k in keys])
        d = gauge.update(p, mandel)
        k = int(np.argmax(d))
        rows.append((t * REACH, float(d[k]), float(gauge.triaxiality[k])))
    return np.array(rows).T


def crossing(delta: np.ndarray, damage: np.ndarray) -> float:
    """δ [m] at which the damage reaches 1, linear between the increments (NaN if never)."""
    k = int(np.argmax(damage >= 1.0))
    if damage[k] < 1.0:
        return float("nan")
    return float(np.interp(1.0, damage[k - 1:k + 1], delta[k - 1:k + 1]))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=RESULTS / "rim_fracture_ccx.csv")
    args = ap.parse_args()
    if shutil.which("ccx") is None:
        raise SystemExit("ccx (CalculiX) is not on the PATH: apt-get install calculix-ccx")
    bearing = DFPBearing()
    criterion = FRACTURE_SETS["median"](rupture_strain=bearing.rupture_strain)
    plate = bottom_plate(bearing)
    fe = PlaneStrainQ1(plate.mesh)
    elements, _ = rim_gauge_average(fe, plate.mesh, "bottom +x", bearing.rim_thickness)
    ours = rim_pushover(bearing, displacement=REACH, steps=STEPS, fracture=criterion)
    with tempfile.TemporaryDirectory() as tmp:
        ccx = calculix_damage(bearing, plate, fe, elements, criterion, Path(tmp))
    grid = np.linspace(0.0, REACH, 57)
    rows = [{"displacement_mm": d * 1e3,
             "damage_ours": np.interp(d, ours.displacement, ours.damage),
             "damage_calculix": np.interp(d, ccx[0], ccx[1]),
             "triaxiality_ours": np.interp(d, ours.displacement, ours.triaxiality),
             "triaxiality_calculix": np.interp(d, ccx[0], ccx[2])} for d in grid]
    args.out.parent.mkdir(parents=True, exist_ok=True)
    write_csv(rows, args.out)
    tear_ours = crossing(ours.displacement, ours.damage)
    tear_ccx = crossing(ccx[0], ccx[1])
    print(f"D = 1 at δ = {tear_ours * 1e3:.2f} mm (ours), {tear_ccx * 1e3:.2f} mm (CalculiX "
          f"C3D8I): ours/CalculiX {tear_ours / tear_ccx:.3f}; -> {args.out}")


if __name__ == "__main__":
    main()
