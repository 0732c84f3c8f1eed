"""Impact spectra of the rigid model under Ricker pulses (paper §3): impact velocity spectra,
impact region spectra and their boundaries, the region of any pulse, and dimensionless design
charts. Built from cached, parallel pulse sweeps (:mod:`rigid.impact.sweep`); the definitions
are in ``docs/theory/impact-spectra.md``."""

from .boundaries import region_boundaries
from .design import design_chart
from .regions import grid_boundaries, nonmonotonic_periods, region_at
from .spectra import (
    bearing_from_attrs,
    default_amplitudes,
    default_periods,
    impact_region_spectrum,
    impact_velocity_spectrum,
    load_spectrum,
    max_impact_velocity_spectra,
    save_spectrum,
    settings_from_attrs,
)
from .sweep import Cell, SweepSettings, compute_cell, run_cells

__all__ = [
    "Cell",
    "SweepSettings",
    "bearing_from_attrs",
    "compute_cell",
    "default_amplitudes",
    "default_periods",
    "design_chart",
    "grid_boundaries",
    "impact_region_spectrum",
    "impact_velocity_spectrum",
    "load_spectrum",
    "max_impact_velocity_spectra",
    "nonmonotonic_periods",
    "region_at",
    "region_boundaries",
    "run_cells",
    "save_spectrum",
    "settings_from_attrs",
]
