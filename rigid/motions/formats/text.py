"""Text handling shared by the record readers: refusing what is not a regular text file,
decoding (UTF-8, UTF-16, Shift-JIS, latin-1, the encoding named in errors), parsing a block of
numbers with messages that name the file and the line, the header fields several formats share
(a sampling rate in Hz, acceleration units, Fortran numbers), the plausibility checks of a
record (docs/limits.md), and short excerpts of file content for messages."""

from __future__ import annotations

import codecs
import functools
import math
import os
import re
import stat
from pathlib import Path

import numpy as np

from ...limits import (
    MAX_FILE_BYTES,
    MAX_RECORD_ACCELERATION,
    MAX_RECORD_DURATION,
    MAX_RECORD_SAMPLES,
    RECORD_DT_RANGE,
)
from ...units import G, to_si
from ..record import GroundMotion, RecordFormatError

#: A number as the record formats write it (Fortran ``D`` exponents included).
NUMBER = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[EeDd][-+]?\d+)?"

#: Most characters of file content quoted in a message.
EXCERPT = 60

#: Names of the encodings for messages.
_ENCODING_NAMES = {"cp932": "Shift-JIS (cp932)", "latin-1": "latin-1"}


def excerpt(text, limit: int = EXCERPT) -> str:
    """``repr`` of at most ``limit`` characters of ``text`` (``…`` marks a cut), so that an
    error message never echoes more than about 80 characters of a file."""
    text = str(text)
    short = text if len(text) <= limit else text[:limit] + "…"
    out = repr(short)
    return out if len(out) <= limit + 20 else out[: limit + 18] + "…" + out[0]


def check_regular_file(path, what: str = "record file") -> Path:
    """``path`` if it is a regular file of at most :data:`~rigid.limits.MAX_FILE_BYTES`;
    RecordFormatError otherwise (missing, a folder, a FIFO, a device, …), decided from
    ``stat`` before the file is opened (opening a FIFO would block)."""
    path = Path(path)
    try:
        st = os.stat(path)
    except FileNotFoundError:
        raise RecordFormatError(path, None, f"no such {what}") from None
    except OSError as exc:
        raise RecordFormatError(path, None, f"cannot read the {what}: {exc.strerror}") from None
    mode = st.st_mode
    if not stat.S_ISREG(mode):
        kind = ("a folder" if stat.S_ISDIR(mode) else "a FIFO (named pipe)"
                if stat.S_ISFIFO(mode) else "a device" if stat.S_ISCHR(mode) or
                stat.S_ISBLK(mode) else "a socket" if stat.S_ISSOCK(mode) else "not a file")
        raise RecordFormatError(path, None, f"expected a regular {what}, found {kind}")
    if st.st_size > MAX_FILE_BYTES:
        raise RecordFormatError(path, None, f"the file has {st.st_size / 2**20:.0f} MiB; a "
                                f"{what} holds at most {MAX_FILE_BYTES / 2**20:.0f} MiB "
                                "(docs/limits.md)")
    return path


def _utf16_without_bom(raw: bytes) -> str | None:
    """'utf-16-le' or 'utf-16-be' when most even (odd) bytes are NUL and the others are not:
    ASCII text written as UTF-16 without a byte-order mark."""
    if len(raw) < 4 or len(raw) % 2:
        return None
    even, odd = raw[0::2], raw[1::2]
    n = len(even)
    if odd.count(0) > 0.9 * n and even.count(0) < 0.1 * n:
        return "utf-16-le"
    if even.count(0) > 0.9 * n and odd.count(0) < 0.1 * n:
        return "utf-16-be"
    return None


def decode(raw: bytes, path) -> tuple[str, str]:
    """(text, encoding) of a file's bytes: a byte-order mark's encoding (UTF-8, UTF-16,
    UTF-32), UTF-16 without one, else UTF-8, else Shift-JIS (cp932, JMA files), else latin-1.
    RecordFormatError "not a text file" for binary content (NUL or other control bytes)."""
    for bom, encoding in ((codecs.BOM_UTF32_LE, "utf-32"), (codecs.BOM_UTF32_BE, "utf-32"),
                          (codecs.BOM_UTF8, "utf-8-sig"), (codecs.BOM_UTF16_LE, "utf-16"),
                          (codecs.BOM_UTF16_BE, "utf-16")):
        if raw.startswith(bom):
            try:
                return raw.decode(encoding), encoding.replace("-sig", "")
            except UnicodeDecodeError:
                raise RecordFormatError(path, None, f"not a text file: it starts with a "
                                        f"{encoding} byte-order mark but does not decode as "
                                        f"{encoding}") from None
    utf16 = _utf16_without_bom(raw)
    if utf16 is not None:
        try:
            return raw.decode(utf16), utf16
        except UnicodeDecodeError:
            pass
    control = sum(raw.count(bytes([c])) for c in range(32) if c not in (9, 10, 11, 12, 13, 26))
    if b"\0" in raw or control > 0.001 * len(raw) + 2:
        raise RecordFormatError(path, None, "not a text file (binary content: NUL or control "
                                "bytes); expected a text record (compressed or spreadsheet "
                                "files must be exported as text)")
    for encoding in ("utf-8", "cp932", "latin-1"):  # JMA files may be Shift-JIS
        try:
            return raw.decode(encoding), encoding
        except UnicodeDecodeError:
            continue
    raise AssertionError("latin-1 decodes any bytes")  # pragma: no cover


def read_text(path, what: str = "record file") -> tuple[list[str], str]:
    """(lines, encoding) of a text file, checked by :func:`check_regular_file` and decoded by
    :func:`decode`; RecordFormatError if it holds no text."""
    path = check_regular_file(path, what)
    try:
        raw = path.read_bytes()
    except OSError as exc:
        raise RecordFormatError(path, None, f"cannot read the {what}: {exc.strerror}") from None
    text, encoding = decode(raw, path)
    lines = text.splitlines()
    if not any(line.strip() for line in lines):
        raise RecordFormatError(path, None, "the file is empty; expected a record")
    return lines, encoding


def read_lines(path) -> list[str]:
    """The lines of a record file (see :func:`read_text`)."""
    return read_text(path)[0]


def names_encoding(reader):
    """Decorate a reader so that its RecordFormatError names the file's encoding when it is
    not UTF-8 or ASCII (a record decoded as latin-1 or Shift-JIS may have been misread)."""

    @functools.wraps(reader)
    def read(path, *args, **kwargs):
        try:
            return reader(path, *args, **kwargs)
        except RecordFormatError as exc:
            if exc.path != str(path) or exc.note:
                raise
            try:
                raw = Path(path).read_bytes()
                _, encoding = decode(raw, path)
            except (OSError, RecordFormatError):
                raise exc from None
            if encoding in ("utf-8", "ascii"):
                raise
            name = _ENCODING_NAMES.get(encoding, encoding.upper())
            raise exc.with_note(f"the file was decoded as {name}, not UTF-8") from None

    return read


def parse_block(path, lines: list[str], first: int, expected: int | None, per_line=None,
                bound: float | None = None):
    """Parse whitespace- or comma-separated numbers from ``lines[first:]``.

    ``first`` is 0-based; messages use 1-based line numbers. Raises RecordFormatError on a
    non-numeric token, NaN, a value beyond ``bound`` (in the file's units; the message says
    why), too many or too few values (when ``expected`` is given), more than
    :data:`~rigid.limits.MAX_RECORD_SAMPLES` values, or a short line before the last one
    (when ``per_line`` is given).
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
                raise RecordFormatError(path, i + 1, f"expected a number, found {excerpt(tok)}"
                                        ) from None
            if not math.isfinite(x):
                raise RecordFormatError(path, i + 1,
                                        f"expected a finite number, found {excerpt(tok)}")
            if bound is not None and abs(x) > bound:
                raise RecordFormatError(path, i + 1, implausible(tok, x, bound))
            values.append(x)
        counts.append((i, len(tokens)))
        if expected is not None and len(values) > expected:
            raise RecordFormatError(
                path,
                i + 1,
                f"NPTS mismatch: the header gives NPTS={expected} but more values follow",
            )
        if len(values) > MAX_RECORD_SAMPLES:
            raise RecordFormatError(path, i + 1, too_many_samples())
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


def implausible(token, value: float, bound: float) -> str:
    """Message for a ``value`` beyond ``bound`` (the largest plausible record acceleration in
    the file's units, :func:`acceleration_bound`)."""
    g = value * (MAX_RECORD_ACCELERATION / G / bound)  # in this order: no overflow
    return (f"value {excerpt(token, 30)} is {g:.3g} g, beyond the "
            f"{MAX_RECORD_ACCELERATION / G:g} g of any recorded ground motion (wrong units "
            "or a damaged file? docs/limits.md)")


def too_many_samples() -> str:
    return (f"more than {MAX_RECORD_SAMPLES:,} samples (an hour at 500 Hz), the most a record "
            "may hold (docs/limits.md)")


def acceleration_bound(factor: float) -> float:
    """Largest plausible |value| in a file whose units are ``factor`` m/s² each."""
    return MAX_RECORD_ACCELERATION / factor


def check_dt(path, line, dt: float, source: str = "DT") -> float:
    """``dt`` [s] if within :data:`~rigid.limits.RECORD_DT_RANGE`, else RecordFormatError at
    ``line`` naming ``source`` (e.g. the header field it came from)."""
    low, high = RECORD_DT_RANGE
    if not (math.isfinite(dt) and low <= dt <= high):
        raise RecordFormatError(path, line, f"{source} gives a time step of {dt:.4g} s; a "
                                f"record's time step must be between {low:g} and {high:g} s "
                                "(accelerographs sample at 10-10,000 Hz; docs/limits.md)")
    return dt


def fortran_float(text: str) -> float:
    """A number as the record formats write it, Fortran ``D`` exponents included
    ("7.845D+03" → 7845.0); ValueError if it is none."""
    return float(text.replace("D", "E").replace("d", "e"))


def sampling_interval(path, line, text: str, expected: str, source: str) -> float:
    """The time step [s] of a header's sampling rate ``text`` such as ``100Hz`` (JMA, K-NET),
    checked by :func:`check_dt` (``source``: the field's name); RecordFormatError at ``line``
    quoting ``expected`` (how the field should read) when it is no positive rate in Hz."""
    m = re.match(r"(\d+(?:\.\d*)?)\s*Hz", text, re.IGNORECASE)
    if not m or float(m.group(1)) <= 0:
        raise RecordFormatError(path, line, f"expected '{expected}', found {excerpt(text)}")
    return check_dt(path, line, 1.0 / float(m.group(1)), source)


def unit_factor(path, line, units: str, expected: str, shown: str | None = None) -> float:
    """m/s² per unit of a header's acceleration ``units`` (:func:`rigid.units.to_si`);
    RecordFormatError at ``line`` quoting ``shown`` (default ``units``: the field as written)
    and ``expected`` when they are not acceleration units."""
    try:
        return to_si(units)
    except ValueError:
        quoted = excerpt(units if shown is None else shown, 20)
        raise RecordFormatError(path, line, f"wrong units {quoted}: expected {expected}") from None


def make_motion(path, line, **fields) -> GroundMotion:
    """A GroundMotion from a reader, after the record checks: at least two samples, at most
    :data:`~rigid.limits.MAX_RECORD_SAMPLES`, at most an hour long; any other problem of the
    samples as a RecordFormatError naming the file (``line``: where the data end)."""
    acc = np.asarray(fields["acceleration"], dtype=float)
    dt = float(fields["dt"])
    if acc.size < 2:
        raise RecordFormatError(path, line, f"expected at least two samples, found {acc.size}")
    if acc.size > MAX_RECORD_SAMPLES:
        raise RecordFormatError(path, line, too_many_samples())
    duration = (acc.size - 1) * dt
    if duration > MAX_RECORD_DURATION:
        raise RecordFormatError(path, line, f"the record lasts {duration:.4g} s ({acc.size} "
                                f"samples of {dt:g} s); a record lasts at most "
                                f"{MAX_RECORD_DURATION:g} s (docs/limits.md)")
    if acc.size and np.max(np.abs(acc)) > MAX_RECORD_ACCELERATION:
        k = int(np.argmax(np.abs(acc)))
        raise RecordFormatError(path, line, f"sample {k + 1} is {acc[k] / G:.3g} g, beyond the "
                                f"{MAX_RECORD_ACCELERATION / G:g} g of any recorded ground "
                                "motion (wrong units? docs/limits.md)")
    try:
        return GroundMotion(**fields)
    except ValueError as exc:
        raise RecordFormatError(path, line, str(exc)) from None
