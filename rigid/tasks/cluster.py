"""Tasks on a Dask cluster, for :func:`rigid.tasks.runner.run_tasks`: the client, a bounded
wait for workers, one error for a cluster that cannot go on (:class:`ClusterError`: scheduler
unreachable or lost, no workers, a task that kills its workers), and a cancellation that
reaches the tasks already running on the workers (:func:`run_cancellable`).

Results come back to the client, which alone writes the result store: a worker needs no view
of the client's files (a task's own cache, such as the rung cache of the validation's rigid
ladders, is kept only where the worker sees the output folder:
:func:`validation.run.record_task`).

Dask cannot stop a task that is running in a worker's thread: cancelling its future only
drops the result. An FE run takes minutes, so each task here runs under a watcher thread that
polls its state on the worker every :data:`POLL` seconds and, once the task is no longer
wanted (cancelled, released), raises :class:`TaskCancelled` in the task's thread
(``PyThreadState_SetAsyncExc``). The exception lands at the next Python bytecode of the task,
so a task in compiled code (one Numba simulation of the rigid model, one sparse solve) stops
when that call returns: well within a second for the models here.
"""

from __future__ import annotations

import contextlib
import ctypes
import threading
import time

__all__ = ["POLL", "ClusterError", "DaskExecutor", "TaskCancelled", "run_cancellable"]

#: Seconds between two looks of a task's watcher at its state on the worker.
POLL = 0.2
#: Seconds between two looks of the client at the scheduler's workers while it waits.
_LOOK = 1.0


class ClusterError(RuntimeError):
    """The Dask cluster cannot run the tasks: its scheduler cannot be reached or was lost,
    no worker joined within the wait, or a task killed the workers that ran it. The message
    (one line) names the scheduler's address."""


class TaskCancelled(Exception):
    """Raised inside a running task whose future was cancelled (:func:`run_cancellable`)."""


def _timed(func, kwargs):
    start = time.perf_counter()
    result = func(**kwargs)
    return result, time.perf_counter() - start


def run_cancellable(func, kwargs):
    """``func(**kwargs)`` and its seconds, in a Dask worker; stopped by :class:`TaskCancelled`
    once its future is no longer wanted (module docstring). Outside a worker: just the call."""
    try:
        from distributed.worker import get_worker, thread_state

        worker, key = get_worker(), thread_state.key
    except (ImportError, ValueError, AttributeError):
        return _timed(func, kwargs)
    target, done, lock = threading.get_ident(), threading.Event(), threading.Lock()
    raise_in = ctypes.pythonapi.PyThreadState_SetAsyncExc

    def wanted() -> bool:
        ts = worker.state.tasks.get(key)
        return ts is not None and ts.state not in ("cancelled", "released", "forgotten")

    def watch():
        while not done.wait(POLL):
            if not wanted():
                with lock:  # never after the task has finished: the thread runs others then
                    if not done.is_set():
                        raise_in(ctypes.c_ulong(target), ctypes.py_object(TaskCancelled))
                return

    threading.Thread(target=watch, daemon=True, name=f"dfp-watch-{key}").start()
    try:
        return _timed(func, kwargs)
    finally:
        with lock:
            done.set()
            raise_in(ctypes.c_ulong(target), None)  # drop one raised too late to matter


class DaskExecutor:
    """The executor of :func:`rigid.tasks.runner.run_tasks` on a Dask cluster.

    Parameters
    ----------
    scheduler : str or dask.distributed.Client
        The scheduler's address, or a client (left open at the end).
    worker_wait : float [s]
        Longest wait for a worker, at the start and whenever every worker has left.
    """

    def __init__(self, scheduler, worker_wait: float = 60.0):
        from dask.distributed import Client

        self.own = not isinstance(scheduler, Client)
        self.address = str(scheduler) if self.own else scheduler.scheduler.address
        self.worker_wait = float(worker_wait)
        try:
            self.client = Client(scheduler) if self.own else scheduler
        except OSError as exc:
            raise ClusterError(f"cannot reach the Dask scheduler at {self.address}: "
                               f"{' '.join(str(exc).split())}") from None
        self._alone_since = None  # when the scheduler was last seen without workers
        self._say = lambda text: None
        self.capacity = self._capacity()

    def _capacity(self) -> int:
        """Tasks kept in flight: two per worker thread (one queued behind each running)."""
        with self._guard():
            return max(1, 2 * sum(self.client.nthreads().values()))

    def _lost(self, exc) -> bool:
        from distributed.comm.core import CommClosedError

        return (self.client.status != "running" or isinstance(exc, CommClosedError)
                or "scheduler-connection-lost" in str(exc))

    @contextlib.contextmanager
    def _guard(self):
        """Raise the errors of a lost scheduler, or of a task that killed its workers, as
        :class:`ClusterError`; a task's own error as it is."""
        from distributed.scheduler import KilledWorker

        try:
            yield
        except ClusterError:
            raise
        except Exception as exc:
            if isinstance(exc, KilledWorker):
                raise ClusterError(f"a task killed every Dask worker that ran it (scheduler "
                                   f"{self.address}; out of memory?): {exc}") from None
            if self._lost(exc):
                raise ClusterError(f"lost the Dask scheduler at {self.address}") from None
            raise

    def start(self, say) -> None:
        """Wait until the scheduler has a worker (at most :attr:`worker_wait`), telling
        ``say(text)`` that it waits; :class:`ClusterError` if none comes."""
        from dask.distributed import TimeoutError as DaskTimeout  # asyncio's before 3.11

        self._say = say
        with self._guard():
            if self.client.nthreads():
                return
            say(f"waiting for Dask workers at {self.address} (up to {self.worker_wait:g} s)")
            try:
                self.client.wait_for_workers(1, timeout=self.worker_wait)
            except (TimeoutError, DaskTimeout, OSError) as exc:
                if self._lost(exc):
                    raise
                raise ClusterError(f"no Dask worker joined the scheduler at {self.address} "
                                   f"within {self.worker_wait:g} s: start some (dask worker "
                                   f"{self.address}) or wait longer (--worker-wait)") from None
            say("")
        self.capacity = self._capacity()

    def submit(self, task):
        with self._guard():
            return self.client.submit(run_cancellable, task.func, task.kwargs,
                                      key=f"{task.kind}-{task.key}", pure=False)

    def wait_one(self, futures):
        """The futures done, at least one; looking at the workers every second: if every
        one has left for :attr:`worker_wait` seconds, :class:`ClusterError`."""
        from dask.distributed import TimeoutError as DaskTimeout
        from dask.distributed import wait

        while True:
            with self._guard():
                try:
                    done = wait(list(futures), timeout=_LOOK, return_when="FIRST_COMPLETED").done
                except (TimeoutError, DaskTimeout):
                    done = None
                if done:
                    self._alone_since = None
                    return done
                if self.client.status != "running":
                    raise ClusterError(f"lost the Dask scheduler at {self.address}")
                workers = self.client.nthreads()
            now = time.monotonic()
            if workers:
                if self._alone_since is not None:
                    self._say("")
                self._alone_since = None
                self.capacity = max(1, 2 * sum(workers.values()))
            elif self._alone_since is None:
                self._alone_since = now
                self._say(f"every Dask worker left {self.address}; waiting for one (up to "
                          f"{self.worker_wait:g} s)")
            elif now - self._alone_since > self.worker_wait:
                raise ClusterError(f"every Dask worker of the scheduler at {self.address} "
                                   f"left and none came back within {self.worker_wait:g} s")

    def result(self, future):
        with self._guard():
            return future.result()

    def close(self, cancel=False, futures=()):
        """Cancel ``futures`` (the tasks stop on the workers: :func:`run_cancellable`) when
        ``cancel``; close our own client."""
        running = self.client.status == "running"
        if cancel and futures and running:
            with contextlib.suppress(Exception):
                self.client.cancel(list(futures), force=True)
        if self.own:
            with contextlib.suppress(Exception):
                self.client.close(timeout=10 if running else 2)
