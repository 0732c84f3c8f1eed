"""The rim pushed by the slider itself (issue #31, the 80 mm rim's law through tearing): the
rigid slider, with its rounded edges, moved along its pendulum path into the +x bottom rim and
pressing it through the dynamic model's penalty contact (docs/theory/finite-elements.md,
Eqs. F15–F19), at finite deformation, with the median fracture criterion and its torn
elements let go over 10 increments of at most 0.25 mm (Eqs. F66–F68, F70), with the rim's
friction and without, beside the push of the rim's upper face by a prescribed displacement
that the laws come from (``fem.rim_law``).
The path (Eq. F71, docs/fe-companion.md, "The rim pushed by the slider"): the slider's
spherical face stays concentric with the dish, its centroid at R − h/2 from the dish's
centre, so δ, its horizontal advance past the first touch, is the only load parameter; the
dish is left out of the contact. Writes ``docs/results/rim_slider_push.csv`` (a row per push)
and ``rim_slider_push_curves.csv``, and ``rim_slider_law_rigid.csv``: the rigid model's
containment SA with the 80 mm rim's law through tearing built from the slider's push (the
face push does not tear that rim), on the first four records at both pressures.

Run (about 6 minutes of CPU)::

    python -m validation.studies.rim_slider_push
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import time
from pathlib import Path

import numpy as np

from fem.pushover import SEPARATED, Pushover, bottom_plate
from rigid.bearing import DFPBearing
from rigid.collapse.comparison import write_csv
from rigid.rims import TEARING_PUSH

from . import RESULTS


def slider_pose(bearing: DFPBearing, angle: float) -> np.ndarray:
    """The slider's pose (X [m], Z [m], Θ [rad]) on its pendulum path at ``angle`` [rad]
    (Eq. F71): its spherical face concentric with the dish, its centroid at R − h/2 from the
    dish's centre (0, R), turned by the same angle."""
    arm = bearing.radius - bearing.slider_height / 2
    return np.array([arm * math.sin(angle), bearing.radius - arm * math.cos(angle), angle])


def touching_angle(bearing: DFPBearing, shape, points: np.ndarray) -> float:
    """The path angle [rad] at which the slider (``shape``) first reaches any of ``points``
    (2, n) [m]: bisection on the deepest point's penetration (Eq. F14), to 1e-12 rad."""
    from fem.contact import body_coordinates, penetration

    def deepest(angle):
        return penetration(shape, body_coordinates(points, slider_pose(bearing, angle)))[0].max()

    lo, hi = 0.0, math.asin(bearing.rim_radius / (bearing.radius - bearing.slider_height / 2))
    if deepest(lo) >= 0.0 or deepest(hi) < 0.0:
        raise ValueError("the slider must start clear of the rim and reach it on its path")
    while hi - lo > 1e-12:
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if deepest(mid) < 0.0 else (lo, mid)
    return hi


def rim_slider_push(bearing: DFPBearing, *, edge_radius: float = 0.02,
                    displacement: float | None = None, steps: int = 40,
                    mesh_options: dict | None = None, fracture=None, erosion_steps: int = 0,
                    stop_short: bool = False, penalty_factor: float = 10.0,
                    tangential_ratio: float = 0.1, cache_dir=None) -> Pushover:
    """Push the +x bottom rim with the slider moved along its pendulum path (Eq. F71), at
    finite deformation.

    The plate's back face is fixed; the slider's pose is prescribed, its advance δ measured
    horizontally from where it first touches the rim; the rim's inner face and top press on
    it through the dynamic model's penalty contact with Coulomb friction (Eqs. F15–F19; the
    dish is left out: the slider rides on it concentrically). Increments of at most
    1/``steps`` of the final δ, halved when Newton fails.

    Parameters
    ----------
    bearing : rigid.DFPBearing
    edge_radius : float [m]
        The slider's rounded edges (:class:`fem.contact.SliderShape`; default 20 mm, the
        validation runs' ``--fem-edge-radius``).
    displacement : float [m], optional
        Final δ; default half the rim height.
    steps : int
        Increments at most.
    mesh_options : dict, optional
        :func:`fem.geometry.build_mesh` sizes [m].
    fracture, erosion_steps, stop_short
        As :func:`fem.rim_pushover`: the rim's ductile damage, its torn elements let go over
        N increments (a node no element holds any more leaves the contact), the push ended
        once the rim is off; stop where Newton fails instead of raising RuntimeError.
    penalty_factor, tangential_ratio : float [-]
        As :func:`fem.dfp.build_system` (ε_N = factor · E / h_c, ε_T / ε_N).
    cache_dir : path-like, optional
        Mesh cache.

    Returns
    -------
    Pushover
        ``displacement`` is the slider's advance δ, ``force`` the horizontal contact force
        on it [N] (times the model's depth).
    """
    from fem import contact as C
    from fem.finite_element import FiniteStrainQ1
    from fem.hencky import FiniteState
    from fem.material import Material

    if erosion_steps and fracture is None:
        raise ValueError("erosion_steps needs fracture")
    delta_end = 0.5 * bearing.rim_height if displacement is None else float(displacement)
    if not (math.isfinite(delta_end) and delta_end > 0):
        raise ValueError(f"displacement must be a positive length [m], got {displacement!r}")
    shape = C.SliderShape.from_bearing(bearing, edge_radius)
    plate = bottom_plate(bearing, mesh_options=mesh_options, cache_dir=cache_dir)
    mesh = plate.mesh
    fe = FiniteStrainQ1(mesh)
    steel = Material.from_bearing(bearing)
    nd = fe.basis.nodal_dofs
    nodes = C.ContactNodes.from_mesh(
        mesh, {"bottom_rim_inner": bearing.rim_friction, "bottom_rim_top": bearing.rim_friction})
    keep = mesh.p[0, nodes.nodes] > 0.0  # the +x rim only
    nodes = dataclasses.replace(nodes, nodes=nodes.nodes[keep], length=nodes.length[keep],
                                friction=nodes.friction[keep], plate=nodes.plate[keep])
    node_dofs = nd[:, nodes.nodes]
    dish = mesh.facets[:, mesh.boundaries["bottom_dish"]]
    h_c = float(np.mean(np.linalg.norm(mesh.p[:, dish[1]] - mesh.p[:, dish[0]], axis=0)))
    eps_n = penalty_factor * bearing.youngs_modulus / h_c
    # Eq. F71: δ = X(angle) − X(touch); the path's X is monotone on the way to the rim
    touch = touching_angle(bearing, shape, mesh.p[:, nodes.nodes])
    arm = bearing.radius - bearing.slider_height / 2
    x_touch = arm * math.sin(touch)

    def pose_at(delta):
        return slider_pose(bearing, math.asin((x_touch + delta) / arm))

    friction, offset = C.initial_state(shape, mesh.p[:, nodes.nodes], pose_at(0.0))
    fixed = np.concatenate([nd[0, plate.support], nd[1, plate.support]])
    state = FiniteState.virgin(fe.point_shape)
    u = np.zeros(fe.ndofs)
    out = {"d": [0.0], "f": [0.0], "frac": [0.0], "p": [0.0], "avg": [0.0], "damage": [0.0],
           "triax": [0.0], "corner": [(0.0, 0.0)]}
    hinge = tear = None
    separated = False
    tracker = None
    if fracture is not None:
        from fem.fracture import RimFracture, criterion_of

        tracker = RimFracture(criterion_of(fracture, bearing.rupture_strain), fe, mesh,
                              bearing.rim_thickness, steps=erosion_steps, rims=("bottom +x",))
        rim, average = tracker.elements[0], tracker.gauges[0].operator
    else:
        from fem.limit_states import rim_gauge_average

        rim, average = rim_gauge_average(fe, mesh, "bottom +x", bearing.rim_thickness)
    delta, h = 0.0, delta_end / steps
    while delta < delta_end * (1 - 1e-12):
        target = min(delta + h, delta_end)
        held, in_contact = fixed, nodes
        if fe.retained is not None:  # nodes no element holds: fixed, and out of the contact
            kept = np.zeros(fe.ndofs, dtype=bool)
            kept[fe.element_dofs[:, fe.retained > 0].ravel()] = True
            loose = np.setdiff1d(np.flatnonzero(~kept), fixed)
            held = np.concatenate([fixed, loose])
            in_contact = dataclasses.replace(nodes, length=nodes.length * kept[node_dofs[0]])
        res = _newton(fe, steel, state, u, held, pose_at(target), shape, in_contact,
                      node_dofs, friction, offset, eps_n, tangential_ratio * eps_n)
        if res is None:  # cut the increment back
            h *= 0.5
            if h < 1e-6 * delta_end:
                if stop_short:
                    break
                raise RuntimeError(f"slider push: Newton did not converge beyond δ = "
                                   f"{delta:.4g} m even with increments of {h:.2g} m")
            continue
        delta, (u, state, stress, friction, slider_force) = target, res
        h = min(2.0 * h, delta_end / steps)
        force = -slider_force[0] * plate.depth  # the rim's push back on the slider, outward +
        p = state.eq_plastic_strain
        out["d"].append(delta)
        out["f"].append(force)
        out["frac"].append(float((p[plate.root_row] > 0).mean()))
        out["p"].append(float(p.max()))
        out["avg"].append(float((average @ p[rim].ravel()).max()))
        out["corner"].append(u[nd[:, plate.face[-1]]])
        if hinge is None and out["frac"][-1] >= 1.0:
            hinge = (delta, force)
        if tracker is not None:
            if tracker.update(delta, p, stress):
                fe.retained = tracker.retained.copy()
            out["damage"].append(tracker.rim_damage[0])
            out["triax"].append(tracker.rim_triaxiality[0])
            if tear is None and tracker.first_tear is not None:
                tear = (delta, force)
            if tear is not None and erosion_steps and force < SEPARATED * max(out["f"]):
                separated = True
                break
    return Pushover(
        displacement=np.array(out["d"]), force=np.array(out["f"]),
        yielded_fraction=np.array(out["frac"]),
        hinge_displacement=None if hinge is None else hinge[0],
        hinge_force=None if hinge is None else hinge[1],
        max_plastic_strain=np.array(out["p"]),
        averaged_plastic_strain=np.array(out["avg"]), kinematics="finite", dofs=fe.ndofs,
        plate=plate, final_displacement=u, final_plastic_strain=state.eq_plastic_strain,
        damage=np.array(out["damage"]) if tracker is not None else np.zeros(0),
        triaxiality=np.array(out["triax"]) if tracker is not None else np.zeros(0),
        fracture_displacement=None if tear is None else tear[0],
        fracture_force=None if tear is None else tear[1],
        torn_elements=0 if tracker is None else len(tracker.torn),
        corner=plate.mesh.p[:, plate.face[-1]] + np.array(out["corner"]),
        separated=separated,
    )


def _newton(fe, steel, state, u, fixed, pose, shape, nodes, node_dofs, friction, offset,
            eps_n, eps_t, rtol=1e-8, max_iter=15):
    """One increment: f_int(u) = f_contact(u) with the slider at ``pose`` and the dofs
    ``fixed`` held where they are; Newton with the consistent tangents of the plate and of
    the contact's node block (Eq. F18). Returns (u, state, stress, friction history,
    slider force [N/m, N/m, N·m/m]) once converged, None if not."""
    from skfem import condense, solve

    from fem import contact as C

    x0 = fe.basis.mesh.p[:, nodes.nodes]
    free = np.setdiff1d(np.arange(u.size), fixed)
    for _ in range(max_iter + 1):
        ev, f_int = fe.evaluate(steel, u, state)
        if not np.isfinite(f_int).all():
            return None
        con = C.evaluate(shape, nodes, x0 + u[node_dofs], pose, friction, offset, eps_n, eps_t)
        f_con = np.zeros_like(f_int)
        np.add.at(f_con, node_dofs.ravel(), con.node_force.ravel())
        r = f_con - f_int
        scale = max(np.linalg.norm(f_int), np.linalg.norm(f_con))
        if scale == 0.0 or np.linalg.norm(r[free]) <= rtol * scale:
            return u, ev.state, ev.stress, con.state, con.slider_force
        # only the nodes' block of the contact tangent: the slider's pose is prescribed
        K = fe.finite_stiffness(steel, ev) + _node_block(con.stiffness, node_dofs, u.size)
        u = u + solve(*condense(K, r, D=fixed))
    return None


def _node_block(stiffness, node_dofs, size):
    """The (x_i, z_i) block of the contact's local tangents scattered into a global matrix."""
    import scipy.sparse as sp

    n = node_dofs.shape[1]
    rows = np.broadcast_to(node_dofs[:, None, :], (2, 2, n)).ravel()
    cols = np.broadcast_to(node_dofs[None, :, :], (2, 2, n)).ravel()
    return sp.csr_matrix((stiffness[:2, :2].ravel(), (rows, cols)), shape=(size, size))


#: The largest push increment [m] and N, as the law through tearing's face push.
INCREMENT, N = TEARING_PUSH
#: (rim thickness [m], reach [m], friction on the rim [-]) of each push: as far as the face
#: push of the law goes (the rim's thickness plus its height), with the bearing's rim friction
#: and without (Newton's trouble past the tear is in part the contact's stick–slip).
PUSHES = tuple((t, t + DFPBearing.rim_height, mu) for t in (0.04, 0.08)
               for mu in (DFPBearing.rim_friction, 0.0))


def push(thickness: float, reach: float, friction: float):
    """One slider push with the median criterion (its Pushover) and its row."""
    t0 = time.process_time()
    bearing = DFPBearing(rim_thickness=thickness, rim_friction=friction)
    p = rim_slider_push(bearing, displacement=reach, steps=round(reach / INCREMENT),
                        fracture="median", erosion_steps=N, stop_short=True)
    torn = p.fracture_displacement is not None
    k = int(p.force.argmax())
    return p, {
        "rim_thickness_mm": round(thickness * 1e3),
        "edge_radius_mm": 20,
        "rim_friction": friction,
        "dofs": p.dofs,
        "peak_force_mn": p.force[k] / 1e6,
        "peak_displacement_mm": p.displacement[k] * 1e3,
        "hinge_displacement_mm": ("" if p.hinge_displacement is None
                                  else p.hinge_displacement * 1e3),
        "tear_displacement_mm": p.fracture_displacement * 1e3 if torn else "",
        "tear_force_mn": p.fracture_force / 1e6 if torn else "",
        "pushed_to_mm": p.displacement[-1] * 1e3,
        "end_force_mn": p.force[-1] / 1e6,
        "end": ("separated" if p.separated
                else "reach" if p.displacement[-1] >= reach * (1 - 1e-9) else "newton"),
        "torn_elements": p.torn_elements,
        "largest_damage": float(p.damage.max()),
        "largest_plastic_strain": float(p.max_plastic_strain.max()),
        "cpu_s": round(time.process_time() - t0, 1),
    }


def rigid_rows(bearing: DFPBearing, push_, records: int) -> list[dict]:
    """The rigid model's containment SA with a law through tearing built from a slider push
    (:func:`rigid.rims.rim_law_through_tearing`, the elastic stiffness of the face push's
    law), on the first ``records`` near-field pulse components at 60 and 10 MPa: the fast
    0.01 g ladder, and how many of its rungs ended numerically."""
    import fem
    import rigid
    from rigid.rims import rim_law_through_tearing

    law = rim_law_through_tearing(bearing, fem.rim_law(bearing).stiffness, push_, push_)
    rows = []
    for motion in rigid.fema_p695("nearfield_pulse")[:records]:
        for pressure in (60e6, 10e6):
            t0 = time.process_time()
            crit = rigid.critical_sa(dataclasses.replace(bearing, pressure=pressure), motion,
                                     search="fast", rims="yielding", rim_law=law,
                                     limit_state="containment")
            rows.append({
                "rim_thickness_mm": round(bearing.rim_thickness * 1e3),
                "record": motion.name, "pressure_mpa": round(pressure / 1e6),
                "containment_sa_g": "" if crit.sa is None else round(crit.sa / rigid.G, 2),
                "rungs": len(crit.rungs),
                "numerical_rungs": sum(bool(r.numerical_failure) for r in crit.rungs),
                "cpu_s": round(time.process_time() - t0, 1)})
            print(rows[-1], flush=True)
    return rows


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=str(RESULTS))
    ap.add_argument("--records", type=int, default=4,
                    help="records of the rigid model's ladders with the 80 mm slider law")
    args = ap.parse_args()
    rows, points, law_rows = [], [], []
    for thickness, reach, friction in PUSHES:
        p, row = push(thickness, reach, friction)
        rows.append(row)
        if thickness == 0.08 and friction == DFPBearing.rim_friction:
            law_rows = rigid_rows(DFPBearing(rim_thickness=thickness), p, args.records)
        bearing = DFPBearing(rim_thickness=thickness)
        root = bearing.dish_depth(bearing.rim_radius)
        points += [{"rim_thickness_mm": row["rim_thickness_mm"], "rim_friction": friction,
                    "displacement_mm": d * 1e3,
                    "force_mn": f / 1e6, "damage": D, "corner_height_mm": (c[1] - root) * 1e3}
                   for d, f, D, c in zip(p.displacement, p.force, p.damage, p.corner,
                                         strict=True)]
        print(row, flush=True)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    write_csv(rows, out / "rim_slider_push.csv")
    write_csv(points, out / "rim_slider_push_curves.csv")
    write_csv(law_rows, out / "rim_slider_law_rigid.csv")
    print(f"wrote {out / 'rim_slider_push.csv'}, rim_slider_push_curves.csv and "
          "rim_slider_law_rigid.csv")


if __name__ == "__main__":
    main()
