"""Text handling shared by the record readers: decoding a file into lines and parsing a block
of numbers with messages that name the file and the line."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ..record import RecordFormatError

#: A number as the record formats write it (Fortran ``D`` exponents included).
NUMBER = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[EeDd][-+]?\d+)?"


def read_lines(path) -> list[str]:
    """The lines of a record file, decoded as UTF-8, else Shift-JIS (JMA files), else latin-1;
    RecordFormatError if it holds no text."""
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


def parse_block(path, lines: list[str], first: int, expected: int | None, per_line=None):
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
