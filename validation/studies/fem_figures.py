"""Pictures of the FE model's uplift failure for the README (docs/images/fem_light_uplift*).

The light bearing (10 MPa) under an antisymmetric Ricker pulse (Tp = 1 s, Ap = 1.2 g) on the
default mesh, with elastic steel (``plasticity=False``: rims that cannot yield, as in the rigid
model): the state at failure (PNG) and the impact that throws the slider out (GIF). The same
pulse with the assumed steel rims ends in a rim-root hinge (tests/test_fem_failure.py).

Run (a few minutes of CPU)::

    VTK_DEFAULT_OPENGL_WINDOW=vtkEGLRenderWindow python -m validation.studies.fem_figures
"""

from __future__ import annotations

import dataclasses
import time

import numpy as np

import fem
from fem.output import render_movie, render_result
from rigid import DFPBearing, G, ricker_record

from . import IMAGES

OUT = IMAGES
FRAMES = 40  # of the GIF, from the first rim contact to the failure


def main() -> None:
    bearing = DFPBearing(pressure=10e6)
    _, a = ricker_record(1.2 * G, 1.0, "antisymmetric", dt=0.005, free=3.0)
    cpu = time.process_time()
    # energy_tolerance 1e-4: the default 1e-3 lets the slider's rattle between the airborne
    # plates reach an energy error of 12 % of the input on this mesh (1.8 % at 1e-4)
    res = fem.simulate(bearing, a, 0.005, plasticity=False, duration=3.0, snapshot_every=2,
                       energy_tolerance=1e-4)
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


if __name__ == "__main__":
    main()
