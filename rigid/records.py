"""Ground-motion records: the :class:`GroundMotion` container and file readers.

Readers (all return accelerations in m/s²; g, gal and cm/s² are converted at the edge):

- :func:`read_peer_at2` — PEER NGA ``.AT2`` (NGA-West2 ``NPTS= …, DT= …`` header and the
  older ``… NPTS, … DT`` form);
- :func:`read_knet` — K-NET / KiK-net ASCII (``Scale Factor`` counts to gal);
- :func:`read_jma_csv` — JMA strong-motion CSV (``SITE CODE=``, ``SAMPLING RATE=``, three
  columns NS, EW, UD);
- :func:`read_plain` — one column (acceleration) or two (time, acceleration), with dt and
  units given by the caller.

:func:`read_record` looks at the first lines of a file to pick the reader. Malformed files
raise :class:`RecordFormatError` naming the file, the line and what was expected.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from .bearing import G

__all__ = [
    "UNITS",
    "GroundMotion",
    "RecordFormatError",
    "read_jma_csv",
    "read_knet",
    "read_peer_at2",
    "read_plain",
    "read_record",
    "to_si",
]

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


class RecordFormatError(ValueError):
    """A record file does not have the expected format.

    The message names the file, the (1-based) line and what was expected there.
    """

    def __init__(self, path, line: int | str | None, message: str):
        self.path = str(path)
        self.line = line
        if line is None:
            where = self.path
        elif isinstance(line, str):  # another kind of location, e.g. "[[record]] 2"
            where = f"{self.path}, {line}"
        else:
            where = f"{self.path}, line {line}"
        super().__init__(f"{where}: {message}")


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
        return integrate(motion.acceleration, self.dt)

    def displacement(self, baseline: int | None = None) -> np.ndarray:
        """Ground displacement [m] by trapezoidal integration of :meth:`velocity`."""
        return integrate(self.velocity(baseline), self.dt)

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
        v = integrate(self.acceleration, self.dt)
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


def integrate(x, dt: float):
    """Cumulative trapezoidal integral of ``x`` with step ``dt`` [s], starting from 0.

    Same as ``scipy.integrate.cumulative_trapezoid(x, dx=dt, initial=0)`` without importing
    scipy.integrate (which would make ``import rigid`` slow).
    """
    x = np.asarray(x, dtype=float)
    out = np.empty_like(x)
    out[..., 0] = 0.0
    np.cumsum(0.5 * dt * (x[..., 1:] + x[..., :-1]), axis=-1, out=out[..., 1:])
    return out


def _read_lines(path) -> list[str]:
    path = Path(path)
    raw = path.read_bytes()
    for encoding in ("utf-8", "cp932", "latin-1"):  # JMA files may be Shift-JIS
        try:
            text = raw.decode(encoding)
            break
        except UnicodeDecodeError:
            continue
    lines = text.splitlines()
    if not any(line.strip() for line in lines):
        raise RecordFormatError(path, None, "the file is empty; expected a record")
    return lines


def _parse_block(path, lines: list[str], first: int, expected: int | None, per_line=None):
    """Parse whitespace- or comma-separated numbers from ``lines[first:]``.

    ``first`` is 0-based; messages use 1-based line numbers. Raises RecordFormatError on a
    non-numeric token, NaN, too many or too few values (when ``expected`` is given), or a
    short line before the last one (when ``per_line`` is given).
    """
    values: list[float] = []
    counts: list[tuple[int, int]] = []  # (0-based line, number of values) of data lines
    for i in range(first, len(lines)):
        tokens = lines[i].replace(",", " ").split()
        if not tokens:
            continue
        for tok in tokens:
            try:
                x = float(tok.replace("D", "E").replace("d", "e"))
            except ValueError:
                raise RecordFormatError(path, i + 1, f"expected a number, found {tok!r}") from None
            if not math.isfinite(x):
                raise RecordFormatError(path, i + 1, f"expected a finite number, found {tok!r}")
            values.append(x)
        counts.append((i, len(tokens)))
        if expected is not None and len(values) > expected:
            raise RecordFormatError(
                path,
                i + 1,
                f"NPTS mismatch: the header gives NPTS={expected} but more values follow",
            )
    if per_line is not None:
        for i, n in counts[:-1]:
            if n != per_line:
                raise RecordFormatError(
                    path,
                    i + 1,
                    f"expected {per_line} values on every data line but the last, found {n} "
                    "(truncated or damaged data)",
                )
    last_data_line = counts[-1][0] if counts else first
    if expected is not None and len(values) < expected:
        raise RecordFormatError(
            path,
            last_data_line + 1,
            f"truncated data: the header gives NPTS={expected} but the file ends after "
            f"{len(values)} values",
        )
    if not values:
        raise RecordFormatError(path, first + 1, "expected data values after the header")
    return np.array(values)


# --------------------------------------------------------------------------- PEER AT2

_NUM = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[EeDd][-+]?\d+)?"
_NGA_WEST2 = re.compile(rf"NPTS\s*=\s*(\d+)\s*,?\s*DT\s*=\s*({_NUM})", re.IGNORECASE)
_NGA_OLD = re.compile(rf"^\s*(\d+)\s*,?\s+({_NUM})\s+.*NPTS\s*,\s*DT", re.IGNORECASE)
_UNITS_LINE = re.compile(r"UNITS\s+OF\s+([A-Za-z][A-Za-z/^*0-9]*)", re.IGNORECASE)


def read_peer_at2(path, name: str | None = None) -> GroundMotion:
    """Read a PEER NGA strong-motion acceleration file (``.AT2``).

    Both header forms are accepted on line 4: NGA-West2 ``NPTS=  8773, DT=   .0050 SEC`` and
    the older ``  4000   .00500   NPTS, DT``. Line 3 must declare an acceleration time series
    and its units (``… IN UNITS OF G``; cm/s² and gal are also accepted).

    Parameters
    ----------
    path : str or Path
        File name.
    name : str, optional
        Label; default the file's stem.

    Returns
    -------
    GroundMotion
        Acceleration in m/s²; ``event`` and ``station`` from line 2 when it has the
        ``event, date, station, component`` form.
    """
    lines = _read_lines(path)
    if len(lines) < 5:
        raise RecordFormatError(path, len(lines), "expected a 4-line PEER header followed by data")
    kind_line = lines[2]
    if "ACCELERATION" not in kind_line.upper():
        raise RecordFormatError(
            path,
            3,
            f"expected 'ACCELERATION TIME SERIES IN UNITS OF …', found {kind_line.strip()!r}",
        )
    m = _UNITS_LINE.search(kind_line)
    if not m:
        raise RecordFormatError(path, 3, "expected the units ('… IN UNITS OF G')")
    units = m.group(1).strip()
    try:
        factor = to_si(units)
    except ValueError:
        raise RecordFormatError(
            path, 3, f"wrong units {units!r}: expected acceleration units (G, CM/S/S, GAL)"
        ) from None
    header = lines[3]
    m = _NGA_WEST2.search(header) or _NGA_OLD.search(header)
    if not m:
        raise RecordFormatError(
            path, 4, "expected 'NPTS= n, DT= dt SEC' or 'n dt NPTS, DT' (missing DT or NPTS)"
        )
    npts, dt = int(m.group(1)), float(m.group(2).replace("D", "E"))
    if not dt > 0:
        raise RecordFormatError(path, 4, f"expected a positive DT, found {m.group(2)}")
    acc = _parse_block(path, lines, 4, npts)
    parts = [p.strip() for p in lines[1].split(",")]
    event = parts[0] if parts else ""
    station = parts[-2] if len(parts) >= 4 else ""
    component = parts[-1] if len(parts) >= 4 else ""
    return GroundMotion(
        name=name or Path(path).stem,
        dt=dt,
        acceleration=acc * factor,
        event=event,
        station=station,
        component=component,
        source_units=units,
        source_file=str(path),
        metadata={"format": "PEER AT2", "header": lines[:4]},
    )


# --------------------------------------------------------------------------- K-NET / KiK-net

_KNET_KEYS = {
    "origin time": "origin_time",
    "lat.": "latitude",
    "long.": "longitude",
    "lon.": "longitude",
    "depth. (km)": "depth_km",
    "mag.": "magnitude",
    "station code": "station",
    "station lat.": "station_latitude",
    "station long.": "station_longitude",
    "station lon.": "station_longitude",
    "station height(m)": "station_height_m",
    "record time": "record_time",
    "sampling freq(hz)": "sampling_frequency",
    "duration time(s)": "duration",
    "dir.": "direction",
    "scale factor": "scale_factor",
    "max. acc. (gal)": "max_acc_gal",
    "last correction": "last_correction",
    "memo.": "memo",
}


def read_knet(path, name: str | None = None, remove_mean: bool = True) -> GroundMotion:
    """Read a K-NET or KiK-net ASCII file (one component, 17 header lines).

    The samples are integer counts; acceleration [gal] = count × numerator/denominator of
    the ``Scale Factor  7845(gal)/8223790`` line. NIED's counts carry an offset, so the mean
    is removed by default, as NIED recommends.

    Parameters
    ----------
    path : str or Path
        File name.
    name : str, optional
        Label; default ``station_direction``.
    remove_mean : bool
        Subtract the record mean (default True).

    Returns
    -------
    GroundMotion
        Acceleration in m/s².
    """
    lines = _read_lines(path)
    header: dict[str, tuple[int, str]] = {}
    first_data = None
    for i, line in enumerate(lines[:40]):
        key = line[:18].strip().lower()
        if key in _KNET_KEYS:
            header[_KNET_KEYS[key]] = (i + 1, line[18:].strip())
            if key == "memo.":
                first_data = i + 1
                break
    if first_data is None:
        raise RecordFormatError(path, None, "expected a K-NET header ending with a 'Memo.' line")
    for key in ("sampling_frequency", "scale_factor"):
        if key not in header:
            raise RecordFormatError(path, None, f"missing header field {key!r}")
    line_no, text = header["sampling_frequency"]
    m = re.match(r"(\d+(?:\.\d*)?)\s*Hz", text, re.IGNORECASE)
    if not m or float(m.group(1)) <= 0:
        raise RecordFormatError(
            path, line_no, f"expected 'Sampling Freq(Hz) 100Hz', found {text!r}"
        )
    dt = 1.0 / float(m.group(1))
    line_no, text = header["scale_factor"]
    m = re.match(rf"({_NUM})\s*\(\s*([^)]+)\)\s*/\s*({_NUM})", text)
    if not m:
        raise RecordFormatError(
            path, line_no, f"expected 'Scale Factor 7845(gal)/8223790', found {text!r}"
        )
    if m.group(2).strip().lower() != "gal":
        raise RecordFormatError(path, line_no, f"wrong units {m.group(2)!r}: expected (gal)")
    gain = float(m.group(1)) / float(m.group(3))
    counts = _parse_block(path, lines, first_data, None, per_line=8)
    if "duration" in header:
        line_no, text = header["duration"]
        try:
            duration = float(text)
        except ValueError:
            raise RecordFormatError(
                path, line_no, f"expected a duration in s, found {text!r}"
            ) from None
        expected = round(duration / dt)
        if counts.size < expected - 1:  # NIED files hold duration·fs samples (± 1)
            raise RecordFormatError(
                path,
                len(lines),
                f"truncated data: Duration Time {duration} s at {1 / dt:g} Hz needs about "
                f"{expected} samples, found {counts.size}",
            )
    acc_gal = counts * gain
    if remove_mean:
        acc_gal = acc_gal - acc_gal.mean()
    station = header.get("station", (0, ""))[1]
    direction = header.get("direction", (0, ""))[1]
    return GroundMotion(
        name=name or f"{station}_{direction}".strip("_") or Path(path).stem,
        dt=dt,
        acceleration=acc_gal * 0.01,
        event=header.get("origin_time", (0, ""))[1],
        station=station,
        component=direction,
        source_units="gal",
        source_file=str(path),
        metadata={"format": "K-NET", **{k: v for k, (_, v) in header.items()}},
    )


# --------------------------------------------------------------------------- JMA CSV


def read_jma_csv(path, component: str = "NS", name: str | None = None) -> GroundMotion:
    """Read a JMA strong-motion CSV file (three components in gal).

    Expected layout: header lines ``SITE CODE= …``, ``LAT.= …``, ``LON.= …``,
    ``SAMPLING RATE= 100Hz``, ``UNIT = gal``, ``INITIAL TIME = …``, then a line naming the
    columns (``NS,EW,UD``) and comma-separated samples.

    Parameters
    ----------
    path : str or Path
        File name.
    component : str
        Column to read: ``"NS"``, ``"EW"`` or ``"UD"`` (case ignored).
    name : str, optional
        Label; default ``site_component``.

    Returns
    -------
    GroundMotion
        Acceleration in m/s².
    """
    lines = _read_lines(path)
    header: dict[str, tuple[int, str]] = {}
    columns = None
    first_data = None
    for i, line in enumerate(lines[:30]):
        if "=" in line:
            key, _, value = line.partition("=")
            header[key.strip().upper()] = (i + 1, value.strip())
            continue
        tokens = [t.strip().upper() for t in line.split(",") if t.strip()]
        if tokens and all(re.fullmatch(r"[A-Z]{2}", t) for t in tokens):
            columns, first_data = tokens, i + 1
            break
    if first_data is None:
        raise RecordFormatError(
            path, None, "expected a column line such as 'NS,EW,UD' after the header"
        )
    if "SAMPLING RATE" not in header:
        raise RecordFormatError(path, None, "missing 'SAMPLING RATE= …Hz' (no time step)")
    line_no, text = header["SAMPLING RATE"]
    m = re.match(r"(\d+(?:\.\d*)?)\s*Hz", text, re.IGNORECASE)
    if not m or float(m.group(1)) <= 0:
        raise RecordFormatError(path, line_no, f"expected 'SAMPLING RATE= 100Hz', found {text!r}")
    dt = 1.0 / float(m.group(1))
    line_no, units = header.get("UNIT", (None, ""))
    unit_key = units.split("(")[0].strip()
    try:
        factor = to_si(unit_key)
    except ValueError:
        raise RecordFormatError(
            path, line_no, f"wrong units {units!r}: expected 'UNIT = gal'"
        ) from None
    comp = component.strip().upper()
    if comp not in columns:
        raise ValueError(f"{path}: component {component!r} not in the file's columns {columns}")
    ncol = len(columns)
    rows = []
    for i in range(first_data, len(lines)):
        tokens = [t.strip() for t in lines[i].split(",")]
        if tokens == [""]:
            continue
        if len(tokens) < ncol:
            raise RecordFormatError(
                path, i + 1, f"expected {ncol} comma-separated values, found {len(tokens)}"
            )
        try:
            row = [float(t) for t in tokens[:ncol]]
        except ValueError:
            raise RecordFormatError(
                path, i + 1, f"expected numbers, found {lines[i].strip()!r}"
            ) from None
        if not all(math.isfinite(x) for x in row):
            raise RecordFormatError(
                path, i + 1, f"expected finite numbers, found {lines[i].strip()!r}"
            )
        rows.append(row)
    if not rows:
        raise RecordFormatError(path, first_data + 1, "expected data rows after the column line")
    data = np.array(rows)[:, columns.index(comp)]
    site = header.get("SITE CODE", (0, ""))[1]
    return GroundMotion(
        name=name or f"{site}_{comp}".strip("_"),
        dt=dt,
        acceleration=data * factor,
        event=header.get("INITIAL TIME", (0, ""))[1],
        station=site,
        component=comp,
        source_units=unit_key,
        source_file=str(path),
        metadata={"format": "JMA CSV", **{k.lower(): v for k, (_, v) in header.items()}},
    )


# --------------------------------------------------------------------------- plain text


def read_plain(
    path, dt: float | None = None, units: str | None = None, name: str | None = None
) -> GroundMotion:
    """Read a plain text record: one column (acceleration) or two (time, acceleration).

    Lines starting with ``#`` are skipped. With one column ``dt`` is required; with two the
    time column must be uniform and gives dt (a ``dt`` given as well must agree to 1e-6
    relative).

    Parameters
    ----------
    path : str or Path
        File name.
    dt : float [s], optional
        Time step.
    units : str
        Units of the values (see :data:`UNITS`), e.g. ``"g"``; required.
    name : str, optional
        Label; default the file's stem.

    Returns
    -------
    GroundMotion
    """
    if units is None:
        raise RecordFormatError(
            path, None, "missing units: plain text records carry none; pass units='g', 'm/s2', …"
        )
    factor = to_si(units)
    lines = _read_lines(path)
    rows, line_nos = [], []
    for i, line in enumerate(lines):
        text = line.split("#")[0].strip()
        if not text:
            continue
        tokens = text.replace(",", " ").split()
        try:
            row = [float(t) for t in tokens]
        except ValueError:
            raise RecordFormatError(path, i + 1, f"expected numbers, found {text!r}") from None
        if not all(math.isfinite(x) for x in row):
            raise RecordFormatError(path, i + 1, f"expected finite numbers, found {text!r}")
        if rows and len(row) != len(rows[0]):
            raise RecordFormatError(
                path, i + 1, f"expected {len(rows[0])} columns as above, found {len(row)}"
            )
        if len(row) not in (1, 2):
            raise RecordFormatError(path, i + 1, f"expected 1 or 2 columns, found {len(row)}")
        rows.append(row)
        line_nos.append(i + 1)
    data = np.array(rows)
    if data.shape[1] == 2:
        steps = np.diff(data[:, 0])
        if steps.size == 0 or not np.all(steps > 0):
            raise RecordFormatError(path, line_nos[0], "expected increasing times in column 1")
        step = float(np.mean(steps))
        bad = np.nonzero(np.abs(steps - step) > 1e-6 * step + 1e-12)[0]
        if bad.size:
            raise RecordFormatError(
                path, line_nos[bad[0] + 1], f"expected a uniform time step {step:g} s"
            )
        if dt is not None and abs(dt - step) > 1e-6 * step:
            raise RecordFormatError(path, line_nos[1], f"time column gives dt={step:g}, not {dt:g}")
        dt = step
        acc = data[:, 1]
    else:
        if dt is None:
            raise RecordFormatError(path, None, "missing DT: a one-column file needs dt=… [s]")
        acc = data[:, 0]
    return GroundMotion(
        name=name or Path(path).stem,
        dt=float(dt),
        acceleration=acc * factor,
        source_units=units,
        source_file=str(path),
        metadata={"format": "plain"},
    )


# --------------------------------------------------------------------------- dispatcher


def detect_format(path) -> str:
    """Guess the format of a record file from its first lines.

    Returns
    -------
    {"peer", "knet", "jma", "plain"}
    """
    head = "\n".join(_read_lines(path)[:20]).upper()
    if head.startswith("PEER") or "UNITS OF" in head or ("NPTS" in head and "DT" in head):
        return "peer"
    if "SCALE FACTOR" in head and "SAMPLING FREQ" in head:
        return "knet"
    if "SITE CODE" in head or "SAMPLING RATE" in head:
        return "jma"
    return "plain"


def read_record(
    path,
    dt: float | None = None,
    units: str | None = None,
    component: str | None = None,
    name: str | None = None,
) -> GroundMotion:
    """Read a ground-motion record, choosing the reader from the file's content.

    Parameters
    ----------
    path : str or Path
        File name. PEER ``.AT2``, K-NET/KiK-net ASCII and JMA CSV are recognised by their
        headers; anything else is read as plain text.
    dt : float [s], optional
        Time step for plain one-column files.
    units : str, optional
        Units for plain text files (``"g"``, ``"m/s2"``, ``"gal"``, …).
    component : str, optional
        Column of a JMA CSV file (default ``"NS"``); for other formats it overrides the
        component label.
    name : str, optional
        Label of the motion.

    Returns
    -------
    GroundMotion
        Acceleration in m/s².
    """
    fmt = detect_format(path)
    if fmt == "peer":
        motion = read_peer_at2(path, name=name)
    elif fmt == "knet":
        motion = read_knet(path, name=name)
    elif fmt == "jma":
        return read_jma_csv(path, component=component or "NS", name=name)
    else:
        motion = read_plain(path, dt=dt, units=units, name=name)
    if component is not None:
        motion = replace(motion, component=str(component))
    return motion
