"""Run independent tasks locally (a process pool) or on a Dask cluster, storing each result as
soon as it arrives and skipping tasks whose results are already stored.

Tasks may spawn follow-up tasks from their results (a ladder of scales steps up until the first
failure; a bisection halves its bracket), so the same loop drives searches as well as sweeps.
It is the library's one process pool: the validation run, the impact sweeps
(:func:`rigid.impact.sweep.run_parallel`) and the critical SA of record sets
(:func:`rigid.collapse.critical_sas`) all go through :func:`run_tasks`; the last two cache inside
their tasks and pass no store.
"""

from __future__ import annotations

import contextlib
import functools
import multiprocessing
import os
import signal
import sys
import threading
import time
from collections import Counter, deque
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field

from .cluster import ClusterError, DaskExecutor, _timed
from .progress import Progress, running, watch
from .store import ResultStore


@dataclass(frozen=True)
class Task:
    """One unit of work: ``func(**kwargs)`` must return a JSON-serialisable result.

    ``func`` must be importable at module level (it is sent to other processes by name).
    ``size`` is the task's share of the progress bar (e.g. the cells of a chunk of a sweep).
    ``leads`` False says the task never brings follow-ups (the rigid ladder of a record
    without FE runs): the time-left estimate then counts its own run only (:class:`Progress`).
    """

    key: str
    kind: str
    func: Callable
    kwargs: dict = field(default_factory=dict)
    size: int = 1
    leads: bool = True


class MissingResultsError(LookupError):
    """Results a replay (``run_tasks(..., replay=True)``) did not find in the store, by task
    kind (``.missing``, a :class:`collections.Counter`): their inputs or the code of the models
    they key on (:data:`rigid.tasks.cache.MODEL_CODE`) differ from those stored."""

    def __init__(self, missing: Counter, store=None):
        self.missing = missing
        kinds = ", ".join(f"{kind} {n}" for kind, n in sorted(missing.items()))
        where = f" in {store.path}" if store is not None else ""
        super().__init__(f"{sum(missing.values())} results are not{where} ({kinds}): their "
                         "inputs or their models' code changed since they were stored; run "
                         "without replay to compute them")


def default_workers() -> int:
    """Worker processes for the local pool: the CPUs this process may use."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not Linux
        return os.cpu_count() or 1


#: Environment variables that set the thread count of the numerical libraries in the workers.
_THREAD_VARIABLES = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS")


def _one_blas_thread():
    """A context that holds the numerical libraries of this process to one thread, unless the
    user set a thread count (:data:`_THREAD_VARIABLES`).

    The environment variables that make the pool's workers single-threaded come too late for
    this process, whose BLAS is loaded with a thread per core; threadpoolctl changes it in
    place. Multithreaded BLAS on the FE model's small dense blocks, beside other busy
    processes, made an FE run 25 times as expensive (BENCHMARKS.md)."""
    if any(var in os.environ for var in _THREAD_VARIABLES):
        return contextlib.nullcontext()
    from threadpoolctl import threadpool_limits

    return threadpool_limits(limits=1)


#: Seconds between two looks of a local worker at the pool's owner where Linux's parent-death
#: signal cannot serve (:func:`_die_with_parent`).
_PARENT_LOOK = 1.0


def _exists(pid: int) -> bool:
    """Whether process ``pid`` runs (a zombie, dead but not yet reaped, does not)."""
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    try:
        with open(f"/proc/{pid}/stat") as fh:
            return fh.read().rsplit(")", 1)[1].split()[0] != "Z"
    except OSError:  # no /proc: alive as far as can be told
        return True


def _die_with_parent(owner: int, initializer=None):
    """Initializer of the local pool's workers: end with the process that made the pool
    (``owner``), even when it is killed by SIGKILL and cannot stop them (an FE run in an
    orphaned worker went on for minutes, holding 300 MB); then run the caller's
    ``initializer``.

    Spawned workers are the owner's children: on Linux the kernel sends them SIGKILL at its
    death (``prctl(PR_SET_PDEATHSIG)``). A forkserver's workers are the server's children,
    and the server lives as long as they do; they, and workers where the signal is missing,
    run a daemon thread that looks every :data:`_PARENT_LOOK` seconds whether the owner still
    runs and ends the process when it does not (as soon as the task lets Python run: a Numba
    call holds the interpreter until it returns)."""
    parent = os.getppid()
    armed = False
    if parent == owner and sys.platform.startswith("linux"):
        try:
            import ctypes

            libc = ctypes.CDLL(None, use_errno=True)
            armed = libc.prctl(1, signal.SIGKILL, 0, 0, 0) == 0  # 1: PR_SET_PDEATHSIG
        except (OSError, AttributeError):
            armed = False
    if not _exists(owner) or (parent == owner and os.getppid() != owner):
        os._exit(1)  # the owner died before the signal was armed
    if not armed:
        def watch():
            while os.getppid() == parent and _exists(owner):
                time.sleep(_PARENT_LOOK)
            os._exit(1)

        threading.Thread(target=watch, daemon=True, name="dfp-owner-watch").start()
    if initializer is not None:
        initializer()


@contextlib.contextmanager
def _signals_held():
    """Hold SIGINT and SIGTERM back for the body, then deliver one that came meanwhile.

    A spawned worker reads its start-up data from a pipe its parent writes just after
    starting it; Ctrl-C or SIGTERM (which :mod:`validation.cli` turns into an exception)
    arriving in between left the pipe empty, and the new worker, never registered with the
    pool and so never stopped, printed ``EOFError: Ran out of input`` after the run's last
    line. The body runs with handlers that only note the signal; the caller's handlers come
    back and the signal is raised again at the end. Off the main thread (where handlers
    cannot be set) the body runs as it is."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    caught = []
    kinds = (signal.SIGINT, signal.SIGTERM)
    previous = {kind: signal.signal(kind, lambda signum, frame: caught.append(signum))
                for kind in kinds}
    try:
        yield
    finally:
        for kind, handler in previous.items():
            signal.signal(kind, handler)
        for signum in dict.fromkeys(caught):
            signal.raise_signal(signum)


class _Local:
    """A process pool (``spawn`` by default: fork is unsafe with Numba threads); with one
    worker, tasks run in this process instead (simplest to debug and profile), with one BLAS
    thread as in the workers."""

    def __init__(self, workers, start_method="spawn", initializer=None):
        from concurrent.futures import ProcessPoolExecutor

        self.capacity = workers
        self.pool = None
        if workers > 1:
            # one single-threaded process per core: BLAS threads on top oversubscribe the
            # cores (an FE run took 4 times as long; BENCHMARKS.md). The workers inherit the
            # environment; a user's own setting is kept.
            for var in _THREAD_VARIABLES:
                os.environ.setdefault(var, "1")
            context = multiprocessing.get_context(start_method)
            # the workers die with this process (_die_with_parent); Linux sends the signal
            # when the thread that started them ends, so they are started here, by the
            # thread that runs the tasks, which outlives the pool
            self.pool = ProcessPoolExecutor(
                max_workers=workers, mp_context=context,
                initializer=functools.partial(_die_with_parent, os.getpid(), initializer))

    def submit(self, task):
        from concurrent.futures import Future

        if self.pool is not None:
            with _signals_held():  # a submit may start a worker process
                return self.pool.submit(_timed, task.func, task.kwargs)
        future = Future()
        with _one_blas_thread():
            future.set_result(_timed(task.func, task.kwargs))
        return future

    def start(self, say):
        """Nothing to wait for: the pool's workers start with the first tasks."""

    def wait_one(self, futures):
        from concurrent.futures import FIRST_COMPLETED, wait

        return wait(futures, return_when=FIRST_COMPLETED).done

    @staticmethod
    def result(future):
        return future.result()

    def close(self, cancel=False, futures=()):
        if self.pool is None:
            return
        manager = self.pool._executor_manager_thread
        if cancel:  # interrupted: stop the running tasks too (an FE run takes minutes)
            for process in list((self.pool._processes or {}).values()):
                process.terminate()
        self.pool.shutdown(wait=not cancel, cancel_futures=cancel)
        if cancel and manager is not None:
            # let the pool's manager thread see its workers gone and end; one still alive at
            # interpreter exit is woken through a pipe it may have closed, and the exit then
            # prints an OSError traceback (CPython issue 83279; seen once after SIGTERM)
            manager.join(timeout=10)


def run_tasks(
    tasks: Iterable[Task],
    store: ResultStore | None,
    *,
    follow_up: Callable | None = None,
    scheduler=None,
    workers: int | None = None,
    progress: bool | None = None,
    description: str = "",
    unit: str = "run",
    start_method: str = "spawn",
    initializer: Callable | None = None,
    log=None,
    worker_wait: float = 60.0,
    replay: bool = False,
    seen: dict | None = None,
) -> dict:
    """Run the tasks whose results are not in ``store``; return every result by key.

    On any exception (Ctrl-C included) the tasks not yet started are cancelled and the running
    ones stopped (local workers terminated; on a cluster, the futures cancelled, which stops
    them on the workers: :mod:`rigid.tasks.cluster`); the results stored so far stay stored.
    Local workers also die with this process when it is killed (:func:`_die_with_parent`).
    A cluster that cannot go on raises :class:`rigid.tasks.cluster.ClusterError`, its message
    ending with the results stored and "rerun to resume".

    Parameters
    ----------
    tasks : iterable of Task
    store : ResultStore or None
        Results are read from it and each new one written to it at once. None: every task
        runs and nothing is stored (for tasks that cache their own parts; their results need
        not be JSON then).
    follow_up : callable, optional
        ``follow_up(task, result)`` → iterable of further tasks, called for every result
        (stored or new), e.g. the next rung of a ladder. They run before the tasks still
        queued, so that a chain of follow-ups (a search) proceeds while a long queue waits.
    scheduler : str or dask.distributed.Client, optional
        Address of a Dask scheduler, or a client: run the tasks there. The results come back
        to this process, which alone writes ``store``.
    workers : int, optional
        Local worker processes; default :func:`default_workers`; 1 runs in this process.
    progress : bool, optional
        True: a progress bar (refreshed every second); None (default): the bar on a terminal,
        elsewhere (a pipe) a plain progress line every :data:`~rigid.tasks.progress.HEARTBEAT`
        seconds on standard error; False: neither.
    description : str
        Label of the progress bar.
    unit : str
        Unit of the progress bar, counted in :attr:`Task.size`.
    start_method : str
        :mod:`multiprocessing` start method of the local pool (not ``"fork"``: Numba).
    initializer : callable, optional
        Run once in each local worker process as it starts (e.g. to load compiled code).
    log : path-like, optional
        Append to this file a line when the first run starts, one per task run (the time, the
        task's kind and seconds, runs done, running and queued, and an estimate of the time
        left for the queue known then: :class:`Progress`; the same figures follow the progress
        bar) and one every :data:`~rigid.tasks.progress.HEARTBEAT` seconds.
    worker_wait : float [s]
        On a cluster, the longest wait for a worker, at the start (the progress bar and the
        log say it waits) and whenever every worker has left.
    replay : bool
        Run nothing: every result comes from ``store`` (and the follow-ups of stored results
        too); the tasks not found there are counted and, once the stored ones are replayed,
        reported by :class:`MissingResultsError`.
    seen : dict, optional
        Filled with every task whose result was read from ``store``, by key (what
        :func:`rigid.tasks.rekey.rekey` reruns to compare).
    """
    from tqdm.auto import tqdm

    queue = deque(tasks)
    if replay:  # nothing runs: no pool, no cluster
        scheduler, workers = None, 1
    executor = (DaskExecutor(scheduler, worker_wait) if scheduler is not None
                else _Local(workers or default_workers(), start_method, initializer))
    plain = progress is None and not sys.stderr.isatty()  # a pipe: plain lines
    progress = sys.stderr.isatty() if progress is None else progress
    bar = tqdm(total=sum(t.size for t in queue), desc=description, unit=unit,
               disable=not progress, file=sys.stderr, dynamic_ncols=True)

    def say(text):  # on the bar, and in the log
        bar.set_postfix_str(text)
        if text and log is not None:
            with open(log, "a") as fh:
                fh.write(f"{time.strftime('%Y-%m-%d %H:%M:%S')}: {text}\n")

    try:
        executor.start(say)
    except BaseException:
        bar.close()
        executor.close(cancel=True)
        raise
    work = _Work(queue, store, follow_up, replay, seen, bar, Progress(executor.capacity, log))
    work.read_stored()
    in_flight, started = work.in_flight, work.started
    beat = watch(work.tally, queue, in_flight, started, bar=bar if progress else None,
                 stream=sys.stderr if plain else None)
    try:
        while queue or in_flight:
            while (len(in_flight) < executor.capacity
                   and (task := work.next_to_run()) is not None):
                beat.begin(len(queue) + 1)  # the log's first line, before any run
                future = executor.submit(task)
                in_flight[future], started[future] = task, work.tally.clock()
            for future in executor.wait_one(in_flight):
                task = in_flight.pop(future)
                started.pop(future, None)
                result, seconds = executor.result(future)
                if store is not None:
                    store.put(task.key, task.kind, result, seconds)
                work.finish(task, result, seconds)
    except ClusterError as exc:
        executor.close(cancel=True, futures=in_flight)
        raise ClusterError(f"{exc}; {_kept(work.results, store)}; rerun to resume") from None
    except BaseException:
        executor.close(cancel=True, futures=in_flight)
        raise
    finally:
        beat.stop()
        bar.close()
    executor.close()
    if work.missing:
        raise MissingResultsError(work.missing, store)
    return work.results


class _Work:
    """The queue of :func:`run_tasks` and its book-keeping: the results by key, the tasks in
    flight (future → task) and when each was submitted, the follow-ups, the progress bar and
    :class:`Progress`; in a replay, the kinds of the tasks not in the store."""

    def __init__(self, queue, store, follow_up, replay, seen, bar, tally):
        self.queue, self.store, self.follow_up = queue, store, follow_up
        self.replay, self.seen, self.bar, self.tally = replay, seen, bar, tally
        self.results, self.in_flight, self.started = {}, {}, {}
        self.missing = Counter()

    def read_stored(self) -> None:
        """Finish every queued task that the store holds, and every follow-up of theirs
        that it holds too, before any run starts: a resumed run's replay all at once, so
        that the log's first line counts the tasks left to run and :class:`Progress` meets
        every read before the first run ends (reads met between runs would make the tasks
        left look free: docs/validate.md, on the time left). The tasks left keep their order."""
        if self.store is None:
            return
        left = []
        while self.queue:
            task = self.queue.popleft()
            if self._pending(task):
                left.append(task)
        self.queue.extend(left)

    def next_to_run(self) -> Task | None:
        """The next queued task that must run, or None once the queue is empty; on the way,
        drop duplicates and finish the tasks found in the store (:meth:`_pending`; in a
        replay, count those that are not)."""
        while self.queue:
            task = self.queue.popleft()
            if not self._pending(task):
                continue
            if not self.replay:
                return task
            self.missing[task.kind] += 1
            self.bar.total -= task.size
        return None

    def _pending(self, task: Task) -> bool:
        """Whether ``task`` is still to be run: a duplicate of a task done or running is
        dropped and one the store holds is finished with its stored result (False)."""
        if task.key in self.results or any(t.key == task.key for t in self.in_flight.values()):
            self.bar.total -= task.size
            return False
        stored = None if self.store is None else self.store.get(task.key)
        if stored is None:
            return True
        if self.seen is not None:
            self.seen[task.key] = task
        if not self.replay:
            self.tally.stored(task.kind, self.store.seconds(task.key))
        self.finish(task, stored)
        return False

    def finish(self, task: Task, result, seconds: float | None = None) -> None:
        """Book ``result`` of ``task`` (run for ``seconds``, or None: read from the store) and
        queue its follow-ups ahead of the queue, so that a search's chain is not starved."""
        self.results[task.key] = result
        new = list(self.follow_up(task, result)) if self.follow_up else []
        self.tally.spawned(task.kind, new, ran=seconds is not None, leads=task.leads,
                           key=task.key)
        self.queue.extendleft(reversed(new))
        self.bar.total += sum(t.size for t in new)
        self.bar.update(task.size)
        if seconds is not None:
            line = self.tally.record(task.kind, seconds, running(self.in_flight, self.started),
                                     self.queue)
            self.bar.set_postfix_str(line.split(": ", 1)[1], refresh=False)


def _kept(results: dict, store) -> str:
    """What a stopped run keeps: the results in ``store`` (or, if it cannot be read, those
    seen)."""
    n, where = len(results), "done"
    if store is not None:
        with contextlib.suppress(OSError):  # a store that fails too: the results seen
            n, where = store.count(), f"stored in {store.path}"
    return f"{n} result{'' if n == 1 else 's'} {where}"
