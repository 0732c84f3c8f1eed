"""Result store: every finished simulation is written at once to SQLite, keyed by a hash of
every input that matters and of the code of the models that computed it
(:func:`task_key`), so an interrupted run resumes, a rerun is instant, and a changed model
never replays an old result.

Each result is its own transaction in WAL mode, so a killed process loses at most the
simulation in flight and never leaves a half-written row; several processes may write to one
file (the impact sweeps' workers do; the task runner writes from the coordinating process).
The log is written into the file at least every :data:`CHECKPOINT_EVERY` seconds of writing,
so that the file alone is never far behind (a checkout that kept the file but not its
``-wal`` lost an hour and a half of a validation run before it was).
A damaged file (a disk error, a copy cut short or taken mid-write, anything not SQLite) is
detected when the store is opened, rebuilt beside it from the results that can still be read,
and only then moved aside (:class:`StoreRecoveredWarning`, which says how many results were
recovered; an empty file, which holds none, is warned about too). A problem of the machine
rather than of the file (a full disk, a read-only folder, an I/O error) never counts as
damage: it is raised as :class:`StoreError`, naming the file, and the store is left as it is
(a full disk is said to be one, with ``errno`` ENOSPC).
"""

from __future__ import annotations

import contextlib
import dataclasses
import errno
import functools
import hashlib
import json
import os
import shutil
import sqlite3
import time
import warnings
from collections import Counter
from pathlib import Path

import numpy as np

from .cache import code_hash

#: Bump when the layout or meaning of stored results changes (code changes are in the key).
SCHEMA = "dfp-results-2"

#: Seconds between two checkpoints of the write-ahead log into the store's file by one
#: writer (:meth:`ResultStore.put`), so that the file alone (a commit of it, a copy that
#: leaves the ``-wal`` file behind) is never more than this behind the results stored.
CHECKPOINT_EVERY = 60.0

#: Metadata of a dataclass field that keys a result only when it differs from its default
#: (``dataclasses.field(..., metadata=KEYED_WHEN_SET)``): a new option, off by default,
#: leaves the keys of the results computed without it as they were.
KEYED_WHEN_SET = {"keyed": "when set"}


def _canonical(value):
    """JSON-ready form of an input; arrays are replaced by their SHA-256; a dataclass's
    fields marked :data:`KEYED_WHEN_SET` are left out while at their defaults."""
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        fields = dataclasses.asdict(value)
        for f in dataclasses.fields(value):
            if f.metadata.get("keyed") == KEYED_WHEN_SET["keyed"] and _at_default(f, value):
                del fields[f.name]
        return {"__type__": type(value).__name__, **_canonical(fields)}
    if isinstance(value, np.ndarray):
        data = np.ascontiguousarray(value)
        digest = hashlib.sha256(data.tobytes()).hexdigest()
        return {"__array__": digest, "dtype": str(data.dtype), "shape": list(data.shape)}
    if isinstance(value, dict):
        return {str(k): _canonical(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_canonical(v) for v in value]
    if isinstance(value, (np.floating, np.integer)):
        return value.item()
    if value is None or isinstance(value, (bool, int, float, str)):
        return value
    raise TypeError(f"cannot hash an input of type {type(value).__name__}")


def _at_default(field, value) -> bool:
    """Whether the dataclass ``value`` holds its default in ``field``."""
    default = (field.default_factory() if field.default_factory is not dataclasses.MISSING
               else field.default)
    now = getattr(value, field.name)
    if isinstance(now, np.ndarray) or isinstance(default, np.ndarray):
        return np.array_equal(np.asarray(now), np.asarray(default))
    return now == default


#: Called with ``(key, kind, models, canonical inputs)`` by every :func:`task_key` when set
#: (:func:`rigid.tasks.rekey.recording`).
RECORD = None
#: ``(kind, models, canonical inputs) -> code hash`` in place of :func:`code_hash` when set
#: (:func:`rigid.tasks.rekey.code_at`).
CODE = None
#: Called with ``(store path, keys found)`` by every read of a :class:`ResultStore` that found
#: results, when set (:func:`rigid.tasks.rekey.reading`).
READ = None


def key_of(kind: str, code: str, canonical) -> str:
    """The key of a task of ``kind`` run by code of hash ``code`` on ``canonical`` inputs."""
    text = json.dumps({"schema": SCHEMA, "kind": kind, "code": code, "inputs": canonical},
                      sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(text.encode()).hexdigest()


def task_key(kind: str, models: tuple[str, ...], /, **inputs) -> str:
    """The one key of every stored result: SHA-256 of :data:`SCHEMA`, the task's kind (e.g.
    ``"ladder-rung"``), the code of the models it ran (:func:`rigid.tasks.cache.code_hash`;
    ``models`` names them, e.g. ``("rigid",)``) and every input (arrays by their SHA-256)."""
    canonical = _canonical(inputs)
    code = code_hash(*models) if CODE is None else CODE(kind, models, canonical)
    key = key_of(kind, code, canonical)
    if RECORD is not None:
        RECORD((key, kind, tuple(models), canonical))
    return key


class StoreError(OSError):
    """A result store could not be read or written (the message names the file)."""


class StoreRecoveredWarning(UserWarning):
    """A damaged result store was moved aside and rebuilt from what could be read."""


#: SQLite's primary result codes that mean a damaged file (SQLITE_CORRUPT, SQLITE_NOTADB);
#: any other error (SQLITE_FULL 13, SQLITE_IOERR 10, SQLITE_READONLY 8, SQLITE_CANTOPEN 14,
#: …) is the machine's.
_DAMAGE_CODES = (11, 26)
_FULL, _IOERR = 13, 10
#: Free space [bytes] below which an I/O error of SQLite is taken for a full disk (SQLite
#: reports a failed write of its shared-memory file as SQLITE_IOERR).
_NEARLY_FULL = 1 << 20


class _Damaged(sqlite3.DatabaseError):
    """The store's own integrity check failed."""


def _damaged(exc) -> bool:
    """Whether a SQLite error says the file is damaged (not the machine: :data:`_DAMAGE_CODES`)."""
    if isinstance(exc, _Damaged):
        return True
    code = getattr(exc, "sqlite_errorcode", None)  # Python ≥ 3.11
    if code is not None:
        return code & 0xFF in _DAMAGE_CODES
    return any(text in str(exc) for text in ("malformed", "not a database"))


def _problem(path: Path, exc) -> StoreError:
    """A :class:`StoreError` for a SQLite error of the store at ``path``; a full disk said to
    be one (``errno`` ENOSPC)."""
    code = (getattr(exc, "sqlite_errorcode", None) or 0) & 0xFF
    try:
        free = shutil.disk_usage(path.parent).free
    except OSError:
        free = None
    if code == _FULL or "disk is full" in str(exc) or (
            code == _IOERR and free is not None and free < _NEARLY_FULL):
        room = "" if free is None else f", {free // 1024} kB free"
        error = StoreError(f"result store {path}: the disk is full ({exc}{room}); the store is "
                           "kept as it was: free some space and rerun to resume")
        error.errno = errno.ENOSPC
        return error
    return StoreError(f"result store {path}: {exc}")


def _named(method):
    """Raise SQLite errors of a store method as :class:`StoreError` naming the file."""

    @functools.wraps(method)
    def call(self, *args, **kwargs):
        try:
            return method(self, *args, **kwargs)
        except sqlite3.Error as exc:
            raise _problem(self.path, exc) from None

    return call


@contextlib.contextmanager
def _exclusive(path: Path):
    """Hold ``path`` (a lock file) exclusively: one process at a time checks and repairs a
    store."""
    try:
        import fcntl
    except ImportError:  # pragma: no cover - not POSIX
        yield
        return
    with open(path, "a") as fh:
        fcntl.flock(fh, fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(fh, fcntl.LOCK_UN)


_COLUMNS = "key, kind, result, seconds, created"
_TABLE = ("CREATE TABLE IF NOT EXISTS results (key TEXT PRIMARY KEY, kind TEXT NOT NULL, "
          "result TEXT NOT NULL, seconds REAL, created REAL NOT NULL)")


def _salvage(path: Path) -> list[tuple]:
    """The rows of a damaged store that can still be read (rows whose result is not valid
    JSON are dropped), batch by batch of rowids, skipping batches that fail."""
    rows: list[tuple] = []
    try:
        db = sqlite3.connect(f"file:{path}?mode=ro", uri=True)
    except sqlite3.Error:
        return rows
    try:
        last, failures = -1, 0
        while failures < 64:
            try:
                batch = db.execute(f"SELECT rowid, {_COLUMNS} FROM results WHERE rowid > ? "
                                   "ORDER BY rowid LIMIT 256", (last,)).fetchall()
            except sqlite3.Error:
                failures += 1
                last += 256
                continue
            if not batch:
                break
            failures = 0
            last = batch[-1][0]
            for row in batch:
                try:
                    json.loads(row[3])
                except (TypeError, ValueError):
                    continue
                rows.append(row[1:])
    finally:
        db.close()
    return rows


class ResultStore:
    """A SQLite table of JSON results keyed by :func:`task_key`.

    Parameters
    ----------
    path : str or Path
        Database file; created with its folder if missing. If it is damaged (SQLite's
        ``quick_check`` fails, or it is not a database) a new store is built beside it from
        the rows that can be read, the damaged one is moved to ``<name>.damaged-<time>``
        (with its WAL) and a :class:`StoreRecoveredWarning` says so; if the new one cannot be
        written (a full disk), the damaged one stays in place. An empty file (0 bytes) is
        opened as an empty store with a :class:`StoreRecoveredWarning`: nothing to resume
        from. Any other error (a full disk, a read-only folder) is a :class:`StoreError`
        and leaves the file as it is.
    """

    def __init__(self, path):
        self.path = Path(path)
        self._checkpointed = time.monotonic()
        self.path.parent.mkdir(parents=True, exist_ok=True)
        with _exclusive(self.path.with_name(self.path.name + ".lock")):
            empty = self.path.is_file() and self.path.stat().st_size == 0 and not (
                self._wal().is_file() and self._wal().stat().st_size > 0)
            try:
                self._db = self._open()
            except sqlite3.Error as exc:
                if not _damaged(exc):
                    raise _problem(self.path, exc) from None
                self._db = self._recover(exc)
        if empty:
            warnings.warn(StoreRecoveredWarning(
                f"result store {self.path} was an empty file (0 bytes: cut short, or left by a "
                "run stopped as it began): no stored result to resume from, every result "
                "will be computed"), stacklevel=2)

    def _wal(self) -> Path:
        return Path(str(self.path) + "-wal")

    def _open(self) -> sqlite3.Connection:
        db = sqlite3.connect(self.path, isolation_level=None, timeout=30)
        try:
            status = db.execute("PRAGMA quick_check").fetchone()[0]
            if status != "ok":
                raise _Damaged(f"quick_check: {str(status)[:80]}")
            db.execute("PRAGMA journal_mode=WAL")
            db.execute("PRAGMA synchronous=NORMAL")
            db.execute(_TABLE)
            db.execute(f"SELECT {_COLUMNS} FROM results LIMIT 1").fetchall()
        except sqlite3.DatabaseError:
            db.close()
            raise
        return db

    def _recover(self, error) -> sqlite3.Connection:
        """Rebuild a damaged store from its readable rows: written beside it first, then the
        damaged files moved aside and the new one renamed in place (a failure on the way,
        a full disk, leaves the damaged store where it was)."""
        rows = _salvage(self.path)
        fresh = self.path.with_name(f".{self.path.name}.rebuild-{os.getpid()}")
        stamp = time.strftime("%Y%m%d-%H%M%S")
        aside = self.path.with_name(f"{self.path.name}.damaged-{stamp}-{os.getpid()}")
        try:
            with contextlib.closing(sqlite3.connect(fresh, isolation_level=None)) as db:
                db.execute(_TABLE)
                db.execute("BEGIN")
                db.executemany(f"INSERT OR REPLACE INTO results ({_COLUMNS}) "
                               "VALUES (?, ?, ?, ?, ?)", rows)
                db.execute("COMMIT")
            for suffix in ("", "-wal", "-shm"):
                src = Path(str(self.path) + suffix)
                if src.exists():
                    os.replace(src, Path(str(aside) + suffix))
            os.replace(fresh, self.path)
        except (sqlite3.Error, OSError) as exc:
            with contextlib.suppress(OSError):
                fresh.unlink()
            if isinstance(exc, sqlite3.Error):
                exc = _problem(self.path, exc)
            why = "the disk is full" if exc.errno == errno.ENOSPC else str(exc)
            raise StoreError(f"result store {self.path} is damaged ({error}) and could not be "
                             f"rebuilt ({why}); it is left where it was") from None
        db = self._open()
        none = "none of its results could be read: every result will be recomputed" \
            if not rows else f"{len(rows)} stored results recovered, the others will be " \
            "recomputed"
        warnings.warn(StoreRecoveredWarning(
            f"result store {self.path} was damaged ({str(error)[:80]}); moved to {aside.name}, "
            f"{none}"), stacklevel=3)
        return db

    @_named
    def get(self, key: str):
        """The stored result (a JSON value) or None."""
        row = self._db.execute("SELECT result FROM results WHERE key = ?", (key,)).fetchone()
        if row is None:
            return None
        self._read((key,))
        return json.loads(row[0])

    @_named
    def get_many(self, keys) -> dict:
        """The stored results of those ``keys`` that have one, by key."""
        keys, found = list(keys), {}
        for i in range(0, len(keys), 500):  # SQLite caps the parameters of one statement
            chunk = keys[i : i + 500]
            rows = self._db.execute(
                f"SELECT key, result FROM results WHERE key IN ({','.join('?' * len(chunk))})",
                chunk,
            ).fetchall()
            found.update((k, json.loads(v)) for k, v in rows)
        self._read(found)
        return found

    @_named
    def __contains__(self, key: str) -> bool:
        row = self._db.execute("SELECT 1 FROM results WHERE key = ?", (key,)).fetchone()
        if row is not None:
            self._read((key,))
        return row is not None

    def _read(self, keys) -> None:
        if READ is not None and keys:
            READ(self.path, keys)

    @_named
    def put(self, key: str, kind: str, result, seconds: float | None = None) -> None:
        """Store one result (JSON-serialisable) in its own transaction; at most every
        :data:`CHECKPOINT_EVERY` seconds, also into the file itself (a passive checkpoint of
        the write-ahead log, which waits for no one)."""
        self._db.execute(
            "INSERT OR REPLACE INTO results (key, kind, result, seconds, created) "
            "VALUES (?, ?, ?, ?, ?)",
            (key, kind, json.dumps(result), seconds, time.time()),
        )
        if time.monotonic() - self._checkpointed >= CHECKPOINT_EVERY:
            self._db.execute("PRAGMA wal_checkpoint(PASSIVE)")
            self._checkpointed = time.monotonic()

    @_named
    def seconds(self, key: str) -> float | None:
        """The seconds the stored result took to compute (None: not stored, or not timed)."""
        row = self._db.execute("SELECT seconds FROM results WHERE key = ?", (key,)).fetchone()
        return None if row is None else row[0]

    @_named
    def copy(self, key: str, new_key: str) -> bool:
        """Store the result of ``key`` under ``new_key`` too (its kind, seconds and time of
        creation kept), unless ``new_key`` has one; True if it was copied."""
        done = self._db.execute(
            "INSERT OR IGNORE INTO results (key, kind, result, seconds, created) "
            "SELECT ?, kind, result, seconds, created FROM results WHERE key = ?",
            (new_key, key))
        return done.rowcount > 0

    @_named
    def count(self, kind: str | None = None) -> int:
        """Number of stored results, of one kind or all."""
        if kind is None:
            return self._db.execute("SELECT COUNT(*) FROM results").fetchone()[0]
        return self._db.execute("SELECT COUNT(*) FROM results WHERE kind = ?",
                                (kind,)).fetchone()[0]

    @_named
    def keep_only(self, keys) -> Counter:
        """Delete every result whose key is not among ``keys`` and compact the file (left
        as it was if none is deleted); the deleted results counted by kind."""
        self._db.execute("CREATE TEMP TABLE IF NOT EXISTS kept (key TEXT PRIMARY KEY)")
        self._db.execute("BEGIN")
        self._db.execute("DELETE FROM kept")
        self._db.executemany("INSERT OR IGNORE INTO kept VALUES (?)", ((k,) for k in keys))
        gone = Counter(dict(self._db.execute(
            "SELECT kind, COUNT(*) FROM results WHERE key NOT IN (SELECT key FROM kept) "
            "GROUP BY kind").fetchall()))
        self._db.execute("DELETE FROM results WHERE key NOT IN (SELECT key FROM kept)")
        self._db.execute("COMMIT")
        if gone:
            self._db.execute("PRAGMA wal_checkpoint(TRUNCATE)")
            self._db.execute("VACUUM")
        return gone

    @_named
    def check(self) -> bool:
        """SQLite's own integrity check."""
        return self._db.execute("PRAGMA integrity_check").fetchone()[0] == "ok"

    def close(self) -> None:
        self._db.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
