"""The committed result stores, the commands that made them, and their carrying over.

Every stored result is keyed by the code of the models that computed it
(:data:`rigid.tasks.cache.MODEL_CODE`), so any edit of a model's files (below ``fem/`` or
``meshes/``, the rigid kernel; a comment included) makes the stored results unreachable.
Where the edit leaves the physics alone, each store is carried over to today's keys by the
command that made it with ``--rekey-from REVISION`` (:func:`rigid.tasks.rekey.rekey`: the two
shortest tasks of each kind are rerun and must come out equal, floats to
:data:`rigid.tasks.rekey.RTOL`). This module is the one list of those stores:
``tests/test_stores.py`` replays the finished ones, and::

    python -m validation.studies.committed_stores --rekey-from REVISION [--only FOLDER ...]

carries the finished ones over, one after the other (about 30 min of CPU in all, most of it the
design spaces' rim pushes), in a checkout whose code is today's; REVISION is the last commit
whose code made them. The stores no code of today reaches (:data:`STALE`) are remade with
``--rerun FOLDER ...`` (hours).

A carrying over copies each result to today's key and keeps the old row, so a store grows
with every code change by the rows no code of today asks for. ``--prune`` replays each
finished store (into a scratch folder, computing nothing) and deletes the results the replay
did not read (:meth:`rigid.tasks.ResultStore.keep_only`); ``tests/test_stores.py`` then shows
that the pruned stores still replay to the answers their folders document.
"""

from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from unittest import mock

from . import DOCS
from .containment_tearing import crushed_args
from .fracture_sensitivity import RIMS, validate_args

#: ``dfp validate`` folders under docs/ that replay with today's code, and the arguments that
#: made each (besides ``--out``); their READMEs give the same commands.
REPLAYABLE = {
    # remade on 2026-11-28 with the containment test mended (Eq. F37)
    "example-report": ["--quick", "--fem-step", "0.005", "--fem-pressure", "60", "10",
                       "--limit-state", "hinge", "rupture", "containment"],
    # remade on 2026-11-28 (STALE before); the validations at the hinge and the rupture only
    "fem-validation": ["--limit-state", "hinge", "rupture"],
    "fem-validation-rims80": ["--rim-thickness", "80", "--limit-state", "hinge", "rupture"],
    "fem-validation-ring/hinge": ["--rim-model", "ring", "--limit-state", "hinge"],
    "fem-validation-ring/rupture": ["--rim-model", "ring", "--limit-state", "rupture"],
    "results/fem_mesh_check": ["--fem-mesh", "default", "--fem-records", "2", "--pressure",
                               "60", "10", "--criteria", "3", "4", "--limit-state", "hinge",
                               "rupture"],
    "rim-design/fem-120": ["--rim-thickness", "120", "--limit-state", "rupture",
                           "--stop", "3"],
    "rim-design/fem-160": ["--rim-thickness", "160", "--limit-state", "rupture",
                           "--stop", "3"],
    "rim-design/fem-240": ["--rim-thickness", "240", "--limit-state", "rupture",
                           "--stop", "3"],
    # remade on 2026-11-28 with the containment test mended (Eq. F37)
    "fem-validation-fracture": ["--limit-state", "containment", "--fem-fracture", "median",
                                "--fem-edge-radius", "20"],
    **{f"fem-validation-fracture-sensitivity/{name}": validate_args(name)
       for name in ("steep", "mild")},
    # remade 2026-11-29 with the containment test mended (Eq. F37); its law was pushed on
    # another machine (2026-11-27): carried over with --keep-stored-laws
    "fem-validation-fracture-rims80": ["--rim-thickness", "80", "--limit-state", "containment",
                                       "--fem-fracture", "median", "--fem-edge-radius", "20",
                                       "--rim-punch", "slider"],
    # made 2026-11-29: the 40 mm containment with crushing and uncovered faces (Eqs. F67b, F68c)
    "fem-validation-fracture-crush": crushed_args(40),
    # made 2026-11-29 (python -m validation.studies.fracture_sensitivity --rim-thickness 80)
    **{f"fem-validation-fracture-sensitivity-rims80/{name}": validate_args(name, RIMS[80][2])
       for name in ("steep", "mild")},
}

#: ``dfp validate`` folders whose run is not finished, not replayed by the tests: carried over
#: as far as their store goes only when named (``--only``), since the command then goes on
#: with the run (hours).
UNFINISHED: dict[str, list[str]] = {
    # started 2026-11-29: the design space's containment with crushing (issue #31, item 4)
    "rim-design/fem-120-containment": crushed_args(120),
}

#: Stores that no code of today reaches (their keys changed with the inputs, not only the
#: code, so ``--rekey-from`` cannot carry them): folder under docs/ → the command that remakes
#: it (module and arguments, besides ``--out``), rerun from scratch with ``--rerun`` in this
#: order; hours of CPU (docs/fem_validation.md, "Which stores replay today"). The validations
#: are remade at the hinge and the rupture only: their containment without fracture is
#: superseded by the containment with tearing (``fem-validation-fracture*``).
STALE: dict[str, list[str]] = {}

#: The design spaces (``python -m validation.studies.rim_design``): folder → arguments.
DESIGN_SPACES = {
    "rim-design": [],
    "rim-design/rims45": ["--thicknesses", "80", "160", "320", "--rim-height", "45"],
}


def rekey_command(folder: str, revision: str, keep_laws: bool = False) -> list[str]:
    """The command that carries the store of ``folder`` (under docs/) over from the keys of
    ``revision``'s code to today's; ``keep_laws``: its rim laws even where today's push
    differs (``--keep-stored-laws`` of ``dfp validate`` and of the design space)."""
    out = ["--out", str(DOCS / folder), "--rekey-from", revision]
    keep = ["--keep-stored-laws"] if keep_laws else []
    if folder in DESIGN_SPACES:
        return [sys.executable, "-m", "validation.studies.rim_design", *DESIGN_SPACES[folder],
                *out, *keep]
    args = {**REPLAYABLE, **UNFINISHED}[folder]
    return [sys.executable, "-m", "validation.cli", "validate", *args, *out, "--no-progress",
            *keep]


def rerun_command(folder: str) -> list[str]:
    """The command that remakes the stale store of ``folder`` (:data:`STALE`) with today's
    code, resumable as every study's store: ``dfp validate`` is given ``--out``, a study
    (``validation.studies.*``) writes where its arguments or defaults say, which must be
    ``folder``."""
    module, *args = STALE[folder]
    out = ["--out", str(DOCS / folder), "--no-progress"] if module == "validation.cli" else []
    return [sys.executable, "-m", module, *args, *out]


def store_file(folder: str) -> Path:
    """The result store of ``folder`` (under docs/)."""
    return DOCS / folder / ("store" if folder in DESIGN_SPACES else "") / "results.sqlite"


def prune(folder: str) -> dict:
    """Delete from the store of ``folder`` (a finished one) every result its replay does not
    read; the deleted results by kind. The replay runs in this process on a copy of the
    store, with an empty library cache (so the rim laws are read from the store too); a
    replay that fails leaves the store as it was (:class:`RuntimeError`)."""
    from rigid.tasks import ResultStore
    from rigid.tasks.rekey import reading
    from validation import cli

    from . import rim_design

    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "out"
        copy = out / store_file(folder).relative_to(DOCS / folder)
        copy.parent.mkdir(parents=True)
        shutil.copy(store_file(folder), copy)
        empty_cache = {"DFP_CACHE_DIR": str(Path(tmp) / "cache")}
        with reading() as found, mock.patch.dict(os.environ, empty_cache):
            if folder in DESIGN_SPACES:
                rim_design.main([*DESIGN_SPACES[folder], "--out", str(out), "--replay"])
                status = 0
            else:
                status = cli.main(["validate", *REPLAYABLE[folder], "--out", str(out),
                                   "--replay", "--no-progress"])
        read = found.get(copy.resolve(), set())
        if status or not read:
            raise RuntimeError(f"{folder}: the replay failed (status {status}, "
                               f"{len(read)} results read); the store is left as it was")
    with ResultStore(store_file(folder)) as store:
        return store.keep_only(read)


def main(argv=None) -> int:
    finished = [*REPLAYABLE, *DESIGN_SPACES]
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    what = p.add_mutually_exclusive_group(required=True)
    what.add_argument("--rekey-from", metavar="REVISION",
                      help="the last commit whose code made the stores")
    what.add_argument("--rerun", nargs="+", choices=list(STALE), metavar="FOLDER",
                      help=f"remake these stale stores from scratch, in this order (hours; "
                      f"{', '.join(STALE)})")
    what.add_argument("--prune", action="store_true",
                      help="delete from the finished stores the results their replay does "
                      "not read (the rows carried over from older code)")
    p.add_argument("--only", nargs="+", choices=[*finished, *UNFINISHED], metavar="FOLDER",
                   help=f"these folders only (default: {', '.join(finished)}"
                   + (f"; an unfinished one, {', '.join(UNFINISHED)}, then goes on with its run)"
                      if UNFINISHED else ")"))
    p.add_argument("--keep-stored-laws", action="store_true",
                   help="carry the stores' rim laws over even where today's push differs "
                   "(--keep-stored-laws of dfp validate and of the design space)")
    args = p.parse_args(argv)
    if args.rerun and (args.only or args.keep_stored_laws):
        p.error("--only and --keep-stored-laws go with --rekey-from, not --rerun")
    if args.prune:
        if set(args.only or ()) & set(UNFINISHED):
            p.error("--prune: an unfinished store is pruned once its run is done")
        for folder in args.only or finished:
            size = store_file(folder).stat().st_size
            gone = prune(folder)
            print(f"{folder}: deleted {sum(gone.values())} results "
                  f"({', '.join(f'{k} {n}' for k, n in sorted(gone.items())) or 'none'}), "
                  f"{size / 1e6:.1f} -> {store_file(folder).stat().st_size / 1e6:.1f} MB",
                  flush=True)
        return 0
    failed = []
    for folder in args.rerun or args.only or finished:
        t0 = time.perf_counter()
        if args.rerun:
            print(f"{folder}: remade with today's code", flush=True)
            done = subprocess.run(rerun_command(folder))
        else:
            print(f"{folder}: carrying over from {args.rekey_from}", flush=True)
            done = subprocess.run(rekey_command(folder, args.rekey_from,
                                                args.keep_stored_laws))
        print(f"{folder}: {'done' if done.returncode == 0 else 'FAILED'} in "
              f"{time.perf_counter() - t0:.0f} s", flush=True)
        if done.returncode:
            failed.append(folder)
    if failed:
        print(f"not {'remade' if args.rerun else 'carried over'}: {', '.join(failed)}",
              file=sys.stderr)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
