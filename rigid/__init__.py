"""Rigid-body model of a double friction pendulum bearing and everything that feeds or reads it.

Bao & Becker (2016), *Predicting failure in sliding isolation bearings under long-period
motions*, reproduced and extended. SI units throughout (m, s, kg, N, Pa; m/s²).
"""

from .bearing import G, DFPBearing, jankowski_damping_ratio
from .pulses import ricker, ricker_displacement, ricker_record, ricker_velocity

__all__ = [
    "G",
    "DFPBearing",
    "jankowski_damping_ratio",
    "ricker",
    "ricker_displacement",
    "ricker_record",
    "ricker_velocity",
]
from .record_sets import fema_p695, read_manifest  # noqa: E402
from .records import GroundMotion, RecordFormatError, read_record  # noqa: E402
from .spectra import pseudo_acceleration, scale_factor, scaling_ladder  # noqa: E402
from .wavelet import Pulse, best_pulse, extract_pulse, extract_pulses  # noqa: E402

__all__ += [
    "GroundMotion",
    "Pulse",
    "RecordFormatError",
    "best_pulse",
    "extract_pulse",
    "extract_pulses",
    "fema_p695",
    "pseudo_acceleration",
    "read_manifest",
    "read_record",
    "scale_factor",
    "scaling_ladder",
]
