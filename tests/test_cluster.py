"""Faults on a real Dask cluster (issue #34): a scheduler and workers started as separate
processes on localhost (``python -m distributed.cli.dask_scheduler`` / ``dask_worker``), as a
user starts them, never a LocalCluster in this process.

Oracles: the exit statuses and one-line messages of docs/limits.md, the result store's count,
the scheduler's own view (its workers, the tasks they process), the workers' CPU time in
/proc, the folders the workers could have written to, and an uninterrupted in-process run.
Each workload is the smallest that shows the fault: one or a few rigid-only records, tasks
spinning in Python, one 2-s FE run on the coarse mesh.
"""

from __future__ import annotations

import contextlib
import dataclasses
import json
import os
import signal
import sqlite3
import subprocess
import sys
import textwrap
import threading
import time
from pathlib import Path

import numpy as np
import pytest

import rigid
from rigid import G
from rigid.tasks import ResultStore, Task, run_tasks
from validation import cli

distributed = pytest.importorskip("dask.distributed")
pytestmark = pytest.mark.skipif(not sys.platform.startswith("linux"),
                                reason="reads worker processes' CPU time from Linux /proc")

TESTS = Path(__file__).resolve().parent
ROOT = TESTS.parent
#: Longest wait for a process of the cluster to come up [s]: an import of dask and numpy in a
#: fresh interpreter, on a loaded two-core machine (2-4 s seen).
START = 60


def _env(cache: Path) -> dict:
    """The cluster's environment: this checkout and the tests importable (the scheduler
    unpickles the tasks' functions too), one BLAS thread (as the local pool), and a mesh
    cache of the test's own."""
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join([str(ROOT), str(TESTS)]
                                        + [p for p in [env.get("PYTHONPATH")] if p])
    env.update(OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1", MKL_NUM_THREADS="1",
               DFP_CACHE_DIR=str(cache))
    return env


class Cluster:
    """A scheduler and ``n`` workers (one process, one thread each, under a nanny), started
    in their own session in ``home`` (their working folder); :meth:`stop` kills exactly them.
    """

    def __init__(self, home: Path, workers: int = 0):
        self.home, self.procs = home, []
        home.mkdir(parents=True, exist_ok=True)
        self.env = _env(home / "cache")
        info = home / "scheduler.json"
        self._start("dask_scheduler", "--host", "127.0.0.1", "--port", "0", "--no-dashboard",
                    "--scheduler-file", str(info))
        deadline = time.monotonic() + START
        while not info.exists() and time.monotonic() < deadline:
            time.sleep(0.1)
        self.address = json.loads(info.read_text())["address"]
        for _ in range(workers):
            self.add_worker()

    def _start(self, command, *args):
        self.procs.append(subprocess.Popen(
            [sys.executable, "-m", f"distributed.cli.{command}", *args], cwd=self.home,
            env=self.env, start_new_session=True, stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL))
        return self.procs[-1]

    def add_worker(self):
        return self._start("dask_worker", self.address, "--nworkers", "1", "--nthreads", "1",
                           "--no-dashboard")

    @property
    def scheduler(self):
        return self.procs[0]

    def client(self):
        return distributed.Client(self.address, timeout=START)

    def stop(self):
        for proc in reversed(self.procs):  # each started its own session: its group
            with contextlib.suppress(ProcessLookupError):
                os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()


@pytest.fixture(scope="module")
def cluster(tmp_path_factory):
    """Two workers, shared by the tests that leave the cluster as they found it."""
    c = Cluster(tmp_path_factory.mktemp("cluster"), workers=2)
    try:
        with c.client() as client:
            client.wait_for_workers(2, timeout=START)
        yield c
    finally:
        c.stop()


def _pulse(amplitude):
    return rigid.ricker_record(amplitude * G, 2.5, "antisymmetric", dt=0.01, free=8.0)[1]


def _manifest(folder: Path, n: int) -> Path:
    lines = ["path,name,dt,units"]
    for i in range(n):
        np.savetxt(folder / f"p{i}.txt", _pulse(0.2 + 0.02 * i) / G)
        lines.append(f"p{i}.txt,pulse {i},0.01,g")
    (folder / "records.csv").write_text("\n".join(lines) + "\n")
    return folder / "records.csv"


#: The smallest validation: rigid rims only, one pressure, one criterion, a short ladder.
TINY = ["--pressure", "10", "--criteria", "4", "--stop", "0.4", "--rims", "rigid", "--no-fem",
        "--no-progress"]


def _stored(path: Path) -> int:
    """Results in the store at ``path``, read without creating it."""
    if not path.exists():
        return 0
    try:
        with contextlib.closing(sqlite3.connect(f"file:{path}?mode=ro", uri=True,
                                                timeout=30)) as db:
            return db.execute("SELECT COUNT(*) FROM results").fetchone()[0]
    except sqlite3.Error:  # not created yet
        return 0


# --------------------------------------------------------------------------- no workers


def test_no_workers_is_a_bounded_wait_with_one_line(tmp_path, capsys):
    """A scheduler without workers: the run says in its progress that it waits, and after
    --worker-wait seconds (2 here) it stops with one line naming the address, exit 4. The
    default wait is at most 60 s (the issue's bound). The 30 s bound on the whole run is
    the wait, a connection and this process's imports on a loaded machine."""
    assert cli.build_parser().parse_args(["validate"]).worker_wait <= 60
    lone = Cluster(tmp_path / "lone")
    try:
        out = tmp_path / "out"
        start = time.monotonic()
        status = cli.main(["validate", "--manifest", str(_manifest(tmp_path, 1)), *TINY,
                           "--scheduler", lone.address, "--worker-wait", "2", "--out",
                           str(out)])
        elapsed = time.monotonic() - start
    finally:
        lone.stop()
    err = capsys.readouterr().err
    assert status == cli.EXIT_CLUSTER, err
    assert err == (f"dfp validate: error: no Dask worker joined the scheduler at {lone.address}"
                   f" within 2 s: start some (dask worker {lone.address}) or wait longer "
                   "(--worker-wait)\n")
    assert 2 <= elapsed < 30
    assert f"waiting for Dask workers at {lone.address} (up to 2 s)" in (
        out / "progress.log").read_text()


def test_workers_all_gone_mid_run_is_a_bounded_wait(tmp_path):
    """The only worker killed (with its nanny) while it runs a task: after --worker-wait
    seconds without a worker the run stops with the cluster's error, saying what was kept;
    the progress log says it waited."""
    from rigid.tasks import ClusterError

    lone = Cluster(tmp_path / "lone", workers=1)
    flag, log = tmp_path / "started", tmp_path / "progress.log"

    def kill_the_worker():
        deadline = time.monotonic() + 4 * START
        while not list(tmp_path.glob("started-*")) and time.monotonic() < deadline:
            time.sleep(0.05)
        os.killpg(lone.procs[1].pid, signal.SIGKILL)

    killer = threading.Thread(target=kill_the_worker)
    killer.start()
    tasks = [Task(str(i), "spin", _spin, {"seconds": 120, "flag": f"{flag}-{i}"})
             for i in range(2)]
    try:
        with pytest.raises(ClusterError) as error:
            run_tasks(tasks, ResultStore(tmp_path / "s.sqlite"), scheduler=lone.address,
                      progress=False, worker_wait=2, log=log)
    finally:
        killer.join()
        lone.stop()
    assert str(error.value) == (f"every Dask worker of the scheduler at {lone.address} left "
                                f"and none came back within 2 s; 0 results stored in "
                                f"{tmp_path / 's.sqlite'}; rerun to resume")
    assert f"every Dask worker left {lone.address}; waiting for one (up to 2 s)" in \
        log.read_text()


# --------------------------------------------------------------------------- scheduler lost


def test_lost_scheduler_is_one_line_with_what_was_kept(tmp_path):
    """kill -9 of the scheduler once a result is stored: dfp ends with exit 4 and one line
    naming the address and the results kept (as many as the store holds), no traceback;
    within 30 s (the client notices a closed connection at once; 30 s is its default
    reconnection time, which must not be waited out twice)."""
    lost = Cluster(tmp_path / "lost", workers=1)
    out = tmp_path / "out"
    try:
        run = subprocess.Popen(
            [sys.executable, "-m", "validation.cli", "validate", "--manifest",
             str(_manifest(tmp_path, 12)), *TINY, "--scheduler", lost.address, "--out",
             str(out)], env=lost.env, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
            text=True)
        try:
            deadline = time.monotonic() + 4 * START
            while run.poll() is None and not _stored(out / "results.sqlite") \
                    and time.monotonic() < deadline:
                time.sleep(0.1)
            assert run.poll() is None, "the run ended before its scheduler could be killed"
            lost.scheduler.kill()
            killed = time.monotonic()
            _, err = run.communicate(timeout=60)
            elapsed = time.monotonic() - killed
        finally:
            if run.poll() is None:
                run.kill()
                run.wait()
    finally:
        lost.stop()
    kept = _stored(out / "results.sqlite")
    assert run.returncode == cli.EXIT_CLUSTER, err
    results = "result" if kept == 1 else "results"
    assert err == (f"dfp validate: error: lost the Dask scheduler at {lost.address}; {kept} "
                   f"{results} stored in {out / 'results.sqlite'}; rerun to resume\n")
    assert 1 <= kept < 12 and elapsed < 30


# --------------------------------------------------------------------------- SIGTERM, SIGKILL


def _spin(seconds, flag):
    """CPU work in Python for ``seconds``, after writing this process's id to ``flag``."""
    Path(flag).write_text(str(os.getpid()))
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        pass
    return {}


SIGNALLED_RUN = textwrap.dedent("""
    import signal, sys
    sys.path.insert(0, {tests!r})
    from test_cluster import _spin
    from rigid.tasks import ResultStore, Task, run_tasks
    from validation import cli
    signal.signal(signal.SIGTERM, cli._terminate)  # as dfp: SIGTERM handled like Ctrl-C
    signal.signal(signal.SIGINT, signal.default_int_handler)  # see test_parallel.py
    tasks = [Task(str(i), "spin", _spin, {{"seconds": 120, "flag": f"{{sys.argv[3]}}-{{i}}"}})
             for i in range(8)]
    try:
        run_tasks(tasks, ResultStore(sys.argv[2]), scheduler=sys.argv[1], progress=False)
    except KeyboardInterrupt:  # cli.Terminated is one
        sys.exit(130)
""")


def _cpu_seconds(pid: int) -> float:
    with open(f"/proc/{pid}/stat") as fh:
        fields = fh.read().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


@pytest.mark.parametrize("signum", [signal.SIGTERM, signal.SIGKILL])
def test_a_stopped_run_stops_its_tasks_on_the_workers(cluster, tmp_path, signum):
    """SIGTERM (or SIGKILL: the scheduler drops a vanished client's tasks) while both workers
    spin in 120-s tasks (8 submitted): the run ends, the scheduler keeps no task of it, no
    queued task starts, and the workers are idle within 5 s of the signal: less than 0.5 s
    of CPU each from 3 to 5 s after it (a task still spinning takes about 2 s; an idle worker
    about 0.1 s). Ctrl-C (SIGINT) takes SIGTERM's way out of the runner (a
    KeyboardInterrupt, of which SIGTERM's Terminated is one)."""
    flag = tmp_path / "started"
    run = subprocess.Popen([sys.executable, "-c", SIGNALLED_RUN.format(tests=str(TESTS)),
                            cluster.address, str(tmp_path / "s.sqlite"), str(flag)],
                           env=cluster.env)
    try:
        deadline = time.monotonic() + START
        while len(list(tmp_path.glob("started-*"))) < 2 and time.monotonic() < deadline:
            time.sleep(0.1)
        pids = {int(f.read_text()) for f in tmp_path.glob("started-*")}
        assert len(pids) == 2, "the tasks did not start on both workers"
        run.send_signal(signum)
        signalled = time.monotonic()
        assert run.wait(timeout=30) == (130 if signum == signal.SIGTERM else -signum)
    finally:
        if run.poll() is None:
            run.kill()
            run.wait()
    time.sleep(max(0.0, signalled + 3 - time.monotonic()))
    before = {p: _cpu_seconds(p) for p in pids}
    time.sleep(max(0.0, signalled + 5 - time.monotonic()))
    busy = {p: _cpu_seconds(p) - before[p] for p in pids}
    assert all(b < 0.5 for b in busy.values()), busy
    assert len(list(tmp_path.glob("started-*"))) == 2  # nothing queued ran
    with cluster.client() as client:
        assert not any(client.processing().values())
    assert ResultStore(tmp_path / "s.sqlite").count() == 0


# --------------------------------------------------------------------------- paths


def test_a_relative_out_is_made_absolute_before_the_workers_see_it(cluster, tmp_path,
                                                                   monkeypatch, capsys):
    """--out given relative to this process's folder: the workers (whose working folder is
    the cluster's) write the rung cache into it, never into their own working folder."""
    here = tmp_path / "here"
    here.mkdir()
    monkeypatch.chdir(here)
    status = cli.main(["validate", "--manifest", str(_manifest(tmp_path, 1)), *TINY,
                       "--scheduler", cluster.address, "--out", "out"])
    assert status == 0, capsys.readouterr().err
    assert (here / "out" / "ladders" / "ladders.sqlite").is_file()
    assert not (cluster.home / "out").exists()
    assert _stored(here / "out" / "results.sqlite") == 1


def test_a_worker_without_the_output_folder_returns_its_result(tmp_path):
    """A worker that does not see the output folder (no shared file system) runs the
    record without the rung cache and creates nothing; its result (returned to the client,
    which stores it) is the same as with the cache."""
    from validation.run import record_task

    kwargs = {"bearing": dataclasses.asdict(rigid.DFPBearing(pressure=10e6)), "name": "p",
              "dt": 0.01, "acceleration": _pulse(0.2), "criteria": [4], "step": 0.01 * G,
              "stop": 0.3 * G, "search": "fast"}
    elsewhere = tmp_path / "client-only" / "out" / "ladders"
    without = record_task(**kwargs, cache=str(elsewhere))
    assert not (tmp_path / "client-only").exists()
    (tmp_path / "out").mkdir()
    with_cache = record_task(**kwargs, cache=str(tmp_path / "out" / "ladders"))
    assert (tmp_path / "out" / "ladders" / "ladders.sqlite").is_file()

    for result in (without, with_cache):  # the CPU seconds spent differ between two runs
        del result["actual"]["cpu_seconds"]
    assert without == with_cache


# --------------------------------------------------------------------------- a worker killed


def _fe_task():
    """One FE run (coarse mesh, 60 MPa, a 1 s half sine at 1.5 m/s² plus 1 s free): about
    2 s of CPU here, longer in a fresh worker."""
    from validation.fem_runs import fem_run

    t = np.arange(0.0, 2.005, 0.01)
    a = np.where(t < 1.0, 3.0 * np.sin(np.pi * t), 0.0)
    kwargs = {"bearing": dataclasses.asdict(rigid.DFPBearing(pressure=60e6)),
              "acceleration": a, "dt": 0.01, "scale": 0.5, "free": 1.0, "max_step": 0.01,
              "impact_step": 5e-4}
    return Task("fe", "fem-run", fem_run, kwargs)


def test_a_worker_killed_during_an_fe_run_is_retried_with_the_same_answer(cluster, tmp_path,
                                                                         monkeypatch):
    """kill -9 of the worker process running an FE run, half a second into it (the run and
    the worker's first import of the FE model take seconds): Dask runs it again on a worker
    and the answer equals an uninterrupted run in this process (bit for bit but for the
    seconds it took)."""
    monkeypatch.setenv("DFP_CACHE_DIR", cluster.env["DFP_CACHE_DIR"])  # the same meshes
    task = _fe_task()
    reference = run_tasks([task], None, workers=1, progress=False)["fe"]
    found, errors = {}, []

    def run():
        try:
            found.update(run_tasks([task], ResultStore(tmp_path / "s.sqlite"),
                                   scheduler=cluster.address, progress=False))
        except BaseException as exc:  # reported below
            errors.append(exc)

    thread = threading.Thread(target=run)
    with cluster.client() as client:
        pids = client.run(os.getpid)
        thread.start()
        deadline, victim = time.monotonic() + START, None
        while victim is None and time.monotonic() < deadline:
            victim = next((w for w, keys in client.processing().items() if keys), None)
            time.sleep(0.05)
        assert victim is not None, "the FE run never started"
        time.sleep(0.5)
        assert client.processing()[victim], "the FE run ended before the worker was killed"
        os.kill(pids[victim], signal.SIGKILL)
        thread.join(timeout=4 * START)
        assert not thread.is_alive() and not errors, errors
        client.wait_for_workers(2, timeout=START)  # the nanny restarts the killed worker
    with pytest.raises(ProcessLookupError):
        os.kill(pids[victim], 0)
    timing = ("cpu_seconds", "wall_seconds")
    assert {k: v for k, v in found["fe"].items() if k not in timing} == \
        {k: v for k, v in reference.items() if k not in timing}
    assert ResultStore(tmp_path / "s.sqlite").count() == 1
