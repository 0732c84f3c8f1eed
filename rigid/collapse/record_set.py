"""Critical SA of every record of a set: :func:`critical_sas`, the records in parallel through
the task runner (:func:`rigid.tasks.run_tasks`), with progress and the rung cache of
:func:`rigid.critical_sa` (docs/theory/collapse.md, Eqs. C1–C3)."""

from __future__ import annotations

import os

from ..bearing import DFPBearing
from .ladder import CriticalSA, critical_sa

__all__ = ["critical_sas", "pool_context"]


def _record_task(bearing, motion, kwargs):
    return critical_sa(bearing, motion, **kwargs)


def pool_context():
    """The multiprocessing context of :func:`critical_sas`'s pool (also used by the critical-SA
    study)."""
    import multiprocessing as mp

    # numba-compiled code and fork can deadlock (threads/locks copied); prefer forkserver
    methods = mp.get_all_start_methods()
    return mp.get_context("forkserver" if "forkserver" in methods else "spawn")


def critical_sas(
    bearing: DFPBearing,
    motions,
    *,
    processes: int | None = None,
    progress: bool = True,
    cache=True,
    **kwargs,
) -> list[CriticalSA]:
    """Critical SA of every record of a set, in parallel, with progress and a resumable cache.

    Parameters
    ----------
    bearing : DFPBearing
    motions : sequence of GroundMotion
    processes : int, optional
        Worker processes of :func:`rigid.tasks.run_tasks` (forkserver, else spawn
        context); default ``os.cpu_count()``; 1 (or a single record) runs in this process.
        On any exception (Ctrl-C included) the records not started are cancelled and the
        workers terminated; finished rungs are already in the cache.
    progress : bool
        Show a tqdm progress bar over records (stderr).
    cache : None, True, str or Path
        Rung cache directory (see :func:`critical_sa`); default the user cache.
    **kwargs
        Passed to :func:`critical_sa` (step, stop, search, after_failure, …).

    Returns
    -------
    list of CriticalSA
        In the order of ``motions``.
    """
    from ..tasks import Task, run_tasks

    motions = list(motions)
    kwargs = {**kwargs, "cache": cache}
    if kwargs.get("rims") == "yielding":  # the law once, here, not in every worker
        from ..rims import resolve_rim_law

        kwargs["rim_law"] = resolve_rim_law(bearing, kwargs.get("rim_law"), stacklevel=3)
    processes = (os.cpu_count() or 1) if processes is None else int(processes)
    tasks = [Task(str(i), "critical-sa", _record_task,
                  {"bearing": bearing, "motion": m, "kwargs": kwargs})
             for i, m in enumerate(motions)]
    results = run_tasks(tasks, None, workers=1 if len(motions) <= 1 else max(1, processes),
                        progress=bool(progress), unit="record",
                        description=f"critical SA ({bearing.pressure / 1e6:g} MPa)",
                        start_method=pool_context().get_start_method())
    return [results[t.key] for t in tasks]
