"""Are the impact spectra's resolution and simulated duration sufficient? (issue 4, "Show").

Prints, for the light bearing (10 MPa) and both pulse kinds:

A. *Duration.* Bisected boundaries (± 0.001 g) at 20 periods with the default records
   (pulse ± 1.25/1.6·Tp, at most 20 s after it, early stop once no rim can be reached) and with
   everything doubled or more (pulse ± 3.2·Tp, 40 s after it). Change of each boundary [g].
B. *Period resolution.* Impact boundary (± 0.001 g) at the default 100 periods (uniform in
   Tb/Tp from 0.6 to 6) and at the 99 midpoints (the doubled grid): the error of the
   documented linear interpolation in Tb/Tp at the midpoints [g].
C. *Amplitude resolution* needs no run: on a monotonic column the grid boundary (midway
   between cells) is within half a step of the bisected one (tests/test_impact.py checks the
   bracket), so halving the 0.01 g step moves it by at most 0.005 + 0.0025 g < 0.01 g. Where
   the failure verdict is not monotonic in Ap no resolution is sufficient; those periods are
   flagged (A prints how many).

Uses the default cache, so a rerun is cheap. Run:
``python -m validation.studies.impact_resolution``.
"""

from __future__ import annotations

import time

import numpy as np

from rigid import DFPBearing, G, SweepSettings, region_boundaries
from rigid.impact import default_periods

BEARING = DFPBearing(pressure=10e6)
TOL = 0.001 * G


def duration_study(kind):
    periods = default_periods(BEARING, 20)
    base = region_boundaries(BEARING, kind, periods, tolerance=TOL, progress=False)
    long = region_boundaries(BEARING, kind, periods, tolerance=TOL, progress=False,
                             settings=SweepSettings(half_width=3.2, free=40.0))
    for name in ("impact", "failure"):
        a, b = base[f"{name}_boundary"].values / G, long[f"{name}_boundary"].values / G
        both = np.isfinite(a) & np.isfinite(b)
        d = np.abs(a - b)[both]
        same_nan = np.sum(np.isnan(a) & np.isnan(b))
        differ_nan = np.sum(np.isnan(a) != np.isnan(b))
        flags = int(np.sum(base[f"nonmonotonic_{name}"].values | long[f"nonmonotonic_{name}"]
                           .values))
        print(f"  A {kind:13s} {name:7s}: max |Δ| = {d.max() if d.size else 0:.4f} g over "
              f"{both.sum()} periods, {np.sum(d < 0.01)} with |Δ| < 0.01 g; not reached in "
              f"both: {same_nan}, in one only: {differ_nan}; flagged non-monotonic: {flags}")
        if d.size and d.max() >= 0.01:
            bad = np.flatnonzero(both)[d >= 0.01]
            for i in bad:
                print(f"      Tb/Tp = {4.5 / periods[i]:.3f}: {a[i]:.3f} g → {b[i]:.3f} g")


def period_study(kind):
    x = np.linspace(BEARING.design_period / 7.5, 6.0, 100)
    mid = 0.5 * (x[1:] + x[:-1])
    coarse = region_boundaries(BEARING, kind, BEARING.design_period / x, tolerance=TOL,
                               failure=False, progress=False)
    fine = region_boundaries(BEARING, kind, BEARING.design_period / mid, tolerance=TOL,
                             failure=False, progress=False)
    xc, bc = coarse.frequency_ratio.values, coarse.impact_boundary.values / G
    o = np.argsort(xc)
    xm, bm = fine.frequency_ratio.values, fine.impact_boundary.values / G
    ok = np.isfinite(bm)
    interp = np.interp(xm[ok], xc[o], bc[o])
    err = np.abs(interp - bm[ok])
    print(f"  B {kind:13s} impact : interpolation error at {ok.sum()} midpoints: max "
          f"{err.max():.4f} g, 95 % {np.percentile(err, 95):.4f} g, median {np.median(err):.4f}"
          f" g (bisection ± {TOL / G:.3f} g each)")
    worst = np.argsort(err)[-3:]
    for i in worst:
        print(f"      Tb/Tp = {xm[ok][i]:.3f}: interpolated {interp[i]:.4f} g, direct "
              f"{bm[ok][i]:.4f} g")


def main() -> None:
    t0 = time.perf_counter()
    for kind in ("symmetric", "antisymmetric"):
        duration_study(kind)
    for kind in ("symmetric", "antisymmetric"):
        period_study(kind)
    print(f"wall time {time.perf_counter() - t0:.0f} s")


if __name__ == "__main__":
    main()
