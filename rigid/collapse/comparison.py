"""Predicted against actual critical SA over a record set: the table and paper Table 2.

A row per record holds the actual critical SA (time history, :func:`rigid.critical_sa`) and,
per criterion, the pulse (kind, Tp, Ap, e_a, e_v) and the predicted critical SA
(:func:`rigid.predict_critical_sa`) with its relative error. Table 2 of the paper counts the
predictions within 20 % of the actual values, split by pulse period (Tp > 0.5 s "long").
Accelerations in the rows are in g (a table is an edge of the program).
"""

from __future__ import annotations

import csv
import math
from pathlib import Path

from ..units import G

__all__ = ["comparison_rows", "ladder_rows", "table2", "write_csv"]


def _g(value):
    return math.nan if value is None else value / G


def comparison_rows(actual, predictions) -> list[dict]:
    """One row per record.

    Parameters
    ----------
    actual : sequence of CriticalSA
    predictions : dict {criterion: sequence of PredictedSA}
        Aligned with ``actual``.

    Returns
    -------
    list of dict
        ``record``, ``record_sa_g``, ``actual_sa_g`` (NaN without failure),
        ``resurrected``, ``rungs``, ``numerical_rungs`` (rungs whose integration stayed
        unstable: neither failures nor survivals), ``uncertain`` (the actual critical SA
        depends on them, :attr:`CriticalSA.uncertain`); per criterion c: ``kind_c``,
        ``tp_c`` [s], ``ap_c_g`` (|Ap| of the unscaled record), ``e_a_c``, ``e_v_c``,
        ``predicted_sa_g_c``, ``error_c`` = predicted/actual − 1, ``uncertain_c`` (the
        prediction depends on numerical rungs).
    """
    rows = []
    for i, a in enumerate(actual):
        row = {
            "record": a.name,
            "record_sa_g": a.record_sa / G,
            "actual_sa_g": _g(a.sa),
            "resurrected": a.resurrected,
            "rungs": len(a.rungs),
            "numerical_rungs": len(a.numerical_failures),
            "uncertain": a.uncertain,
        }
        for c, preds in sorted(predictions.items()):
            p = preds[i]
            if p.name != a.name:
                raise ValueError(f"predictions for criterion {c} are not aligned: "
                                 f"{p.name!r} against {a.name!r}")
            row[f"kind_{c}"] = p.pulse.kind
            row[f"tp_{c}"] = p.pulse.period
            row[f"ap_{c}_g"] = abs(p.pulse.amplitude) / G
            row[f"e_a_{c}"] = p.pulse.e_a
            row[f"e_v_{c}"] = p.pulse.e_v
            row[f"predicted_sa_g_{c}"] = _g(p.sa)
            row[f"error_{c}"] = (p.sa / a.sa - 1.0) if (p.sa is not None and a.sa) else math.nan
            row[f"uncertain_{c}"] = p.uncertain
        rows.append(row)
    return rows


def table2(rows, criterion: int, tolerance: float = 0.2, split: float = 0.5) -> dict:
    """Share of good predictions (|predicted/actual − 1| ≤ tolerance), paper Table 2
    (docs/theory/collapse.md, Eq. C6).

    Parameters
    ----------
    rows : list of dict
        From :func:`comparison_rows`.
    criterion : int
    tolerance : float [-]
        Paper: 20 %.
    split : float [s]
        Pulses with Tp > split are "long period" (paper: 0.5 s).

    Returns
    -------
    dict
        For ``"all"``, ``"long"`` (Tp > split) and ``"short"``: ``(good, n)``. Records without
        an actual failure, or whose actual critical SA depends on numerical rungs
        (``uncertain``), are left out; a missing prediction, or one that depends on numerical
        rungs, counts as not good.
    """
    out = {"all": [0, 0], "long": [0, 0], "short": [0, 0]}
    for r in rows:
        if math.isnan(r["actual_sa_g"]) or r.get("uncertain", False):
            continue
        err = r[f"error_{criterion}"]
        good = ((not math.isnan(err)) and abs(err) <= tolerance + 1e-12
                and not r.get(f"uncertain_{criterion}", False))
        group = "long" if r[f"tp_{criterion}"] > split else "short"
        for g in ("all", group):
            out[g][0] += int(good)
            out[g][1] += 1
    return {k: tuple(v) for k, v in out.items()}


def ladder_rows(actual) -> list[dict]:
    """Every rung of every ladder: record, sa_g, scale, failed, numerical_failure, impacts,
    max_impact_velocity [m/s], max_uplift [m], resurrection (survived above a failure)."""
    rows = []
    for a in actual:
        res = {r.index for r in a.resurrections}
        for r in a.rungs:
            rows.append({
                "record": a.name, "sa_g": r.sa / G, "scale": r.scale, "failed": r.failed,
                "numerical_failure": r.numerical_failure, "impacts": r.impacts,
                "max_impact_velocity": r.max_impact_velocity, "max_uplift": r.max_uplift,
                "resurrection": r.index in res,
            })
    return rows


def write_csv(rows, path) -> Path:
    """Write a list of dicts (same keys) as CSV, floats with 6 significant digits; written to a
    temporary file beside ``path`` and renamed over it, so a failed write (a full disk) leaves
    the previous file."""
    from ..tasks.files import atomic_write

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    with atomic_write(path, "w", newline="") as fh:
        if rows:
            w = csv.DictWriter(fh, fieldnames=list(rows[0]))
            w.writeheader()
            for r in rows:
                w.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v)
                            for k, v in r.items()})
    return path
