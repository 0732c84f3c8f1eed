"""Rigid-body model of a double friction pendulum bearing and everything that feeds or reads it.

Bao & Becker (2016), *Predicting failure in sliding isolation bearings under long-period
motions*, reproduced and extended. SI units throughout (m, s, kg, N, Pa; m/s²).
"""

from .bearing import DFPBearing, G, jankowski_damping_ratio
from .fragility import (
    CollapseMargin,
    LognormalFit,
    collapse_margin,
    fit_lognormal,
    set_collapse_intensity,
)
from .ida import CriticalSA, critical_sa, critical_sas
from .impact import (
    design_chart,
    impact_region_spectrum,
    impact_velocity_spectrum,
    load_spectrum,
    max_impact_velocity_spectra,
    region_at,
    region_boundaries,
    save_spectrum,
)
from .model import Impact, NumericalInstabilityError, SimulationResult, simulate
from .predict import PredictedSA, predict_critical_sa
from .pulses import ricker, ricker_displacement, ricker_record, ricker_velocity
from .record_sets import fema_p695, read_manifest
from .records import GroundMotion, RecordFormatError, read_record
from .spectra import pseudo_acceleration, scale_factor, scaling_ladder
from .sweep import SweepSettings
from .wavelet import Pulse, best_pulse, extract_pulse, extract_pulses

__all__ = [
    "CollapseMargin",
    "CriticalSA",
    "DFPBearing",
    "G",
    "GroundMotion",
    "Impact",
    "LognormalFit",
    "NumericalInstabilityError",
    "PredictedSA",
    "Pulse",
    "RecordFormatError",
    "SimulationResult",
    "SweepSettings",
    "best_pulse",
    "collapse_margin",
    "critical_sa",
    "critical_sas",
    "design_chart",
    "extract_pulse",
    "extract_pulses",
    "fema_p695",
    "fit_lognormal",
    "impact_region_spectrum",
    "impact_velocity_spectrum",
    "jankowski_damping_ratio",
    "load_spectrum",
    "max_impact_velocity_spectra",
    "predict_critical_sa",
    "pseudo_acceleration",
    "read_manifest",
    "read_record",
    "region_at",
    "region_boundaries",
    "ricker",
    "ricker_displacement",
    "ricker_record",
    "ricker_velocity",
    "save_spectrum",
    "scale_factor",
    "scaling_ladder",
    "set_collapse_intensity",
    "simulate",
]
