"""Ground motions: records and their file formats, record sets, Ricker pulses, response spectra
and FEMA P695 scaling, wavelet pulse extraction (paper §§3–4.1).

Nothing here knows the bearing: records are plain accelerations in m/s² with their time step.
The equations are in ``docs/theory/ground-motions.md``.
"""

from .cwt import MAX_PULSE_PERIOD, SOURCES, WEIGHTINGS, wavelet_transform
from .formats import read_record
from .pulse_extraction import (
    ALL_WEIGHTINGS,
    CRITERIA,
    Pulse,
    best_pulse,
    extract_pulse,
    extract_pulses,
)
from .pulses import KINDS, ricker, ricker_displacement, ricker_record, ricker_velocity
from .record import GroundMotion, RecordFormatError, cumulative_integral
from .record_sets import FEMA_P695_SETS, fema_p695, fema_p695_spectra, read_manifest
from .spectra import pseudo_acceleration, scale_factor, scaling_ladder, spectral_displacement

__all__ = [
    "ALL_WEIGHTINGS",
    "CRITERIA",
    "FEMA_P695_SETS",
    "KINDS",
    "MAX_PULSE_PERIOD",
    "SOURCES",
    "WEIGHTINGS",
    "GroundMotion",
    "Pulse",
    "RecordFormatError",
    "best_pulse",
    "cumulative_integral",
    "extract_pulse",
    "extract_pulses",
    "fema_p695",
    "fema_p695_spectra",
    "pseudo_acceleration",
    "read_manifest",
    "read_record",
    "ricker",
    "ricker_displacement",
    "ricker_record",
    "ricker_velocity",
    "scale_factor",
    "scaling_ladder",
    "spectral_displacement",
    "wavelet_transform",
]
