"""Every table of the report in one NetCDF file: a group per table, a variable per column
along the table's ``row`` dimension, units in the variables' attributes.

Column names of the report's tables carry their unit (``actual_sa_g``, ``tp_3``,
``dt [s]``); :func:`column_units` reads it and :func:`variable_name` makes a NetCDF-safe name
(the original column name is kept in the ``long_name`` attribute).
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np

#: Units of report columns that do not name their unit in brackets or a suffix.
_UNITS = [
    (re.compile(r"\[(.+)\]"), None),  # "dt [s]" → the bracket's content
    (re.compile(r"(^|_)sa_g(_|$)|_g$|_g_"), "g"),
    (re.compile(r"^tp_\d$"), "s"),
    (re.compile(r"_s$"), "s"),
    (re.compile(r"_mpa$"), "MPa"),
    (re.compile(r"_mn$"), "MN"),
    (re.compile(r"^max_impact_velocity$"), "m/s"),
    (re.compile(r"^max_uplift$"), "m"),
    (re.compile(r"^cpu_min$|_min$"), "min"),
]


def column_units(name: str) -> str:
    """Unit of a report column from its name ("1" when dimensionless or not numeric)."""
    for pattern, unit in _UNITS:
        m = pattern.search(name)
        if m:
            return unit or m.group(1)
    return "1"


def variable_name(name: str) -> str:
    """A NetCDF-safe variable name: the column name without its bracketed unit, other
    characters than letters, digits and underscores replaced by underscores."""
    text = re.sub(r"\s*\[.*?\]", "", name).strip()
    text = re.sub(r"[^0-9A-Za-z_]+", "_", text).strip("_")
    return text if text and not text[0].isdigit() else f"v_{text}"


def _column(values):
    if all(isinstance(v, bool) for v in values):
        return np.array(values, dtype=np.int8), {"flag_values": [0, 1],
                                                  "flag_meanings": "no yes"}
    if all(v is None or (isinstance(v, (int, float, np.number)) and not isinstance(v, bool))
           for v in values):
        return np.array([math.nan if v is None else float(v) for v in values]), {}
    return np.array(["" if v is None else str(v) for v in values], dtype=object), {}


def write_tables(tables: dict, path, attrs: dict | None = None) -> Path:
    """Write ``{table name: list of dict rows}`` to one NetCDF-4 file, a group per table.

    Booleans are stored as int8 0/1 (with ``flag_meanings``), None as NaN (numbers) or ""
    (text). ``attrs`` go to the root group. The file is written beside ``path`` under a
    temporary name and renamed over it once complete, so a failed write (a full disk) leaves
    the previous file; the NetCDF library's errors are raised as OSError naming the file.
    """
    import xarray as xr

    from rigid.tasks import atomic_path

    path = Path(path)
    datasets = [(None, xr.Dataset(attrs=attrs or {}))]
    for name, rows in tables.items():
        data = {}
        for key in (rows[0] if rows else {}):
            values, extra = _column([r.get(key) for r in rows])
            var = variable_name(key)
            if var in data:
                raise ValueError(f"table {name}: columns collide as NetCDF variable {var!r}")
            data[var] = ("row", values, {"long_name": key, "units": column_units(key), **extra})
        datasets.append((name, xr.Dataset(data, attrs={"rows": len(rows)})))
    try:
        with atomic_path(path) as tmp:
            for group, ds in datasets:
                ds.to_netcdf(tmp, mode="w" if group is None else "a", group=group,
                             engine="netcdf4")
    except (RuntimeError, OSError) as exc:  # netCDF4 raises RuntimeError ("NetCDF: HDF error")
        raise OSError(f"cannot write {path}: {exc}") from None
    return path


def read_table(path, name: str) -> list[dict]:
    """One table back as dict rows keyed by the original column names (int8 flags as bool)."""
    import xarray as xr

    with xr.open_dataset(path, group=name, engine="netcdf4") as ds:
        columns = {}
        for var in ds.data_vars:
            v = ds[var]
            values = v.values
            if "flag_meanings" in v.attrs:
                values = values.astype(bool)
            columns[v.attrs.get("long_name", var)] = [x.item() if hasattr(x, "item") else x
                                                      for x in values]
        n = int(ds.attrs.get("rows", 0))
    return [{k: col[i] for k, col in columns.items()} for i in range(n)]
