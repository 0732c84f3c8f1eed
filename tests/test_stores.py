"""The committed validation stores replay with today's code: `dfp validate --replay` rewrites
each folder's report from its store alone, running no rigid ladder, no FE run and no rim push,
and gives the FE critical SA the folder documents.

A store is keyed by its inputs and the code of the models that computed it
(rigid.tasks.cache.MODEL_CODE), so a change to that code makes the stored runs unreachable:
this test then fails, and the change must either leave the physics' code alone or rerun what
the folder documents (docs/fem_validation.md, "Which code made the stores"). The rim laws come
from the store too: the library's cache is pointed at an empty folder.
"""

import csv
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from validation.studies.committed_stores import DESIGN_SPACES, REPLAYABLE, UNFINISHED, rekey_command

DOCS = Path(__file__).resolve().parents[1] / "docs"


def _answers(path: Path) -> dict:
    """The FE and yielding-rim critical SA of every search, by (record, pressure, state)."""
    with open(path, newline="") as fh:
        return {(r["record"], r["pressure_mpa"], r["limit_state"]):
                (r["fem_sa_g"], r["yielding_sa_g"], r["fem_runs"], r["fem_failure_mode"])
                for r in csv.DictReader(fh)}


@pytest.mark.parametrize("folder", sorted(REPLAYABLE))
def test_committed_store_replays_without_computing(tmp_path, folder):
    out = tmp_path / "out"
    out.mkdir()
    shutil.copy(DOCS / folder / "results.sqlite", out)
    env = {**os.environ, "DFP_CACHE_DIR": str(tmp_path / "empty-cache")}
    done = subprocess.run(
        [sys.executable, "-m", "validation.cli", "validate", *REPLAYABLE[folder],
         "--out", str(out), "--replay", "--no-progress"],
        capture_output=True, text=True, timeout=600, env=env)
    assert done.returncode == 0, done.stderr
    assert _answers(out / "fem_comparison.csv") == _answers(DOCS / folder / "fem_comparison.csv")


@pytest.mark.parametrize("folder", sorted(DESIGN_SPACES))
def test_the_design_space_replays_without_computing(tmp_path, folder):
    """Its 560 rigid-model cases and its rims' laws (the 2-D pushes) from the stores alone."""
    out = tmp_path / "out"
    (out / "store").mkdir(parents=True)
    shutil.copy(DOCS / folder / "store" / "results.sqlite", out / "store")
    env = {**os.environ, "DFP_CACHE_DIR": str(tmp_path / "empty-cache")}
    done = subprocess.run(
        [sys.executable, "-m", "validation.studies.rim_design", *DESIGN_SPACES[folder],
         "--out", str(out), "--replay"], capture_output=True, text=True, timeout=600, env=env)
    assert done.returncode == 0, done.stderr
    for name in ("cases.csv", "rim_capacity.csv", "failure_mode_map.csv"):
        assert (out / name).read_text() == (DOCS / folder / name).read_text(), name


def test_the_registry_names_the_committed_stores():
    """Every folder of validation.studies.committed_stores holds a store, and its carrying
    over is the command that made it with --rekey-from (the design spaces' study, or dfp
    validate with the folder's arguments)."""
    for folder in [*REPLAYABLE, *UNFINISHED]:
        assert (DOCS / folder / "results.sqlite").is_file(), folder
        command = rekey_command(folder, "abc1234")
        assert command[2:4] == ["validation.cli", "validate"]
        assert command[command.index("--out") + 1] == str(DOCS / folder)
    for folder in DESIGN_SPACES:
        assert (DOCS / folder / "store" / "results.sqlite").is_file(), folder
        assert rekey_command(folder, "abc1234")[-2:] == ["--rekey-from", "abc1234"]
    for folder in [*REPLAYABLE, *UNFINISHED, *DESIGN_SPACES]:  # --keep-stored-laws passed on
        assert rekey_command(folder, "abc1234", keep_laws=True)[-1] == "--keep-stored-laws"


def test_the_stale_stores_have_a_command_that_parses():
    """Every stale store of the registry is a committed folder, and the command that remakes
    it is one today's dfp parser accepts, writing into that folder (the studies: their default
    folders are the registered ones)."""
    from validation.cli import build_parser
    from validation.studies import FEM_VALIDATION, RESULTS
    from validation.studies.committed_stores import STALE, rerun_command

    for folder in STALE:
        command = rerun_command(folder)
        assert (DOCS / folder).is_dir(), folder
        if command[2] == "validation.cli":
            args = build_parser().parse_args(command[3:])
            assert Path(args.out) == DOCS / folder and args.func.__name__ == "validate"
    assert DOCS / "results" / "yielding_rims_fe" == RESULTS / "yielding_rims_fe"
    assert DOCS / "fem-validation" == FEM_VALIDATION


def test_the_rim_pushes_replay_without_computing(tmp_path):
    """The 3-D and 2-D rim pushes of docs/rim-3d (ours and CalculiX's) from its store."""
    out = tmp_path / "out"
    (out / "store").mkdir(parents=True)
    shutil.copy(DOCS / "rim-3d" / "store" / "results.sqlite", out / "store")
    done = subprocess.run(
        [sys.executable, "-m", "validation.studies.rim3d", "--replay", "--out", str(out)],
        capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr
    assert (out / "pushes.csv").read_text() == (DOCS / "rim-3d" / "pushes.csv").read_text()


def _cache_a_law_pushed_elsewhere(store_path: Path, path: Path):
    """Write to the cache file ``path`` the law stored in ``store_path`` under its key with a
    stiffness 1e-12 off (the same push on another machine); return (stored, cached)."""
    import dataclasses

    from rigid.rims import save_rim_law
    from rigid.tasks import ResultStore
    from validation.stored_rim_laws import _from_json

    with ResultStore(store_path) as store:
        stored = _from_json(store.get(path.stem))
    elsewhere = dataclasses.replace(stored, stiffness=stored.stiffness * (1 + 1e-12))
    save_rim_law(elsewhere, path)
    return stored, elsewhere


def test_a_stored_law_replaces_a_cached_one_pushed_elsewhere(tmp_path, monkeypatch):
    """The same push made on another machine differs in its last digits, and the stored runs
    key on the law's numbers: a run resumed from a store must use the store's law, not the one
    in the user's cache (else every rigid record of the store is computed again)."""
    from rigid import DFPBearing
    from rigid.rims import load_rim_law, rim_law_cache_file
    from rigid.tasks import ResultStore
    from validation.stored_rim_laws import keep_rim_laws

    monkeypatch.setenv("DFP_CACHE_DIR", str(tmp_path / "cache"))
    shutil.copy(DOCS / "example-report" / "results.sqlite", tmp_path)
    bearing = DFPBearing()
    path = rim_law_cache_file(bearing, "plane-strain")
    stored, elsewhere = _cache_a_law_pushed_elsewhere(tmp_path / "results.sqlite", path)
    with ResultStore(tmp_path / "results.sqlite") as store:
        keep_rim_laws(store, bearing, ["plane-strain"], replay=True)
    assert load_rim_law(path).stiffness == stored.stiffness != elsewhere.stiffness


def _smooth_law(samples: int, skip=(), strength: float = 1.0):
    """A rim law whose curves sample F = 2.4 MN·tanh(u/2 mm) (times ``strength``) at
    ``samples`` points, less the indices ``skip``: the same law as another push's increments
    would sample it."""
    import numpy as np

    from rigid.rims import RimLaw

    def curve(top):
        x = np.delete(np.linspace(0.0, top, samples), list(skip))
        return x, strength * 2.4e6 * np.tanh(x / 2e-3)

    sets, force = curve(0.02)
    push, push_force = curve(0.0175)
    return RimLaw(stiffness=6.1e9, plastic_set=sets, force=force, first_yield_force=4.7e5,
                  hinge_displacement=5.5e-4, hinge_force=1.9e6, hinge_set=2.4e-4,
                  rupture_displacement=9.0e-3, rupture_set=8.6e-3, lever=0.02625,
                  push_displacement=push, push_force=push_force)


def test_two_samplings_of_a_law_agree_and_a_stronger_law_does_not():
    """A law pushed again on another machine may take other increments (measured: one
    increment of 131 moved, 2.3e-4 of the peak force apart at the samples both share): it is
    the same law. A steel 0.2 % stronger is not, nor are marks 0.2 % apart, nor a curve with
    too few samples in common to tell: the tolerance, 1e-3, must tell them apart."""
    import dataclasses

    from validation.stored_rim_laws import LAW_RTOL, law_differences

    law = _smooth_law(160)
    assert law_differences(_smooth_law(160, skip=[60]), law) == []
    assert law_differences(_smooth_law(160, strength=1.002), law) == ["push_force", "force"]
    later = dataclasses.replace(law, rupture_set=law.rupture_set * (1 + 2 * LAW_RTOL))
    assert law_differences(later, law) == ["rupture_set"]
    heights = dataclasses.replace(law, corner_height=law.plastic_set * 0.0 + 0.045)
    assert law_differences(heights, law) == ["corner_height"]
    shifted = _smooth_law(160)  # sampled half-way between: nothing to compare with
    shifted.push_displacement[1:-1] += 0.5 * shifted.push_displacement[1]
    assert law_differences(shifted, law) == ["push_force"]


def test_a_law_through_tearing_is_compared_up_to_its_first_tear():
    """After the first tear the push is not repeatable from machine to machine (measured: up
    to 12 % of the backbone's peak, the rim off 4 % apart): two laws that differ only there
    agree; a difference before the tear does not."""
    import dataclasses

    import numpy as np

    from validation.stored_rim_laws import law_differences

    law = dataclasses.replace(_smooth_law(160), tear_set=0.01, off_set=0.03)

    def weakened(beyond):
        return dataclasses.replace(law, force=np.where(law.plastic_set > beyond,
                                                       0.9 * law.force, law.force))

    assert law_differences(dataclasses.replace(weakened(0.012), off_set=0.028), law) == []
    assert law_differences(weakened(0.008), law) == ["force"]


def test_rekey_carries_the_stored_law_once_todays_push_agrees(tmp_path, monkeypatch):
    """``--rekey-from``: the law stored under the keys of a revision's code moves to today's
    keys, its own numbers kept (the stored runs key on them), once today's push agrees with
    it; a push that differs is refused and nothing moves, unless the stored law is to be kept
    (``--keep-stored-laws``)."""
    import contextlib

    import validation.stored_rim_laws as laws
    from rigid import DFPBearing
    from rigid.rims import rim_law_cache_file
    from rigid.tasks import ResultStore, rekey
    from rigid.tasks import store as store_module

    @contextlib.contextmanager
    def code_then(revision, today=("rim-law",), current=None):
        monkeypatch.setattr(store_module, "CODE", lambda kind, models, canonical: "then")
        yield revision
        monkeypatch.setattr(store_module, "CODE", None)

    monkeypatch.setattr(rekey, "code_at", code_then)
    monkeypatch.setenv("DFP_CACHE_DIR", str(tmp_path / "cache"))
    bearing = DFPBearing()
    stored = _smooth_law(160)
    with code_then("REV"):
        then = rim_law_cache_file(bearing).stem
    now = rim_law_cache_file(bearing).stem
    assert then != now
    with ResultStore(tmp_path / "results.sqlite") as store:
        store.put(then, "rim-law", laws._to_json(stored))
        monkeypatch.setattr(laws, "_push", lambda *args: _smooth_law(160, strength=1.002))
        with pytest.raises(rekey.RekeyError, match="force"):
            laws.carry_rim_laws(store, bearing, ["plane-strain"], "REV")
        assert now not in store
        monkeypatch.setattr(laws, "_push", lambda *args: _smooth_law(160, skip=[60]))
        assert laws.carry_rim_laws(store, bearing, ["plane-strain"], "REV") == [
            "the plane-strain rim law carried over: today's push agrees"]
        assert store.get(now) == laws._to_json(stored)
        assert laws.carry_rim_laws(store, bearing, ["plane-strain"], "REV") == []
    with ResultStore(tmp_path / "kept.sqlite") as store:  # kept on request, the difference said
        store.put(then, "rim-law", laws._to_json(stored))
        monkeypatch.setattr(laws, "_push", lambda *args: _smooth_law(160, strength=1.002))
        assert laws.carry_rim_laws(store, bearing, ["plane-strain"], "REV",
                                   keep_differing=True) == [
            "the plane-strain rim law carried over, kept although today's push differs in "
            "push_force, force"]
        assert store.get(now) == laws._to_json(stored)


def test_the_status_of_a_run_replays_with_the_stores_law(tmp_path, monkeypatch):
    """validation.studies.fem_validation_status reads a run's searches from its store with
    the store's rim law, not one pushed on this machine (last digits apart): on the first
    two records of docs/fem-validation-fracture, the FE answers the folder documents."""
    from rigid import DFPBearing, G, fema_p695
    from rigid.rims import rim_law_cache_file
    from validation.studies.fem_validation_status import replayed, run_settings

    monkeypatch.setenv("DFP_CACHE_DIR", str(tmp_path / "cache"))
    shutil.copy(DOCS / "fem-validation-fracture" / "results.sqlite", tmp_path)
    _cache_a_law_pushed_elsewhere(tmp_path / "results.sqlite",
                                  rim_law_cache_file(DFPBearing(), "plane-strain", "median"))
    motions = fema_p695("nearfield_pulse")[:2]
    settings = run_settings(("containment",), fracture="median", edge_radius_mm=20.0)
    searches, owners = replayed(tmp_path, settings, motions)
    found = {(motions[i].name, f"{p / 1e6:g}"): f"{r.sa / G:g}"
             for (p, i), r in zip(owners, searches.results(), strict=True)}
    with open(DOCS / "fem-validation-fracture" / "fem_comparison.csv", newline="") as fh:
        documented = {(r["record"], r["pressure_mpa"]): r["fem_sa_g"]
                      for r in csv.DictReader(fh) if (r["record"], r["pressure_mpa"]) in found}
    assert len(found) == 4 and found == documented


def test_a_replay_names_what_its_store_lacks(tmp_path):
    """An empty store: the rim law (yielding rims, the default) is the first thing missing;
    with rigid rims only, the record's ladders; one line, nothing computed."""
    record = tmp_path / "pulse.txt"
    record.write_text("0\n0.1\n0\n")
    manifest = tmp_path / "m.csv"
    manifest.write_text("path,dt,units\npulse.txt,0.01,g\n")
    env = {**os.environ, "DFP_CACHE_DIR": str(tmp_path / "empty-cache")}
    for rims, missing in ((["rigid", "yielding"], "(rim-law 1)"),
                          (["rigid"], "(rigid-record 2)")):
        done = subprocess.run(
            [sys.executable, "-m", "validation.cli", "validate", "--manifest", str(manifest),
             "--rims", *rims, "--out", str(tmp_path / "out"), "--replay", "--no-progress"],
            capture_output=True, text=True, timeout=600, env=env)
        lines = done.stderr.strip().splitlines()
        assert done.returncode != 0 and len(lines) == 1, done.stderr
        assert missing in lines[0] and "not in" in lines[0], lines[0]
    assert not (tmp_path / "empty-cache" / "rim-laws").exists()


def _toy(x, root):
    """The toy model of the re-keying tests: ``f`` of the file ``toy.py`` under ``root``."""
    import time

    space: dict = {}
    exec((Path(root) / "toy.py").read_text(), space)
    return {"y": space["f"](x), "cpu_seconds": time.process_time()}


SQUARE = "def f(x):\n    return x * x\n"


def _toy_repo(tmp_path, monkeypatch, files: dict, model_code: dict) -> Path:
    """A git repository of ``files`` (path → text), committed, that the library's code
    hashes read (its ROOT) with ``model_code`` as its MODEL_CODE."""
    from rigid.tasks import cache

    repo = tmp_path / "repo"
    for name, text in files.items():
        (repo / name).parent.mkdir(parents=True, exist_ok=True)
        (repo / name).write_text(text)
    git = ["git", "-C", str(repo), "-c", "user.name=t", "-c", "user.email=t@t"]
    subprocess.run([*git, "init", "-q"], check=True)
    subprocess.run([*git, "add", "."], check=True)
    subprocess.run([*git, "commit", "-qm", "toy"], check=True)
    monkeypatch.setattr(cache, "ROOT", repo)
    monkeypatch.setattr(cache, "MODEL_CODE", model_code)
    cache.code_hash.cache_clear()
    return repo


def _edit_toy(repo: Path, text: str) -> None:
    """Today's ``toy.py`` (uncommitted), its hash computed afresh."""
    from rigid.tasks import cache

    (repo / "toy.py").write_text(text)
    cache.code_hash.cache_clear()


def _toy_tasks(repo: Path, n: int) -> list:
    from rigid.tasks import Task, task_key

    return [Task(task_key("toy", ("toy",), x=x), "toy", _toy, {"x": x, "root": str(repo)})
            for x in range(n)]


def _toy_replay(store, repo: Path, n: int):
    """``replay(seen=None)`` of ``n`` toy tasks from ``store``, as :func:`rekey` calls it."""
    from rigid.tasks import run_tasks

    return lambda seen=None: run_tasks(_toy_tasks(repo, n), store, progress=False,
                                       replay=True, seen=seen)


@pytest.mark.skipif(shutil.which("git") is None, reason="re-keying reads code through git")
def test_rekey_carries_results_over_a_change_that_leaves_the_physics_alone(tmp_path,
                                                                          monkeypatch):
    """A toy model in its own git repository: its results, stored by the committed code,
    are carried over to the keys of an edit that changes no result (a comment), after a
    rerun; an edit that changes a result is refused, and nothing is carried over."""
    from rigid.tasks import MissingResultsError, ResultStore, cache, run_tasks
    from rigid.tasks.rekey import RekeyError, rekey

    repo = _toy_repo(tmp_path, monkeypatch, {"toy.py": SQUARE}, {"toy": ("toy.py",)})
    store = ResultStore(tmp_path / "r.sqlite")
    replay = _toy_replay(store, repo, 4)
    run_tasks(_toy_tasks(repo, 4), store, workers=1, progress=False)
    _edit_toy(repo, "def f(x):\n    return x * x  # the same physics\n")
    with pytest.raises(MissingResultsError):
        replay()
    assert rekey(store, replay, "HEAD") == {"toy": 4}
    assert [r["y"] for r in replay().values()] == [0, 1, 4, 9]

    # an unfinished run's store: what it holds is carried, what it lacks counted
    partial = ResultStore(tmp_path / "partial.sqlite")
    _edit_toy(repo, SQUARE)
    run_tasks(_toy_tasks(repo, 3), partial, workers=1, progress=False)
    _edit_toy(repo, "def f(x):\n    return x * x  # the same physics\n")
    carried = rekey(partial, _toy_replay(partial, repo, 4), "HEAD")
    assert carried == {"toy": 3} and carried.missing == {"toy": 1}
    assert carried.describe().startswith("carried over toy 3 (")
    assert carried.describe().endswith("not stored, to be computed by a run: toy 1")

    _edit_toy(repo, "def f(x):\n    return x * x + 1\n")
    with pytest.raises(RekeyError, match="differs"):
        rekey(store, replay, "HEAD")
    with pytest.raises(MissingResultsError):
        replay()
    cache.code_hash.cache_clear()


@pytest.mark.skipif(shutil.which("git") is None, reason="re-keying reads code through git")
def test_rekey_accepts_another_machines_rounding_and_nothing_more(tmp_path, monkeypatch):
    """A rerun on another machine rounds differently (measured: up to 1.4e-9 relative on an FE
    run): a change of 1e-12 relative is carried over, and the largest one reported; a change
    of 1e-5, ten times the tolerance (rigid.tasks.rekey.RTOL), is refused."""
    from rigid.tasks import ResultStore, run_tasks
    from rigid.tasks.rekey import RTOL, RekeyError, rekey

    assert RTOL == 1e-6
    repo = _toy_repo(tmp_path, monkeypatch, {"toy.py": SQUARE}, {"toy": ("toy.py",)})
    store = ResultStore(tmp_path / "r.sqlite")
    run_tasks(_toy_tasks(repo, 4), store, workers=1, progress=False)
    _edit_toy(repo, "def f(x):\n    return x * x * (1 + 1e-5)\n")
    with pytest.raises(RekeyError, match="differs"):
        rekey(store, _toy_replay(store, repo, 4), "HEAD")
    _edit_toy(repo, "def f(x):\n    return x * x * (1 + 1e-12)\n")
    carried = rekey(store, _toy_replay(store, repo, 4), "HEAD")
    assert carried == {"toy": 4}
    assert carried.largest_change == pytest.approx(1e-12, rel=1e-3)


@pytest.mark.skipif(shutil.which("git") is None, reason="re-keying reads code through git")
def test_rekey_accepts_one_newton_iteration_in_a_thousand_and_no_more(tmp_path, monkeypatch):
    """The Newton iterations count the solver's effort (rigid.tasks.rekey.EFFORT_RTOL):
    another machine took 2 144 where 2 143 were stored, floats within 6e-9. One iteration
    more in 2 143 is carried over; ten more is refused, and so is one more accepted step
    (steps are held to equality)."""
    from rigid.tasks import ResultStore, run_tasks
    from rigid.tasks.rekey import RekeyError, rekey

    def toy(iterations: int, steps: int = 500) -> str:
        return (f"def f(x):\n    return {{'value': x * x, 'newton_iterations': {iterations}, "
                f"'steps': {steps}}}\n")

    repo = _toy_repo(tmp_path, monkeypatch, {"toy.py": toy(2143)}, {"toy": ("toy.py",)})
    store = ResultStore(tmp_path / "r.sqlite")
    run_tasks(_toy_tasks(repo, 3), store, workers=1, progress=False)
    for refused in (toy(2153), toy(2143, steps=501)):
        _edit_toy(repo, refused)
        with pytest.raises(RekeyError, match="differs"):
            rekey(store, _toy_replay(store, repo, 3), "HEAD")
    _edit_toy(repo, toy(2144))
    assert rekey(store, _toy_replay(store, repo, 3), "HEAD") == {"toy": 3}


@pytest.mark.skipif(shutil.which("git") is None, reason="re-keying reads code through git")
def test_rekey_hashes_a_revision_with_its_own_model_code(tmp_path, monkeypatch):
    """A toy repository whose committed MODEL_CODE gives a sub-folder a model of its own;
    today's merges it into its parent (as fem/fracture joined fem). The results stored under
    the revision's split are found, rerun identical and carried over: the revision's code is
    hashed with the revision's MODEL_CODE, not today's."""
    from rigid.tasks import ResultStore, cache, run_tasks
    from rigid.tasks.rekey import rekey

    split = {"toy": ("toy.py", "toy"), "toy-sub": ("toy/sub",)}
    repo = _toy_repo(tmp_path, monkeypatch, {
        "toy.py": SQUARE, "toy/core.py": "A = 1\n", "toy/sub/part.py": "B = 2\n",
        "rigid/tasks/cache.py": f"MODEL_CODE = {split!r}\n"}, split)
    store = ResultStore(tmp_path / "r.sqlite")
    run_tasks(_toy_tasks(repo, 3), store, workers=1, progress=False)
    monkeypatch.setattr(cache, "MODEL_CODE", {"toy": ("toy.py", "toy")})  # the sub merged in
    cache.code_hash.cache_clear()
    carried = rekey(store, _toy_replay(store, repo, 3), "HEAD")
    assert carried == {"toy": 3} and not carried.missing
    cache.code_hash.cache_clear()
