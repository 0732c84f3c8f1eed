"""Result store and task runner: keys, persistence, resume after a kill, local pool vs Dask."""

import dataclasses
import math
import os
import signal
import subprocess
import sys
import textwrap
import time

import numpy as np
import pytest

from rigid import DFPBearing, G, ricker_record
from rigid.collapse.ladder import _run_rung
from rigid.tasks.runner import MissingResultsError, Task, run_tasks
from rigid.tasks.store import ResultStore, task_key

RIGID = ("rigid",)


def test_task_key_is_canonical_and_sensitive():
    b = DFPBearing()
    a = np.linspace(0, 1, 11)
    k = task_key("rigid", RIGID, bearing=b, acceleration=a, scale=1.0)
    assert k == task_key("rigid", RIGID, scale=1.0, acceleration=a.copy(), bearing=DFPBearing())
    assert k != task_key("rigid", RIGID, bearing=b, acceleration=a, scale=1.01)
    assert k != task_key("rigid", RIGID, bearing=dataclasses.replace(b, friction=0.06),
                         acceleration=a, scale=1.0)
    changed = a.copy()
    changed[5] += 1e-12
    assert k != task_key("rigid", RIGID, bearing=b, acceleration=changed, scale=1.0)
    assert k != task_key("rigid", ("rigid", "fem"), bearing=b, acceleration=a, scale=1.0)
    with pytest.raises(TypeError, match="object"):
        task_key("rigid", RIGID, thing=object())


def test_task_key_changes_with_the_models_code(tmp_path, monkeypatch):
    """A stored result of an edited model is never replayed: the key holds the hash of the
    model's source files, so editing one byte of them gives another key (the files here are
    stand-ins in a temporary root; the real ones are rigid/model.py, fem/, …)."""
    from rigid.tasks import cache

    (tmp_path / "model").mkdir()
    source = tmp_path / "model" / "kernel.py"
    source.write_text("x = 1\n")
    monkeypatch.setattr(cache, "ROOT", tmp_path)
    monkeypatch.setitem(cache.MODEL_CODE, "rigid", ("model",))
    cache.code_hash.cache_clear()
    before = task_key("rung", RIGID, scale=1.0)
    source.write_text("x = 2\n")
    cache.code_hash.cache_clear()
    after = task_key("rung", RIGID, scale=1.0)
    cache.code_hash.cache_clear()
    assert before != after
    with pytest.raises(ValueError, match="unknown model"):
        task_key("rung", ("kernel",), scale=1.0)


def test_only_yielding_rim_ladders_key_on_the_rim_law(tmp_path, monkeypatch):
    """Editing the yielding rims' law (rigid/rims.py, stood in for here by a temporary file)
    moves the key of a ladder rung with yielding rims and leaves one with rigid rims (and so
    the stored FE runs of a validation, which run the rigid model with rigid rims only)."""
    from rigid.collapse.ladder import _Store
    from rigid.tasks import cache

    (tmp_path / "kernel.py").write_text("y = 1\n")
    law = tmp_path / "rims.py"
    law.write_text("x = 1\n")
    monkeypatch.setattr(cache, "ROOT", tmp_path)
    monkeypatch.setitem(cache.MODEL_CODE, "rigid", ("kernel.py",))
    monkeypatch.setitem(cache.MODEL_CODE, "rim-law", ("rims.py",))
    ladders = [_Store(None, {"dt": 0.01, "simulate": {"rims": rims}})
               for rims in ("rigid", "yielding")]
    cache.code_hash.cache_clear()
    before = [s._key(3) for s in ladders]
    law.write_text("x = 2\n")
    cache.code_hash.cache_clear()
    after = [s._key(3) for s in ladders]
    cache.code_hash.cache_clear()
    assert before[0] == after[0] and before[1] != after[1]


def test_store_round_trip(tmp_path):
    with ResultStore(tmp_path / "r.sqlite") as store:
        store.put("k1", "rigid", {"failed": True, "v": [1.5, 2.0]}, seconds=0.1)
        assert "k1" in store and "k2" not in store
        assert store.get("k1") == {"failed": True, "v": [1.5, 2.0]}
        assert store.count() == 1 and store.count("fem") == 0
    with ResultStore(tmp_path / "r.sqlite") as store:  # persisted
        assert store.get("k1")["v"] == [1.5, 2.0] and store.check()


def _square(x):
    return {"y": x * x}


def _tasks(n):
    return [Task(task_key("square", RIGID, x=x), "square", _square, {"x": x}) for x in range(n)]


def _blas_threads():
    from threadpoolctl import threadpool_info

    return {"threads": [p["num_threads"] for p in threadpool_info() if p["user_api"] == "blas"]}


def test_in_process_tasks_run_with_one_blas_thread(monkeypatch):
    """With one worker the tasks run in this process, whose BLAS was loaded with a thread per
    core: the runner holds it to one thread while a task runs (as the pool's workers are by
    their environment), and gives the threads back afterwards. A thread count the user set
    (OMP_NUM_THREADS & co.) is left alone."""
    from rigid.tasks.runner import _THREAD_VARIABLES

    for var in _THREAD_VARIABLES:
        monkeypatch.delenv(var, raising=False)
    before = _blas_threads()["threads"]
    if not before or max(before) == 1:
        pytest.skip("this process's BLAS has one thread already: nothing to limit")
    task = Task(task_key("blas", RIGID), "blas", _blas_threads)
    inside = run_tasks([task], None, workers=1, progress=False)[task.key]
    assert inside["threads"] == [1] * len(before)
    assert _blas_threads()["threads"] == before
    monkeypatch.setenv("OMP_NUM_THREADS", "2")
    assert run_tasks([task], None, workers=1, progress=False)[task.key]["threads"] == before


def test_rerun_reuses_stored_results(tmp_path):
    store = ResultStore(tmp_path / "r.sqlite")
    first = run_tasks(_tasks(5), store, workers=1, progress=False)
    assert [first[t.key]["y"] for t in _tasks(5)] == [0, 1, 4, 9, 16]
    calls = []

    def spy(task, result):
        calls.append(task.key)
        return ()

    again = run_tasks(_tasks(5), store, workers=1, progress=False, follow_up=spy)
    assert again == first and len(calls) == 5 and store.count() == 5


def test_progress_log_has_a_line_per_run_with_the_time_left(tmp_path):
    """A first line as the first run starts, then one line per task run (none for results
    read from the store), counting runs done and queued; the estimate of the time left
    reaches zero with the queue."""
    from rigid.tasks.runner import Progress

    log = tmp_path / "progress.log"
    store = ResultStore(tmp_path / "r.sqlite")
    run_tasks(_tasks(3), store, workers=1, progress=False, log=log)
    lines = log.read_text().splitlines()
    assert len(lines) == 4
    assert "started, 3 queued on 1 worker(s)" in lines[0]
    assert "1 run, 0 running, 2 queued; square" in lines[1]
    assert "3 run, 0 running, 0 queued" in lines[-1] and "about 0 s left" in lines[-1]
    run_tasks(_tasks(3), store, workers=1, progress=False, log=log)  # all stored: no line
    assert len(log.read_text().splitlines()) == 4
    # two workers, 60 s runs of one kind, four queued: 4 × 60 / 2 = 2 min, plus half the
    # running one's mean over the workers (0.25 min)
    tally = Progress(2)
    line = tally.record("fem-run", 60.0, 1, [Task("k", "fem-run", _square, {})] * 4)
    assert "about 2 min left" in line


def test_time_left_counts_the_follow_ups_expected():
    """A search: each 10 s "ladder" task has brought 2 "fem" runs and each 60 s "fem" run half
    a further one (a chain of 2 on average). Expected work per fem run W_f = 60 / (1 − 0.5)
    = 120 s, per ladder W_l = 10 + 2 W_f = 250 s (closed form of the Progress docstring);
    three ladders queued, nothing running, one worker: 750 s = 12.5 min, shown rounded."""
    from rigid.tasks.runner import Progress

    tally = Progress(1, half_life=math.inf)  # equal weights: the closed form above holds
    fem = Task("f", "fem", _square, {})
    tally.spawned("ladder", [fem, fem])
    tally.spawned("fem", [fem])
    tally.spawned("fem", [])
    tally.seconds = {"ladder": [10.0], "fem": [60.0]}
    line = tally.record("fem", 60.0, 0, [Task("l", "ladder", _square, {})] * 3)
    # record() added a third 60 s fem run: the means stay 10 and 60 s; 12.5 min is shown as
    # "12 min" (format rounds half to even)
    assert "about 12 min left" in line
    assert tally._work({"ladder": 10.0, "fem": 60.0}, 35.0) == pytest.approx(
        {"ladder": 250.0, "fem": 120.0}, rel=1e-12)
    # a resumed run: the fem runs so far were all read from the store, so a ladder's expected
    # work is its own 10 s (W_f = 0 · 60 / (1 − 0.5) = 0)
    tally.ran["fem"] = 0
    assert tally._work({"ladder": 10.0, "fem": 60.0}, 35.0) == pytest.approx(
        {"ladder": 10.0, "fem": 0.0}, abs=1e-12)
    # a chain that has always gone on (1 follow-up per run): no finite answer, the run's own
    # mean only
    always = Progress(1)
    always.spawned("fem", [fem])
    assert always._work({"fem": 60.0}, 60.0) == {"fem": 60.0}


def test_time_left_counts_no_follow_ups_for_tasks_that_bring_none():
    """A validation run with FE runs for some records only: the first ladder (10 s) brought 2
    fem runs of 60 s, the next one none (Task.leads False). Three queued ladders that bring
    none are worth their own 3 × 10 s = 30 s; counted as leading they would be worth
    3 × (10 + 2 × 60) s = 6.5 min, which is what the estimate showed before."""
    from rigid.tasks.runner import Progress

    fem = Task("f", "fem", _square, {})
    tally = Progress(1, half_life=math.inf)
    tally.spawned("ladder", [fem, fem])
    tally.spawned("ladder", [], leads=False)  # teaches nothing of a search's shape
    for _ in range(2):
        tally.spawned("fem", [])
    tally.seconds = {"ladder": [10.0, 10.0], "fem": [60.0]}
    assert tally._work({"ladder": 10.0, "fem": 60.0}, 35.0)["ladder"] == pytest.approx(130.0)
    quiet = [Task("l", "ladder", _square, {}, leads=False)] * 3
    assert "about 30 s left" in tally.record("fem", 60.0, 0, quiet)
    leading = [Task("l", "ladder", _square, {})] * 3
    assert "about 6 min left" in tally.record("fem", 60.0, 0, leading)


def test_time_left_after_a_resume_follows_the_searches_still_open():
    """A resumed run reads finished searches from its store (fem runs in chains of 2) and
    runs the open ones (chains of 5, 100 s each); what is left per chain start is
    W = 100 / (1 − 0.8) = 500 s.

    - The replay before the first run ends leaves s (how often a fem task runs) alone but
      teaches the searches' shape: a ladder read then brought 3 fem tasks, so a queued one is
      worth 3 W_f.
    - Replays met later weigh by recency: 100 replays then 200 runs give s = 0.67, r = 0.7,
      W = 222 s (0.44 of the truth) with equal weights and 433 s (0.87) with a half-life of 50
      tasks. The bounds sit between and fail if the weighting is lost."""
    from rigid.tasks.runner import Progress

    fem = Task("f", "fem", _square, {})

    tally = Progress(1, half_life=math.inf)
    for _ in range(10):  # read before any run: ladders and their finished searches
        tally.spawned("ladder", [fem] * 3, ran=False)
    for i in range(200):
        tally.spawned("fem", [fem] * (i % 2 == 0), ran=False)
    tally.spawned("fem", [fem], ran=True)
    assert tally._share("fem") == 1.0 and tally._share("ladder") == 1.0
    work = tally._work({"fem": 100.0}, 100.0)
    assert work["ladder"] == pytest.approx(100.0 + 3 * work["fem"], rel=1e-12)

    def estimate(half_life):
        tally = Progress(1, half_life=half_life)
        tally.seconds = {"fem": [100.0]}  # a first run has ended: later replays count
        for i in range(100):
            tally.spawned("fem", [fem] * (i % 2 == 0), ran=False)
        for i in range(200):
            tally.spawned("fem", [fem] * (i % 5 != 4), ran=True)
        tally.seconds = {"fem": [100.0] * 200}
        return tally._work({"fem": tally._mean("fem")}, 100.0)["fem"] / 500.0

    assert estimate(math.inf) < 0.5
    assert 0.8 < estimate(50.0) < 1.0


def _next_rung(task, result):
    """A ladder's follow-up: step x up until x² exceeds 20, as the critical-SA search does."""
    x = task.kwargs["x"]
    return [] if result["y"] > 20 else [Task(task_key("square", RIGID, x=x + 1), "square",
                                             _square, {"x": x + 1})]


def test_follow_up_tasks_run_until_the_search_stops(tmp_path):
    """A ladder: step x up until x² exceeds 20, as the critical-SA search does."""
    store = ResultStore(tmp_path / "r.sqlite")

    results = run_tasks(_tasks(1), store, workers=1, progress=False, follow_up=_next_rung)
    assert sorted(r["y"] for r in results.values()) == [0, 1, 4, 9, 16, 25]


def _refuse(x):
    raise AssertionError("a replay ran a task")


def test_replay_reads_the_store_and_counts_what_is_missing(tmp_path):
    """A replay runs nothing: the stored results (and the follow-ups of stored results) come
    back as a run would return them; a task not stored (here: a kind whose function would
    fail if run) is counted by kind, after the stored ones were replayed."""
    store = ResultStore(tmp_path / "r.sqlite")

    ran = run_tasks(_tasks(1), store, workers=1, progress=False, follow_up=_next_rung)
    replayed = run_tasks(_tasks(1), store, progress=False, follow_up=_next_rung, replay=True)
    assert replayed == ran and store.count() == 6
    new = [Task(task_key("cube", RIGID, x=x), "cube", _refuse, {"x": x}) for x in (1, 2)]
    seen = []
    with pytest.raises(MissingResultsError, match=r"2 results are not in .*\(cube 2\)") as info:
        run_tasks([*new, *_tasks(1)], store, progress=False, replay=True,
                  follow_up=lambda t, r: seen.append(t.key) or _next_rung(t, r))
    assert info.value.missing == {"cube": 2} and len(seen) == 6 and store.count() == 6



def test_a_resumed_run_reads_its_store_before_the_first_run(tmp_path):
    """A resumed run finishes the stored tasks of its queue, and the stored follow-ups they
    bring, before it starts a run, wherever they stand in the queue: its log's first line
    counts the one task left to run, not the stored chain queued behind it (3 → 4 → 5)."""
    store = ResultStore(tmp_path / "r.sqlite")
    chain = [Task(task_key("square", RIGID, x=3), "square", _square, {"x": 3})]
    stored = run_tasks(chain, store, workers=1, progress=False, follow_up=_next_rung)
    new = Task(task_key("cube", RIGID, x=2), "cube", _square, {"x": 2})
    log = tmp_path / "progress.log"
    resumed = run_tasks([new, *chain], store, workers=1, progress=False, log=log,
                        follow_up=_next_rung)
    assert resumed == {**stored, new.key: {"y": 4}} and len(stored) == 3
    first = next(line for line in log.read_text().splitlines() if "started" in line)
    assert "started, 1 queued" in first, first

def test_pruning_keeps_what_a_replay_reads(tmp_path):
    """A store pruned to what its replay read (rigid.tasks.rekey.reading,
    ResultStore.keep_only) loses the rows no replay asks for (here: another run's; in a
    committed store, the rows keyed by older code) and replays to the same results."""
    from rigid.tasks.rekey import reading

    store = ResultStore(tmp_path / "r.sqlite")
    ran = run_tasks(_tasks(1), store, workers=1, progress=False, follow_up=_next_rung)
    other = [Task(task_key("cube", RIGID, x=x), "cube", _square, {"x": x}) for x in (7, 8)]
    run_tasks(other, store, workers=1, progress=False)
    assert store.count() == 8
    with reading() as found:
        run_tasks(_tasks(1), store, progress=False, follow_up=_next_rung, replay=True)
    read = found[(tmp_path / "r.sqlite").resolve()]
    assert len(read) == 6 and not read & {t.key for t in other}
    assert store.keep_only(read) == {"cube": 2} and store.count() == 6
    assert run_tasks(_tasks(1), store, progress=False, follow_up=_next_rung,
                     replay=True) == ran

def _rigid_tasks(n):
    """Rungs of a scaling ladder, run by the critical-SA search's own rung function."""
    bearing = DFPBearing(pressure=10e6)
    _, a = ricker_record(0.1 * G, 3.0, dt=0.01)  # fails at 0.8 g (tests/test_model.py)
    sim = {"on_instability": "refine", "free": 10.0}
    return [Task(task_key("rigid", RIGID, bearing=bearing, acc=a, dt=0.01, scale=s, sim=sim),
                 "rigid", _run_rung,
                 {"bearing": bearing, "acc": a, "dt": 0.01, "scale": s, "sim": sim})
            for s in np.linspace(1.0, 8.0, n)]


def _thread_settings():
    return {v: os.environ.get(v) for v in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS")}


def test_pool_workers_run_single_threaded_blas(tmp_path, monkeypatch):
    """Worker processes get one BLAS thread each (threads on top of one process per core made an
    FE run 4 times slower), unless the user set a thread count, which is kept."""
    monkeypatch.delenv("OMP_NUM_THREADS", raising=False)
    monkeypatch.setenv("OPENBLAS_NUM_THREADS", "3")
    task = Task("threads", "threads", _thread_settings, {})
    (seen,) = run_tasks([task], None, workers=2, progress=False).values()
    assert seen == {"OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "3"}


def test_local_pool_and_dask_give_identical_results(tmp_path):
    """The same tasks in this process, in a spawned process pool and on a Dask LocalCluster."""
    distributed = pytest.importorskip("dask.distributed")
    tasks = _rigid_tasks(4)
    inline = run_tasks(tasks, ResultStore(tmp_path / "a.sqlite"), workers=1, progress=False)
    pool = run_tasks(tasks, ResultStore(tmp_path / "b.sqlite"), workers=2, progress=False)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster:
        dask = run_tasks(tasks, ResultStore(tmp_path / "c.sqlite"),
                         scheduler=cluster.scheduler_address, progress=False)
    assert inline == pool == dask
    outcomes = [r["failed"] for r in inline.values()]
    assert any(outcomes) and not all(outcomes)


def _paused_rung(pause, **kwargs):
    """A rung followed by a pause [s]: the killed run below must still be running when the
    test has seen three results stored (a rung alone takes only tens of ms)."""
    result = _run_rung(**kwargs)
    time.sleep(pause)
    return result


RESUMABLE_RUN = textwrap.dedent("""
    import dataclasses, sys
    sys.path.insert(0, {tests!r})
    from test_parallel import _paused_rung, _rigid_tasks
    from rigid.tasks.runner import run_tasks
    from rigid.tasks.store import ResultStore
    tasks = [dataclasses.replace(t, func=_paused_rung, kwargs={{**t.kwargs, "pause": 1.0}})
             for t in _rigid_tasks(8)]
    run_tasks(tasks, ResultStore(sys.argv[1]), workers=1, progress=False)
""")


def test_killed_run_resumes_with_the_same_results(tmp_path):
    """Kill a run (SIGKILL, no cleanup) after some results are stored; the rerun completes
    them without redoing stored work and matches an uninterrupted run; the store is sound."""
    db = tmp_path / "killed.sqlite"
    script = RESUMABLE_RUN.format(tests=os.path.dirname(__file__))
    proc = subprocess.Popen([sys.executable, "-c", script, str(db)])
    deadline = time.time() + 120
    while time.time() < deadline and proc.poll() is None:
        if db.exists() and ResultStore(db).count() >= 3:
            break
        time.sleep(0.05)
    assert proc.poll() is None, "the run finished before it could be interrupted"
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    store = ResultStore(db)
    done = store.count()
    assert 3 <= done < 8 and store.check()
    redone = []
    resumed = run_tasks(_rigid_tasks(8), store, workers=1, progress=False,
                        follow_up=lambda t, r: redone.append(t.key) or ())
    assert store.count() == 8 and len(redone) == 8
    clean = run_tasks(_rigid_tasks(8), ResultStore(tmp_path / "clean.sqlite"), workers=1,
                      progress=False)
    assert resumed == clean


def _sleep(seconds, flag):
    open(flag, "w").close()
    time.sleep(seconds)
    return {}


# The child restores Python's SIGINT handler: a test suite started in the background of a
# non-interactive shell (`pytest &`, some CI runners) inherits SIGINT ignored, and Python then
# keeps ignoring it, so the Ctrl-C under test would never arrive.
INTERRUPTED_RUN = textwrap.dedent("""
    import signal
    import sys
    signal.signal(signal.SIGINT, signal.default_int_handler)
    sys.path.insert(0, {tests!r})
    from test_parallel import _sleep
    from rigid.tasks.runner import MissingResultsError, Task, run_tasks
    from rigid.tasks.store import ResultStore
    tasks = [Task(str(i), "sleep", _sleep, {{"seconds": 300, "flag": sys.argv[2] + str(i)}})
             for i in range(2)]
    try:
        run_tasks(tasks, ResultStore(sys.argv[1]), workers=2, progress=False)
    except KeyboardInterrupt:
        sys.exit(130)
""")


def test_ctrl_c_stops_running_tasks_of_the_pool(tmp_path):
    """Ctrl-C (SIGINT) while two 300 s tasks run in the local pool: the command ends within
    seconds (the workers are terminated, not awaited: an FE run takes minutes) and stores
    nothing for them. 60 s bound: a spawned worker's start-up under load, not the tasks."""
    script = INTERRUPTED_RUN.format(tests=os.path.dirname(__file__))
    flag = str(tmp_path / "started")
    proc = subprocess.Popen([sys.executable, "-c", script, str(tmp_path / "s.sqlite"), flag])
    deadline = time.time() + 120
    while time.time() < deadline and not all(os.path.exists(flag + str(i)) for i in range(2)):
        time.sleep(0.1)
    assert all(os.path.exists(flag + str(i)) for i in range(2)), "the tasks did not start"
    start = time.time()
    proc.send_signal(signal.SIGINT)
    assert proc.wait(timeout=60) == 130
    assert time.time() - start < 60
    assert ResultStore(tmp_path / "s.sqlite").count() == 0
