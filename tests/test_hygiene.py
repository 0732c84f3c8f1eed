"""Small things a user meets first: the default output folders are git-ignored; the folder
lock is removed on every way out (done, error, SIGTERM, Ctrl-C) and a lock left by a killed
run is taken over with a warning; a mistyped subcommand, choice or option gets the nearest
one; result objects print as their key numbers and shapes, not their arrays."""

import os
import signal
import subprocess
import sys
import warnings
from pathlib import Path

import pytest

from rigid.tasks import FolderLock
from validation import cli

ROOT = Path(__file__).resolve().parents[1]


def _git_ignored(path: str) -> bool:
    done = subprocess.run(["git", "check-ignore", "-q", path], cwd=ROOT)
    if done.returncode == 128:
        pytest.skip("not a git checkout")
    return done.returncode == 0


def test_default_output_folders_are_ignored():
    """The defaults of every --out, read from the parser (not restated here)."""
    parser = cli.build_parser()
    defaults = {a.default for p in parser.commands.values() for a in p._actions
                if "--out" in a.option_strings}
    assert defaults >= {"dfp-validation", "dfp-simulate", "dfp-pulses"}
    for folder in defaults:
        assert _git_ignored(f"{folder}/report.html"), folder
        assert _git_ignored(f"some/where/{folder}/report.html"), folder
    assert not _git_ignored("rigid/model.py")  # the check can say no


def _dead_pid() -> int:
    child = subprocess.Popen([sys.executable, "-c", "pass"])
    child.wait()
    return child.pid


def test_lock_file_is_removed_on_release_and_a_stale_one_taken_over(tmp_path):
    lock = FolderLock(tmp_path).acquire()
    assert (tmp_path / ".dfp.lock").read_text() == str(os.getpid())
    lock.release()
    assert not (tmp_path / ".dfp.lock").exists()
    lock.release()  # twice is harmless
    pid = _dead_pid()
    (tmp_path / ".dfp.lock").write_text(str(pid))
    with pytest.warns(UserWarning, match=f"stale lock of process {pid} \\(no longer running"):
        lock = FolderLock(tmp_path).acquire()
    assert (tmp_path / ".dfp.lock").read_text() == str(os.getpid())
    lock.release()
    with warnings.catch_warnings():  # a clean folder: no warning
        warnings.simplefilter("error")
        FolderLock(tmp_path).acquire().release()


def test_the_command_removes_its_lock_and_names_a_stale_one(tmp_path, capsys):
    """A normal exit and an error after the lock was taken (a missing record) both leave no
    lock file; a stale lock is one warning line on standard error, then the run goes on."""
    out = tmp_path / "o"
    out.mkdir()
    pid = _dead_pid()
    (out / ".dfp.lock").write_text(str(pid))
    status = cli.main(["simulate", "--amplitude", "0.1", "--out", str(out)])
    err = capsys.readouterr().err.strip()
    assert status == 0 and err == (f"dfp simulate: warning: took over the stale lock of "
                                   f"process {pid} (no longer running) on {out}")
    assert not (out / ".dfp.lock").exists()
    status = cli.main(["simulate", "--record", str(tmp_path / "none.txt"), "--out", str(out)])
    assert status == cli.EXIT_USAGE and not (out / ".dfp.lock").exists()


_SLOW_COMMAND = """
import sys, time
from validation import cli, commands

def slow(args):
    commands._locked_output_folder(args)
    print("locked", flush=True)
    time.sleep(60)

cli.simulate = slow
sys.exit(cli.main(["simulate", "--out", sys.argv[1]]))
"""


@pytest.mark.parametrize("signum, status", [(signal.SIGTERM, cli.EXIT_TERMINATED),
                                            (signal.SIGINT, cli.EXIT_INTERRUPTED)])
def test_lock_is_removed_when_terminated_or_interrupted(tmp_path, signum, status):
    out = tmp_path / "o"
    # a shell's background job ignores SIGINT, and Python then installs no Ctrl-C handler:
    # the child gets the default disposition, as a command run at a terminal has
    child = subprocess.Popen([sys.executable, "-c", _SLOW_COMMAND, str(out)],
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                             env={**os.environ, "PYTHONPATH": str(ROOT)},
                             preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    try:
        assert child.stdout.readline().strip() == "locked"
        assert (out / ".dfp.lock").exists()
        child.send_signal(signum)
        assert child.wait(timeout=30) == status
    finally:
        child.kill()
        child.wait()
    assert not (out / ".dfp.lock").exists()


@pytest.mark.parametrize("argv, hint", [
    (["valdate"], "(did you mean validate?)"),
    (["critcal-sa"], "(did you mean critical-sa?)"),
    (["validate", "--presure", "60"], "(did you mean --pressure?)"),
    (["simulate", "--amplitde=0.3"], "(did you mean --amplitude?)"),
    (["validate", "--rims", "rigd"], "(did you mean rigid?)"),
])
def test_did_you_mean(argv, hint, capsys):
    assert cli.main(argv) == cli.EXIT_USAGE
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and hint in err, err


def test_no_suggestion_for_a_word_unlike_any(capsys):
    assert cli.main(["xyzzy"]) == cli.EXIT_USAGE
    assert "did you mean" not in capsys.readouterr().err


def test_results_print_their_key_numbers_not_their_arrays():
    """A rigid run keeps 13 histories of ~1300 samples; its repr names the failure and the
    arrays' shape on one short line (400 characters would hold about 40 numbers: no history
    fits)."""
    import rigid
    from rigid import G

    _, a = rigid.ricker_record(0.8 * G, 3.0, "symmetric", dt=0.005)
    result = rigid.simulate(rigid.DFPBearing(pressure=10e6), a, dt=0.005)
    text = repr(result)
    assert "\n" not in text and len(text) < 1000
    assert "failure_mode='uplift'" in text and f"({result.time.size},)" in text
    assert f"impacts=[{len(result.impacts)} items]" in text
    record = rigid.GroundMotion(name="pulse", dt=0.005, acceleration=a)
    crit = rigid.critical_sa(rigid.DFPBearing(pressure=10e6), record, search="fast", stop=G)
    text = repr(crit)
    assert len(text) < 400 and f"({crit.sa / G:.3g} g)" in text and "items]" in text


def test_the_validation_results_print_short_too():
    """An FE search with its runs (probes: one dict per FE run) prints its answer and the
    number of runs, not the runs."""
    from rigid import G
    from validation.fem_search import FECritical

    probes = [{"sa": 0.3 * G, "history": list(range(1000))}] * 12
    text = repr(FECritical("rec A", 60e6, 0.31 * G, 0.30 * G, 0.29 * G, "yielding", 4.2,
                           probes))
    assert len(text) < 400 and "probes=[12 items]" in text and "(0.3 g)" in text


def test_fe_results_print_short_too():
    """An FE run's result (fem.FEMResult) with histories of 5 000 steps prints on one line of
    fewer than 1 500 characters, each history as its shape."""
    import dataclasses

    import numpy as np

    import fem

    values = {f.name: np.zeros(5000) for f in dataclasses.fields(fem.FEMResult)}
    text = repr(fem.FEMResult(**values))
    assert "\n" not in text and len(text) < 1500 and "(5000,)" in text
    assert "0.0, 0.0" not in text
