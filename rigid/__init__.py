"""Rigid-body model of a double friction pendulum bearing and everything that feeds or reads it.

Bao & Becker (2016), *Predicting failure in sliding isolation bearings under long-period
motions*, reproduced and extended. SI units throughout (m, s, kg, N, Pa; m/s²).
"""

from .bearing import DFPBearing, G, jankowski_damping_ratio
from .ida import CriticalSA, critical_sa, critical_sas
from .model import Impact, NumericalInstabilityError, SimulationResult, simulate
from .pulses import ricker, ricker_displacement, ricker_record, ricker_velocity
from .record_sets import fema_p695, read_manifest
from .records import GroundMotion, RecordFormatError, read_record
from .spectra import pseudo_acceleration, scale_factor, scaling_ladder
from .wavelet import Pulse, best_pulse, extract_pulse, extract_pulses

__all__ = [
    "CriticalSA",
    "DFPBearing",
    "G",
    "GroundMotion",
    "Impact",
    "NumericalInstabilityError",
    "Pulse",
    "RecordFormatError",
    "SimulationResult",
    "best_pulse",
    "critical_sa",
    "critical_sas",
    "extract_pulse",
    "extract_pulses",
    "fema_p695",
    "jankowski_damping_ratio",
    "pseudo_acceleration",
    "read_manifest",
    "read_record",
    "ricker",
    "ricker_displacement",
    "ricker_record",
    "ricker_velocity",
    "scale_factor",
    "scaling_ladder",
    "simulate",
]
