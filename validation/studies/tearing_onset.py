"""Where the two models part on the loss of containment with rims that tear: the rim's first tear
(the rupture, Eqs. F67 and R56c) of the FE runs against the rigid model's law through tearing,
on every finished case of the containment validations with fracture (issue #31, item 5).

For each case the FE search's stored runs give the lowest SA at which an FE rim tore (an upper
bound of the FE model's rupture SA: the search probes near the containment SA, not below it)
and the highest SA below that at which none did, if a run was made there. Beside them:

- the rigid model's rupture SA with the run's own law (the store's), by the validation's ladder
  (0.01 g, the fast search) at the rupture limit state;
- one rigid run at the SA where the FE rim first tore: the largest rim set it reaches against
  the law's rupture set, and its largest uplift (Eq. R54).

With ``--pose RECORD:PRESSURE:SA ...`` (the start of a record's name, MPa, g; the 80 mm
validation's stored runs), those FE runs are made again, stopped at the first tear, and the
slider's pose there is set against its pendulum path, the path the law's push holds it to (Eq.
F71): its rotation less the path angle on each dish, its rise above the bottom dish's path,
the largest rim force, and how far the torn rim's face and its partner's (the other plate's
rim on the other side, loaded in series by the same impact) have moved out, beside the rigid
model's sets of the same two rims at that instant, and where each model's energy balance put
the kinetic energy the tearing impact brought
(``docs/results/tearing_onset_pose.csv``; a few minutes of CPU a run). With ``--tilt DEG ...``
the 80 mm rim is pushed as for its law, but with the slider turned that far off its path
(``docs/results/tearing_onset_tilt.csv``; about a minute a push).

Writes ``docs/results/tearing_onset.csv`` and prints, per thickness and pressure, the cases where
the FE rim tore at least 10 % below the rigid model's rupture SA. Reads the stores of
:data:`validation.studies.containment_tearing.FOLDERS` (an unfinished run's finished searches,
as listed in its ``status.csv``); a few minutes of CPU.

Run: ``python -m validation.studies.tearing_onset``.
"""

from __future__ import annotations

import argparse
import math
from collections import defaultdict
from pathlib import Path

import numpy as np

from rigid import DFPBearing, G, fema_p695, simulate
from rigid.collapse import critical_sa
from rigid.collapse.comparison import write_csv
from rigid.model import RIM_NAMES
from rigid.tasks import ResultStore
from validation.stored_rim_laws import stored_rim_law

from . import RESULTS, read_csv, validation_table
from .containment_tearing import FOLDERS
from .fem_validation_status import run_settings, stored_runs

#: Rim thickness [mm] → what pushed the rim for its law: the face (40 mm) or the slider with
#: 20 mm edges (80 mm), as the validations were run (their READMEs).
PUNCH = {40.0: ("face", None), 80.0: ("slider", 0.02)}
#: FE tearing this far below the rigid model's rupture SA counts as "earlier" [-].
EARLIER = 0.9


def validation(thickness: float):
    """The containment validation with tearing at ``thickness`` [mm]: its folder, its settings
    (:func:`validation.studies.fem_validation_status.run_settings`) and its rims' laws by
    pressure [MPa], the store's."""
    folder = FOLDERS[thickness]
    punch, edge = PUNCH[thickness]
    settings = run_settings(["containment"], None if thickness == 40.0 else thickness,
                            "median", 20.0, punch)
    with ResultStore(folder / "results.sqlite") as store:
        laws = {p: stored_rim_law(store, settings.bearing_at(p * 1e6), fracture="median",
                                  edge_radius=edge) for p in (60, 10)}
    return folder, settings, laws


def rigid_run(bearing, motion, scale: float, law, limit_state: str, until=None):
    """The rigid model with yielding rims on ``motion`` scaled by ``scale``, run as a ladder's
    rung is (the record and 20 s after it, stopped when quiet), or to ``until`` [s]."""
    full = (motion.acceleration.size - 1) * motion.dt + 20.0
    return simulate(bearing, motion.acceleration * scale, motion.dt,
                    duration=full if until is None else until, rims="yielding",
                    limit_state=limit_state, rim_law=law, stop_when_quiet=until is None,
                    on_instability="refine")


def fe_tearing(out: Path, settings, motions) -> dict:
    """(record name, pressure [MPa]) → the SAs [g] of the stored FE runs, each with whether a
    rim tore in it (its rupture time is set)."""
    runs = defaultdict(list)
    for result, kwargs, motion, sa in stored_runs(out, settings, motions):
        pressure = round(kwargs["bearing"]["pressure"] / 1e6)
        runs[(motion.name, pressure)].append((sa, result["limit_states"]["rupture"] is not None))
    return runs


def case_row(thickness, motion, pressure, runs, law, settings, table_row) -> dict:
    """The row of one case (module docstring)."""
    torn = [sa for sa, tore in runs if tore]
    tore_at = min(torn) if torn else math.nan
    intact_at = max((sa for sa, tore in runs if not tore and not sa > tore_at), default=math.nan)
    bearing = settings.bearing_at(pressure * 1e6)
    ladder = critical_sa(bearing, motion, step=settings.step, stop=settings.stop,
                         search=settings.search, rims="yielding", limit_state="rupture",
                         rim_law=law)
    row = {"rim_thickness_mm": thickness, "record": motion.name, "pressure_mpa": pressure,
           "fe_tore_at_g": tore_at, "fe_intact_at_g": intact_at,
           "rigid_rupture_sa_g": math.nan if ladder.sa is None else ladder.sa / G,
           "fe_containment_sa_g": float(table_row["fem_sa_g"]),
           "rigid_containment_sa_g": float(table_row["yielding_sa_g"]),
           "law_rupture_set_mm": law.rupture_set * 1e3}
    row["fe_tore_over_rigid_rupture"] = row["fe_tore_at_g"] / row["rigid_rupture_sa_g"]
    if torn:  # the rigid model at the SA where the FE rim first tore
        r = rigid_run(bearing, motion, tore_at * G / ladder.record_sa, law, "rupture")
        row["rigid_max_set_mm_at_fe_tear"] = float(r.rim_set.max()) * 1e3
        row["rigid_max_uplift_mm_at_fe_tear"] = r.max_uplift * 1e3
    return row


def pose_at_tear(cases, motions) -> list[dict]:
    """The FE runs of the 80 mm validation named by ``cases`` ((record start, pressure [MPa],
    SA [g])) made again to their first tear, each beside the rigid model's run of the same
    scaled record with the run's law: the slider's pose at the tear against its path, how far
    the superstructure has travelled, how far the torn rim and its partner have moved out, and
    where the tearing impact's energy went (module docstring)."""
    from threadpoolctl import threadpool_limits

    import fem
    from validation.fem_runs import fem_run

    folder, settings, laws = validation(80.0)
    rows, made = [], []

    def keep(*args, **options):  # fem_run's stand-in for fem.simulate: keeps the result
        made.append(fem.simulate(*args, **options))
        return made[-1]

    for result, kwargs, motion, sa in stored_runs(folder, settings, motions):
        pressure = round(kwargs["bearing"]["pressure"] / 1e6)
        if not any(motion.name.startswith(name) and pressure == p and abs(sa - s) < 0.005
                   for name, p, s in cases) or result["limit_states"]["rupture"] is None:
            continue
        with threadpool_limits(1):  # as in a worker
            stopped = fem_run(**{**kwargs, "limit_state": "rupture"}, simulate=keep)
        r = made[-1]
        tear = stopped["limit_states"]["rupture"]  # [s from the record's start]
        if abs(r.time[-1] + stopped["start"] - tear) > 1e-6:  # the run ends at its tear
            raise RuntimeError(f"{motion.name}: the FE run did not stop at its first tear")
        # the rigid model to the FE tear: all that is compared, and its rims' sets there
        rigid = rigid_run(settings.bearing_at(pressure * 1e6), motion, kwargs["scale"],
                          laws[pressure], "containment", until=tear)
        sets = dict(zip(RIM_NAMES, rigid.rim_sets, strict=True))
        fe_energy = impact_energy(r.time + stopped["start"], r.rim_force.sum(axis=1), tear,
                                  r.energy, {"kinetic": "kinetic", "plastic": "plastic",
                                             "hht": "residual"})
        rigid_energy = impact_energy(rigid.time, rigid.rim_force, tear, rigid.energy,
                                     {"kinetic": "kinetic", "plastic": "plastic",
                                      "damper": "impact", "potential": "potential"})
        rim = first_torn_rim(r)
        arm = r.bearing.radius - r.bearing.slider_height / 2  # the path's radius (Eq. F71)
        x, d, rotation = r.slider_displacement[-1], r.displacement[-1], r.slider_rotation[-1]
        bottom = math.asin(x / arm)  # concentric with the bottom dish; the top: x − d = −arm sin
        upto = rigid.time <= tear
        fe_rise = rise_above_path(r.slider_rise, r.slider_displacement, arm)
        rigid_rise = rise_above_path(rigid.slider_rise, rigid.slider_displacement, arm)
        at_tear = min(np.searchsorted(rigid.time, tear), rigid.time.size - 1)
        rows.append({"record": motion.name, "pressure_mpa": pressure, "sa_g": round(sa, 3),
                     "first_tear_s": tear, "rim": rim,
                     "rotation_off_bottom_path_deg": math.degrees(rotation - bottom),
                     "rotation_off_top_path_deg": math.degrees(rotation + math.asin((x - d) / arm)),
                     "fe_rise_above_path_mm": float(fe_rise[-1]) * 1e3,
                     "rigid_rise_above_path_mm": float(rigid_rise[upto].max()) * 1e3,
                     "fe_travel_mm": float(np.abs(r.displacement).max()) * 1e3,
                     "rigid_travel_mm": float(np.abs(rigid.displacement[upto]).max()) * 1e3,
                     # the normal forces on all four rims, summed (the rigid model's rim_force)
                     "fe_max_rim_force_mn": float(r.rim_force.sum(axis=1).max()) / 1e6,
                     "rigid_max_rim_force_mn": float(rigid.rim_force[upto].max()) / 1e6,
                     "fe_torn_rim_face_set_mm": face_set(r, rim) * 1e3,
                     "rigid_largest_set_mm": float(rigid.rim_set[upto].max()) * 1e3,
                     # the rigid slider against the bottom dish's path at the FE tear
                     "rigid_rotation_off_bottom_path_deg": math.degrees(
                         rigid.slider_rotation[at_tear]
                         - math.asin(rigid.slider_displacement[at_tear] / arm)),
                     # the impact's two rims in series: the torn one and the other plate's
                     # rim on the other side (its partner), in each model at the FE tear
                     "fe_partner_face_set_mm": face_set(r, partner(rim)) * 1e3,
                     "rigid_torn_rim_set_mm": sets[rim] * 1e3,
                     "rigid_partner_set_mm": sets[partner(rim)] * 1e3,
                     **{f"fe_{k}": v for k, v in fe_energy.items()},
                     **{f"rigid_{k}": v for k, v in rigid_energy.items()}})
        print(rows[-1], flush=True)
    return rows


def rise_above_path(rise, x, arm):
    """The slider's rise above its pendulum path on the bottom dish [m] (Eq. F71): its rise
    less arm·(1 − cos θ), sin θ = x/arm."""
    return rise - arm * (1.0 - np.cos(np.arcsin(np.clip(x / arm, -1.0, 1.0))))


def impact_energy(time, rim_force, tear: float, energy, names) -> dict:
    """Where the impact in which a rim tore at ``tear`` [s] put its energy, by a model's
    energy balance (``names``: column label → its field): the kinetic energy at the impact's
    start (the last sample up to the tear with under 1 kN on the rims together) and the change
    of the others from there to the tear [kJ]. ``time`` [s from the record's start],
    ``rim_force`` [N] the rims' force together. The changes are zero if no impact is under way
    then."""
    k0 = int(np.nonzero((time <= tear) & (rim_force < 1e3))[0][-1])
    k1 = min(int(np.searchsorted(time, tear)), time.size - 1)
    series = {label: getattr(energy, name) for label, name in names.items()}
    return {f"impact_{name}_kj": float(e[k0] if name == "kinetic" else e[k1] - e[k0]) / 1e3
            for name, e in series.items()}


def partner(rim: str) -> str:
    """The rim loaded in series with ``rim`` by one impact: the other plate's, on the other
    side ("top -x" → "bottom +x")."""
    plate, side = rim.split()
    return f"{'top' if plate == 'bottom' else 'bottom'} {'+x' if side == '-x' else '-x'}"


def first_torn_rim(r) -> str:
    """The rim of an FE result's first torn element ("bottom +x", …)."""
    return next(iter(r.torn_elements.values()))[1]


def face_set(r, rim: str) -> float:
    """How far a rim's inner face has moved outward at the end of an FE run [m]: the largest
    horizontal displacement of its face nodes relative to their plate (the top plate moves
    with the superstructure block's top; the bottom plate's back face is held)."""
    from skfem import Basis, ElementQuad1, ElementVector

    mesh = r.mesh
    ux = r.final_displacement[Basis(mesh, ElementVector(ElementQuad1())).nodal_dofs[0]]
    plate, side = rim.split()
    sign = 1.0 if side == "+x" else -1.0
    face = np.unique(mesh.facets[:, mesh.boundaries[f"{plate}_rim_inner"]])
    face = face[sign * mesh.p[0, face] > 0]
    base = 0.0 if plate == "bottom" else ux[
        np.unique(mesh.facets[:, mesh.boundaries["block_top"]])].mean()
    return float((sign * (ux[face] - base)).max())


def tilted_push(tilts) -> list[dict]:
    """The 80 mm rim pushed by the slider as the law's push is (Eq. F71, the median criterion,
    its increments), but turned by each of ``tilts`` [deg] off its path: where the rim first
    tears, and the push's peak force."""
    from unittest import mock

    from fem import slider_push
    from validation.studies.rim_slider_push import INCREMENT, N

    bearing = DFPBearing(rim_thickness=0.08)
    reach = bearing.rim_thickness + bearing.rim_height
    path = slider_push.slider_pose
    rows = []
    for tilt in tilts:
        def pose(b, angle, tilt=tilt):  # the path's pose, turned by the tilt
            return path(b, angle) + np.array([0.0, 0.0, math.radians(tilt)])

        with mock.patch.object(slider_push, "slider_pose", pose):
            p = slider_push.rim_slider_push(bearing, displacement=reach,
                                            steps=round(reach / INCREMENT), fracture="median",
                                            erosion_steps=N, stop_short=True)
        k = int(p.force.argmax())
        torn = p.fracture_displacement is not None
        rows.append({"tilt_deg": tilt, "peak_force_mn": float(p.force[k]) / 1e6,
                     "peak_displacement_mm": p.displacement[k] * 1e3,
                     "tear_displacement_mm": p.fracture_displacement * 1e3 if torn else math.nan,
                     "tear_force_mn": float(p.fracture_force) / 1e6 if torn else math.nan,
                     "pushed_to_mm": float(p.displacement[-1]) * 1e3})
        print(rows[-1], flush=True)
    return rows


def main(argv=None) -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--out", type=Path, default=RESULTS)
    p.add_argument("--pose", nargs="+", metavar="RECORD:PRESSURE:SA",
                   help="make these FE runs of the 80 mm validation again to their first tear")
    p.add_argument("--tilt", nargs="+", type=float, metavar="DEG",
                   help="push the 80 mm rim with the slider turned this far off its path")
    args = p.parse_args(argv)
    if args.tilt:
        write_csv(tilted_push(args.tilt), args.out / "tearing_onset_tilt.csv")
        return
    motions = fema_p695("nearfield_pulse")
    if args.pose:
        cases = [(c.split(":")[0], int(c.split(":")[1]), float(c.split(":")[2]))
                 for c in args.pose]
        write_csv(pose_at_tear(cases, motions), args.out / "tearing_onset_pose.csv")
        return
    rows = []
    for thickness, folder in FOLDERS.items():
        table = validation_table(folder)
        if table is None:
            continue
        _, settings, laws = validation(thickness)
        finished = {(r["record"], round(float(r["pressure_mpa"]))): r
                    for r in read_csv(folder / table[0])
                    if table[1] or r["finished"] == "True"}
        runs = fe_tearing(folder, settings, motions)
        for motion in motions:
            for pressure in (60, 10):
                if (motion.name, pressure) in finished:
                    rows.append(case_row(thickness, motion, pressure,
                                         runs[(motion.name, pressure)], laws[pressure],
                                         settings, finished[(motion.name, pressure)]))
    write_csv(rows, args.out / "tearing_onset.csv")
    for thickness in FOLDERS:
        for pressure in (60, 10):
            group = [r for r in rows if r["rim_thickness_mm"] == thickness
                     and r["pressure_mpa"] == pressure]
            if not group:
                continue
            ratio = [r["fe_tore_over_rigid_rupture"] for r in group]
            earlier = [r for r in group if r["fe_tore_over_rigid_rupture"] < EARLIER]
            print(f"{thickness:g} mm, {pressure} MPa, {len(group)} cases: FE tore at "
                  f"{np.nanmedian(ratio):.2f} of the rigid rupture SA (median), at least 10 % "
                  f"below it on {len(earlier)}"
                  + "".join(f"\n  {r['record']}: FE tore at {r['fe_tore_at_g']:.2f} g, rigid "
                            f"rupture {r['rigid_rupture_sa_g']:.2f} g (rigid set there "
                            f"{r['rigid_max_set_mm_at_fe_tear']:.1f} of "
                            f"{r['law_rupture_set_mm']:.1f} mm)" for r in earlier))


if __name__ == "__main__":
    main()
