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
