"""Running many simulations: a SQLite result store keyed by inputs and model code, the cache
root, and a task runner (local process pool or a Dask cluster: cluster) that stores each result
as it arrives, so that every long computation of the library can be resumed and audited."""

from .cache import cache_root, code_hash
from .cluster import ClusterError
from .files import FolderBusyError, FolderLock, atomic_path, atomic_write
from .runner import MissingResultsError, Task, default_workers, run_tasks
from .store import ResultStore, StoreError, StoreRecoveredWarning, task_key

__all__ = ["ClusterError", "FolderBusyError", "FolderLock", "MissingResultsError",
           "ResultStore", "StoreError", "StoreRecoveredWarning", "Task", "atomic_path",
           "atomic_write", "cache_root", "code_hash", "default_workers", "run_tasks", "task_key"]
