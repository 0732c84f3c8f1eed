"""PEER NGA strong-motion acceleration files (``.AT2``), both header forms."""

from __future__ import annotations

import re
from pathlib import Path

from ...limits import MAX_RECORD_SAMPLES
from ..record import GroundMotion, RecordFormatError
from .text import (
    NUMBER,
    acceleration_bound,
    check_dt,
    excerpt,
    fortran_float,
    make_motion,
    names_encoding,
    parse_block,
    read_lines,
    too_many_samples,
    unit_factor,
)

_NGA_WEST2 = re.compile(rf"NPTS\s*=\s*(\d+)\s*,?\s*DT\s*=\s*({NUMBER})", re.IGNORECASE)
_NGA_OLD = re.compile(rf"^\s*(\d+)\s*,?\s+({NUMBER})\s+.*NPTS\s*,\s*DT", re.IGNORECASE)
_UNITS_LINE = re.compile(r"UNITS\s+OF\s+([A-Za-z][A-Za-z/^*0-9]*)", re.IGNORECASE)


@names_encoding
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
    lines = read_lines(path)
    if len(lines) < 5:
        raise RecordFormatError(path, len(lines), "expected a 4-line PEER header followed by data")
    kind_line = lines[2]
    if "ACCELERATION" not in kind_line.upper():
        raise RecordFormatError(
            path,
            3,
            "expected 'ACCELERATION TIME SERIES IN UNITS OF …', found "
            f"{excerpt(kind_line.strip())}",
        )
    m = _UNITS_LINE.search(kind_line)
    if not m:
        raise RecordFormatError(path, 3, "expected the units ('… IN UNITS OF G')")
    units = m.group(1).strip()
    factor = unit_factor(path, 3, units, "acceleration units (G, CM/S/S, GAL)")
    header = lines[3]
    m = _NGA_WEST2.search(header) or _NGA_OLD.search(header)
    if not m:
        raise RecordFormatError(
            path, 4, "expected 'NPTS= n, DT= dt SEC' or 'n dt NPTS, DT' (missing DT or NPTS)"
        )
    if len(m.group(1)) > 9:
        raise RecordFormatError(path, 4, f"NPTS={m.group(1)[:12]}: {too_many_samples()}")
    npts, dt = int(m.group(1)), fortran_float(m.group(2))
    if not dt > 0:
        raise RecordFormatError(path, 4, f"expected a positive DT, found {excerpt(m.group(2))}")
    check_dt(path, 4, dt, "DT")
    if npts > MAX_RECORD_SAMPLES:
        raise RecordFormatError(path, 4, f"NPTS={npts}: {too_many_samples()}")
    acc = parse_block(path, lines, 4, npts, bound=acceleration_bound(factor))
    parts = [p.strip() for p in lines[1].split(",")]
    event = parts[0] if parts else ""
    station = parts[-2] if len(parts) >= 4 else ""
    component = parts[-1] if len(parts) >= 4 else ""
    return make_motion(
        path,
        len(lines),
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
