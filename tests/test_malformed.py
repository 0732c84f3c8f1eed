"""Malformed inputs reach the user as one line naming what was wrong, with the documented exit
status, and never as a traceback or a hang (issue #16).

The corpus (tests/malformed.py, built in tmp_path) holds record files of every format with
broken headers, values and encodings, files that are not text or not files, broken manifests
and implausible arguments; each case states the message it expects. Most cases run in-process
through ``validation.cli.main`` (fast); a handful run as the installed command would, in a
subprocess, to check the real exit status and that no traceback reaches standard error.
"""

import re
import subprocess
import sys

import pytest
from malformed import build_corpus

from validation import cli

#: Every case must fail within this time [s]: the errors come before anything is computed, so
#: even a slow machine takes well under a second; a hang (a FIFO opened, a 1000 s DT run)
#: would take minutes.
TIMEOUT = 120


@pytest.fixture(scope="module")
def corpus(tmp_path_factory):
    return build_corpus(tmp_path_factory.mktemp("malformed"))


def test_the_corpus_is_large_and_ids_are_unique(corpus):
    assert len(corpus) >= 60
    assert len({c.id for c in corpus}) == len(corpus)


def _check(case, status, stderr):
    lines = stderr.strip().splitlines()
    assert len(lines) == 1, f"{case.id}: expected one line, got:\n{stderr}"
    line = lines[0]
    assert "Traceback" not in stderr
    assert status == case.status, f"{case.id}: status {status}, {line}"
    assert re.search(case.stderr, line), f"{case.id}: {line!r} !~ {case.stderr!r}"
    # never more than ~80 characters of a file's content, so a line stays readable
    assert len(line) <= cli.MAX_MESSAGE + 40, f"{case.id}: {len(line)} characters"


def test_every_case_in_process(corpus, capsys):
    """Run each case through cli.main; collect every mismatch so one run shows them all."""
    failures = []
    for case in corpus:
        capsys.readouterr()
        status = cli.main(list(case.argv))
        err = capsys.readouterr().err
        try:
            _check(case, status, err)
        except AssertionError as exc:
            failures.append(str(exc))
    assert not failures, "\n".join(failures)


SUBPROCESS_CASES = ("binary", "fifo", "knet-zero-denominator", "peer-1e308", "pressure-tiny",
                    "scale-huge", "manifest-misspelt", "peer-binary-body")


@pytest.mark.parametrize("case_id", SUBPROCESS_CASES)
def test_cases_as_a_command(corpus, case_id):
    """The real command: exit status, one line, no traceback, no hang."""
    (case,) = [c for c in corpus if c.id == case_id]
    result = subprocess.run([sys.executable, "-m", "validation.cli", *case.argv],
                            capture_output=True, text=True, timeout=TIMEOUT)
    _check(case, result.returncode, result.stderr)


def test_an_unexpected_exception_is_reported_as_a_bug(monkeypatch, capsys, tmp_path):
    """A bug (here a ZeroDivisionError planted in the simulate command) gives one line asking
    for a report and exit status 3; --debug adds the traceback."""
    def broken(args):
        return 1 / 0

    monkeypatch.setattr(cli, "simulate", broken)
    assert cli.main(["simulate", "--out", str(tmp_path)]) == cli.EXIT_BUG
    err = capsys.readouterr().err.strip()
    assert err == ("dfp simulate: internal error (please report, with the output of --debug): "
                   "ZeroDivisionError: division by zero")
    assert cli.main(["simulate", "--debug", "--out", str(tmp_path)]) == cli.EXIT_BUG
    err = capsys.readouterr().err
    assert err.startswith("Traceback") and "ZeroDivisionError" in err
    assert err.strip().splitlines()[-1].startswith("dfp simulate: internal error")


def test_numerical_instability_is_no_answer(monkeypatch, capsys, tmp_path):
    """A run that blows up numerically is reported as no answer (exit 1), never as a
    failure of the bearing."""
    import rigid

    def unstable(*args, **kwargs):
        raise rigid.NumericalInstabilityError("the state became non-finite at t = 0.1 s")

    monkeypatch.setattr(rigid, "simulate", unstable)
    assert cli.main(["simulate", "--out", str(tmp_path)]) == cli.EXIT_FAILED
    out, err = capsys.readouterr()
    assert "FAILED" not in out
    assert re.fullmatch(r"dfp simulate: no answer: numerical instability, not a physical "
                        r"failure: the state became non-finite at t = 0\.1 s \(.*\)\n", err)
