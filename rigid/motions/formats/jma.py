"""JMA strong-motion CSV files: a ``KEY= value`` header, a column line, three components."""

from __future__ import annotations

import math
import re

import numpy as np

from ...limits import MAX_RECORD_SAMPLES
from ..record import GroundMotion, RecordFormatError
from .text import (
    acceleration_bound,
    excerpt,
    implausible,
    make_motion,
    names_encoding,
    read_lines,
    sampling_interval,
    too_many_samples,
    unit_factor,
)


@names_encoding
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
    lines = read_lines(path)
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
    dt = sampling_interval(path, line_no, text, "SAMPLING RATE= 100Hz", "SAMPLING RATE")
    line_no, units = header.get("UNIT", (None, ""))
    unit_key = units.split("(")[0].strip()
    factor = unit_factor(path, line_no, unit_key, "'UNIT = gal'", shown=units)
    bound = acceleration_bound(factor)
    comp = component.strip().upper()
    if comp not in columns:
        raise RecordFormatError(path, first_data, f"component {excerpt(component, 20)} is not "
                                f"one of the file's columns {', '.join(columns)}")
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
                path, i + 1, f"expected numbers, found {excerpt(lines[i].strip())}"
            ) from None
        if not all(math.isfinite(x) for x in row):
            raise RecordFormatError(
                path, i + 1, f"expected finite numbers, found {excerpt(lines[i].strip())}"
            )
        for x, token in zip(row, tokens, strict=False):
            if abs(x) > bound:
                raise RecordFormatError(path, i + 1, implausible(token, x, bound))
        rows.append(row)
        if len(rows) > MAX_RECORD_SAMPLES:
            raise RecordFormatError(path, i + 1, too_many_samples())
    if not rows:
        raise RecordFormatError(path, first_data + 1, "expected data rows after the column line")
    data = np.array(rows)[:, columns.index(comp)]
    site = header.get("SITE CODE", (0, ""))[1]
    return make_motion(
        path,
        len(lines),
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
