"""Uplift of the light bearing when its rims cannot yield: FE (``plasticity=False``) against
the rigid model, pulse by pulse.

With the assumed steel rims the light bearing's FE model fails by rim yielding, never by uplift
(``validation/studies/fem_uplift.py``). This study keeps the FE steel elastic, as the rigid
model keeps its rims rigid, and scans Ricker pulses (both kinds, Tp = 1, 2, 3 s, Ap on a ladder)
through both models: the FE model (coarse mesh, small strain,
``limit_state="containment"``) and the rigid model at several coefficients of restitution
e (the paper's 0.65 and higher: an elastic FE impact dissipates little). Small strain because
the elastic rims stay within it and finite deformation costs 10 times more in these flights and
landings (docs/fe-companion.md). For every pulse it prints the lowest failing amplitude of each
model and writes every run to a CSV, with the horizontal rebound ratio of the first rim impact
(−u̇ after / u̇ before, u the top plate relative to the bottom; both models measured alike).

Run: ``OMP_NUM_THREADS=1 python -m validation.studies.fem_elastic_rims [--out DIR]`` (32 min of
CPU, 17 min on two cores, for the default ladder 0.2–1.5 g by 0.1 g; runs go through the local
pool).
"""

from __future__ import annotations

import argparse
import csv
import os
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np

from fem.geometry import COARSE_MESH
from rigid import DFPBearing, G, ricker_record
from rigid.tasks import Task, run_tasks

from . import RESULTS

PULSES = [("symmetric", 1.0), ("symmetric", 2.0), ("symmetric", 3.0),
          ("antisymmetric", 1.0), ("antisymmetric", 2.0), ("antisymmetric", 3.0)]
RESTITUTIONS = (0.65, 0.8, 0.9, 0.95)
DT = 0.005  # input sampling [s]
PRESSURE = 10e6  # the light bearing [Pa]


def rebound_ratio(time, displacement, rim_force, merge=5e-3):
    """−u̇(after)/u̇(before) of the first rim contact episode (gaps < ``merge`` [s] joined);
    NaN without a rim contact or if the run ends inside it."""
    touching = np.flatnonzero(np.asarray(rim_force).reshape(len(time), -1).max(axis=1) > 0)
    if touching.size == 0:
        return float("nan")
    gaps = np.flatnonzero(np.diff(time[touching]) > merge)
    first, last = touching[0], touching[gaps[0]] if gaps.size else touching[-1]
    if first == 0 or last + 1 >= len(time):
        return float("nan")
    velocity = np.gradient(displacement, time)
    return float(-velocity[last + 1] / velocity[first - 1])


def run_pulse(kind: str, tp: float, ap_g: float, cache: str) -> dict:
    """Both models on one pulse; a JSON-able row."""
    import fem
    import rigid

    _, a = ricker_record(ap_g * G, tp, kind, dt=DT, free=3.0)
    row = {"kind": kind, "tp_s": tp, "ap_g": ap_g}
    for e in RESTITUTIONS:
        r = rigid.simulate(DFPBearing(pressure=PRESSURE, restitution=e), a, DT)
        row[f"rigid_e{e}"] = r.failure_mode or "none"
        if e == RESTITUTIONS[0]:
            row["rigid_impact_velocity_m_s"] = max((abs(i.velocity) for i in r.impacts),
                                                   default=0.0)
            row["rigid_rebound"] = rebound_ratio(r.time, r.displacement, r.rim_force)
    cpu = time.process_time()
    res = fem.simulate(DFPBearing(pressure=PRESSURE), a, DT, mesh_options=COARSE_MESH,
                       limit_state="containment", plasticity=False, kinematics="small",
                       cache_dir=cache)
    row.update(
        fem=("numerical" if res.numerical_failure else res.failure_mode or "none"),
        fem_failure_time_s=res.failure_time, fem_detail=res.failure_detail or "",
        fem_rebound=rebound_ratio(res.time, res.displacement, res.rim_force),
        fem_peak_rim_force_MN=float(res.rim_force.max() / 1e6),
        fem_max_top_plate_rise_mm=float(res.top_plate_rise.max() * 1e3),
        fem_energy_error=float(np.abs(res.energy["residual"]).max()
                               / max(np.abs(res.energy["input"]).max(), 1e-30)),
        fem_cpu_s=time.process_time() - cpu,
    )
    return row


def lowest_failure(rows, column):
    """Smallest amplitude [g] at which ``column`` reports a failure, or None."""
    failing = [r["ap_g"] for r in rows if r[column] not in ("none", "numerical")]
    return min(failing) if failing else None


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=RESULTS)
    parser.add_argument("--amplitudes", type=float, nargs=3, default=(0.2, 1.5, 0.1),
                        metavar=("FIRST", "LAST", "STEP"), help="Ap ladder [g]")
    args = parser.parse_args()
    first, last, step = args.amplitudes
    amplitudes = np.round(np.arange(first, last + step / 2, step), 3)
    with tempfile.TemporaryDirectory() as cache:
        from fem.geometry import build_mesh

        # once, not per worker
        build_mesh(DFPBearing(pressure=PRESSURE), cache_dir=cache, **COARSE_MESH)
        tasks = [Task(f"{kind}-{tp}-{ap}", "pulse", run_pulse,
                      {"kind": kind, "tp": tp, "ap_g": float(ap), "cache": cache})
                 for kind, tp in PULSES for ap in amplitudes]
        wall = time.perf_counter()
        results = run_tasks(tasks, None, progress=True, description="pulses")
        wall = time.perf_counter() - wall
    rows = [results[t.key] for t in tasks]
    args.out.mkdir(parents=True, exist_ok=True)
    path = args.out / "fem_elastic_rims_uplift.csv"
    with open(path, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    columns = ["fem"] + [f"rigid_e{e}" for e in RESTITUTIONS]
    print(f"light bearing ({PRESSURE / 1e6:.0f} MPa), lowest failing Ap [g] on "
          f"{first}–{last} g by {step} g; FE steel elastic")
    print(f"{'pulse':>10} " + " ".join(f"{c:>11}" for c in columns)
          + "   FE rebound / rigid(e=0.65) rebound at the first rim impact, median")
    for kind, tp in PULSES:
        sub = [r for r in rows if r["kind"] == kind and r["tp_s"] == tp]
        lows = [lowest_failure(sub, c) for c in columns]
        with np.errstate(all="ignore"), warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)  # all-NaN: no rim contact
            fe_e = np.nanmedian([r["fem_rebound"] for r in sub])
            rb_e = np.nanmedian([r["rigid_rebound"] for r in sub])
        cells = " ".join(f"{'-' if v is None else f'{v:.2f}':>11}" for v in lows)
        print(f"{kind[:4]} {tp:3.0f} s  {cells}   {fe_e:.2f} / {rb_e:.2f}")
    worst = max(r["fem_energy_error"] for r in rows)
    cpu = sum(r["fem_cpu_s"] for r in rows)
    print(f"largest FE energy-balance error (up to the stop) {worst:.1e} of the input; FE CPU "
          f"{cpu:.0f} s, wall {wall:.0f} s on {os.cpu_count()} CPUs; rows in {path}")


if __name__ == "__main__":
    main()
