"""The rim as a ring: 3-D static pushes of the rim (:func:`fem.ring.ring_push`) against the
plane-strain strip of the same section, and the effective depth d_eff = F_3D / f_2D at the
hinge, at the rupture strain and at the limit load (docs/rim-3d/README.md;
docs/theory/finite-elements.md, Eqs. F54–F58).

The pushes run as a resumable task set (``docs/rim-3d/store/results.sqlite``): the slider as a
rigid cylinder on rims 40–320 mm thick, 35 and 70 mm high, under sliders of 0.4 and 0.6 m; on
the baseline rim also rigid punches and uniform pressures of widths b/4, πb/4 and b, and the
coarse and fine meshes. Writes ``docs/rim-3d/pushes.csv`` (one row a model, load, mesh and rim)
and ``docs/rim-3d/curves.csv`` (the force–displacement curves); the figure is
:mod:`validation.studies.rim3d_figures`, the check with CalculiX
:mod:`validation.studies.rim3d_ccx`.

Run (about an hour on two cores; an interrupted run resumes)::

    python -m validation.studies.rim3d [--workers 2] [--only baseline]
"""

from __future__ import annotations

import argparse
import csv
import dataclasses
import math
from pathlib import Path

import numpy as np

from fem.ring import COARSE, DEFAULT
from fem.ring.ccx import ccx_available

from . import DOCS

#: The study's folder: tables, store and figures.
FOLDER = DOCS / "rim-3d"
#: The rims (thickness [mm], height [mm], slider diameter [m]), the full factorial of four
#: thicknesses, two heights and two sliders: the thickness sweep at the baseline's height and
#: slider, the taller rim and the larger slider at a thin and a thick rim (the first study),
#: then the other eight.
GEOMETRIES = ((40, 35, 0.4), (80, 35, 0.4), (160, 35, 0.4), (320, 35, 0.4),
              (40, 70, 0.4), (160, 70, 0.4), (40, 35, 0.6), (160, 35, 0.6),
              (80, 70, 0.4), (320, 70, 0.4), (80, 35, 0.6), (320, 35, 0.6),
              (40, 70, 0.6), (80, 70, 0.6), (160, 70, 0.6), (320, 70, 0.6))
#: The meshes of the convergence check (MeshSizes fields, which key the stored pushes):
#: fem.ring's coarse and default, and a finer one made here (6 elements across the rim and up
#: its height, 6.7 mm arcs; the plate strip as the default's: the rim's section and arc are
#: what the hinge and contact resolve).
STUDY_MESHES = {"coarse": dataclasses.astuple(COARSE), "default": dataclasses.astuple(DEFAULT),
                "fine": (6, 6, 4, 4, 0.010 / 1.5, 1.3 ** (1 / 1.5))}
COLUMNS = ("model", "load", "mesh", "rim_thickness_mm", "rim_height_mm", "slider_diameter_m",
           "first_yield_mn", "hinge_mn", "rupture_mn", "limit_mn", "d_eff_first_yield_m",
           "d_eff_hinge_m", "d_eff_rupture_m", "d_eff_limit_m", "hinge_displacement_mm",
           "rupture_displacement_mm", "plastic_arc_m", "dofs", "increments", "cpu_s")


def bearing_for(thickness_mm: float, height_mm: float, slider_m: float):
    """The baseline bearing with the given rim thickness and height [mm] and slider diameter
    [m], the slider raised where needed to keep the baseline's clearance between the rims."""
    from rigid import DFPBearing

    base = DFPBearing()
    bearing = dataclasses.replace(base, rim_thickness=thickness_mm / 1e3)
    # a taller rim or a wider slider (a deeper dish at the rim) needs a taller slider to keep
    # the baseline's clearance between the plates' rims; the push does not involve it
    height = base.slider_height
    while True:  # the lowest slider, in mm, that keeps the baseline's clearance
        try:
            trial = dataclasses.replace(bearing, rim_height=height_mm / 1e3,
                                        slider_diameter=slider_m, slider_height=height)
            if trial.rim_clearance >= base.rim_clearance - 1e-12:
                return trial
        except ValueError:
            pass
        height = round(height + 1e-3, 6)


def mesh_for(bearing, kind: str, sizes: tuple):
    """The push's mesh: the strip's slab, the patch loads' ring with layer edges on the three
    patches' edges (b/4, πb/4, b), the cylinder's with 10 mm layers to b/4 either side."""
    from fem.ring import MeshSizes, load_patch_widths, ring_mesh

    if kind == "strip":
        return ring_mesh(bearing, sizes=MeshSizes(*sizes), kind="slab")
    widths = (load_patch_widths(bearing) if kind in ("punch", "pressure")
              else (0.5 * bearing.slider_diameter,))
    return ring_mesh(bearing, sizes=MeshSizes(*sizes), patch_widths=widths)


def push_task(thickness_mm: float, height_mm: float, slider_m: float, kind: str,
              width_m: float, mesh: str, sizes: tuple) -> dict:
    """One push (the task's function): its points and curve as JSON [N, m; the strip per m]."""
    from fem.ring import Load, ring_push

    bearing = bearing_for(thickness_mm, height_mm, slider_m)
    push = ring_push(bearing, Load(kind, width_m), mesh=mesh_for(bearing, kind, sizes))
    return {
        "first_yield": push.first_yield_force, "hinge": push.hinge_force,
        "rupture": push.rupture_force, "limit": push.limit_force,
        "hinge_displacement": push.hinge_displacement,
        "rupture_displacement": push.rupture_displacement, "plastic_arc": push.plastic_arc,
        "dofs": int(push.dofs), "increments": int(push.increments),
        "cpu": float(push.cpu_time), "wall": float(push.wall_time),
        "displacement": push.displacement.tolist(), "force": push.force.tolist(),
    }


def ccx_task(thickness_mm: float, height_mm: float, slider_m: float, kind: str,
             width_m: float, mesh: str, sizes: tuple, nlgeom: bool) -> dict:
    """The same push by CalculiX (a punch or the strip; :func:`fem.ring.ccx.run_ccx`), in the
    increments of ours: 0.05 mm to 2 mm, then 0.5 mm."""
    from fem.ring import Load
    from fem.ring.ccx import quadratic_nodes, run_ccx

    bearing = bearing_for(thickness_mm, height_mm, slider_m)
    grid = mesh_for(bearing, kind, sizes)
    end = 0.5 * bearing.rim_height
    push = run_ccx(grid, Load(kind, width_m), [(2e-3, 40), (end, round((end - 2e-3) / 5e-4))],
                   nlgeom=nlgeom)
    whole = np.flatnonzero(push.root_yielded >= 1.0)
    return {
        "first_yield": math.nan, "rupture": math.nan, "rupture_displacement": math.nan,
        "hinge": float(push.force[whole[0]]) if whole.size else math.nan,
        "hinge_displacement": float(push.displacement[whole[0]]) if whole.size else math.nan,
        "limit": float(push.force.max()), "plastic_arc": math.nan,
        "dofs": int(3 * quadratic_nodes(grid)[0].shape[1]),
        "increments": int(push.displacement.size - 1),
        "cpu": float(push.cpu_time), "wall": math.nan,
        "displacement": push.displacement.tolist(), "force": push.force.tolist(),
    }


def cases(only: str | None = None) -> list[dict]:
    """Every push of the study (model, geometry, load, mesh), the most telling first: the
    baseline rim under the cylinder, CalculiX's checks, the patches, the other rims, the
    meshes; last the baseline's cylinder on the fine mesh and the other rims' on the default
    one (the costliest pushes)."""
    b = 0.4
    base = dict(thickness_mm=40, height_mm=35, slider_m=b, model="ours")

    def case(kind, width=0.0, mesh="default", **kw):
        return dict(base, kind=kind, width_m=width, mesh=mesh, sizes=STUDY_MESHES[mesh], **kw)

    out = [case("strip"), case("cylinder")]
    if ccx_available():
        out += [case(kind, w, model=model) for model in ("ccx", "ccx-nlgeom")
                for kind, w in (("strip", 0.0), ("punch", math.pi * b / 4))]
    else:
        print("CalculiX (ccx) is not on the PATH: its pushes are left out")
    out += [case(kind, w) for kind in ("punch", "pressure") for w in (b / 4, math.pi * b / 4, b)]
    out += [case(kind, mesh="coarse") for kind in ("strip", "cylinder")]
    if only != "baseline":  # the rims: the πb/4 punch on the default mesh, the cylinder on
        # the coarse one (ten times cheaper; the baseline's two meshes tie them)
        for t, h, slider in GEOMETRIES[1:]:
            rim = dict(thickness_mm=t, height_mm=h, slider_m=slider)
            out += [dict(case("strip"), **rim),
                    dict(case("punch", math.pi * slider / 4), **rim),
                    dict(case("strip", mesh="coarse"), **rim),
                    dict(case("cylinder", mesh="coarse"), **rim)]
    out += [case("punch", math.pi * b / 4, mesh=mesh) for mesh in ("coarse", "fine")]
    out += [case("strip", mesh="fine")]
    out += [case("cylinder", mesh="fine")]  # the cylinder's third mesh
    if only != "baseline":  # the cylinder on the default mesh for the other rims too
        out += [dict(case("cylinder"), thickness_mm=t, height_mm=h, slider_m=slider)
                for t, h, slider in GEOMETRIES[1:]]
    return out


def _tasks(only: str | None = None):
    """The study's tasks and their cases by key."""
    from rigid.tasks import Task, task_key

    tasks, keyed = [], {}
    for case in cases(only):
        kw = {k: v for k, v in case.items() if k != "model"}
        if case["model"] == "ours":
            key = task_key("ring-push", ("fem-ring",), **kw)
            tasks.append(Task(key=key, kind="ring-push", func=push_task, kwargs=kw))
        else:
            kw["nlgeom"] = case["model"] == "ccx-nlgeom"
            key = task_key("ccx-ring-push", ("fem-ring",), **kw)
            tasks.append(Task(key=key, kind="ccx-ring-push", func=ccx_task, kwargs=kw))
        keyed[key] = case
    return tasks, keyed


ORDER = ("thickness_mm", "height_mm", "slider_m", "kind", "width_m", "mesh", "model")


def run(only: str | None = None, workers: int | None = None, store_path=None,
        replay: bool = False) -> dict:
    """Run the pushes not yet stored (``replay``: none, read what is stored); return every
    result by case: (thickness, height, slider, kind, width, mesh, model)."""
    from rigid.tasks import ResultStore, run_tasks

    store_path = Path(store_path or FOLDER / "store" / "results.sqlite")
    store = ResultStore(store_path)
    tasks, keyed = _tasks(only)
    if replay:
        results = store.get_many(keyed)
    else:
        results = run_tasks(tasks, store, workers=workers, description="rim pushes",
                            log=store_path.parent / "progress.log")
    store.close()
    return {tuple(keyed[k][f] for f in ORDER): v for k, v in results.items()}


def _mn(x: float) -> float:
    return x / 1e6 if math.isfinite(x) else math.nan


def rows(results: dict) -> tuple[list[dict], list[dict]]:
    """The table of pushes and the curves' rows from the results (:func:`run`)."""
    table, curves = [], []
    for (t, h, b, kind, width, mesh, model), r in sorted(results.items(), key=lambda kv: (
            kv[0][6], kv[0][5] != "default", kv[0][5], *kv[0][:5])):
        strip = results.get((t, h, b, "strip", 0.0, mesh, model))
        depth = math.pi * b / 4  # today's out-of-plane depth (Eq. F1)
        label = kind if kind in ("strip", "cylinder") else f"{kind} {width * 1e3:.0f} mm"
        name = "2d" if kind == "strip" else "3d"
        row = {"model": name if model == "ours" else model.replace("ccx", "ccx-" + name),
               "load": label, "mesh": mesh,
               "rim_thickness_mm": t, "rim_height_mm": h, "slider_diameter_m": b,
               "dofs": r["dofs"], "increments": r["increments"], "cpu_s": round(r["cpu"], 1),
               "hinge_displacement_mm": r["hinge_displacement"] * 1e3,
               "rupture_displacement_mm": r["rupture_displacement"] * 1e3,
               "plastic_arc_m": r["plastic_arc"]}
        scale = depth if kind == "strip" else 1.0  # the 2-D rows as today's model sees them
        for point in ("first_yield", "hinge", "rupture", "limit"):
            value = r[point] * scale
            row[f"{point}_mn"] = _mn(value)
            if kind == "strip":  # today's model: the depth by definition
                row[f"d_eff_{point}_m"] = depth
            else:  # Eq. F54, against the strip of the same mesh and model
                per_depth = strip[point] if strip is not None else math.nan
                row[f"d_eff_{point}_m"] = value / per_depth if math.isfinite(per_depth) \
                    and math.isfinite(value) else math.nan
        table.append(row)
        for d, f in zip(r["displacement"], r["force"], strict=True):
            curves.append({"model": row["model"], "load": label, "mesh": mesh,
                           "rim_thickness_mm": t, "rim_height_mm": h, "slider_diameter_m": b,
                           "displacement_mm": round(d * 1e3, 6), "force_mn": f * scale / 1e6})
    return table, curves


def write(path: Path, records: list[dict], columns) -> None:
    """A CSV of the records with the given columns, numbers to 6 significant digits."""
    path.parent.mkdir(parents=True, exist_ok=True)
    with open(path, "w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=list(columns))
        writer.writeheader()
        for rec in records:
            writer.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v)
                             for k, v in rec.items() if k in columns})


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--only", choices=["baseline"], help="only the baseline rim's pushes")
    ap.add_argument("--workers", type=int, default=None, help="local processes (default: cores)")
    ap.add_argument("--out", default=str(FOLDER))
    ap.add_argument("--replay", action="store_true",
                    help="write the tables from the stored pushes only, running none")
    args = ap.parse_args()
    out = Path(args.out)
    results = run(args.only, args.workers, out / "store" / "results.sqlite", args.replay)
    table, curves = rows(results)
    write(out / "pushes.csv", table, COLUMNS)
    write(out / "curves.csv", curves, ("model", "load", "mesh", "rim_thickness_mm",
                                       "rim_height_mm", "slider_diameter_m",
                                       "displacement_mm", "force_mn"))
    for row in table:
        if row["mesh"] == "default":
            print(f"{row['model']} {row['load']:>16} t={row['rim_thickness_mm']:>3} "
                  f"h={row['rim_height_mm']} b={row['slider_diameter_m']}: hinge "
                  f"{row['hinge_mn']:.3f} MN, limit {row['limit_mn']:.3f} MN, d_eff "
                  f"{row['d_eff_hinge_m']:.3f}/{row['d_eff_limit_m']:.3f} m")


if __name__ == "__main__":
    main()
