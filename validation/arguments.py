"""The argument types of the ``dfp`` command: numbers checked against their plausibility
limits (docs/limits.md) with a one-line message naming the bound (:func:`number`)."""

from __future__ import annotations

import argparse
import math

from rigid.limits import MAX_SA_STOP, PRESSURE_RANGE
from rigid.units import G

__all__ = ["PRESSURE", "STOP", "number", "positive"]


def number(kind, low=None, high=None, unit="", why="", low_open=False):
    """An argparse type: a finite number of ``kind`` in [low, high] (``low_open``: above
    low), in the command line's units (``unit``, for the message)."""

    def parse(text):
        try:
            value = kind(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"not a number: {text[:40]!r}") from None
        ok = math.isfinite(value)
        if ok and low is not None:
            ok = value > low if low_open else value >= low
        if ok and high is not None:
            ok = value <= high
        if not ok:
            if low_open and low == 0 and high is None:
                bounds = "positive and finite"
            elif low_open and low == 0:
                bounds = f"positive and at most {high:g}{unit}"
            elif high is None:
                bounds = f"at least {low:g}{unit}"
            else:
                bounds = f"between {low:g} and {high:g}{unit}"
            reason = f" ({why}; docs/limits.md)" if why else ""
            raise argparse.ArgumentTypeError(f"must be {bounds}{reason}, got {text[:40]}")
        return value

    return parse


def positive(kind):
    """An argparse type: a positive, finite number of ``kind``."""
    return number(kind, 0, None, low_open=True)


#: Slider pressure [MPa].
PRESSURE = number(float, PRESSURE_RANGE[0] / 1e6, PRESSURE_RANGE[1] / 1e6, " MPa",
                  "what sliding bearings are designed for")
#: Top of a ladder of SA [g].
STOP = number(float, 0, MAX_SA_STOP / G, " g", "every studied record fails below 1.5 g",
              low_open=True)
