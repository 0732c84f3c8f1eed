"""Plane-strain grooved specimens of the rim steel against the fracture criterion's closed
form (issue #31 item 3; docs/theory/finite-elements.md, Eqs. F62–F65): a flat bar pulled
along its length in plane strain (the grooves run across the whole depth), smooth or with
two circular grooves of radius R that leave a ligament 2a = 10 mm wide, computed by the FE
companion's finite-strain element and J2 steel (``fem.finite_element.FiniteStrainQ1``,
``fem.newton.solve_increment``) on a quarter of the bar.

At the centre of the ligament, where such specimens break, the study records the plastic
strain and the triaxiality (F62) at every increment and accumulates the damage along them
(F64, the median criterion), and sets them beside the closed forms:

* the triaxiality of a plane-strain grooved bar at the centre of its ligament in the
  undeformed geometry, T = (1 + 2 ln(1 + a/(2R)))/√3 (Bai, Teng & Wierzbicki 2009, after
  Bridgman's analysis of a neck); 1/√3 for the smooth bar (R → ∞; Eq. F65);
* the criterion's fracture strain at that triaxiality, ε_c(T) = ε_r exp(−c (T − 1/3)) (F63);
  and, as a check of the damage's sum along the path (F64), ε_c at the FE's own triaxiality
  averaged over the plastic strain to fracture.

Writes ``docs/results/grooved_specimens.csv`` (a row per specimen) and
``grooved_specimens_path.csv`` (the centre's path). Run (about a minute of CPU)::

    python -m validation.studies.grooved_specimens
"""

from __future__ import annotations

import argparse
import math
import time
from pathlib import Path

import numpy as np

from fem.fracture import FRACTURE_SETS, triaxiality
from rigid import DFPBearing
from rigid.collapse.comparison import write_csv

from . import RESULTS

#: Half the ligament a [m] and the groove radii R [m] (None: the smooth bar): a/(2R) = 0,
#: 1/4 and 1/2, T = 0.577, 0.835 and 1.045 in the closed form.
HALF_LIGAMENT = 0.005
GROOVES = (None, 0.01, 0.005)
#: Half the bar's length [m] (four ligaments: the ends stay elastic-uniform) and the
#: elements across the ligament's half and along the half length.
HALF_LENGTH = 0.02
ELEMENTS = (16, 48)
#: The largest pull of the bar's end per increment [m] (0.5 % of its half length).
INCREMENT = 1e-4


def closed_form_triaxiality(a: float, radius: float | None) -> float:
    """T at the ligament's centre of a plane-strain grooved bar (Bai, Teng & Wierzbicki 2009,
    with the ligament t = 2a): (1 + 2 ln(1 + a/(2R)))/√3; 1/√3 without a groove."""
    ratio = 0.0 if radius is None else a / (2.0 * radius)
    return (1.0 + 2.0 * math.log(1.0 + ratio)) / math.sqrt(3.0)


def quarter_bar(a: float, radius: float | None):
    """The quarter of the bar, x ∈ [0, edge(y)] across, y ∈ [0, HALF_LENGTH] along, as a
    mapped quadrilateral mesh graded towards the ligament (y = 0) and its centre (x = 0):
    the groove's arc, centred at (a + R, 0), is the edge up to where it meets the bar's
    outer face x = 2a; a smooth bar's edge is x = a throughout."""
    from skfem import MeshQuad1

    nx, ny = ELEMENTS
    xi = np.linspace(0.0, 1.0, nx + 1) ** 1.3  # finer at the centre
    eta = np.linspace(0.0, 1.0, ny + 1) ** 1.6  # finer at the ligament
    base = MeshQuad1.init_tensor(xi, eta)
    s, t = base.p
    y = t * HALF_LENGTH
    if radius is None:
        edge = np.full_like(y, a)
    else:
        outer = 2.0 * a
        reach = math.sqrt(radius**2 - (outer - a - radius) ** 2)  # where the arc meets it
        arc = a + radius - np.sqrt(np.maximum(radius**2 - y**2, 0.0))
        edge = np.where(y < reach, arc, outer)
    return MeshQuad1(np.vstack([s * edge, y]), base.t)


def pull(bearing: DFPBearing, radius: float | None, criterion, reach: float = 1.5) -> dict:
    """Pull the quarter bar until the centre's damage passes ``reach`` (or Newton stops):
    the centre's path (the end's pull [m], plastic strain, triaxiality, damage: arrays), the
    CPU time [s] and the dofs."""
    from fem.finite_element import FiniteStrainQ1
    from fem.hencky import FiniteState
    from fem.material import Material
    from fem.newton import solve_increment

    a = HALF_LIGAMENT
    mesh = quarter_bar(a, radius)
    fe = FiniteStrainQ1(mesh)
    steel = Material.from_bearing(bearing)
    nd = fe.basis.nodal_dofs
    x, y = mesh.p
    left = np.flatnonzero(np.abs(x) < 1e-12)
    bottom = np.flatnonzero(np.abs(y) < 1e-12)
    top = np.flatnonzero(np.abs(y - HALF_LENGTH) < 1e-12)
    fixed = np.concatenate([nd[0, left], nd[1, bottom], nd[1, top]])
    # the element at the centre of the ligament; its points' mean stands for the centre
    centre = int(np.argmin(np.hypot(*mesh.p[:, mesh.t].mean(axis=1))))
    state = FiniteState.virgin(fe.point_shape)
    u, zero = np.zeros(fe.ndofs), np.zeros(fe.ndofs)
    stretch, h = 0.0, INCREMENT
    path = {"p": [0.0], "T": [0.0], "D": [0.0], "stretch": [0.0]}
    t0 = time.process_time()
    while path["D"][-1] < reach:
        target = stretch + h
        values = np.concatenate([np.zeros(left.size + bottom.size), np.full(top.size, target)])
        res = solve_increment(fe, steel, state, u, zero, fixed, values, rtol=1e-8, max_iter=15)
        if not res.converged:
            h *= 0.5
            if h < 1e-9:
                break
            continue
        stretch, u, state = target, res.displacement, res.state
        h = min(2.0 * h, INCREMENT)
        p = float(res.state.eq_plastic_strain[centre].mean())
        tri = float(triaxiality(res.stress[:, centre].T).mean())
        step = p - path["p"][-1]
        mean = 0.5 * (tri + path["T"][-1])  # over the increment, as the gauge's T̄ (F66)
        path["D"].append(path["D"][-1] + float(criterion.damage_increment(step, mean)))
        path["p"].append(p)
        path["T"].append(tri)
        path["stretch"].append(stretch)
    out = {k: np.array(v) for k, v in path.items()}
    out["cpu_s"] = time.process_time() - t0
    out["dofs"] = fe.ndofs
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=str(RESULTS))
    args = ap.parse_args()
    bearing = DFPBearing()
    criterion = FRACTURE_SETS["median"](rupture_strain=bearing.rupture_strain)
    rows, points = [], []
    for radius in GROOVES:
        path = pull(bearing, radius, criterion)
        a = HALF_LIGAMENT
        closed = closed_form_triaxiality(a, radius)
        p_f = (float(np.interp(1.0, path["D"], path["p"])) if path["D"][-1] >= 1.0
               else math.nan)
        plastic = path["p"] > 0
        weights = np.diff(path["p"], prepend=0.0)
        upto = plastic & (path["D"] <= 1.0)
        mean_t = float(np.sum(path["T"][upto] * weights[upto]) / np.sum(weights[upto]))
        label = "smooth" if radius is None else f"R = {radius * 1e3:g} mm"
        rows.append({
            "specimen": label, "groove_radius_mm": "" if radius is None else radius * 1e3,
            "a_over_2r": 0.0 if radius is None else a / (2 * radius), "dofs": path["dofs"],
            "triaxiality_closed_form": closed,
            "triaxiality_fe_onset": float(path["T"][np.argmax(plastic)]),
            "triaxiality_fe_mean": mean_t,
            "triaxiality_error": mean_t / closed - 1.0,
            "fracture_strain_closed_form": float(criterion.critical_strain(closed)),
            "fracture_strain_fe": p_f,
            "fracture_strain_error": p_f / float(criterion.critical_strain(closed)) - 1.0,
            # the criterion at the FE's own mean triaxiality: the damage's sum along a path
            # whose triaxiality varies, against its constant-T value
            "fracture_strain_at_fe_triaxiality": float(criterion.critical_strain(mean_t)),
            "cpu_s": round(path["cpu_s"], 1)})
        points += [{"specimen": label, "stretch_mm": s * 1e3, "plastic_strain": p,
                    "triaxiality": t, "damage": d}
                   for s, p, t, d in zip(path["stretch"], path["p"], path["T"], path["D"],
                                         strict=True)]
        print(rows[-1], flush=True)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    write_csv(rows, out / "grooved_specimens.csv")
    write_csv(points, out / "grooved_specimens_path.csv")
    print(f"wrote {out / 'grooved_specimens.csv'} and grooved_specimens_path.csv")


if __name__ == "__main__":
    main()
