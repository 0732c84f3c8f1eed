"""Ground-motion file readers; :func:`read_record` picks one from the file's first lines.

All readers return a :class:`~rigid.motions.record.GroundMotion` in m/s² (g, gal and cm/s² are
converted at the edge) and raise :class:`~rigid.motions.record.RecordFormatError` naming the
file, the line and what was expected:

- :func:`read_peer_at2` — PEER NGA ``.AT2`` (NGA-West2 ``NPTS= …, DT= …`` header and the older
  ``… NPTS, … DT`` form);
- :func:`read_knet` — K-NET / KiK-net ASCII (``Scale Factor`` counts to gal);
- :func:`read_jma_csv` — JMA strong-motion CSV (``SITE CODE=``, ``SAMPLING RATE=``, three
  columns NS, EW, UD);
- :func:`read_plain` — one column (acceleration) or two (time, acceleration), with dt and units
  given by the caller.
"""

from __future__ import annotations

from dataclasses import replace

from ..record import GroundMotion
from .jma import read_jma_csv
from .knet import read_knet
from .peer import read_peer_at2
from .plain import read_plain
from .text import read_lines

__all__ = ["detect_format", "read_jma_csv", "read_knet", "read_peer_at2", "read_plain",
           "read_record"]


def detect_format(path) -> str:
    """Guess the format of a record file from its first lines.

    Returns
    -------
    {"peer", "knet", "jma", "plain"}
    """
    head = "\n".join(read_lines(path)[:20]).upper()
    if head.startswith("PEER") or "UNITS OF" in head or ("NPTS" in head and "DT" in head):
        return "peer"
    knet_keys = ("ORIGIN TIME", "STATION CODE", "SAMPLING FREQ", "SCALE FACTOR", "MEMO.")
    if sum(key in head for key in knet_keys) >= 2:  # a K-NET header, perhaps incomplete
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
