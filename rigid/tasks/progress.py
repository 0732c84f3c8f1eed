"""What a run of tasks tells the people watching it (:func:`rigid.tasks.run_tasks`): the time
left, estimated from the measured run times (:class:`Progress`), and a line at a fixed
interval whatever the tasks do (:class:`Heartbeat`): on a terminal the progress bar is
refreshed, elsewhere (a pipe, a log collector) a plain line is printed; the log file gets a
line when the first run starts and at every interval."""

from __future__ import annotations

import threading
import time
from pathlib import Path

import numpy as np

__all__ = ["HEARTBEAT", "Heartbeat", "Progress", "running", "watch"]

#: Chain lengths kept per kind (:class:`Progress`): the latest ones, for changes of pace.
CHAINS = 50
#: Seconds between two progress lines when nothing else is printed (a pipe), and between two
#: heartbeat lines of the log file: under the 30 s that issue #32 asks for, with room for a
#: thread woken late on a busy machine.
HEARTBEAT = 25.0


class Progress:
    """Figures of a run of tasks for people watching it: runs done, running and queued, seconds
    per run by kind, and the time left: the queued and running tasks and the follow-ups they
    are expected to bring (a search's next runs), at the rates seen so far; appended to a log
    file when one is given.

    Each finished task of kind A has brought r_AB follow-ups of kind B on average and has run
    (rather than been read from the store) with frequency s_A, so the expected work of one
    task of kind A, its follow-ups included, solves W_A = s_A m_A + Σ_B r_AB W_B (m: mean
    seconds per run of each kind), i.e. W = (I − R)⁻¹ (s m); where that has no finite
    positive solution (a chain that has so far always gone on) only the known queue counts.
    Tasks that say they bring none (:attr:`Task.leads` False) are left out of r_AB and count
    s_A m_A alone: otherwise the FE searches of two records made every one of 54 queued
    ladders look like the start of a search (65 h left shown after the first FE run of the
    default-mesh check, which has 4 searches).

    A resumed run first reads what its store holds (finished searches, s_A ≈ 0) and then
    meets the searches still open (s_A ≈ 1, longer chains); counted in, that replay makes the
    estimate far too low (a resumed FE validation showed 15 min where 2 h were left). So s_A
    leaves out the tasks read from the store before the first run ends (they still teach r_AB,
    the searches' shape), and the counts and the mean seconds weigh the tasks of each kind by
    recency, with a half-life of ``half_life`` tasks of that kind (``math.inf``: equal
    weights), for the replays and changes of pace that come later.

    A search is a chain of runs of one kind, each bringing the next until it ends; its
    length is bounded (a bracket, then a bisection), which the fixed r_AA of the sum above
    does not know: counted from the runs so far (the open chains' runs all continued) and
    applied as much to a chain's tenth run as to its first, it overstated the time left up to
    5-fold (tests/test_progress.py). So, where :meth:`spawned` is given the tasks' keys, the
    lengths of the chains that ended are kept (and those of the open ones, as far as known),
    and a chain's run at depth d (the d-th after its first) is worth
    s_A m_A (1 + E[L − d − 1 | L > d]) (:meth:`_chain_rest`); a new chain s_A m_A E[L], which
    replaces r_AA in the sum (a ladder that starts searches counts their runs so). Without
    the keys, the sum above stands.

    A resumed run also learns how long its stored results took to run (:meth:`stored`, the
    store's record of each): they start the mean seconds of their kind, oldest first, so
    that its first estimates do not rest on its first runs alone (the shortest end first),
    and its own runs take over by recency."""

    def __init__(self, capacity: int, log=None, half_life: float = 50.0, clock=time.monotonic):
        self.capacity = max(1, int(capacity))
        self.clock = clock  # seconds, for the time so far and the running tasks' elapsed
        self.log = None if log is None else Path(log)
        self.decay = 0.5 ** (1.0 / half_life)  # weight kept by the older tasks of a kind
        self.seconds: dict = {}    # kind → seconds of the runs of this run, in order
        self.timed: dict = {}      # kind → seconds of the stored results read, in order
        self.finished: dict = {}   # kind → weight of the tasks finished (run or read)
        self.leading: dict = {}    # the same, of the tasks that may bring follow-ups
        self.met: dict = {}        # the same without the replay before the first run ends
        self.ran: dict = {}        # kind → weight of the tasks run
        self.children: dict = {}   # (kind, follow-up kind) → weight of the follow-ups brought
        self.depth: dict = {}      # key → (kind, runs before it in its chain), while open
        self.chains: dict = {}     # kind → lengths of the chains that ended, latest last
        self.started = clock()
        self.left: float | None = None  # the last estimate of the time left [s]
        self._last = None  # kind of the last task recorded

    def spawned(self, kind: str, follow_ups, ran: bool = True, leads: bool = True,
                key: str | None = None) -> None:
        """Enter the follow-ups a finished task of ``kind`` brought, whether it ran (False:
        its result was read from the store) and whether it could bring any (:attr:`Task.leads`);
        ``key``, the task's key, places it in its chain (class docstring)."""
        def count(counts, amount):  # one more task of this kind: the older ones decay
            counts[kind] = counts.get(kind, 0.0) * self.decay + amount

        if key is not None:
            depth = self.depth.pop(key, (kind, 0))[1]
            same = [t for t in follow_ups if t.kind == kind]
            for t in same:
                self.depth[t.key] = (kind, depth + 1)
            if not same and (depth or leads):
                self.chains.setdefault(kind, []).append(depth + 1)
                del self.chains[kind][:-CHAINS]

        count(self.finished, 1.0)
        if ran or self.seconds:  # the replay before the first run ends teaches r_AB only
            count(self.met, 1.0)
            count(self.ran, float(bool(ran)))
        if not (leads or follow_ups):
            return
        count(self.leading, 1.0)
        for pair in self.children:
            if pair[0] == kind:
                self.children[pair] *= self.decay
        for t in follow_ups:
            self.children[kind, t.kind] = self.children.get((kind, t.kind), 0.0) + 1.0

    def stored(self, kind: str, seconds: float | None) -> None:
        """Enter the seconds a stored result of ``kind`` took when it ran (None: not timed)."""
        if seconds is not None:
            self.timed.setdefault(kind, []).append(float(seconds))

    def _mean(self, kind: str) -> float:
        """Recency-weighted mean seconds of the runs of ``kind``, the stored ones' first
        (class docstring)."""
        runs = self.timed.get(kind, []) + self.seconds.get(kind, [])
        weights = self.decay ** np.arange(len(runs) - 1, -1, -1, dtype=float)
        return float(np.dot(weights, runs) / weights.sum())

    def _share(self, kind: str) -> float:
        """s_A: how often a task of ``kind`` runs rather than being read (class docstring)."""
        return self.ran[kind] / self.met[kind] if self.met.get(kind) else 1.0

    def _work(self, mean: dict, default: float) -> dict:
        """Expected seconds of one task of each kind with its follow-ups (class docstring):
        a kind that chains, with chains known, counts its chain's runs, 1 + E[L − 1], in
        place of the fixed continuation rate r_AA."""
        kinds = sorted(set(mean) | set(self.finished) | {b for _, b in self.children})
        m = np.array([mean.get(k, default) * self._share(k) for k in kinds])
        r = np.array([[self.children.get((a, b), 0) / self.leading[a] if self.leading.get(a)
                       else 0.0 for b in kinds] for a in kinds])
        for i, kind in enumerate(kinds):
            rest = self._chain_rest(kind, 0) if self.children.get((kind, kind)) else None
            if rest is not None:
                m[i] *= 1.0 + rest
                r[i, i] = 0.0
        try:
            w = np.linalg.solve(np.eye(len(kinds)) - r, m)
        except np.linalg.LinAlgError:
            w = m
        if not np.all(np.isfinite(w)) or np.any(w < m * (1 - 1e-9)):  # round-off allowed
            w = m
        return dict(zip(kinds, w.tolist(), strict=True))

    def _chain_rest(self, kind: str, depth: int) -> float | None:
        """E[L − d − 1 | L > d]: the runs expected after a chain's run at ``depth`` (class
        docstring), over the chains of ``kind`` that ended and those still open (a run under
        way or queued at depth k: taken as k + 1 long, as far as known); where none is
        longer than d, d more (a chain that went on d runs may go on as many again); None
        when no chain of ``kind`` is known (the sum of the class docstring then)."""
        ended = self.chains.get(kind, [])
        open_ = [k + 1 for kd, k in list(self.depth.values()) if kd == kind]
        if not ended and not open_:
            return None
        longer = [n for n in (*ended, *open_) if n > depth]
        return sum(n - depth - 1 for n in longer) / len(longer) if longer else float(depth)

    def estimate(self, running, queue) -> float | None:
        """Seconds left: the queued tasks with their expected follow-ups, and the running ones
        (``running``: their number, or ``(task, started)`` pairs, started on :attr:`clock`),
        over the workers; None before any run has finished (no rate known)."""
        every = [x for v in (*self.timed.values(), *self.seconds.values()) for x in v]
        if not every:
            return None
        overall = sum(every) / len(every)  # for kinds not timed yet
        mean = {k: self._mean(k) for k in {*self.timed, *self.seconds}}
        work = self._work(mean, overall)

        def after(task):  # the work a task's follow-ups bring, beyond its own run
            own = mean.get(task.kind, overall) * self._share(task.kind)
            if not task.leads:
                return 0.0
            later = work.get(task.kind, own) - own  # a new chain's, for a kind that chains
            if self.children.get((task.kind, task.kind)):  # where this run is in its chain
                depth = self.depth.get(task.key, (task.kind, 0))[1]
                new, rest = self._chain_rest(task.kind, 0), self._chain_rest(task.kind, depth)
                if rest is not None:
                    later += (rest - new) * own
            return later

        queued = [mean.get(t.kind, overall) * self._share(t.kind) + after(t) for t in queue]
        now = self.clock()
        if isinstance(running, int):  # elapsed unknown: half the last kind's mean is left
            from types import SimpleNamespace

            last = SimpleNamespace(kind=self._last, key=None, leads=True)
            running = [(last, now - mean.get(self._last, overall) / 2)] * running
        busy = []
        for task, started in running:
            own = mean.get(task.kind, overall)
            # a run past its kind's mean is taken to need a tenth of the mean more (it is
            # about to end, or slow: either way the queue behind it dominates)
            busy.append(max(own - (now - started), 0.1 * own) + after(task))
        # the work over the workers, but never less than its longest piece (a chain of
        # follow-ups runs one run after another)
        return max((sum(busy) + sum(queued)) / self.capacity, max(busy + queued, default=0.0))

    def line(self, running, queue, what: str = "") -> str:
        """The progress line: runs done, running and queued, ``what`` (the run that just
        ended), the time left (:meth:`estimate`) and so far."""
        done = sum(len(v) for v in self.seconds.values())
        count = running if isinstance(running, int) else len(running)
        self.left = self.estimate(running, queue)
        left = ("time left not known until a run ends" if self.left is None
                else f"about {_duration(self.left)} left with the follow-ups expected")
        return (f"{time.strftime('%Y-%m-%d %H:%M:%S')}: {done} run, {count} running, "
                f"{len(queue)} queued; {what}{left}, "
                f"{_duration(self.clock() - self.started)} so far")

    def write(self, line: str) -> None:
        """Append ``line`` to the log file, if any."""
        if self.log is not None:
            with open(self.log, "a") as fh:
                fh.write(line + "\n")

    def record(self, kind: str, seconds: float, running, queue) -> str:
        """Enter a finished task that ran ``seconds``; return (and log) the progress line
        (``running``: as :meth:`estimate`)."""
        self.seconds.setdefault(kind, []).append(float(seconds))
        self._last = kind
        line = self.line(running, queue,
                         f"{kind} {seconds:.0f} s (mean {self._mean(kind):.0f} s); ")
        self.write(line)
        return line


def _duration(seconds: float) -> str:
    """``1 h 05 min``, ``12 min``, ``40 s``."""
    if seconds >= 3600:
        return f"{int(seconds // 3600)} h {int(seconds % 3600 // 60):02d} min"
    return f"{seconds / 60:.0f} min" if seconds >= 60 else f"{seconds:.0f} s"


class Heartbeat:
    """A background thread that, every ``interval`` seconds (default :data:`HEARTBEAT`)
    until :meth:`stop`, calls
    ``status()`` for the current progress line and writes it: to ``stream`` (plain lines:
    for a pipe) when given, to ``progress``'s log, and to ``bar`` (a tqdm bar, refreshed so
    that its clock moves) when given. ``status`` must not raise; a line it cannot make (the
    run's queue changed under it) is skipped.

    Use as ``beat = Heartbeat(...).start()`` … ``beat.stop()``.
    """

    def __init__(self, status, *, interval: float | None = None, stream=None, progress=None,
                 bar=None):
        self.status = status
        self.interval = HEARTBEAT if interval is None else interval
        self.stream, self.progress, self.bar = stream, progress, bar
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, name="dfp-progress", daemon=True)

    def start(self) -> Heartbeat:
        self._thread.start()
        return self

    def _run(self) -> None:
        tick = min(self.interval, 1.0) if self.bar is not None else self.interval
        last = time.monotonic()
        while not self._stop.wait(tick):
            if self.bar is not None:
                self.bar.refresh()
            if time.monotonic() - last < self.interval:
                continue
            last = time.monotonic()
            try:
                line = self.status()
            except Exception:  # e.g. the queue changed while read: the next beat will do
                continue
            if self.stream is not None:
                print(line, file=self.stream, flush=True)
            if self.progress is not None:
                self.progress.write(line)

    def stop(self) -> None:
        self._stop.set()
        if self._thread.is_alive():
            self._thread.join(timeout=5)


def running(in_flight: dict, started: dict) -> list:
    """``(task, started)`` of each task under way (:meth:`Progress.estimate`), from the
    runner's futures → tasks and futures → submission times."""
    return [(task, started[f]) for f, task in list(in_flight.items()) if f in started]


class _Watch(Heartbeat):
    """The heartbeat of :func:`rigid.tasks.run_tasks`, with the log's first line."""

    def begin(self, queued: int) -> None:
        """Write the log's first line when the first run starts (not for a run whose
        results are all stored), and on a pipe the same at once; start beating."""
        if self._thread.is_alive() or self._stop.is_set():
            return
        p = self.progress
        line = (f"{time.strftime('%Y-%m-%d %H:%M:%S')}: started, {queued} queued on "
                f"{p.capacity} worker(s); a line per run and every {self.interval:g} s")
        p.write(line)
        if self.stream is not None:  # a pipe: say at once that lines will come
            print(line.replace("a line per run and ", "a progress line "), file=self.stream,
                  flush=True)
        self.start()


def watch(progress: Progress, queue, in_flight: dict, started: dict, *, bar=None,
          stream=None, interval: float | None = None) -> _Watch:
    """The heartbeat of a run of tasks (started by its ``begin``), reading the runner's
    ``queue``, ``in_flight`` (futures → tasks) and ``started`` (futures → times)."""
    def status():
        line = progress.line(running(in_flight, started), list(queue))
        if bar is not None:
            bar.set_postfix_str(line.split(": ", 1)[1], refresh=False)
        return line

    return _Watch(status, interval=interval, stream=stream, progress=progress, bar=bar)
