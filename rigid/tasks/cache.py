"""Where stored results live and what their keys include besides the inputs: the code that
computed them.

One cache root for every stored result of the library (ladder rungs, impact-spectrum cells,
meshes): ``$DFP_CACHE_DIR``, else ``$XDG_CACHE_HOME/dfp-failure``, else
``~/.cache/dfp-failure``. A validation run keeps its own store in its output folder.

Every key of a stored result (:func:`rigid.tasks.store.task_key`) includes :func:`code_hash`
of the models the result ran, so a change to a model's code makes its old results unreachable
instead of replaying them.
"""

from __future__ import annotations

import hashlib
import os
from functools import cache
from pathlib import Path, PurePosixPath

__all__ = ["MODEL_CODE", "cache_root", "code_hash"]

#: The repository root (the folder holding ``rigid``, ``fem`` and ``meshes``).
ROOT = Path(__file__).resolve().parents[2]

#: The source files of each model, relative to :data:`ROOT`; a folder means every ``.py`` and
#: ``.geo`` file below it.
MODEL_CODE = {
    # the rigid-body model: what rigid.simulate runs with rigid rims
    "rigid": ("rigid/units.py", "rigid/bearing.py", "rigid/model.py", "rigid/_kernel.py",
              "rigid/limit_states.py", "rigid/inputs.py", "rigid/results.py"),
    # the yielding rims' law as data and its derivation from the FE push (the push itself,
    # fem/rim_laws.py, is in "fem"); results of runs with yielding rims key on it too, and on
    # the law they were given (its numbers are part of their inputs)
    "rim-law": ("rigid/rims.py",),
    # the Ricker pulses of the impact-spectrum cells
    "pulses": ("rigid/motions/pulses.py",),
    # records, spectra, scaling and pulse extraction
    "motions": ("rigid/motions",),
    # ladders, predictions, trimming
    "collapse": ("rigid/collapse",),
    # the trimming of scaled records alone (what an FE run of the validation uses of it)
    "trimming": ("rigid/collapse/trimming.py",),
    # the FE companion and its geometry, the rims' fracture included (not its 3-D rim pushes,
    # fem/ring: below)
    "fem": ("fem", "meshes"),
    # the 3-D static pushes of the rim as a ring
    "fem-ring": ("fem/ring",),
    # one FE run of the validation: trimming and the end-of-run energy check
    "fem-run": ("validation/fem_runs.py",),
    # one FE run of a Ricker pulse (the yielding-rims study)
    "fem-pulse-run": ("validation/studies/pulse_fe_runs.py",),
    # one case of the rim design space: a record with rigid and yielding rims
    "rim-design-case": ("validation/studies/rim_design_case.py",),
}


def cache_root() -> Path:
    """The library's cache folder: ``$DFP_CACHE_DIR``, else ``$XDG_CACHE_HOME/dfp-failure``,
    else ``~/.cache/dfp-failure`` (not created here)."""
    root = os.environ.get("DFP_CACHE_DIR")
    if root:
        return Path(root)
    xdg = os.environ.get("XDG_CACHE_HOME")
    return (Path(xdg) if xdg else Path.home() / ".cache") / "dfp-failure"


def _select(entry: str, paths, code: dict) -> list[PurePosixPath]:
    """The files of one entry of ``code`` (a :data:`MODEL_CODE`) among ``paths`` (relative
    to :data:`ROOT`): the file itself, or a folder's ``.py`` and ``.geo`` files less the
    sub-folders that are entries of their own (``fem/ring`` is not part of ``fem``), in a
    fixed order."""
    top = PurePosixPath(entry)
    if top in paths:
        return [top]
    own = [PurePosixPath(e) for codes in code.values() for e in codes
           if e != entry and PurePosixPath(e).is_relative_to(top)
           and PurePosixPath(e) not in paths]  # folders: entries that are no file
    return sorted(p for p in paths if p.is_relative_to(top) and p.suffix in (".py", ".geo")
                  and not any(p.is_relative_to(o) for o in own))


def digest(models, paths, read, code: dict | None = None) -> str:
    """SHA-256 of the source of ``models`` (keys of ``code``, by default today's
    :data:`MODEL_CODE`), file names included: their files among ``paths`` (relative to
    :data:`ROOT`), each read by ``read(path)`` → bytes. :func:`code_hash` reads the work tree;
    :mod:`rigid.tasks.rekey` a git revision, with that revision's ``MODEL_CODE``."""
    code = MODEL_CODE if code is None else code
    paths = set(paths)
    h = hashlib.sha256()
    for model in sorted(set(models)):
        for entry in code[model]:
            for path in _select(entry, paths, code):
                h.update(str(path).encode())
                h.update(read(path))
    return h.hexdigest()


def _work_tree(models) -> set:
    """The files below the models' entries in the work tree, relative to :data:`ROOT` (an
    entry that is no folder as itself)."""
    found = set()
    for model in models:
        for entry in MODEL_CODE[model]:
            path = ROOT / entry
            if path.is_dir():
                found.update(PurePosixPath(p.relative_to(ROOT).as_posix())
                             for p in path.rglob("*") if p.is_file())
            else:
                found.add(PurePosixPath(entry))
    return found


@cache
def code_hash(*models: str) -> str:
    """SHA-256 of the source of the named models (keys of :data:`MODEL_CODE`), file names
    included, in a fixed order (:func:`digest` of the work tree).

    Parameters
    ----------
    *models : str
        E.g. ``code_hash("rigid", "pulses")`` for an impact-spectrum cell.
    """
    unknown = [m for m in models if m not in MODEL_CODE]
    if unknown or not models:
        raise ValueError(f"unknown model {unknown}; expected some of {sorted(MODEL_CODE)}")
    return digest(models, _work_tree(models), lambda path: (ROOT / path).read_bytes())
