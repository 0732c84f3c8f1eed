"""Speed and memory of the 3-D rim push (fem.ring.ring_push) against CalculiX on the same mesh.

1. The baseline rim (40 × 35 mm, b = 0.4 m) pushed to half its height on the default 3-D mesh
   (``--mesh coarse`` for a quick look): the πb/4 punch, and with ``--cylinder`` the slider as
   a rigid cylinder on the rim-3d study's mesh for it (about 3 min of CPU on the default
   mesh); CPU and wall time, increments, factorisations, dofs and the process's peak memory.
2. The same punch push by CalculiX (``ccx``, C3D20R, small strain, the same increments): CPU
   time of the ccx process (skipped where ccx is absent).
3. The factorisation alone (one tangent of the default mesh): PARDISO's Cholesky, with its
   analysis of the pattern and reusing it, against SciPy's SuperLU (median of ``--repeat``).

Run: ``OMP_NUM_THREADS=1 MKL_NUM_THREADS=1 python benchmarks/bench_ring.py [--repeat N]
[--mesh coarse] [--cylinder]`` (about 7 minutes on an idle core, 3 more with ``--cylinder``).
Prints the machine's load before and after.
"""

from __future__ import annotations

import argparse
import math
import os
import resource
import time

import numpy as np

from fem.ring import COARSE, DEFAULT, Load, load_patch_widths, ring_mesh, ring_push
from fem.ring.ccx import ccx_available, run_ccx
from rigid import DFPBearing


def _peak_mb() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3, help="repeats of the factorisation timing")
    ap.add_argument("--mesh", choices=["coarse", "default"], default="default")
    ap.add_argument("--cylinder", action="store_true", help="also push with the cylinder")
    args = ap.parse_args()
    print(f"load average before: {os.getloadavg()}")
    bearing = DFPBearing()
    sizes = COARSE if args.mesh == "coarse" else DEFAULT
    mesh = ring_mesh(bearing, sizes=sizes, patch_widths=load_patch_widths(bearing))
    # the cylinder on the rim-3d study's mesh: layer edges at b/4 either side of the push
    cylinder_mesh = ring_mesh(bearing, sizes=sizes,
                              patch_widths=(0.5 * bearing.slider_diameter,))
    loads = [(Load("punch", math.pi * bearing.slider_diameter / 4), mesh)]
    loads += [(Load("cylinder"), cylinder_mesh)] if args.cylinder else []
    for load, grid in loads:
        push = ring_push(bearing, load, mesh=grid)
        print(f"ours {load.label}: CPU {push.cpu_time:.1f} s, wall {push.wall_time:.1f} s, "
              f"{push.increments} increments, {push.factorizations} factorisations, "
              f"{push.dofs} dofs, peak memory {_peak_mb():.0f} MB")
    if ccx_available():
        end = 0.5 * bearing.rim_height
        ccx = run_ccx(mesh, Load("punch", math.pi * bearing.slider_diameter / 4),
                      [(2e-3, 40), (end, round((end - 2e-3) / 5e-4))])
        print(f"CalculiX punch: CPU {ccx.cpu_time:.1f} s, {ccx.displacement.size - 1} "
              "increments")
    from fem.ring.linear import TangentSolver, default_backend
    from fem.ring.push import _Problem

    pb = _Problem(mesh, Load("cylinder"), True)
    _, tangent, _, plastic, _, _ = pb.residual(np.zeros(pb.solid.ndofs), 0.0, pb.state)
    K = pb.solid.stiffness(tangent, plastic, pb.elastic)[pb.free][:, pb.free]
    backends = ["superlu"] + (["pardiso"] if default_backend() == "pardiso" else [])
    b = np.ones(K.shape[0])
    for backend in backends:
        solver = TangentSolver(backend)
        solver.solve(K, b)  # warm-up: the solver's set-up (PARDISO looks for MKL once)
        fresh, reused = [], []
        for _ in range(args.repeat):
            for times, forget in ((fresh, True), (reused, False)):
                if forget:  # a new pattern: PARDISO's analysis (reordering) again
                    for pardiso in solver._pardiso.values():
                        pardiso.pattern = None
                t0 = time.process_time()
                solver.solve(K, b)
                times.append(time.process_time() - t0)
        line = f"factorisation and solve, {backend}: median {np.median(fresh):.2f} s CPU"
        if backend == "pardiso":
            line += f", {np.median(reused):.2f} s reusing the analysis"
        print(f"{line} ({K.shape[0]} unknowns)")
    print(f"load average after: {os.getloadavg()}")


if __name__ == "__main__":
    main()
