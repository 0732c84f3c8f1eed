"""K-NET and KiK-net ASCII files (NIED): integer counts and a ``Scale Factor`` to gal."""

from __future__ import annotations

import math
import re
from pathlib import Path

from ..record import GroundMotion, RecordFormatError
from .text import (
    NUMBER,
    acceleration_bound,
    excerpt,
    fortran_float,
    make_motion,
    names_encoding,
    parse_block,
    read_lines,
    sampling_interval,
)

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


@names_encoding
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
    lines = read_lines(path)
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
    dt = sampling_interval(path, line_no, text, "Sampling Freq(Hz) 100Hz", "Sampling Freq(Hz)")
    line_no, text = header["scale_factor"]
    m = re.match(rf"({NUMBER})\s*\(\s*([^)]+)\)\s*/\s*({NUMBER})", text)
    if not m:
        raise RecordFormatError(
            path, line_no, f"expected 'Scale Factor 7845(gal)/8223790', found {excerpt(text)}"
        )
    if m.group(2).strip().lower() != "gal":
        raise RecordFormatError(path, line_no,
                                f"wrong units {excerpt(m.group(2), 20)}: expected (gal)")
    numerator, denominator = (fortran_float(m.group(k)) for k in (1, 3))
    if not (0 < numerator < float("inf") and 0 < denominator < float("inf")):
        raise RecordFormatError(path, line_no, "expected a positive, finite scale factor "
                                f"(gal per count), found {excerpt(text)}")
    gain = numerator / denominator
    if not gain > 0:
        raise RecordFormatError(path, line_no, f"scale factor {excerpt(text)} is zero")
    counts = parse_block(path, lines, first_data, None, per_line=8,
                         bound=acceleration_bound(0.01 * gain))
    if "duration" in header:
        line_no, text = header["duration"]
        try:
            duration = float(text)
        except ValueError:
            raise RecordFormatError(
                path, line_no, f"expected a duration in s, found {excerpt(text)}"
            ) from None
        if not (math.isfinite(duration) and duration >= 0):
            raise RecordFormatError(path, line_no,
                                    f"expected a duration in s, found {excerpt(text)}")
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
    return make_motion(
        path,
        len(lines),
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
