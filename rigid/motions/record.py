"""One component of a ground-motion record in SI units (:class:`GroundMotion`), the error the
readers raise (:class:`RecordFormatError`) and the cumulative trapezoidal integral used for
velocities and displacements. The file readers are in :mod:`rigid.motions.formats`."""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np

from ..units import G

__all__ = ["GroundMotion", "RecordFormatError", "cumulative_integral"]

class RecordFormatError(ValueError):
    """A record or manifest file does not have the expected format, or holds implausible
    values (docs/limits.md).

    The message names the file, the (1-based) line and what was expected there; ``note``
    (e.g. the encoding the file was decoded with) is appended in brackets.
    """

    def __init__(self, path, line: int | str | None, message: str, note: str = ""):
        self.path = str(path)
        self.line = line
        self.message = message
        self.note = note
        if line is None:
            where = self.path
        elif isinstance(line, str):  # another kind of location, e.g. "[[record]] 2"
            where = f"{self.path}, {line}"
        else:
            where = f"{self.path}, line {line}"
        super().__init__(f"{where}: {message}" + (f" ({note})" if note else ""))

    def with_note(self, note: str) -> RecordFormatError:
        """The same error with ``note`` added."""
        return RecordFormatError(self.path, self.line, self.message, note)

    def __reduce__(self):  # picklable across worker processes
        return (RecordFormatError, (self.path, self.line, self.message, self.note))


@dataclass(frozen=True, eq=False)
class GroundMotion:
    """One component of a ground-motion record, in SI units.

    Parameters
    ----------
    name : str
        Label used in tables and plots.
    dt : float [s]
        Time step.
    acceleration : ndarray [m/s²]
        Ground acceleration, sample i at t = i·dt. Stored as a read-only float array.
    event, station, component : str
        Descriptive metadata ("" when unknown).
    source_units : str
        Units of the source file (the samples here are always m/s²).
    source_file : str
        Path of the source file ("" when built in memory).
    metadata : dict
        Anything else (record-set number, magnitude, normalisation factor, …).
    """

    name: str
    dt: float
    acceleration: np.ndarray
    event: str = ""
    station: str = ""
    component: str = ""
    source_units: str = "m/s2"
    source_file: str = ""
    metadata: dict = field(default_factory=dict)

    def __post_init__(self):
        if not (isinstance(self.dt, (int, float)) and math.isfinite(self.dt) and self.dt > 0):
            raise ValueError(
                f"GroundMotion.dt must be a positive number of seconds, got {self.dt!r}"
            )
        acc = np.array(self.acceleration, dtype=float).ravel()
        if acc.size < 2:
            raise ValueError("GroundMotion.acceleration needs at least two samples")
        if not np.all(np.isfinite(acc)):
            raise ValueError("GroundMotion.acceleration contains NaN or infinite values")
        acc.flags.writeable = False
        object.__setattr__(self, "dt", float(self.dt))
        object.__setattr__(self, "acceleration", acc)

    @property
    def npts(self) -> int:
        """Number of samples."""
        return self.acceleration.size

    @property
    def duration(self) -> float:
        """(npts − 1)·dt [s]."""
        return (self.npts - 1) * self.dt

    @property
    def time(self) -> np.ndarray:
        """Sample times [s], starting at 0."""
        return np.arange(self.npts) * self.dt

    @property
    def pga(self) -> float:
        """Peak ground acceleration [m/s²]."""
        return float(np.max(np.abs(self.acceleration)))

    @property
    def pgv(self) -> float:
        """Peak ground velocity [m/s] of the uncorrected trapezoidal integral."""
        return float(np.max(np.abs(self.velocity())))

    def velocity(self, baseline: int | None = None) -> np.ndarray:
        """Ground velocity [m/s] by the trapezoidal rule, zero at t = 0.

        Parameters
        ----------
        baseline : int, optional
            Off by default. If given, a least-squares polynomial of this order in t is
            removed from the velocity (so its derivative is removed from the acceleration);
            order 1 removes a constant acceleration offset. See :meth:`baseline_corrected`.
        """
        motion = self if baseline is None else self.baseline_corrected(baseline)
        return cumulative_integral(motion.acceleration, self.dt)

    def displacement(self, baseline: int | None = None) -> np.ndarray:
        """Ground displacement [m] by trapezoidal integration of :meth:`velocity`."""
        return cumulative_integral(self.velocity(baseline), self.dt)

    def baseline_corrected(self, order: int = 1) -> GroundMotion:
        """A copy with a polynomial velocity baseline removed.

        The velocity v(t) (trapezoid, v(0) = 0) is fitted by least squares with a polynomial
        p(t) of degree ``order`` constrained to p(0) = 0, and p′(t) is subtracted from the
        acceleration. This is the common least-squares polynomial baseline correction; it is
        never applied unless asked for (spectra and pulse extraction use the record as given).

        Parameters
        ----------
        order : int
            Degree of the velocity polynomial, ≥ 1.
        """
        if int(order) < 1:
            raise ValueError(f"baseline order must be ≥ 1, got {order!r}")
        t = self.time
        v = cumulative_integral(self.acceleration, self.dt)
        powers = np.arange(1, int(order) + 1)
        coef, *_ = np.linalg.lstsq(t[:, None] ** powers, v, rcond=None)  # p(t) = Σ c_k t^k
        slope = (powers * coef * t[:, None] ** (powers - 1)).sum(axis=1)  # p′(t)
        return replace(
            self,
            acceleration=self.acceleration - slope,
            metadata={**self.metadata, "baseline_order": int(order)},
        )

    def scaled(self, factor: float, name: str | None = None) -> GroundMotion:
        """A copy with the acceleration multiplied by ``factor`` [-]."""
        meta = {**self.metadata, "scale": self.metadata.get("scale", 1.0) * float(factor)}
        return replace(
            self,
            acceleration=self.acceleration * float(factor),
            name=self.name if name is None else name,
            metadata=meta,
        )

    def __repr__(self) -> str:
        return (
            f"GroundMotion(name={self.name!r}, dt={self.dt}, npts={self.npts}, "
            f"pga={self.pga / G:.3f} g)"
        )


# --------------------------------------------------------------------------- helpers


def cumulative_integral(x, dt: float):
    """Cumulative trapezoidal integral of ``x`` with step ``dt`` [s], starting from 0.

    Same as ``scipy.integrate.cumulative_trapezoid(x, dx=dt, initial=0)`` without importing
    scipy.integrate (which would make ``import rigid`` slow).
    """
    x = np.asarray(x, dtype=float)
    out = np.empty_like(x)
    out[..., 0] = 0.0
    np.cumsum(0.5 * dt * (x[..., 1:] + x[..., :-1]), axis=-1, out=out[..., 1:])
    return out
