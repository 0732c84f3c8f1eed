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
    :meth:`release` (which removes the file) or the process ends (the kernel releases the
    lock even on SIGKILL). A lock file left by a process that ended without removing it (it
    was killed) holds no lock: it is taken over, with a warning naming the old process id.
    :class:`FolderBusyError` names the holder's process id when the lock is taken. Where
    ``fcntl`` is missing (Windows) the lock is a no-op.

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
        while True:
            fh = open(self.path, "a+")
            try:
                fcntl.flock(fh, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except BlockingIOError:
                holder = _holder(fh)
                fh.close()
                who = f" (process {holder})" if holder else ""
                raise FolderBusyError(f"another dfp run{who} is using the folder "
                                      f"{self.path.parent}; wait for it to finish or choose "
                                      "another output folder") from None
            # the holder may have removed the file between our open and our lock: then the
            # lock is on a file nobody else will open; start again on the path's file
            try:
                same = os.stat(self.path).st_ino == os.fstat(fh.fileno()).st_ino
            except FileNotFoundError:
                same = False
            if same:
                break
            fh.close()
        stale = _holder(fh)
        if stale and int(stale) != os.getpid():
            import warnings

            state = "no longer running" if not _alive(int(stale)) else "not holding it"
            warnings.warn(f"took over the stale lock of process {stale} ({state}) on "
                          f"{self.path.parent}", stacklevel=2)
        fh.seek(0)
        fh.truncate()
        fh.write(str(os.getpid()))
        fh.flush()
        self._fh = fh
        return self

    def release(self) -> None:
        """Remove the lock file and release the lock (idempotent)."""
        if self._fh is not None:
            with contextlib.suppress(OSError):  # removed by hand, or the folder is gone
                if os.stat(self.path).st_ino == os.fstat(self._fh.fileno()).st_ino:
                    self.path.unlink()
            self._fh.close()  # closing releases the flock
            self._fh = None

    def __enter__(self):
        return self.acquire()

    def __exit__(self, *exc):
        self.release()


def _holder(fh) -> str:
    """The process id written in an open lock file, or "" if none."""
    fh.seek(0)
    text = fh.read(40).strip()
    return text if text.isdigit() else ""


def _alive(pid: int) -> bool:
    """Whether a process ``pid`` exists (signal 0: no signal sent, only the check)."""
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except OSError:  # exists, owned by another user
        return True
    return True
