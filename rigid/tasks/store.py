"""Result store: every finished simulation is written at once to SQLite, keyed by a hash of
every input that matters and of the code of the models that computed it
(:func:`task_key`), so an interrupted run resumes, a rerun is instant, and a changed model
never replays an old result.

Each result is its own transaction in WAL mode, so a killed process loses at most the
simulation in flight and never leaves a half-written row; several processes may write to one
file (the impact sweeps' workers do; the task runner writes from the coordinating process).
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import sqlite3
import time
from pathlib import Path

import numpy as np

from .cache import code_hash

#: Bump when the layout or meaning of stored results changes (code changes are in the key).
SCHEMA = "dfp-results-2"


def _canonical(value):
    """JSON-ready form of an input; arrays are replaced by their SHA-256."""
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return {"__type__": type(value).__name__, **_canonical(dataclasses.asdict(value))}
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


def task_key(kind: str, models: tuple[str, ...], /, **inputs) -> str:
    """The one key of every stored result: SHA-256 of :data:`SCHEMA`, the task's kind (e.g.
    ``"ladder-rung"``), the code of the models it ran (:func:`rigid.tasks.cache.code_hash`;
    ``models`` names them, e.g. ``("rigid",)``) and every input (arrays by their SHA-256)."""
    text = json.dumps({"schema": SCHEMA, "kind": kind, "code": code_hash(*models),
                       "inputs": _canonical(inputs)},
                      sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(text.encode()).hexdigest()


class ResultStore:
    """A SQLite table of JSON results keyed by :func:`task_key`.

    Parameters
    ----------
    path : str or Path
        Database file; created with its folder if missing.
    """

    def __init__(self, path):
        self.path = Path(path)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self._db = sqlite3.connect(self.path, isolation_level=None, timeout=30)
        self._db.execute("PRAGMA journal_mode=WAL")
        self._db.execute("PRAGMA synchronous=NORMAL")
        self._db.execute(
            "CREATE TABLE IF NOT EXISTS results (key TEXT PRIMARY KEY, kind TEXT NOT NULL, "
            "result TEXT NOT NULL, seconds REAL, created REAL NOT NULL)"
        )

    def get(self, key: str):
        """The stored result (a JSON value) or None."""
        row = self._db.execute("SELECT result FROM results WHERE key = ?", (key,)).fetchone()
        return None if row is None else json.loads(row[0])

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
        return found

    def __contains__(self, key: str) -> bool:
        row = self._db.execute("SELECT 1 FROM results WHERE key = ?", (key,)).fetchone()
        return row is not None

    def put(self, key: str, kind: str, result, seconds: float | None = None) -> None:
        """Store one result (JSON-serialisable) in its own transaction."""
        self._db.execute(
            "INSERT OR REPLACE INTO results (key, kind, result, seconds, created) "
            "VALUES (?, ?, ?, ?, ?)",
            (key, kind, json.dumps(result), seconds, time.time()),
        )

    def count(self, kind: str | None = None) -> int:
        """Number of stored results, of one kind or all."""
        if kind is None:
            return self._db.execute("SELECT COUNT(*) FROM results").fetchone()[0]
        return self._db.execute("SELECT COUNT(*) FROM results WHERE kind = ?",
                                (kind,)).fetchone()[0]

    def check(self) -> bool:
        """SQLite's own integrity check."""
        return self._db.execute("PRAGMA integrity_check").fetchone()[0] == "ok"

    def close(self) -> None:
        self._db.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
