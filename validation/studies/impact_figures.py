"""Figures of the impact spectra for the documentation (docs/images/impact_*.png).

Paper Figs. 6–8 for the light (10 MPa) and heavy (60 MPa) bearings and a dimensionless
design chart. Uses the default sweep cache, so reruns are cheap. Grid sizes are arguments
(defaults: 30 periods × 30 amplitudes for Fig. 8 and 50 periods for the bisected boundaries,
enough for a picture; the full grid is ``--periods 100 --amplitudes 100``).

Run: ``python -m validation.studies.impact_figures [--out docs/images]``.
"""

from __future__ import annotations

import argparse
import dataclasses
from pathlib import Path

import numpy as np

from rigid import (
    DFPBearing,
    G,
    design_chart,
    impact_region_spectrum,
    impact_velocity_spectrum,
    region_boundaries,
    save_spectrum,
)
from rigid.impact import default_amplitudes, default_periods
from rigid.impact.plots import (
    plot_design_chart,
    plot_impact_region_spectrum,
    plot_impact_velocity_spectrum,
    plot_max_impact_velocity_spectra,
)

from . import IMAGES


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=IMAGES)
    parser.add_argument("--periods", type=int, default=30)
    parser.add_argument("--amplitudes", type=int, default=30)
    parser.add_argument("--data", type=Path, default=None, help="also save NetCDF here")
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    for pressure, tag in ((10e6, "light"), (60e6, "heavy")):
        b = DFPBearing(pressure=pressure)
        for kind in ("symmetric", "antisymmetric"):
            ds = impact_velocity_spectrum(b, kind, 0.8 * G, default_periods(b))
            plot_impact_velocity_spectrum(ds, args.out / f"impact_fig6_{tag}_{kind}.png")
            if args.data:
                save_spectrum(ds, args.data / f"ivs_{tag}_{kind}_0.8g.nc")
    light = DFPBearing(pressure=10e6)
    for kind in ("symmetric", "antisymmetric"):
        grid = impact_region_spectrum(light, kind, default_periods(light, args.periods),
                                      default_amplitudes(args.amplitudes))
        bounds = region_boundaries(light, kind, default_periods(light, 50))
        plot_impact_region_spectrum(grid, args.out / f"impact_fig8_light_{kind}.png",
                                    boundaries=bounds)
        plot_max_impact_velocity_spectra(grid, args.out / f"impact_fig7_light_{kind}.png",
                                         amplitudes=G * np.array([0.2, 0.4, 0.6, 0.8, 1.0]))
        if args.data:
            save_spectrum(grid, args.data / f"irs_light_{kind}.nc")
            save_spectrum(bounds, args.data / f"bounds_light_{kind}.nc")
        print(kind, "non-monotonic periods (failure / impact):",
              int(grid.nonmonotonic_failure.sum()), int(grid.nonmonotonic_impact.sum()),
              "of", grid.sizes["period"])
    cases = [dataclasses.replace(light, friction=mu, capacity=cap)
             for mu in (0.03, 0.05, 0.08) for cap in (0.20, 0.30)]
    chart = design_chart(cases, "symmetric", np.linspace(0.6, 6.0, 12), scan_step=None)
    plot_design_chart(chart, args.out / "impact_design_chart_symmetric.png")
    if args.data:
        chart.to_netcdf(args.data / "design_chart_symmetric.nc")


if __name__ == "__main__":
    main()
