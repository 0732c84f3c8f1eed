"""Bounded fuzzing of every reader (PEER AT2, K-NET, JMA CSV, plain text, manifests) with
hypothesis: whatever the bytes, a reader returns a valid GroundMotion or raises its own
RecordFormatError (a ValueError naming the file), never anything else (issue #16).

Oracle: the readers' contract. The inputs are mutations of valid files (a line replaced,
bytes inserted, deleted or flipped, a header value swapped for odd text, numbers made huge,
tiny or negative) and raw bytes; a returned GroundMotion must satisfy the plausibility limits
of docs/limits.md. 200 examples per reader keep the whole file to a few seconds; the database is
off so every run is independent of earlier ones and the set is reproducible (derandomize).
"""

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st

from rigid.limits import MAX_RECORD_ACCELERATION, MAX_RECORD_DURATION, RECORD_DT_RANGE
from rigid.motions import GroundMotion, RecordFormatError, read_manifest
from rigid.motions.formats import read_jma_csv, read_knet, read_peer_at2, read_plain, read_record

EXAMPLES = 200
FUZZ = settings(max_examples=EXAMPLES, deadline=None, database=None, derandomize=True,
                suppress_health_check=[HealthCheck.function_scoped_fixture,
                                       HealthCheck.too_slow])

PEER = ("PEER NGA STRONG MOTION DATABASE RECORD\nTest, 1/1/2000, Station, 090\n"
        "ACCELERATION TIME SERIES IN UNITS OF G\nNPTS=   12, DT=   .0100 SEC\n"
        "  0.01  0.02 -0.03  0.04  0.05\n  0.01  0.02  0.03  0.01  0.02\n  0.1 -0.2\n")
KNET = "".join(f"{k:<18s}{v}\n" for k, v in [
    ("Origin Time", "1995/01/17 05:46:00"), ("Lat.", "34.595"), ("Long.", "135.035"),
    ("Depth. (km)", "16"), ("Mag.", "7.3"), ("Station Code", "HYG007"),
    ("Station Lat.", "34.7"), ("Station Long.", "135.2"), ("Station Height(m)", "10"),
    ("Record Time", "1995/01/17 05:46:15"), ("Sampling Freq(Hz)", "100Hz"),
    ("Duration Time(s)", "0.16"), ("Dir.", "N-S"), ("Scale Factor", "7845(gal)/8223790"),
    ("Max. Acc. (gal)", "818.0"), ("Last Correction", "1995/01/17 05:46:15"), ("Memo.", "")])
KNET += "1 2 3 4 5 6 7 8\n-1 -2 -3 -4 -5 -6 -7 -8\n"
JMA = (" SITE CODE= 7B1\n LAT.= 34.69\n LON.= 135.18\n SAMPLING RATE= 100Hz\n"
       " UNIT  = gal\n INITIAL TIME = 1995 01 17 05 46 00\n NS,EW,UD\n"
       "1.0,2.0,3.0\n4.0,-5.0,6.0\n7.0,8.0,-9.0\n")
PLAIN = "# time acceleration\n0.00 0.1\n0.01 0.2\n0.02 -0.1\n0.03 0.05\n"
ODD = ["", " ", "0", "-1", "1e308", "-1e308", "1e-320", "nan", "inf", "1e999", "0Hz",
       "7845(gal)/0", "7845(gal)/-1", "99999999999", "x" * 200, "\x00", "\ufeff", "é",
       "神戸", ",", ",,,", "1 2 3 4 5 6 7 8 9", "NPTS= 5, DT= 1000", "NS,EW", "=", "1_0"]


@st.composite
def mutated(draw, base: str):
    """A valid file's bytes after a few random edits."""
    data = bytearray(base.encode("utf-8"))
    for _ in range(draw(st.integers(0, 4))):
        op = draw(st.sampled_from(["line", "insert", "delete", "flip", "number"]))
        lines = data.decode("utf-8", "replace").split("\n")
        if op == "line":
            i = draw(st.integers(0, len(lines) - 1))
            lines[i] = draw(st.sampled_from(ODD) | st.text(max_size=40))
            data = bytearray("\n".join(lines).encode("utf-8", "surrogatepass"))
        elif op == "number":
            i = draw(st.integers(0, len(lines) - 1))
            tokens = lines[i].split(" ")
            j = draw(st.integers(0, len(tokens) - 1))
            tokens[j] = draw(st.sampled_from(ODD[:14]) | st.floats().map(repr))
            lines[i] = " ".join(tokens)
            data = bytearray("\n".join(lines).encode("utf-8"))
        elif op == "insert":
            i = draw(st.integers(0, len(data)))
            data[i:i] = draw(st.binary(min_size=1, max_size=8))
        elif op == "delete" and data:
            i = draw(st.integers(0, len(data) - 1))
            del data[i: i + draw(st.integers(1, 20))]
        elif data:
            i = draw(st.integers(0, len(data) - 1))
            data[i] = draw(st.integers(0, 255))
    if draw(st.booleans()) and draw(st.integers(0, 9)) == 0:
        encoding = draw(st.sampled_from(["utf-16", "utf-16-be", "latin-1", "cp932"]))
        try:
            data = bytearray(data.decode("utf-8").encode(encoding))
        except (UnicodeDecodeError, UnicodeEncodeError):
            pass
    return bytes(data)


def _valid(motion):
    assert isinstance(motion, GroundMotion)
    assert RECORD_DT_RANGE[0] <= motion.dt <= RECORD_DT_RANGE[1]
    assert motion.npts >= 2 and motion.duration <= MAX_RECORD_DURATION
    assert np.all(np.isfinite(motion.acceleration))
    assert motion.pga <= MAX_RECORD_ACCELERATION


def _check(reader, path, data):
    path.write_bytes(data)
    try:
        motion = reader(path)
    except RecordFormatError as exc:
        assert str(path) in str(exc)
        assert len(str(exc)) < len(str(path)) + 400  # never echoes a long stretch of the file
        event(f"error: {exc.message.split(':')[0][:30]}")
        return
    event("valid record")
    _valid(motion)


READERS = {
    "peer": (read_peer_at2, PEER),
    "knet": (read_knet, KNET),
    "jma": (read_jma_csv, JMA),
    "plain": (lambda p: read_plain(p, units="g"), PLAIN),
    "any": (lambda p: read_record(p, dt=0.01, units="g"), PEER),
}


@pytest.mark.parametrize("name", sorted(READERS))
def test_reader_fuzz(name, tmp_path):
    reader, base = READERS[name]
    _valid(reader(_write(tmp_path / "valid", base)))  # the base file itself is valid

    @FUZZ
    @given(data=mutated(base) | st.binary(max_size=200))
    def run(data):
        _check(reader, tmp_path / "record", data)

    run()


def _write(path, text):
    path.write_text(text)
    return path


MANIFEST_TOML = '[[record]]\npath = "r.txt"\nname = "A"\nscale = 1.5\ndt = 0.01\nunits = "g"\n'
MANIFEST_CSV = "path,name,scale,dt,units\nr.txt,A,1.5,0.01,g\nr.txt,B,2,0.01,g\n"


@pytest.mark.parametrize("suffix, base", [(".toml", MANIFEST_TOML), (".csv", MANIFEST_CSV)])
def test_manifest_fuzz(suffix, base, tmp_path):
    (tmp_path / "r.txt").write_text("0.1\n-0.2\n0.3\n0.05\n")
    assert read_manifest(_write(tmp_path / f"valid{suffix}", base))[0].name == "A"

    @FUZZ
    @given(data=mutated(base) | st.binary(max_size=200))
    def run(data):
        path = tmp_path / f"manifest{suffix}"
        path.write_bytes(data)
        try:
            motions = read_manifest(path)
        except RecordFormatError as exc:
            assert len(str(exc)) < 2 * len(str(path)) + 400
            return
        for m in motions:
            assert isinstance(m, GroundMotion) and math.isfinite(m.metadata["scale"])
            _valid(m)
        assert len({m.name for m in motions}) == len(motions)

    run()
