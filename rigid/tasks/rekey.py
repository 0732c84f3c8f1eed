"""Carry stored results across a change of code that leaves the physics alone.

Every stored result's key holds the hash of its models' source (:func:`.cache.code_hash`), so
any edit to a model (a comment, a repr, a new option that is off by default) makes its
stored results unreachable. :func:`rekey` carries them over, with evidence: it replays a
run with the models' code hashed as it was at an earlier git revision (:func:`code_at`), so
that the replay asks for the keys the stored results have; it records the kind and inputs of
every key asked for (:func:`recording`); it reruns a few of the stored tasks with today's
code and requires their results to be equal, timings aside, floats to :data:`RTOL` and
Newton iterations to :data:`EFFORT_RTOL` (another machine rounds differently); only then does
it copy every result found under the key today's code asks for. Tasks whose inputs changed,
not only their code, are out of its reach: they are asked for under other keys and stay
missing. A store whose run was not finished is carried over as far as it goes: what the
replay did not find is counted (:attr:`Rekeyed.missing`), and a run resumed with today's code
computes it.
"""

from __future__ import annotations

import json
import math
import subprocess
from collections import Counter
from collections.abc import Callable
from contextlib import contextmanager
from pathlib import Path, PurePosixPath

from . import cache
from . import store as _store
from .runner import MissingResultsError, _one_blas_thread

__all__ = ["RekeyError", "Rekeyed", "code_at", "reading", "recording", "rekey"]

#: Result fields that measure the machine, not the physics: left out of the comparison, as
#: is any field named with one of them as its end (``yielding_cpu_s``).
TIMINGS = frozenset({"cpu_seconds", "wall_seconds", "cpu_s", "seconds", "elapsed_s"})


#: Relative tolerance of a rerun's floats against the stored ones. The same code run on
#: another machine (CPU, libm, BLAS) rounds differently: the two shortest stored tasks of
#: each kind of the committed stores, rerun on another machine, differed by up to 8e-14
#: (rigid records) and 1.4e-9 (FE runs) relative (docs/fem_validation.md, "Which stores
#: replay today"). 1e-6 is almost three orders above that and far below what a change of
#: physics moves (the 2nd to 4th digit). Integers (steps), verdicts and names must be equal;
#: Newton iterations within :data:`EFFORT_RTOL`.
RTOL = 1e-6

#: Result fields that count the solver's effort, not the physics: the Newton iterations of a
#: run. On another machine a residual that rounds across the convergence tolerance costs an
#: iteration more or less. Measured on 2026-11-28: the FE run of ``docs/fem-validation`` that
#: a re-keying reran first took 2 144 Newton iterations on a fresh machine where the machine
#: that stored it took 2 143, with every float within 6e-9 relative, and the code of the
#: revision that stored it (16373b1), rerun on the fresh machine, did the same. They may
#: differ by :data:`EFFORT_RTOL` relative, and by one at least; a change of physics shows in
#: the floats, the steps and the verdicts, which are held to :data:`RTOL` and equality.
EFFORT = frozenset({"newton_iterations"})
EFFORT_RTOL = 1e-3


def _is_timing(field) -> bool:
    return isinstance(field, str) and (field in TIMINGS or field.endswith(
        tuple("_" + t for t in TIMINGS)))


class Rekeyed(dict):
    """{kind: number of results carried over}, in ``missing`` (a Counter by kind) the
    results the replay asked for and the store did not hold (an unfinished run), and in
    ``largest_change`` the largest relative change of a rerun's float (:data:`RTOL`)."""

    def __init__(self, carried=(), missing=None, largest_change: float = 0.0):
        super().__init__(carried)
        self.missing = Counter() if missing is None else missing
        #: the largest relative difference of a rerun's float from the stored one
        self.largest_change = largest_change

    def describe(self) -> str:
        """One line for the user: what was carried over by kind, the largest change of a
        rerun's float, and what the store lacked (for a run to compute)."""
        what = ", ".join(f"{kind} {n}" for kind, n in sorted(self.items()))
        line = (f"carried over {what} (the shortest two of each kind rerun with today's code: "
                f"equal, largest relative change of a float {self.largest_change:.1e})"
                if self else "nothing to carry over")
        if self.missing:
            lacking = ", ".join(f"{kind} {n}" for kind, n in sorted(self.missing.items()))
            line += f"; not stored, to be computed by a run: {lacking}"
        return line


class RekeyError(RuntimeError):
    """A rerun with today's code differs from the stored result, or the revision is unknown:
    nothing was carried over."""


def _git(*args: str) -> bytes:
    try:
        return subprocess.run(["git", "-C", str(cache.ROOT), *args], check=True,
                              capture_output=True).stdout
    except (OSError, subprocess.CalledProcessError) as exc:
        detail = getattr(exc, "stderr", b"") or str(exc).encode()
        raise RekeyError(f"git {' '.join(args[:2])}: "
                         f"{detail.decode(errors='replace').strip()}") from None


#: Where :data:`.cache.MODEL_CODE` is written, relative to the repository root.
_MODEL_CODE_FILE = "rigid/tasks/cache.py"


def _model_code_at(revision: str, listed) -> dict:
    """:data:`.cache.MODEL_CODE` as it was at ``revision`` (which files made which model
    then: an entry may have been merged or split since); today's if that revision has no
    such file (a repository of other models)."""
    if _MODEL_CODE_FILE not in listed:
        return cache.MODEL_CODE
    source = _git("show", f"{revision}:{_MODEL_CODE_FILE}").decode()
    space: dict = {"__name__": "rigid.tasks._cache_at_revision", "__file__": str(cache.__file__)}
    exec(compile(source, f"{revision}:{_MODEL_CODE_FILE}", "exec"), space)
    return space["MODEL_CODE"]


def _hash_at(revision: str, models: tuple[str, ...]) -> str:
    """:func:`.cache.code_hash` of the models' source at ``revision``: the same
    :func:`.cache.digest` of the files git lists there, with that revision's MODEL_CODE."""
    listed = _git("ls-tree", "-r", "--name-only", revision).decode().splitlines()
    return cache.digest(models, map(PurePosixPath, listed),
                        lambda path: _git("show", f"{revision}:{path}"),
                        code=_model_code_at(revision, listed))


@contextmanager
def code_at(revision: str, today: tuple = ("rim-law",), current=None):
    """Inside, :func:`.store.task_key` hashes the models' code as it was at the git
    ``revision`` (a commit of the repository holding the models), not as it is now, except
    for the kinds in ``today`` (the library's caches of derived data, a rim law, which
    today's code reads or computes anyway) and the tasks for which ``current(key)`` says
    today's key is already stored."""
    resolved = _git("rev-parse", "--verify", f"{revision}^{{commit}}").decode().strip()
    memo: dict = {}

    def hashed(kind, models, canonical):
        now = cache.code_hash(*models)
        if kind in today or (current is not None
                             and current(_store.key_of(kind, now, canonical))):
            return now
        key = tuple(sorted(set(models)))
        if key not in memo:
            memo[key] = _hash_at(resolved, key)
        return memo[key]

    previous = _store.CODE
    _store.CODE = hashed
    try:
        yield resolved
    finally:
        _store.CODE = previous


@contextmanager
def recording():
    """Inside, every :func:`.store.task_key` call is recorded: the list yielded holds
    ``(key, kind, models, canonical inputs)``."""
    calls: list = []
    previous = _store.RECORD
    _store.RECORD = calls.append
    try:
        yield calls
    finally:
        _store.RECORD = previous


@contextmanager
def reading():
    """Inside, every result a :class:`.store.ResultStore` finds is recorded: the dict yielded
    holds the keys found, by the store file's resolved path (what a replay reads, so that
    :meth:`.store.ResultStore.keep_only` can drop the rest)."""
    found: dict = {}
    previous = _store.READ
    _store.READ = lambda path, keys: found.setdefault(Path(path).resolve(), set()).update(keys)
    try:
        yield found
    finally:
        _store.READ = previous


def _physics(result):
    """A result as JSON reads it back, without its timings."""
    def strip(x):
        if isinstance(x, dict):
            return {k: strip(v) for k, v in x.items() if not _is_timing(k)}
        if isinstance(x, list):
            return [strip(v) for v in x]
        return x

    return strip(json.loads(json.dumps(result)))


def _leaves(now, then, where: str = ""):
    """The plain values of two results read back from JSON, pairwise, with their paths
    (``a.b[2]``); a dict's key in one only, or lists of other lengths, pair as wholes."""
    if isinstance(now, dict) and isinstance(then, dict):
        for k in sorted(set(now) | set(then), key=str):
            yield from _leaves(now.get(k), then.get(k), f"{where}.{k}".lstrip("."))
    elif isinstance(now, list) and isinstance(then, list) and len(now) == len(then):
        for i, (a, b) in enumerate(zip(now, then, strict=True)):
            yield from _leaves(a, b, f"{where}[{i}]")
    else:
        yield where or "the result", now, then


def _relative_change(now, then) -> float | None:
    """|now − then| / max(|now|, |then|) of two finite numbers one of which is a float, else
    None (integers, booleans and names compare exactly)."""
    numbers = all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in (now, then))
    if not (numbers and (isinstance(now, float) or isinstance(then, float))
            and math.isfinite(now) and math.isfinite(then)):
        return None
    return 0.0 if now == then else abs(now - then) / max(abs(now), abs(then))


def _within_effort(where: str, now, then) -> bool:
    """Whether two counts of the solver's effort (:data:`EFFORT`) are within
    :data:`EFFORT_RTOL` of each other, or one apart."""
    counts = all(isinstance(x, int) and not isinstance(x, bool) for x in (now, then))
    return (counts and where.rpartition(".")[2] in EFFORT
            and abs(now - then) <= max(1.0, EFFORT_RTOL * max(abs(now), abs(then))))


def _both_nan(now, then) -> bool:
    """Whether both values are NaN (a quantity the run did not reach, e.g. the impact
    velocity of a rung that never touched a rim): the same result, though NaN != NaN."""
    return all(isinstance(x, float) and math.isnan(x) for x in (now, then))


def _differences(now, then, rtol: float = RTOL) -> list[str]:
    """Where two results read back from JSON differ (floats by more than ``rtol``
    relative, the solver's effort beyond :data:`EFFORT_RTOL`), with both values: what a
    refused re-keying reports."""
    return [f"{where}: {a!r} now, {b!r} stored" for where, a, b in _leaves(now, then)
            if a != b and not _both_nan(a, b) and not _within_effort(where, a, b)
            and ((change := _relative_change(a, b)) is None or change > rtol)]


def _largest_change(now, then) -> float:
    """The largest relative change of a float between two results (0: none changed)."""
    return max((c for _, a, b in _leaves(now, then)
                if (c := _relative_change(a, b)) is not None), default=0.0)


def rekey(store, replay: Callable[[dict], None], revision: str, *,
          verify: int = 2) -> dict:
    """Carry the results of ``store`` keyed by the code of ``revision`` over to today's keys.

    Parameters
    ----------
    store : ResultStore
    replay : callable
        ``replay(seen)`` replays the run (``run_tasks(..., replay=True, seen=seen)``), which
        fills ``seen`` with every task found, by key; a task not found stops it
        (:class:`.runner.MissingResultsError`).
    revision : str
        The git revision whose code made the stored results.
    verify : int
        Tasks of each kind rerun with today's code (the shortest stored), whose results must
        equal the stored ones, timings aside (:data:`TIMINGS`), floats within :data:`RTOL`.

    Returns
    -------
    Rekeyed
        {kind: number of results carried over}, with what the store lacked in ``missing``;
        :class:`RekeyError` if a rerun differs.
    """
    seen: dict = {}
    missing = Counter()
    with recording() as calls, code_at(revision, current=store.__contains__):
        try:
            replay(seen)
        except MissingResultsError as exc:  # an unfinished run: carry what it holds
            missing = exc.missing
    today = {}  # the tasks found under the revision's key → today's key
    for old, kind, models, inputs in calls:
        new = _store.key_of(kind, cache.code_hash(*models), inputs)
        if old in seen and new != old:
            today[old] = new
    by_kind: dict = {}
    for key in today:
        by_kind.setdefault(seen[key].kind, []).append(key)
    largest = 0.0
    for kind, keys in by_kind.items():
        keys.sort(key=lambda k: store.seconds(k) or 0.0)
        for key in keys[:verify]:
            task = seen[key]
            with _one_blas_thread():  # as in a worker: BLAS's rounding depends on threads
                now = _physics(task.func(**task.kwargs))
            then = _physics(store.get(key))
            fields = _differences(now, then)
            if fields:
                raise RekeyError(f"a {kind} task rerun with today's code differs from the one "
                                 f"stored by {revision} ({', '.join(fields[:4])}): the physics "
                                 "changed; nothing was carried over (rerun instead)")
            largest = max(largest, _largest_change(now, then))
    carried = Rekeyed(missing=missing, largest_change=largest)
    for old, new in today.items():
        if store.copy(old, new):
            carried[seen[old].kind] = carried.get(seen[old].kind, 0) + 1
    return carried
