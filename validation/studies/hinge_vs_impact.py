"""How far the FE hinge lies above the first rim impact: for every record and pressure of a
validation run's FE comparison, the lowest SA(4.5 s) on the 0.01 g ladder at which the rigid
model (rigid rims) hits a rim at all, beside the FE and yielding-rim critical SA under the
hinge limit state. Searched from the FE answer: down while the rung still impacts, else up
until it does (the impact boundary is smooth in SA: docs/impact_spectra.md).

Run: ``python -m validation.studies.hinge_vs_impact [--out docs/fem-validation]``; writes
``docs/results/hinge_vs_first_impact.csv`` and prints the differences.
"""

from __future__ import annotations

import argparse
import collections
import csv
from pathlib import Path

import numpy as np

from rigid import DFPBearing, G, fema_p695, scale_factor, simulate
from rigid.collapse.comparison import write_csv

from . import FEM_VALIDATION, RESULTS

FREE = 20.0   # s simulated after the record, as the ladders


def lowest_rung(holds, start: int) -> int:
    """The lowest rung k ≥ 1 at which ``holds(k)`` is true (a rim impact), searched from
    ``start``: down while it still holds, else up until it does (the impact boundary is smooth
    in SA: docs/impact_spectra.md)."""
    k = start
    if not holds(k):
        k += 1
        while not holds(k):
            k += 1
        return k
    while k > 1 and holds(k - 1):
        k -= 1
    return k


def first_impact_rung(bearing, motion, start: int) -> tuple[int, float]:
    """(k, v): the lowest rung k (SA(Tb) = k × 0.01 g) with a rim impact, searched from
    ``start`` (:func:`lowest_rung`), and its largest impact velocity [m/s]."""
    a = np.asarray(motion.acceleration)
    per_sa = scale_factor(a, motion.dt, 1.0, period=bearing.design_period)  # PSA is linear
    velocity = {}

    def impact_velocity(k):  # 0 without impact
        r = simulate(bearing, a * (k * 0.01 * G * per_sa), motion.dt,
                     duration=(a.size - 1) * motion.dt + FREE, stop_at_failure=True,
                     stop_when_quiet=True, record_every=a.size, on_instability="refine")
        velocity[k] = float(r.max_impact_velocity) if len(r.impacts) else 0.0
        return velocity[k]

    k = lowest_rung(lambda k: impact_velocity(k) > 0.0, start)
    return k, velocity[k]


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--out", type=Path, default=FEM_VALIDATION,
                   help="the validation run's folder (its fem_comparison.csv)")
    args = p.parse_args()
    motions = {m.name: m for m in fema_p695("nearfield_pulse")}
    with open(args.out / "fem_comparison.csv") as fh:
        compared = [r for r in csv.DictReader(fh) if r["limit_state"] == "hinge"
                    and r["fem_sa_g"] not in ("", "nan")]
    rows = []
    for r in compared:
        bearing = DFPBearing(pressure=float(r["pressure_mpa"]) * 1e6)
        k, v = first_impact_rung(bearing, motions[r["record"]], round(float(r["fem_sa_g"]) * 100))
        rows.append({"record": r["record"], "pressure_mpa": float(r["pressure_mpa"]),
                     "first_impact_sa_g": k / 100, "first_impact_velocity_m_s": v,
                     "yielding_hinge_sa_g": float(r["yielding_sa_g"]),
                     "fem_hinge_sa_g": float(r["fem_sa_g"])})
    path = RESULTS / "hinge_vs_first_impact.csv"
    write_csv(rows, path)
    gap = collections.Counter(round(r["fem_hinge_sa_g"] - r["first_impact_sa_g"], 2)
                              for r in rows)
    v = [r["first_impact_velocity_m_s"] for r in rows]
    print(f"FE hinge SA minus first-impact SA [g]: {dict(sorted(gap.items()))}; impact "
          f"velocity at the first impact {min(v):.3f}–{max(v):.3f} m/s; {path}")


if __name__ == "__main__":
    main()
