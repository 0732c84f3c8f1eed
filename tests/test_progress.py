"""Progress anywhere (rigid/tasks/progress.py): the time left, estimated from measured run
times, within 50 % of the truth once 20 % of the run is done (runs of tasks played on a fake
clock); a plain line at a fixed interval when standard error is not a terminal; the log's
first line before the first run ends."""

import io
import itertools
import time
from collections import deque

import numpy as np
import pytest

from rigid.tasks import progress as P
from rigid.tasks import run_tasks
from rigid.tasks.runner import Task

_ids = itertools.count()


def _noop():
    return None


def _task(kind, seconds, children=(), leads=True):
    """A task that, played by :func:`_play`, runs ``seconds`` and then brings ``children``."""
    return Task(f"t{next(_ids)}", kind, _noop, {"seconds": seconds, "children": list(children)},
                leads=leads)


class _Clock:
    now = 0.0

    def __call__(self):
        return self.now


def _play(tasks, workers):
    """Play a run as :func:`rigid.tasks.run_tasks` drives it (follow-ups ahead of the queue,
    a task to each free worker), on a fake clock; return the run's length and, at each task's
    end, (time, estimate of the time left)."""
    clock = _Clock()
    tally = P.Progress(workers, clock=clock)
    queue, running, seen = deque(tasks), [], []
    while queue or running:
        while queue and len(running) < workers:
            t = queue.popleft()
            running.append((clock.now + t.kwargs["seconds"], clock.now, t))
        running.sort(key=lambda r: r[0])
        end, start, t = running.pop(0)
        clock.now = end
        tally.spawned(t.kind, t.kwargs["children"], leads=t.leads, key=t.key)
        queue.extendleft(reversed(t.kwargs["children"]))
        tally.record(t.kind, end - start, [(r[2], r[1]) for r in running], queue)
        seen.append((clock.now, tally.left))
    return clock.now, seen


def _independent(rng):
    """40 tasks of one kind, lognormal run times (median 30 s, σ 0.5: a rigid ladder's time
    varies with its record's length), two workers."""
    return [_task("ladder", float(30 * rng.lognormal(0, 0.5))) for _ in range(40)]


def _searches(rng, records=20, searches=2):
    """A validation run: each record's ladder (20-40 s) brings its FE searches, each a chain
    of 2-4 FE runs (median 120 s, σ 0.3), each run bringing the next until the search ends."""
    tasks = []
    for _ in range(records):
        chains = []
        for _ in range(searches):
            chain = None
            for _ in range(int(rng.integers(2, 5))):
                chain = _task("fem", float(120 * rng.lognormal(0, 0.3)), [chain] if chain else [])
            chains.append(chain)
        tasks.append(_task("ladder", float(rng.uniform(20, 40)), chains))
    return tasks


@pytest.mark.parametrize("make", [_independent, _searches])
@pytest.mark.parametrize("seed", range(10))
def test_time_left_within_half_of_the_truth(make, seed):
    """From 20 % of the run done, the estimate is within 50 % of the time actually left (the
    issue's bound). Checked until 20 % is left: the last runs' own spread (a lognormal σ 0.5
    run lasts 0.45-2.2 times its median) is beyond what any rate foresees. The estimate
    before this version missed the bound on 1 of 20 independent runs and, on searches with
    few chains (4 searches of 2-4 runs), overstated the time left up to 5-fold (the fixed
    continuation rate of a chain); now at most 2.2-fold there, which this test does not
    assert (measured, #32's closing note)."""
    total, seen = _play(make(np.random.default_rng(seed)), workers=2)
    checked = [(now, left) for now, left in seen if 0.2 * total <= now <= 0.8 * total]
    assert len(checked) >= 5  # the bound is not checked vacuously
    for now, left in checked:
        truth = total - now
        assert abs(left - truth) <= 0.5 * truth, (now / total, left, truth)


def test_a_running_task_counts_what_is_left_of_it():
    """Two workers, one 60 s kind: a run started 50 s ago has 10 s left, one just started
    60 s; nothing queued: the longest, 60 s, is left (the work over the workers, 35 s, is
    less than one run)."""
    clock = _Clock()
    tally = P.Progress(2, clock=clock)
    tally.spawned("fem", [], key="a")
    tally.record("fem", 60.0, [], [])
    clock.now = 100.0
    old, new = _task("fem", 0), _task("fem", 0)
    assert tally.estimate([(old, 50.0), (new, 100.0)], []) == pytest.approx(60.0)
    # with 4 queued: (10 + 60 + 4 × 60) / 2 workers
    queue = [_task("fem", 0) for _ in range(4)]
    assert tally.estimate([(old, 50.0), (new, 100.0)], queue) == pytest.approx(155.0)


def test_a_chains_rest_comes_from_the_chains_that_ended():
    """Chains of 2 and 4 runs ended: a chain's run at depth 1 expects (0 + 2) / 2 = 1 more,
    at depth 2 (only the 4-run chain got there) 1 more, at depth 3 none; a new chain
    E[L] − 1 = 2 more. Past every chain seen (depth 5), as many again as done (5)."""
    tally = P.Progress(1)
    for length in (2, 4):
        keys = [f"c{length}-{i}" for i in range(length)]
        for i, key in enumerate(keys):
            nxt = [Task(keys[i + 1], "fem", _noop)] if i + 1 < length else []
            tally.spawned("fem", nxt, key=key)
    assert [tally._chain_rest("fem", d) for d in (0, 1, 2, 3, 5)] == [2.0, 1.0, 1.0, 0.0, 5.0]


def test_heartbeat_prints_plain_lines_at_its_interval():
    """A status line every interval (here 0.05 s for the test; 25 s in use), whatever the
    tasks do; a status that fails skips a beat, it does not stop the thread."""
    out = io.StringIO()
    calls = itertools.count()

    def status():
        n = next(calls)
        if n == 1:
            raise RuntimeError("deque mutated during iteration")
        return f"line {n}"

    beat = P.Heartbeat(status, interval=0.05, stream=out).start()
    time.sleep(0.5)
    beat.stop()
    lines = out.getvalue().splitlines()
    assert lines[0] == "line 0" and "line 1" not in lines and len(lines) >= 3


def _slow(seconds, log):
    """A task that sleeps and reports whether the log already had its first line."""
    started = log.read_text().splitlines()[0] if log.exists() else ""
    time.sleep(seconds)
    return {"log": started}


def test_piped_run_prints_plain_lines_and_logs_before_the_first_run_ends(tmp_path, capsys,
                                                                        monkeypatch):
    """Standard error is not a terminal under pytest: no bar, plain lines at the heartbeat's
    interval (0.1 s here), the same lines in the log; the log's first line is there while the
    first run is still running."""
    monkeypatch.setattr(P, "HEARTBEAT", 0.1)
    log = tmp_path / "progress.log"
    tasks = [Task(f"s{i}", "slow", _slow, {"seconds": 0.4, "log": log}) for i in range(2)]
    results = run_tasks(tasks, None, workers=1, log=log)
    assert "started, 2 queued on 1 worker(s)" in results["s0"]["log"]
    err = capsys.readouterr().err.splitlines()
    assert "started, 2 queued on 1 worker(s); a progress line every 0.1 s" in err[0]
    beats = [line for line in err if " running, " in line and "so far" in line]
    assert len(beats) >= 4, err  # 0.8 s of runs at 0.1 s: about 7
    assert not any("\r" in line for line in err)  # no bar
    logged = log.read_text().splitlines()
    assert len(logged) >= 1 + 2 + 4  # started, a line per run, the beats


def test_a_resumed_run_starts_from_its_stored_run_times():
    """A resumed run whose store timed its ten earlier runs (100 s each) estimates before its
    own first run ends: 4 queued runs that bring nothing, on two workers, 4 × 100 / 2 s. Its
    first run, 20 s (the shortest end first), weighs as the newest of eleven (half-life 50
    runs), not as the only one."""
    tally = P.Progress(2, clock=_Clock())
    queue = [_task("fem", 0, leads=False) for _ in range(4)]
    assert tally.estimate([], queue) is None  # nothing timed yet
    for _ in range(10):
        tally.stored("fem", 100.0)
    tally.stored("fem", None)  # a result the store did not time: no weight
    assert tally.estimate([], queue) == pytest.approx(200.0)
    tally.record("fem", 20.0, [], queue)
    w = tally.decay ** np.arange(10, -1, -1.0)
    assert tally._mean("fem") == pytest.approx((100 * w[:-1].sum() + 20) / w.sum())
    assert 90 < tally._mean("fem") < 95
