"""Files that survive failures: writes that replace a file only once the new one is complete
(:func:`atomic_write`, :func:`atomic_path`), and an exclusive lock on a folder's lock file
(:class:`FolderLock`) so that two runs never share one output folder."""

from __future__ import annotations

import contextlib
import os
import tempfile
from pathlib import Path

__all__ = ["FolderBusyError", "FolderLock", "atomic_path", "atomic_write"]


@contextlib.contextmanager
def atomic_path(path):
    """Yield a temporary path in the folder of ``path``; when the block ends without an
    exception, rename it over ``path`` (:func:`os.replace`, atomic on one file system), else
    delete it. A failed write (a full disk, an interrupted run) leaves the previous file. The
    file gets the permissions of a newly created one (the umask's), not mkstemp's owner-only."""
    path = Path(path)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    os.close(fd)
    tmp = Path(tmp)
    umask = os.umask(0)
    os.umask(umask)
    os.chmod(tmp, 0o666 & ~umask)
    try:
        yield tmp
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            tmp.unlink()
        raise


@contextlib.contextmanager
def atomic_write(path, mode: str = "w", **open_kwargs):
    """``open`` a temporary file beside ``path`` and rename it over ``path`` once written and
    flushed to disk (see :func:`atomic_path`)."""
    with atomic_path(path) as tmp:
        with open(tmp, mode, **open_kwargs) as fh:
            yield fh
            fh.flush()
            os.fsync(fh.fileno())


class FolderBusyError(OSError):
    """Another process holds the folder's lock."""


class FolderLock:
    """An exclusive, non-blocking lock on ``folder/.dfp.lock`` (``fcntl.flock``), held until
    :meth:`release` or the process ends (the kernel releases it even on SIGKILL, so a stale
    lock file never blocks a later run). :class:`FolderBusyError` names the holder's process
    id when the lock is taken. Where ``fcntl`` is missing (Windows) the lock is a no-op.

    Parameters
    ----------
    folder : str or Path
        An existing folder.
    """

    NAME = ".dfp.lock"

    def __init__(self, folder):
        self.path = Path(folder) / self.NAME
        self._fh = None

    def acquire(self) -> FolderLock:
        try:
            import fcntl
        except ImportError:  # pragma: no cover - not POSIX
            return self
        fh = open(self.path, "a+")
        try:
            fcntl.flock(fh, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            fh.seek(0)
            holder = fh.read().strip()[:20]
            fh.close()
            who = f" (process {holder})" if holder.isdigit() else ""
            raise FolderBusyError(f"another dfp run{who} is using the folder "
                                  f"{self.path.parent}; wait for it to finish or choose "
                                  "another output folder") from None
        fh.seek(0)
        fh.truncate()
        fh.write(str(os.getpid()))
        fh.flush()
        self._fh = fh
        return self

    def release(self) -> None:
        if self._fh is not None:
            self._fh.close()  # closing releases the flock
            self._fh = None

    def __enter__(self):
        return self.acquire()

    def __exit__(self, *exc):
        self.release()
