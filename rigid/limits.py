"""Plausibility limits of the inputs, checked before anything is allocated or run, so that a
wrong header, wrong units or a mistyped argument gives a clear error instead of a hang, an
out-of-memory crash or a numerical blow-up reported as a result.

Every limit is in SI units (seconds, m/s², Pa) and is documented, with its reason, in
``docs/limits.md``. Two tiers: what a *record file or a user argument* may hold (the edges: the
readers, manifests, the ``dfp`` command), and what the *models* accept
(:func:`rigid.model.check_model_input`), which is wider because ladders scale records beyond
anything recorded.
"""

from __future__ import annotations

import math

from .units import G

__all__ = [
    "MAX_FILE_BYTES",
    "MAX_MODEL_ACCELERATION",
    "MAX_MODEL_DURATION",
    "MAX_MODEL_SAMPLES",
    "MAX_RECORD_ACCELERATION",
    "MAX_RECORD_DURATION",
    "MAX_RECORD_SAMPLES",
    "MAX_SA_STOP",
    "PRESSURE_RANGE",
    "RECORD_DT_RANGE",
    "RICKER_AMPLITUDE_MAX",
    "RICKER_PERIOD_RANGE",
    "check_range",
    "format_si",
]

#: Time step of a record [s]: accelerographs sample at 50–1000 Hz (0.001–0.02 s); 0.1 s (10 Hz)
#: still resolves the 0.5 s pulses of the method, 1e-4 s (10 kHz) is beyond any accelerograph.
#: Outside this range the header is wrong (e.g. DT in ms, or a frequency read as a step).
RECORD_DT_RANGE = (1e-4, 0.1)

#: Longest record [s]: the longest strong-motion records (2011 Tōhoku, K-NET) last 300 s;
#: an hour leaves a wide margin and keeps a run bounded.
MAX_RECORD_DURATION = 3600.0

#: Most samples in a record: an hour at 500 Hz (16 MB of float64); reading more text would
#: take minutes and gigabytes.
MAX_RECORD_SAMPLES = 2_000_000

#: Largest record file read [bytes]: MAX_RECORD_SAMPLES values of up to 50 characters.
MAX_FILE_BYTES = 100 * 2**20

#: Largest |acceleration| in a record file or of a record scaled by the user [m/s²]: the
#: largest accelerations ever recorded are about 4 g (2008 Iwate–Miyagi, IWTH25); 10 g means
#: wrong units (e.g. mm/s² declared as gal) or a wrong scale factor.
MAX_RECORD_ACCELERATION = 10.0 * G

#: Largest |ground acceleration| the models accept [m/s²]: scaling ladders take records beyond
#: nature (up to 8.3 g peak in the FEMA P695 studies of docs/critical_sa.md); 100 g leaves a
#: factor of ten above that and stops inputs whose response would be numerical nonsense
#: (e.g. a record scaled by 1e20 "fails" in its first step without moving).
MAX_MODEL_ACCELERATION = 100.0 * G

#: Longest simulated time [s]: the longest record and the free vibration after it.
MAX_MODEL_DURATION = 2 * MAX_RECORD_DURATION

#: Most output samples of one simulation (duration/dt): the rigid model keeps 13 float64
#: channels per sample, so 4e6 samples are 416 MB.
MAX_MODEL_SAMPLES = 4_000_000

#: Slider (contact) pressure [Pa]: sliding bearings are designed for 10–60 MPa (the paper's
#: light and heavy bearings); below 1 MPa the supported mass is under 13 t and the contact
#: stiffness no longer matches the load, above 200 MPa the slider's liner and the plates'
#: steel (f_y = 345 MPa) would crush.
PRESSURE_RANGE = (1e6, 200e6)

#: Ricker pulse period Tp [s]: 0.05 s is a 20 Hz pulse (no displacement), 20 s is beyond the
#: longest velocity pulses observed (≈ 15 s) and four times the isolation period.
RICKER_PERIOD_RANGE = (0.05, 20.0)

#: Largest Ricker pulse amplitude Ap [m/s²]: as :data:`MAX_RECORD_ACCELERATION`.
RICKER_AMPLITUDE_MAX = MAX_RECORD_ACCELERATION

#: Highest SA(Tb) of a ladder [m/s²]: every record of the FEMA P695 studies fails the bearing
#: below 1.5 g; 5 g bounds a full ladder to 500 rungs.
MAX_SA_STOP = 5.0 * G


def format_si(value: float, unit: str) -> str:
    """``value`` in ``unit`` for a message: m/s² also in g, Pa in MPa, others as given."""
    if unit == "m/s2":
        return f"{value:.3g} m/s² ({value / G:.3g} g)"
    if unit == "Pa":
        return f"{value / 1e6:.3g} MPa"
    return f"{value:.3g} {unit}".rstrip()


def check_range(name: str, value, low: float | None, high: float | None, unit: str = "",
                *, low_open: bool = False, why: str = "") -> float:
    """``value`` as a float if ``low ≤ value ≤ high`` (``low < value`` with ``low_open``;
    None: no bound), else ValueError naming ``name``, the value, the range and ``why``.

    Parameters
    ----------
    name : str
        What the value is, e.g. ``"dt"``.
    value : float
        In SI units (``unit`` says which: ``"s"``, ``"m/s2"``, ``"Pa"``, ``""``).
    low, high : float or None
        The bounds, in the same units.
    """
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a number, got {str(value)[:40]!r}") from None
    ok = math.isfinite(x)
    if ok and low is not None:
        ok = x > low if low_open else x >= low
    if ok and high is not None:
        ok = x <= high
    if ok:
        return x
    if low is not None and high is not None:
        bounds = (f"between {format_si(low, unit)} and {format_si(high, unit)}" if not low_open
                  else f"above {format_si(low, unit)} and at most {format_si(high, unit)}")
    elif low is not None:
        bounds = f"{'above' if low_open else 'at least'} {format_si(low, unit)}"
    else:
        bounds = f"finite and at most {format_si(high, unit)}"
    got = format_si(x, unit) if math.isfinite(x) else repr(x)
    reason = f" ({why})" if why else ""
    raise ValueError(f"{name} must be {bounds}{reason}, got {got}")
