"""The fast search of a scaling ladder: every ``coarse``-th rung up to the first failure, then
the fine rungs of each coarse interval that may hide a failure (docs/theory/collapse.md, Eq.
C4). Used by :func:`rigid.critical_sa` (``search="fast"``), the prediction's ladder and the
trimming check."""

from __future__ import annotations

import math

__all__ = ["coarse_scan", "fast_search"]


def coarse_scan(hit, n_rungs: int, coarse: int) -> tuple[list, int | None]:
    """Every ``coarse``-th rung (and the last) up to the first j with ``hit(j)``: the rungs
    run and that first hit (None if none). The first stage of the fast searches."""
    ends = []
    for j in range(coarse - 1, n_rungs + coarse - 1, coarse):
        j = min(j, n_rungs - 1)
        ends.append(j)
        if hit(j):
            return ends, j
        if j == n_rungs - 1:
            break
    return ends, None


def fast_search(rung, done: dict, n_rungs: int, coarse: int, ratio: float):
    """Index of the lowest failing rung found by the coarse-then-fine search, or None (Eq. C4
    of docs/theory/collapse.md).

    ``rung(j)`` runs (or looks up) rung j and returns an object with ``failed`` and
    ``max_impact_velocity`` [m/s]; ``done`` maps the rungs run so far to those objects;
    ``coarse`` and ``ratio`` are :func:`critical_sa`'s ``coarse`` and ``refine_ratio``."""
    # coarse rungs run, up to the first coarse failure
    ends, first = coarse_scan(lambda j: rung(j).failed, n_rungs, coarse)
    if first is None:
        return None

    def speed(j):
        v = rung(j).max_impact_velocity if j >= 0 else 0.0
        return v if math.isfinite(v) else math.inf  # unknown (numerical failure): scan

    scanned = set()
    while True:
        v_fail = min(speed(j) for j, r in done.items() if r.failed)
        intervals = [(lo, hi) for lo, hi in zip([-1, *ends[:-1]], ends, strict=True)
                     if lo < first and (lo, hi) not in scanned
                     and max(speed(lo), speed(hi)) >= ratio * v_fail]  # Eq. C4
        if not intervals:
            return first
        lo, hi = intervals[0]
        scanned.add((lo, hi))
        for j in range(lo + 1, min(hi, first)):
            if rung(j).failed:
                first = j
                break
