"""Critical SA of one record under every limit state of the yielding rims from one set of
rungs: :func:`critical_sa_by_limit_state`.

Each rung runs to the loss of containment (``limit_state="containment"``) and keeps the limit
states it reached on the way (:attr:`Rung.limit_states`) and how it failed
(:attr:`Rung.failure_mode`). A limit state is reached at a rung when the rung reached it or
failed (a slider that escapes by uplift before the rim hinges has failed under every limit
state; Eq. R62 of docs/theory/rigid-body.md). The search of each limit state is the ladder's
own (full, or coarse-then-fine, Eq. C4 of docs/theory/collapse.md) over the shared rungs, so
the three answers cost about as much as the containment ladder alone. A run to containment is
the same run as one stopped at the hinge up to the moment of the hinge (the limit state only
says when to stop), which tests/test_yielding_rims.py checks against :func:`rigid.critical_sa`
run per limit state.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

from ..bearing import DFPBearing
from ..limit_states import LIMIT_STATES, check_limit_states
from ..units import G
from .ladder import _SEARCHES, CriticalSA, _ladder, check_ladder
from .search import fast_search

__all__ = ["critical_sa_by_limit_state", "failure_mode"]


@dataclass(frozen=True)
class _Reached:
    """A rung seen by the search of one limit state."""

    failed: bool
    max_impact_velocity: float


class _View(Mapping):
    """The rungs run so far (``done``), as failures under one limit state."""

    def __init__(self, done: dict, limit_state: str):
        self.done, self.limit_state = done, limit_state

    def __getitem__(self, j):
        return reached(self.done[j], self.limit_state)

    def __iter__(self):
        return iter(self.done)

    def __len__(self):
        return len(self.done)


def reached(rung, limit_state: str) -> _Reached:
    """Whether ``rung`` (a :class:`Rung` run to containment) fails under ``limit_state``."""
    return _Reached(rung.failed or limit_state in rung.limit_states, rung.max_impact_velocity)


def failure_mode(critical: CriticalSA) -> str | None:
    """How the record fails at its critical rung under the ladder's limit state: ``"rim"``
    (the rim reached the limit state: hinge, rupture, or let the slider through), ``"uplift"``
    (the slider climbed over a rim or overturned first), or None (no failure up to the
    ladder's top)."""
    if critical.sa is None:
        return None
    rung = next(r for r in critical.rungs if r.sa == critical.sa)
    if critical.limit_state != "containment" and critical.limit_state in rung.limit_states:
        return "rim"
    return "rim" if rung.failure_mode == "yielding" else "uplift"


def critical_sa_by_limit_state(
    bearing: DFPBearing,
    motion,
    rim_law,
    *,
    limit_states=LIMIT_STATES,
    step: float = 0.01 * G,
    stop: float = 3.0 * G,
    search: str = "fast",
    coarse: int = 10,
    refine_ratio: float = 0.8,
    period: float | None = None,
    damping: float = 0.05,
    dt: float | None = None,
    free: float = 20.0,
    cache=None,
    max_step: float | None = None,
    impact_merge_time: float = 0.05,
    coarse_factor: int | None = None,
) -> dict[str, CriticalSA]:
    """Critical SA(Tb) of a record with yielding rims under each limit state, from one set of
    rungs run to the loss of containment.

    Parameters
    ----------
    bearing : DFPBearing
    motion : GroundMotion or array_like [m/s²]
        The record (an array needs ``dt``).
    rim_law : rigid.rims.RimLaw
        The yielding rims' law (``fem.rim_law(bearing)``).
    limit_states : sequence of {"hinge", "rupture", "containment"}
    step, stop, search, coarse, refine_ratio, period, damping, dt, free, cache, max_step,
    impact_merge_time, coarse_factor
        As :func:`rigid.critical_sa` (SA in m/s², the ladder starting at one ``step``).

    Returns
    -------
    dict
        Limit state → :class:`CriticalSA` (``rims="yielding"``; every one lists all the rungs
        run); :func:`failure_mode` says how each failed.
    """
    start = check_ladder(bearing, search, _SEARCHES, step, coarse, None, stop)
    limit_states = check_limit_states(limit_states)
    rung = _ladder(bearing, motion, dt, start=start, step=step, stop=stop, period=period,
                   damping=damping, free=free, cache=cache, rims="yielding",
                   limit_state="containment", rim_law=rim_law, max_step=max_step,
                   impact_merge_time=impact_merge_time, coarse_factor=coarse_factor)
    n_rungs = rung.n_rungs

    firsts = {}
    for state in limit_states:
        view = _View(rung.done, state)

        def seen(j, state=state):
            return reached(rung(j), state)

        if search == "full":
            firsts[state] = next((j for j in range(n_rungs) if seen(j).failed), None)
        else:
            firsts[state] = fast_search(seen, view, n_rungs, int(coarse), float(refine_ratio))

    return {state: rung.critical(first, search, state) for state, first in firsts.items()}
