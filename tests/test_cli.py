"""The dfp command: one-line errors with a non-zero exit for bad input, and a small
end-to-end validation run on a user manifest that writes the report and its data."""

import csv
import os
import subprocess
import sys

import numpy as np
import pytest

from rigid import G, ricker_record


def dfp(*args, cwd=None):
    return subprocess.run([sys.executable, "-m", "validation.cli", *args], capture_output=True,
                          text=True, cwd=cwd, timeout=600)


def _pulse_manifest(tmp_path, scale="1.0"):
    _, a = ricker_record(0.2 * G, 2.5, "antisymmetric", dt=0.01, free=8.0)
    np.savetxt(tmp_path / "pulse.txt", a / G)
    manifest = tmp_path / "records.csv"
    manifest.write_text(f"path,name,scale,dt,units\npulse.txt,pulse,{scale},0.01,g\n")
    return manifest


def _one_line_error(result, *words):
    assert result.returncode != 0
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1, result.stderr  # no traceback
    for w in words:
        assert w in lines[0], lines[0]


def test_missing_manifest(tmp_path):
    _one_line_error(dfp("validate", "--manifest", str(tmp_path / "none.csv"), "--out",
                        str(tmp_path / "o")), "none.csv")


def test_malformed_record(tmp_path):
    (tmp_path / "bad.txt").write_text("0.1\n0.2\nnot-a-number\n")
    manifest = tmp_path / "m.csv"
    manifest.write_text("path,dt,units\nbad.txt,0.01,g\n")
    _one_line_error(dfp("validate", "--manifest", str(manifest), "--out", str(tmp_path / "o")),
                    "bad.txt", "line 3")


def test_unknown_set(tmp_path):
    _one_line_error(dfp("validate", "--set", "japan", "--out", str(tmp_path / "o")), "japan")


def test_negative_scale(tmp_path):
    manifest = _pulse_manifest(tmp_path, scale="-2")
    _one_line_error(dfp("validate", "--manifest", str(manifest), "--out", str(tmp_path / "o")),
                    "scale")


@pytest.mark.skipif(os.geteuid() == 0, reason="root can write anywhere")
def test_unwritable_output(tmp_path):
    locked = tmp_path / "locked"
    locked.mkdir(mode=0o500)
    _one_line_error(dfp("validate", "--manifest", str(_pulse_manifest(tmp_path)), "--out",
                        str(locked / "o")), "cannot write")


def test_output_is_a_file(tmp_path):
    (tmp_path / "file").write_text("")
    _one_line_error(dfp("validate", "--manifest", str(_pulse_manifest(tmp_path)), "--out",
                        str(tmp_path / "file")), "cannot write")


def test_fem_pressure_not_in_the_run(tmp_path):
    _one_line_error(dfp("validate", "--manifest", str(_pulse_manifest(tmp_path)), "--pressure",
                        "10", "--fem-pressure", "60", "--out", str(tmp_path / "o")),
                    "--fem-pressure 60")


def test_slider_edges_the_slider_cannot_have(tmp_path):
    """An edge radius beyond half the height of the slider's flat sides (92 mm for the
    baseline) is refused before anything runs, in one line naming the option."""
    out = tmp_path / "o"
    _one_line_error(dfp("validate", "--manifest", str(_pulse_manifest(tmp_path)),
                        "--fem-edge-radius", "95", "--out", str(out)),
                    "--fem-edge-radius 95", "edge_radius")
    assert not (out / "results.sqlite").exists()


def test_a_law_through_tearing_needs_the_plane_strain_push(tmp_path):
    """--rim-fracture with --rim-model ring is refused before anything runs, in one line
    naming the option (the law through tearing comes from the plane-strain push)."""
    out = tmp_path / "o"
    _one_line_error(dfp("validate", "--manifest", str(_pulse_manifest(tmp_path)),
                        "--rim-fracture", "median", "--rim-model", "ring", "--no-fem",
                        "--out", str(out)),
                    "--rim-fracture", "plane-strain")
    assert not (out / "results.sqlite").exists()


def test_keeping_the_stored_laws_needs_a_carrying_over(tmp_path):
    """--keep-stored-laws without --rekey-from is refused before anything runs, in one
    line naming both options."""
    out = tmp_path / "o"
    _one_line_error(dfp("validate", "--manifest", str(_pulse_manifest(tmp_path)),
                        "--keep-stored-laws", "--no-fem", "--out", str(out)),
                    "--keep-stored-laws", "--rekey-from")
    assert not (out / "results.sqlite").exists()


def test_bad_number_from_argparse(tmp_path):
    result = dfp("demo", "--period", "-1")
    assert result.returncode == 2 and "must be between 0.05 and 20 s" in result.stderr
    assert len(result.stderr.strip().splitlines()) == 1  # no usage block


def test_validation_run_on_a_manifest(tmp_path):
    """A Ricker pulse record: the report, CSVs and report.nc are written, and the prediction
    of criterion 4 lands within one 0.01 g rung of the actual critical SA (the method is exact
    for a record that is its own pulse; tests/test_predict.py checks this in depth). No FE
    runs here (minutes each; tests/test_fem_search.py tests their search)."""
    from validation.report.netcdf import read_table

    out = tmp_path / "run"
    result = dfp("validate", "--manifest", str(_pulse_manifest(tmp_path)), "--pressure", "10",
                 "--criteria", "4", "--stop", "1.2", "--workers", "1", "--no-progress",
                 "--no-fem", "--out", str(out))
    assert result.returncode == 0, result.stderr
    assert (out / "report.html").stat().st_size > 10_000  # with embedded figures
    with open(out / "comparison_10MPa.csv") as fh:
        (row,) = list(csv.DictReader(fh))
    actual, predicted = float(row["actual_sa_g"]), float(row["predicted_sa_g_4"])
    assert actual > 0 and abs(predicted - actual) <= 0.01 + 1e-9
    (nc,) = read_table(out / "report.nc", "comparison_10MPa")  # CSV has 6 digits
    assert nc["actual_sa_g"] == pytest.approx(actual, rel=1e-5)
    assert nc["predicted_sa_g_4"] == pytest.approx(predicted, rel=1e-5)
    again = dfp("validate", "--manifest", str(_pulse_manifest(tmp_path)), "--pressure", "10",
                "--criteria", "4", "--stop", "1.2", "--workers", "1", "--no-progress",
                "--no-fem", "--out", str(out))
    assert again.returncode == 0 and again.stdout.splitlines()[1:] == result.stdout.splitlines()[1:]


def test_validation_run_of_a_bearing_variant(tmp_path):
    """--bearing FILE and --rim-thickness reach the bearing of every task: the file's pressure
    is the run's, and the report's bearing table and settings show the file's friction and the
    option's 80 mm rims (the option wins over the file's 50 mm), each beside the baseline. An
    impossible variant is a one-line error (a 150 mm rim leaves no clearance between the
    plates' rims)."""
    from validation.report.netcdf import read_table

    out = tmp_path / "run"
    (tmp_path / "b.toml").write_text("pressure = 10\nfriction = 0.06\nrim_thickness = 0.05\n")
    result = dfp("validate", "--manifest", str(_pulse_manifest(tmp_path)), "--bearing",
                 str(tmp_path / "b.toml"), "--criteria", "4", "--stop", "1.2", "--workers",
                 "1", "--no-progress", "--no-fem", "--rims", "rigid", "--rim-thickness", "80",
                 "--out", str(out))
    assert result.returncode == 0, result.stderr
    rows = {r["parameter"]: r for r in read_table(out / "report.nc", "bearing_10MPa")}
    row = rows["rim thickness"]
    assert float(row["value"]) * {"m": 1e3, "mm": 1.0}[row["unit"]] == pytest.approx(80.0)
    assert float(rows["friction"]["value"]) == 0.06 and float(rows["friction"]["baseline"]) == 0.05
    settings = {r["setting"]: r["value"] for r in read_table(out / "report.nc", "settings")}
    assert settings["bearing variant"] == "friction 0.06, rim thickness 80 mm"
    assert settings["pressures"] == "10"
    _one_line_error(dfp("validate", "--rim-height", "150", "--no-fem", "--out", str(out)),
                    "no clearance")


def test_simulate_pulses_and_critical_sa_on_a_record(tmp_path):
    """The single-record subcommands run on a plain-text record and write their plots."""
    _pulse_manifest(tmp_path)
    record = ["--record", str(tmp_path / "pulse.txt"), "--dt", "0.01", "--units", "g"]
    sim = dfp("simulate", *record, "--scale", "2", "--out", str(tmp_path / "s"))
    assert sim.returncode == 0, sim.stderr
    assert "rim impact" in sim.stdout and (tmp_path / "s" / "response.png").exists()
    pulses = dfp("pulses", *record, "--out", str(tmp_path / "p"))
    assert pulses.returncode == 0, pulses.stderr
    assert pulses.stdout.count("antisymmetric") == 4  # every criterion finds the pulse itself
    (tmp_path / "b.toml").write_text("pressure = 30\nrim_height = 0.03\n")
    crit = dfp("critical-sa", *record, "--search", "fast", "--after-failure", "0", "--bearing",
               str(tmp_path / "b.toml"), "--stop", "1.2")
    assert crit.returncode == 0 and "critical SA" in crit.stdout and "predicted SA" in crit.stdout
    # what was run is said first: the file's pressure and rims, the ladder's top
    bearing_line, ladder_line = crit.stdout.splitlines()[:2]
    assert "30 MPa" in bearing_line and "rims 40 × 30 mm" in bearing_line, bearing_line
    assert "rigid, failure = containment" in bearing_line, bearing_line
    assert "up to 1.2 g (not the default 1.5 g)" in ladder_line, ladder_line


def test_simulate_with_yielding_rims(tmp_path):
    """--rims yielding: the heavy bearing under a pulse that its rigid rims survive fails by
    the first hinge (the default limit state of yielding rims); a limit state that rigid rims
    cannot reach is a one-line error."""
    pulse = ["--pressure", "60", "--amplitude", "0.8", "--period", "2"]
    rigid_rims = dfp("simulate", *pulse, "--out", str(tmp_path / "r"))
    assert rigid_rims.returncode == 0 and "no failure" in rigid_rims.stdout
    yielding = dfp("simulate", *pulse, "--rims", "yielding", "--out", str(tmp_path / "y"))
    assert yielding.returncode == 0, yielding.stderr
    assert "FAILED by yielding" in yielding.stdout and "hinge" in yielding.stdout
    _one_line_error(dfp("simulate", *pulse, "--limit-state", "hinge", "--out",
                        str(tmp_path / "e")), "--rims yielding")
