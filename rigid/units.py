"""Gravity and acceleration units: the one place where g is defined.

Everything inside the project is SI (m, s, kg, N, Pa; accelerations in m/s²). g appears only at
the edges (readers, command line, tables, plots), through :data:`G` and :func:`to_si`.
"""

from __future__ import annotations

__all__ = ["UNITS", "G", "to_si"]

#: Standard gravity [m/s²] (FEMA P695 uses the same value).
G = 9.80665

#: Factors from acceleration units to m/s² (keys are lower case, spaces removed).
UNITS = {
    "g": G,
    "m/s2": 1.0,
    "m/s^2": 1.0,
    "m/s/s": 1.0,
    "m/s**2": 1.0,
    "cm/s2": 0.01,
    "cm/s^2": 0.01,
    "cm/s/s": 0.01,
    "cm/sec/sec": 0.01,
    "cm/sec2": 0.01,
    "cm/s**2": 0.01,
    "gal": 0.01,
    "mm/s2": 0.001,
    "mm/s^2": 0.001,
}


def to_si(units: str) -> float:
    """Factor that converts an acceleration in ``units`` to m/s².

    Parameters
    ----------
    units : str
        One of :data:`UNITS` (case and spaces ignored), e.g. ``"g"``, ``"gal"``, ``"cm/s2"``.

    Returns
    -------
    float [m/s² per unit]
    """
    key = str(units).strip().lower().replace(" ", "")
    if key not in UNITS:
        raise ValueError(f"unknown acceleration units {units!r}; expected one of {sorted(UNITS)}")
    return UNITS[key]
