"""Plain text records: one column (acceleration) or two (time, acceleration); the caller gives
the units and, for one column, the time step."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ...limits import MAX_RECORD_SAMPLES
from ...units import to_si
from ..record import GroundMotion, RecordFormatError
from .text import (
    acceleration_bound,
    check_dt,
    excerpt,
    implausible,
    make_motion,
    names_encoding,
    read_lines,
    too_many_samples,
)


@names_encoding
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
    lines = read_lines(path)
    if units is None:
        raise RecordFormatError(
            path, None, "missing units: plain text records carry none; pass units='g', 'm/s2', …"
        )
    try:
        factor = to_si(units)
    except ValueError as exc:
        raise RecordFormatError(path, None, str(exc)) from None
    if dt is not None:
        dt = check_dt(path, None, float(dt), "the given dt")
    bound = acceleration_bound(factor)
    rows, line_nos = [], []
    for i, line in enumerate(lines):
        text = line.split("#")[0].strip()
        if not text:
            continue
        tokens = text.replace(",", " ").split()
        try:
            row = [float(t) for t in tokens]
        except ValueError:
            raise RecordFormatError(path, i + 1, f"expected numbers, found {excerpt(text)}"
                                    ) from None
        if not all(math.isfinite(x) for x in row):
            raise RecordFormatError(path, i + 1,
                                    f"expected finite numbers, found {excerpt(text)}")
        if rows and len(row) != len(rows[0]):
            raise RecordFormatError(
                path, i + 1, f"expected {len(rows[0])} columns as above, found {len(row)}"
            )
        if len(row) not in (1, 2):
            raise RecordFormatError(path, i + 1, f"expected 1 or 2 columns, found {len(row)}")
        if abs(row[-1]) > bound:
            raise RecordFormatError(path, i + 1, implausible(tokens[-1], row[-1], bound))
        rows.append(row)
        line_nos.append(i + 1)
        if len(rows) > MAX_RECORD_SAMPLES:
            raise RecordFormatError(path, i + 1, too_many_samples())
    if not rows:
        raise RecordFormatError(path, None, "expected numbers; the file has only comments")
    data = np.array(rows)
    if data.shape[1] == 2:
        steps = np.diff(data[:, 0])
        if steps.size == 0 or not np.all(steps > 0):
            raise RecordFormatError(path, line_nos[0], "expected increasing times in column 1")
        first = float(steps[0])  # the first step is the reference: the first odd one is blamed
        bad = np.nonzero(np.abs(steps - first) > 1e-6 * first + 1e-12)[0]
        if bad.size:
            raise RecordFormatError(
                path, line_nos[bad[0] + 1], f"expected a uniform time step {first:g} s"
            )
        step = float(np.mean(steps))
        if dt is not None and abs(dt - step) > 1e-6 * step:
            raise RecordFormatError(path, line_nos[1], f"time column gives dt={step:g}, not {dt:g}")
        dt = check_dt(path, line_nos[1], step, "the time column")
        acc = data[:, 1]
    else:
        if dt is None:
            raise RecordFormatError(path, None, "missing DT: a one-column file needs dt=… [s]")
        acc = data[:, 0]
    return make_motion(
        path,
        line_nos[-1],
        name=name or Path(path).stem,
        dt=float(dt),
        acceleration=acc * factor,
        source_units=units,
        source_file=str(path),
        metadata={"format": "plain"},
    )
