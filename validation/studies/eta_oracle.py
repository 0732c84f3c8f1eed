"""How close can any time-left estimate come? The run progress's estimate (rigid/tasks/progress.py)
against an oracle that knows the true distributions of the run times and of the FE searches'
lengths (but not the draws of the run being watched), on runs played on a fake clock.

A validation run is modelled as in tests/test_progress.py: each record's rigid ladder (20-40 s,
uniform) brings its FE searches, each a chain of 2, 3 or 4 FE runs (equally likely; median
120 s, lognormal σ 0.3), on two workers, follow-ups ahead of the queue. At every run's end
from 20 % to 80 % of the run, the oracle's estimate is the mean, over 300 simulated
completions, of the time left: the unrun tasks' times and the open searches' lengths drawn
from their true distributions (a search at its d-th run is longer than d), a running task's
time drawn above what it has already run. A miss is an estimate more than 50 % from the time
actually left (#32's bound). Writes ``docs/results/eta_oracle.csv``: per run shape (records ×
searches per record), the seeds on which each estimate missed at least once, and the range of
estimate/truth.

    python -m validation.studies.eta_oracle
"""

from __future__ import annotations

import argparse
import itertools
from collections import deque

import numpy as np

from rigid.tasks.progress import Progress
from rigid.tasks.runner import Task

from . import RESULTS

LENGTHS = (2, 3, 4)
SIGMA, MEDIAN_FE = 0.3, 120.0
LADDER = (20.0, 40.0)
BOUND = 0.5
_ids = itertools.count()


def _noop():
    return None


def _fe_time(rng, above: float = 0.0) -> float:
    """An FE run's time [s], drawn above ``above`` (a running task's elapsed time)."""
    while True:
        t = float(MEDIAN_FE * rng.lognormal(0, SIGMA))
        if t > above:
            return t


def _run(rng, records: int, searches: int) -> list[Task]:
    """The run's first tasks, every draw made: a ladder per record with its chains."""
    tasks = []
    for _ in range(records):
        chains = []
        for _ in range(searches):
            length, chain = int(rng.choice(LENGTHS)), None
            for depth in reversed(range(length)):
                chain = Task(f"f{next(_ids)}", "fem", _noop, {
                    "seconds": _fe_time(rng), "children": [chain] if chain else [],
                    "depth": depth})
            chains.append(chain)
        tasks.append(Task(f"l{next(_ids)}", "ladder", _noop, {
            "seconds": float(rng.uniform(*LADDER)), "children": chains}))
    return tasks


def _oracle(rng, now, queue, running, searches: int, samples: int = 300) -> float:
    """Mean time left over ``samples`` completions drawn from the true distributions."""
    total = 0.0
    for _ in range(samples):
        def fem(depth, elapsed=None):  # an open search's rest: (kind, time, depth, length)
            length = int(rng.choice([n for n in LENGTHS if n > depth]))
            return ("fem", _fe_time(rng, elapsed or 0.0) - (elapsed or 0.0), depth, length)

        busy = []
        for task, started in running:
            elapsed = now - started
            if task.kind == "fem":
                busy.append(fem(task.kwargs["depth"], elapsed))
            else:
                lo = max(LADDER[0], elapsed)
                busy.append(("ladder", float(rng.uniform(lo, max(lo, LADDER[1]))) - elapsed,
                             0, 0))
        todo = deque(fem(t.kwargs["depth"]) if t.kind == "fem" else
                     ("ladder", float(rng.uniform(*LADDER)), 0, 0) for t in queue)
        clock, ends = 0.0, [(b[1], b) for b in busy]
        while todo or ends:
            while todo and len(ends) < 2:
                item = todo.popleft()
                ends.append((clock + item[1], item))
            ends.sort(key=lambda e: e[0])
            clock, (kind, _, depth, length) = ends.pop(0)
            if kind == "ladder":
                todo.extendleft(reversed([fem(0) for _ in range(searches)]))
            elif depth + 1 < length:
                todo.appendleft(("fem", _fe_time(rng), depth + 1, length))
        total += clock
    return total / samples


def play(records: int, searches: int, seed: int) -> dict:
    """One run on a fake clock: the ratio estimate/truth of :class:`Progress` and of the oracle
    at every run's end from 20 % to 80 % of the run."""
    rng = np.random.default_rng(seed)
    tasks = _run(rng, records, searches)
    clock = [0.0]
    tally = Progress(2, clock=lambda: clock[0])
    queue, running, states = deque(tasks), [], []
    while queue or running:
        while queue and len(running) < 2:
            t = queue.popleft()
            running.append((clock[0] + t.kwargs["seconds"], clock[0], t))
        running.sort(key=lambda r: r[0])
        end, start, t = running.pop(0)
        clock[0] = end
        tally.spawned(t.kind, t.kwargs["children"], key=t.key)
        queue.extendleft(reversed(t.kwargs["children"]))
        now_running = [(r[2], r[1]) for r in running]
        tally.record(t.kind, end - start, now_running, queue)
        states.append((end, tally.left, list(queue), now_running))
    total = clock[0]
    oracle_rng = np.random.default_rng(seed + 10_000)
    ours, best = [], []
    for now, left, q, r in states:
        if 0.2 * total <= now <= 0.8 * total:
            truth = total - now
            ours.append(left / truth)
            best.append(_oracle(oracle_rng, now, q, r, searches) / truth)
    return {"ours": ours, "oracle": best}


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=20)
    args = parser.parse_args(argv)
    rows = []
    for records, searches in ((2, 2), (4, 1), (4, 2), (8, 1), (20, 2), (28, 1)):
        runs = [play(records, searches, seed) for seed in range(args.seeds)]
        row = {"records": records, "searches_per_record": searches, "runs": args.seeds}
        for name in ("ours", "oracle"):
            ratios = [x for r in runs for x in r[name]]
            row[f"{name}_missed_runs"] = sum(any(abs(x - 1) > BOUND for x in r[name])
                                             for r in runs)
            row[f"{name}_min_ratio"] = round(min(ratios), 3)
            row[f"{name}_max_ratio"] = round(max(ratios), 3)
        rows.append(row)
        print(row, flush=True)
    path = RESULTS / "eta_oracle.csv"
    with open(path, "w") as fh:
        fh.write(",".join(rows[0]) + "\n")
        fh.writelines(",".join(str(v) for v in row.values()) + "\n" for row in rows)
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
