"""Pictures of the FE model's failures for the docs (docs/images/fem_*).

``uplift`` (default): the light bearing (10 MPa) under an antisymmetric Ricker pulse
(Tp = 1 s, Ap = 1.2 g) on the default mesh, small strain, with elastic steel
(``plasticity=False``: rims that cannot yield, as in the rigid model): the state at failure
(``fem_light_uplift.png``) and the impact that throws the slider out (``.gif``). The same pulse
with the assumed steel rims ends in a rim-root hinge (tests/test_fem_failure.py).

``past-hinge``: the heavy bearing (60 MPa; ``--pressure 10``: the light one) under
SUPERST/B-PTS_037 scaled to ``--sa`` [g] of SA(4.5 s), default mesh, finite deformation, run
past the first hinge and the rupture to the loss of containment: the state then
(``fem_heavy_past_hinge.png`` or ``fem_light_…``, and ``_rim.png``, zoomed on the rim that let
go) and the sequence from just before the hinge (``.gif``). ``--edge-radius MM`` rounds the
slider's edges (``fem.simulate(edge_radius=…)``; file names end in ``_rounded``).

Run (``uplift``: a few minutes of CPU; ``past-hinge``: about half an hour)::

    VTK_DEFAULT_OPENGL_WINDOW=vtkEGLRenderWindow python -m validation.studies.fem_figures \
        [uplift | past-hinge [--sa 0.20] [--mesh coarse] [--pressure 10] [--edge-radius 20]]
"""

from __future__ import annotations

import argparse
import dataclasses
import time

import numpy as np

import fem
import rigid
from fem.limit_states import corner_nodes
from fem.output import render_movie, render_result
from rigid import DFPBearing, G, ricker_record
from rigid.collapse.trimming import trimmed_window

from . import IMAGES

OUT = IMAGES
FRAMES = 40  # of the GIF, from the first rim contact to the failure


def uplift() -> None:
    """The light bearing with elastic steel (module docstring)."""
    bearing = DFPBearing(pressure=10e6)
    _, a = ricker_record(1.2 * G, 1.0, "antisymmetric", dt=0.005, free=3.0)
    cpu = time.process_time()
    # energy_tolerance 1e-4: the default 1e-3 lets the slider's rattle between the airborne
    # plates reach an energy error of 12 % of the input on this mesh (1.8 % at 1e-4)
    res = fem.simulate(bearing, a, 0.005, plasticity=False, duration=3.0, snapshot_every=2,
                       energy_tolerance=1e-4, kinematics="small")
    cpu = time.process_time() - cpu
    print(res.summary())
    print(f"CPU {cpu:.0f} s; largest top-plate rise {res.top_plate_rise.max() * 1e3:.0f} mm; "
          f"energy error {np.abs(res.energy['residual']).max() / 1e3:.1f} kJ")
    title = (f"10 MPa bearing, elastic steel: {res.failure_mode} at t = {res.failure_time:.3f} s"
             f" ({res.failure_detail})")
    # colour scale capped at f_u: red is where the assumed steel would have yielded
    clims = {"von_mises": (0.0, bearing.ultimate_stress / 1e6), "eq_plastic_strain": (0.0, 1.0)}
    render_result(OUT / "fem_light_uplift.png", res, title=title, clims=clims)
    first_contact = res.time[np.flatnonzero(res.rim_force.max(axis=1) > 0)[0]]
    frames = [s for s in res.snapshots if s[0] >= first_contact - 0.02]
    frames = frames[:: max(1, len(frames) // FRAMES)]
    impact = dataclasses.replace(res, snapshots=tuple(frames))
    render_movie(OUT / "fem_light_uplift.gif", impact, title="10 MPa, elastic steel", fps=8,
                 window=(1000, 625), clims=clims)


def past_the_hinge(sa_g: float, mesh: str = "default", pressure_mpa: float = 60.0,
                   edge_radius_mm: float = 0.0) -> None:
    """A bearing past the hinge to the loss of containment (module docstring), on the default
    or the coarse mesh (file names with ``_coarse``); ``pressure_mpa`` [MPa] 60 or 10;
    ``edge_radius_mm`` [mm] the slider's edge radius (0: sharp)."""
    from validation.fem_runs import MESHES

    weight = {60.0: "heavy", 10.0: "light"}[pressure_mpa]
    name = (f"fem_{weight}_past_hinge" + ("" if mesh == "default" else f"_{mesh}")
            + ("_rounded" if edge_radius_mm else ""))
    bearing = DFPBearing(pressure=pressure_mpa * 1e6)
    motion = next(m for m in rigid.fema_p695("nearfield_pulse") if "B-PTS_037" in m.name)
    a = motion.acceleration * rigid.scale_factor(motion.acceleration, motion.dt, sa_g * G)
    window = trimmed_window(bearing, a, motion.dt, "end", lead=0.1)
    t0 = window.start * motion.dt
    cpu = time.process_time()
    res = fem.simulate(bearing, a[window.start:], motion.dt, limit_state="containment",
                       duration=(a.size - 1) * motion.dt - t0 + 5.0, snapshot_every=4,
                       mesh_options=MESHES[mesh], edge_radius=edge_radius_mm / 1e3)
    cpu = time.process_time() - cpu
    print(res.summary())
    print(f"CPU {cpu:.0f} s; energy error {np.abs(res.energy['residual']).max() / 1e3:.1f} kJ "
          f"of {res.energy['input'].max() / 1e6:.2f} MJ input")
    states = ", ".join(f"{k} {t0 + v:.3f} s" for k, v in res.limit_states.items()
                       if v is not None)
    outcome = ("numerical: " + res.failure_detail if res.numerical_failure
               else res.failure_mode or "no failure")
    edges = f", edges rounded to {edge_radius_mm:g} mm" if edge_radius_mm else ""
    title = (f"{pressure_mpa:g} MPa, B-PTS_037 at {sa_g:g} g, {mesh} mesh{edges}: {states}; "
             f"{outcome}")
    clims = {"von_mises": (0.0, bearing.ultimate_stress / 1e6), "eq_plastic_strain": (0.0, 1.0)}
    render_result(OUT / f"{name}.png", res, title=title, clims=clims)
    # zoom on the first rim to hinge, at its deformed inner corner (vector dofs interleaved)
    rim = min(res.hinge_times, key=res.hinge_times.get) if res.hinge_times else "bottom +x"
    node = corner_nodes(res.mesh, bearing)[rim]
    x, z = res.mesh.p[:, node] + res.final_displacement[[2 * node, 2 * node + 1]]
    render_result(OUT / f"{name}_rim.png", res, title=f"{title}; {rim} rim", clims=clims,
                  focus=(x, z, 0.12))
    hinge = res.limit_states["hinge"]
    if hinge is None:
        return
    frames = [s for s in res.snapshots if s[0] >= hinge - 0.05]
    frames = frames[:: max(1, len(frames) // FRAMES)]
    movie = dataclasses.replace(res, snapshots=tuple(frames))
    render_movie(OUT / f"{name}.gif", movie,
                 title=f"{pressure_mpa:g} MPa, finite deformation{edges}", fps=8,
                 window=(1000, 625), clims=clims)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("case", nargs="?", choices=("uplift", "past-hinge"), default="uplift")
    ap.add_argument("--sa", type=float, default=0.20, help="SA(4.5 s) [g] (past-hinge)")
    ap.add_argument("--mesh", choices=("default", "coarse"), default="default",
                    help="FE mesh (past-hinge)")
    ap.add_argument("--pressure", type=float, choices=(60.0, 10.0), default=60.0,
                    help="slider pressure [MPa] (past-hinge)")
    ap.add_argument("--edge-radius", type=float, default=0.0,
                    help="radius of the slider's rounded edges [mm] (past-hinge; 0: sharp)")
    args = ap.parse_args()
    if args.case == "uplift":
        uplift()
    else:
        past_the_hinge(args.sa, args.mesh, args.pressure, args.edge_radius)


if __name__ == "__main__":
    main()
