"""Rigid-body model of a double friction pendulum bearing and everything that feeds or reads it.

Bao & Becker (2016), *Predicting failure in sliding isolation bearings under long-period
motions*, reproduced and extended. SI units throughout (m, s, kg, N, Pa; m/s²).

Layout: the neutral base that ``fem`` and ``validation`` build on too (:mod:`rigid.units`,
:mod:`rigid.bearing`, :mod:`rigid.limit_states`, :mod:`rigid.inputs`, :mod:`rigid.limits`;
:mod:`rigid.tasks`: result store, cache, task runner); the model itself (:mod:`rigid.model`
and its Numba kernel; :mod:`rigid.rims`, the law of its yielding rims as data, computed by
``fem.rim_law``); :mod:`rigid.motions` (records, record sets, pulses, spectra, pulse
extraction); :mod:`rigid.impact` (impact spectra, paper §3); :mod:`rigid.collapse` (critical
SA, its prediction, fragility, paper §4). ``rigid`` never imports ``fem`` or ``validation``
(docs/architecture.md). Every public name is importable from ``rigid`` itself.
"""

from .bearing import DFPBearing, jankowski_damping_ratio
from .collapse import (
    CollapseMargin,
    CriticalSA,
    LognormalFit,
    PredictedSA,
    collapse_margin,
    critical_sa,
    critical_sa_by_limit_state,
    critical_sas,
    fit_lognormal,
    predict_critical_sa,
    set_collapse_intensity,
)
from .impact import (
    SweepSettings,
    design_chart,
    impact_region_spectrum,
    impact_velocity_spectrum,
    load_spectrum,
    max_impact_velocity_spectra,
    region_at,
    region_boundaries,
    save_spectrum,
)
from .limit_states import LIMIT_STATES, check_limit_state
from .model import Impact, NumericalInstabilityError, SimulationResult, simulate
from .motions import (
    GroundMotion,
    Pulse,
    RecordFormatError,
    best_pulse,
    extract_pulse,
    extract_pulses,
    fema_p695,
    pseudo_acceleration,
    read_manifest,
    read_record,
    ricker,
    ricker_displacement,
    ricker_record,
    ricker_velocity,
    scale_factor,
    scaling_ladder,
)
from .reprs import install as _short_reprs
from .results import EnergyBalance
from .rims import RimLaw, rim_law
from .units import G

_short_reprs(SimulationResult, EnergyBalance, CriticalSA, PredictedSA, CollapseMargin, RimLaw)

__all__ = [
    "LIMIT_STATES",
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
    "RimLaw",
    "SimulationResult",
    "SweepSettings",
    "best_pulse",
    "check_limit_state",
    "collapse_margin",
    "critical_sa",
    "critical_sa_by_limit_state",
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
    "rim_law",
    "save_spectrum",
    "scale_factor",
    "scaling_ladder",
    "set_collapse_intensity",
    "simulate",
]
