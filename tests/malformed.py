"""A corpus of malformed inputs for the ``dfp`` command, built in a temporary folder at test time
(nothing generated is committed): broken record files of every format, files that are not
text or not files, wrong manifests, and implausible arguments.

Each :class:`Case` holds the command line, the exit status it must give and a regular
expression its one line on standard error must match: the message names what was wrong
(file, line, field, value, what was expected). The expected messages are written here from
the readers' and the command's specification, not copied from a run.

``python tests/malformed.py FOLDER`` builds the corpus into FOLDER and prints the cases.
"""

from __future__ import annotations

import codecs
import os
import sys
from dataclasses import dataclass
from pathlib import Path

USAGE, FAILED = 2, 1  # exit statuses of validation.cli


@dataclass(frozen=True)
class Case:
    id: str
    argv: tuple
    status: int
    stderr: str  # a regular expression the one stderr line must match (re.search)


PEER_HEAD = ["PEER NGA STRONG MOTION DATABASE RECORD", "Test, 1/1/2000, Station, 090",
             "ACCELERATION TIME SERIES IN UNITS OF G", "NPTS=    8, DT=   .0100 SEC"]
PEER_BODY = ["  0.01  0.02  0.03  0.04  0.05", "  0.01  0.02  0.03"]


def _peer(*, line3=None, line4=None, body=None, head=None) -> str:
    lines = list(head or PEER_HEAD)
    if line3 is not None:
        lines[2] = line3
    if line4 is not None:
        lines[3] = line4
    return "\n".join(lines + (PEER_BODY if body is None else body)) + "\n"


def _knet(*, fs="100Hz", scale="7845(gal)/8223790", duration="0.16", counts=None,
          drop=None) -> str:
    header = [("Origin Time", "1995/01/17 05:46:00"), ("Lat.", "34.595"), ("Long.", "135.035"),
              ("Depth. (km)", "16"), ("Mag.", "7.3"), ("Station Code", "HYG007"),
              ("Station Lat.", "34.7"), ("Station Long.", "135.2"),
              ("Station Height(m)", "10"), ("Record Time", "1995/01/17 05:46:15"),
              ("Sampling Freq(Hz)", fs), ("Duration Time(s)", duration), ("Dir.", "N-S"),
              ("Scale Factor", scale), ("Max. Acc. (gal)", "818.0"),
              ("Last Correction", "1995/01/17 05:46:15"), ("Memo.", "")]
    lines = [f"{k:<18s}{v}" for k, v in header if k != drop]
    counts = list(range(16)) if counts is None else counts
    lines += [" ".join(str(c) for c in counts[i: i + 8]) for i in range(0, len(counts), 8)]
    return "\n".join(lines) + "\n"


def _jma(*, rate="100Hz", unit="gal", columns=" NS,EW,UD", rows=None, site="7B1") -> str:
    lines = [f" SITE CODE= {site}", " LAT.= 34.69", " LON.= 135.18", f" SAMPLING RATE= {rate}",
             f" UNIT  = {unit}", " INITIAL TIME = 1995 01 17 05 46 00"]
    if columns is not None:
        lines.append(columns)
    lines += ["1.0,2.0,3.0", "4.0,5.0,6.0", "7.0,8.0,9.0"] if rows is None else rows
    return "\n".join(lines) + "\n"


def build_corpus(root) -> list[Case]:
    """Write the corpus's files under ``root`` (an existing, empty folder) and return the
    cases. Record cases run ``dfp pulses`` (the record is read before anything is
    computed), manifest cases ``dfp validate --no-fem``."""
    root = Path(root)
    files, out = root / "files", str(root / "out")
    files.mkdir()
    cases: list[Case] = []

    def write(name, content) -> str:
        path = files / name
        if isinstance(content, bytes):
            path.write_bytes(content)
        else:
            path.write_text(content, encoding="utf-8")
        return str(path)

    def record(id, name, content, stderr, extra=(), status=USAGE):
        path = write(name, content) if content is not None else str(files / name)
        cases.append(Case(id, ("pulses", "--record", path, *extra, "--out", out), status,
                          stderr))

    plain = ("--dt", "0.01", "--units", "g")
    # ---------------------------------------------------------------- not text, not files
    record("empty", "empty.txt", "", r"empty\.txt: the file is empty")
    record("blank", "blank.txt", "  \n\t\n \n", r"blank\.txt: the file is empty")
    record("binary", "random.bin", bytes(range(256)) * 40, r"random\.bin: not a text file")
    record("gzip", "rec.AT2.gz", b"\x1f\x8b\x08\x00" + bytes(300), r"rec\.AT2\.gz: not a text")
    record("spreadsheet", "rec.xlsx", b"PK\x03\x04\x14\x00\x06\x00" + bytes(500),
           r"rec\.xlsx: not a text file")
    record("control-bytes", "ctl.txt", "0.1\n" * 10 + "\x01\x02\x03\x04\x05" * 20,
           r"ctl\.txt: not a text file", plain)
    bad_peer = _peer(body=["  0.01  0.02  0.03  0.04  0.05", "  0.01  abc  0.03"])
    record("utf16-bom", "bom16.AT2", codecs.BOM_UTF16_LE + bad_peer.encode("utf-16-le"),
           r"bom16\.AT2, line 6: expected a number, found 'abc' \(the file was decoded as "
           r"UTF-16, not UTF-8\)")
    record("utf16-be-no-bom", "be16.AT2", bad_peer.encode("utf-16-be"),
           r"be16\.AT2, line 6: expected a number, found 'abc' .*UTF-16-BE")
    record("latin1", "latin.AT2", _peer(head=["PEER NGA", "Caf\xe9 , 1/1/2000, St, 090",
                                              *PEER_HEAD[2:]],
                                        body=["0.01 0.02 x"]).encode("latin-1"),
           r"latin\.AT2, line 5: expected a number, found 'x' \(the file was decoded as "
           r"latin-1, not UTF-8\)")
    record("cp932", "jma.csv", _jma(site="神戸", rows=["1.0,2.0,3.0", "1.0,oops,3.0"])
           .encode("cp932"),
           r"jma\.csv, line 9: expected numbers, found '1\.0,oops,3\.0' \(the file was "
           r"decoded as Shift-JIS \(cp932\)")
    (files / "folder").mkdir()
    record("folder", "folder", None, r"folder: expected a regular record file, found a folder")
    os.mkfifo(files / "pipe")
    record("fifo", "pipe", None, r"pipe: expected a regular record file, found a FIFO")
    cases.append(Case("device", ("pulses", "--record", "/dev/zero", "--out", out), USAGE,
                      r"/dev/zero: expected a regular record file, found a device"))
    record("missing", "nope.AT2", None, r"record file .*nope\.AT2 does not exist")
    # ---------------------------------------------------------------- PEER AT2
    record("peer-short-header", "short.AT2", "\n".join(PEER_HEAD[:3]) + "\n",
           r"short\.AT2, line 3: expected a 4-line PEER header")
    record("peer-not-acceleration", "vel.AT2", _peer(line3="VELOCITY TIME SERIES IN CM/S"),
           r"vel\.AT2, line 3: expected 'ACCELERATION TIME SERIES IN UNITS OF")
    record("peer-units", "furlong.AT2", _peer(line3="ACCELERATION IN UNITS OF FURLONGS"),
           r"furlong\.AT2, line 3: wrong units 'FURLONGS'")
    record("peer-no-npts", "nonpts.AT2", _peer(line4="DT= .01 SEC"),
           r"nonpts\.AT2, line 4: expected 'NPTS= n, DT= dt SEC'")
    record("peer-dt-zero", "dt0.AT2", _peer(line4="NPTS=    8, DT=   0.0 SEC"),
           r"dt0\.AT2, line 4: expected a positive DT, found '0\.0'")
    record("peer-dt-1000", "dt1000.AT2", _peer(line4="NPTS=    8, DT=   1000 SEC"),
           r"dt1000\.AT2, line 4: DT gives a time step of 1000 s; .*between 0\.0001 and 0\.1 s")
    record("peer-dt-1e-9", "dtnano.AT2", _peer(line4="NPTS=    8, DT=   1E-9 SEC"),
           r"dtnano\.AT2, line 4: DT gives a time step of 1e-09 s")
    record("peer-npts-huge", "huge.AT2", _peer(line4="NPTS= 99999999999, DT= .01 SEC"),
           r"huge\.AT2, line 4: NPTS=99999999999: more than 2,000,000 samples")
    record("peer-npts-3", "npts3.AT2", _peer(line4="NPTS=  3000000, DT= .01 SEC"),
           r"npts3\.AT2, line 4: NPTS=3000000: more than 2,000,000 samples")
    record("peer-one-sample", "one.AT2", _peer(line4="NPTS=    1, DT= .01 SEC", body=["0.1"]),
           r"one\.AT2, line 5: expected at least two samples, found 1")
    record("peer-token", "token.AT2", _peer(body=["0.01 0.02 0.03 0.04 0.05", "0.01 1.2.3 0"]),
           r"token\.AT2, line 6: expected a number, found '1\.2\.3'")
    record("peer-nan", "nan.AT2", _peer(body=["0.01 0.02 0.03 0.04 0.05", "0.01 nan 0.03"]),
           r"nan\.AT2, line 6: expected a finite number, found 'nan'")
    record("peer-1e308", "big.AT2", _peer(body=["0.01 1e308 0.03 0.04 0.05", "0.01 0.02 0.3"]),
           r"big\.AT2, line 5: value '1e308' is 1e\+308 g, beyond the 10 g of any recorded")
    record("peer-1e300-cm", "bigcm.AT2",
           _peer(line3="ACCELERATION IN UNITS OF CM/S/S",
                 body=["1 2 3 4 5", "1 -1e300 3"]),
           r"bigcm\.AT2, line 6: value '-1e300' is -1\.02e\+297 g, beyond")
    record("peer-truncated", "trunc.AT2", _peer(line4="NPTS=  100, DT= .01 SEC"),
           r"trunc\.AT2, line 6: truncated data: the header gives NPTS=100 but the file ends "
           r"after 8 values")
    record("peer-extra", "extra.AT2", _peer(body=[*PEER_BODY, "0.5 0.6"]),
           r"extra\.AT2, line 7: NPTS mismatch")
    record("peer-binary-body", "blob.AT2", _peer(body=["x" * 60_000]),
           r"blob\.AT2, line 5: expected a number, found 'x{60}…'$")
    record("peer-long-header", "longhead.AT2", _peer(line3="VELOCITY " + "y" * 10_000),
           r"longhead\.AT2, line 3: expected 'ACCELERATION .*found 'VELOCITY y{51}…'$")
    # ---------------------------------------------------------------- K-NET
    record("knet-zero-denominator", "zero.NS", _knet(scale="7845(gal)/0"),
           r"zero\.NS, line 14: expected a positive, finite scale factor \(gal per count\), "
           r"found '7845\(gal\)/0'")
    record("knet-negative-scale", "neg.NS", _knet(scale="7845(gal)/-8223790"),
           r"neg\.NS, line 14: expected a positive, finite scale factor")
    record("knet-units", "cm.NS", _knet(scale="3920(cm/s)/8223790"),
           r"cm\.NS, line 14: wrong units 'cm/s': expected \(gal\)")
    record("knet-no-scale", "noscale.NS", _knet(drop="Scale Factor"),
           r"noscale\.NS: missing header field 'scale_factor'")
    record("knet-fs-zero", "fs0.NS", _knet(fs="0Hz"),
           r"fs0\.NS, line 11: expected 'Sampling Freq\(Hz\) 100Hz', found '0Hz'")
    record("knet-fs-huge", "fs.NS", _knet(fs="100000Hz"),
           r"fs\.NS, line 11: Sampling Freq\(Hz\) gives a time step of 1e-05 s")
    record("knet-short-line", "shortline.NS",
           _knet().replace("0 1 2 3 4 5 6 7\n", "0 1 2 3 4 5\n"),
           r"shortline\.NS, line 18: expected 8 values on every data line but the last, found 6")
    record("knet-truncated", "short.EW", _knet(duration="60"),
           r"short\.EW, line 19: truncated data: Duration Time 60\.0 s at 100 Hz")
    record("knet-no-memo", "nomemo.NS", _knet(drop="Memo."),
           r"nomemo\.NS: expected a K-NET header ending with a 'Memo\.' line")
    record("knet-huge-counts", "counts.NS", _knet(counts=[0] * 8 + [10**15] + [0] * 7),
           r"counts\.NS, line 19: value '1000000000000000' is .* g, beyond the 10 g")
    # ---------------------------------------------------------------- JMA CSV
    record("jma-no-columns", "nocol.csv", _jma(columns=None, rows=[]),
           r"nocol\.csv: expected a column line such as 'NS,EW,UD'")
    record("jma-rate", "rate.csv", _jma(rate="fast"),
           r"rate\.csv, line 4: expected 'SAMPLING RATE= 100Hz', found 'fast'")
    record("jma-units", "unit.csv", _jma(unit="furlong"),
           r"unit\.csv, line 5: wrong units 'furlong': expected 'UNIT = gal'")
    record("jma-short-row", "row.csv", _jma(rows=["1.0,2.0,3.0", "1.0,2.0"]),
           r"row\.csv, line 9: expected 3 comma-separated values, found 2")
    record("jma-no-rows", "norows.csv", _jma(rows=[]),
           r"norows\.csv, line 8: expected data rows after the column line")
    record("jma-huge", "hugejma.csv", _jma(rows=["1.0,2.0,3.0", "1.0,2.0,1e9"]),
           r"hugejma\.csv, line 9: value '1e9' is 1\.02e\+06 g, beyond")
    # ---------------------------------------------------------------- plain text
    record("plain-no-units", "nounits.txt", "0.1\n0.2\n0.3\n",
           r"nounits\.txt: missing units: plain text records carry none", ("--dt", "0.01"))
    record("plain-no-dt", "nodt.txt", "0.1\n0.2\n0.3\n",
           r"nodt\.txt: missing DT: a one-column file needs dt", ("--units", "g"))
    record("plain-bad-units", "badunits.txt", "0.1\n0.2\n0.3\n",
           r"badunits\.txt: unknown acceleration units 'furlong'",
           ("--dt", "0.01", "--units", "furlong"))
    record("plain-three-columns", "three.txt", "0 0.1 0.2\n0.01 0.1 0.2\n",
           r"three\.txt, line 1: expected 1 or 2 columns, found 3", plain)
    record("plain-ragged", "ragged.txt", "0.1\n0.2\n0.3 0.4\n",
           r"ragged\.txt, line 3: expected 1 columns as above, found 2", plain)
    record("plain-uneven-time", "uneven.txt", "0 0.1\n0.01 0.2\n0.03 0.1\n0.04 0\n",
           r"uneven\.txt, line 3: expected a uniform time step", ("--units", "g"))
    record("plain-decreasing-time", "back.txt", "0.02 0.1\n0.01 0.2\n0 0.1\n",
           r"back\.txt, line 1: expected increasing times in column 1", ("--units", "g"))
    record("plain-comments", "comments.txt", "# nothing\n# here\n",
           r"comments\.txt: expected numbers; the file has only comments", plain)
    record("plain-one-sample", "single.txt", "0.1\n",
           r"single\.txt, line 1: expected at least two samples, found 1", plain)
    record("plain-1e308", "huge.txt", "0.1\n1e308\n",
           r"huge\.txt, line 2: value '1e308' is 1e\+308 g, beyond the 10 g", plain)
    record("plain-too-long", "long.txt", "".join(f"{0.1 * i:.1f} 0\n" for i in range(40_001)),
           r"long\.txt, line 40001: the record lasts 4000 s .*at most 3600 s", ("--units", "g"))
    record("plain-time-dt-1000", "slow.txt", "0 0.1\n1000 0.2\n2000 0.1\n",
           r"slow\.txt, line 2: the time column gives a time step of 1000 s", ("--units", "g"))
    record("plain-text", "words.txt", "hello world\n",
           r"words\.txt, line 1: expected numbers, found 'hello world'", plain)

    # ---------------------------------------------------------------- manifests
    good = write("good.txt", "".join(f"{0.1 * (i % 7 - 3):.2f}\n" for i in range(200)))

    def manifest(id, name, content, stderr, status=USAGE):
        path = write(name, content) if content is not None else str(files / name)
        cases.append(Case(id, ("validate", "--manifest", path, "--no-fem", "--workers", "1",
                               "--no-progress", "--out", out), status, stderr))

    manifest("manifest-misspelt", "scael.toml",
             f'[[record]]\npath = "{good}"\ndt = 0.01\nunits = "g"\nscael = 2.0\n',
             r"scael\.toml, \[\[record\]\] 1: unknown field 'scael' .*did you mean 'scale'\?")
    manifest("manifest-misspelt-csv", "scael.csv", f"path,scael,dt,units\n{good},2,0.01,g\n",
             r"scael\.csv, line 1: unknown field 'scael' .*did you mean 'scale'\?")
    manifest("manifest-duplicate", "dup.csv",
             f"path,name,dt,units\n{good},A,0.01,g\n# a comment\n{good},A,0.01,g\n",
             r"dup\.csv, line 4: duplicate record name 'A' \(also at line 2\)")
    manifest("manifest-duplicate-stem", "dupstem.toml",
             f'[[record]]\npath = "{good}"\ndt = 0.01\nunits = "g"\n'
             f'[[record]]\npath = "{good}"\ndt = 0.01\nunits = "g"\nscale = 2\n',
             r"dupstem\.toml, \[\[record\]\] 2: duplicate record name 'good' \(also at "
             r"\[\[record\]\] 1\)")
    manifest("manifest-dt-zero", "dt0.csv", f"path,dt,units\n{good},0,g\n",
             r"dt0\.csv, line 2: 'dt' gives a time step of 0 s")
    manifest("manifest-dt-1000", "dt1000.toml",
             f'[[record]]\npath = "{good}"\ndt = 1000\nunits = "g"\n',
             r"dt1000\.toml, \[\[record\]\] 1: 'dt' gives a time step of 1000 s")
    manifest("manifest-negative-scale", "neg.csv", f"path,scale,dt,units\n{good},-2,0.01,g\n",
             r"neg\.csv, line 2: expected a positive, finite 'scale', got -2")
    manifest("manifest-huge-scale", "big.csv", f"path,scale,dt,units\n{good},1e20,0.01,g\n",
             r"big\.csv, line 2: 'scale' 1e\+20 takes the record's peak acceleration to "
             r"3e\+19 g, beyond the 10 g")
    manifest("manifest-no-path", "nopath.csv", "name,scale\nx,1\n",
             r"nopath\.csv, line 1: expected a CSV header with at least a 'path' column")
    manifest("manifest-missing-record", "missing.csv", "path\nnope.AT2\n",
             r"missing\.csv, line 2: record file .*nope\.AT2 does not exist")
    manifest("manifest-record-fifo", "fifo.csv", f"path\n{files / 'pipe'}\n",
             r"fifo\.csv, line 2: record file .*pipe: expected a regular record file, found a "
             r"FIFO")
    bad = write("bad.txt", "0.1\n0.2\nnot-a-number\n")
    manifest("manifest-bad-record", "badrec.csv", f"path,dt,units\n{bad},0.01,g\n",
             r"bad\.txt, line 3: expected numbers, found 'not-a-number' \(listed in .*badrec"
             r"\.csv, line 2\)")
    manifest("manifest-invalid-toml", "broken.toml", "[[record]\npath = 1\n",
             r"broken\.toml: invalid TOML: .*line 1")
    manifest("manifest-no-records", "none.toml", 'title = "x"\n',
             r"none\.toml: expected one or more \[\[record\]\] tables")
    manifest("manifest-top-level-key", "top.toml",
             f'title = "x"\n[[record]]\npath = "{good}"\n',
             r"top\.toml: unknown top-level key 'title'")
    manifest("manifest-scale-text", "scale.toml",
             f'[[record]]\npath = "{good}"\nscale = "big"\n',
             r"scale\.toml, \[\[record\]\] 1: expected a number for 'scale', found 'big'")
    manifest("manifest-path-list", "pathlist.toml", "[[record]]\npath = [1, 2]\n",
             r"pathlist\.toml, \[\[record\]\] 1: expected text for 'path', found '\[1, 2\]'")
    manifest("manifest-extra-fields", "extra.csv", f"path,dt\n{good},0.01,g,9\n",
             r"extra\.csv, line 2: expected at most 2 comma-separated fields as in the header, "
             "found 4")
    manifest("manifest-folder", "folder", None,
             r"folder: expected a regular manifest, found a folder")
    manifest("manifest-binary", "m.csv", b"\x00\x01path\x00" * 50, r"m\.csv: not a text file")
    manifest("manifest-empty", "empty.csv", "# only a comment\n",
             r"empty\.csv: expected a CSV header with at least a 'path' column")
    manifest("manifest-only-header", "header.csv", "path,scale\n",
             r"header\.csv: expected at least one record after the header")
    manifest("manifest-missing", "absent.csv", None, r"absent\.csv: no such manifest")

    # ---------------------------------------------------------------- arguments
    def args(id, argv, stderr, status=USAGE):
        cases.append(Case(id, tuple(argv), status, stderr))

    rec = ("--record", good, *plain)
    args("pressure-tiny", ["simulate", "--pressure", "0.001", "--out", out],
         r"argument --pressure: must be between 1 and 200 MPa .*got 0\.001")
    args("pressure-huge", ["critical-sa", *rec, "--pressure", "1e6", "--stop", "0.3"],
         r"argument --pressure: must be between 1 and 200 MPa .*got 1e6")
    args("pressure-text", ["simulate", "--pressure", "heavy"],
         r"argument --pressure: not a number: 'heavy'")
    args("amplitude-huge", ["simulate", "--amplitude", "1e300", "--out", out],
         r"argument --amplitude: must be positive and at most 10 g .*got 1e300")
    args("amplitude-nan", ["simulate", "--amplitude", "nan"],
         r"argument --amplitude: must be positive and at most 10 g .*got nan")
    args("period-huge", ["simulate", "--period", "1e9"],
         r"argument --period: must be between 0\.05 and 20 s .*got 1e9")
    args("period-zero", ["demo", "--period", "0"],
         r"argument --period: must be between 0\.05 and 20 s")
    args("scale-huge", ["simulate", *rec, "--scale", "1e20", "--out", out],
         r"--scale 1e\+20 takes the peak acceleration of good to 3e\+19 g, beyond the 10 g")
    args("scale-negative", ["simulate", *rec, "--scale", "-1"],
         r"argument --scale: must be positive and finite, got -1")
    args("scale-inf", ["simulate", *rec, "--scale", "inf"],
         r"argument --scale: must be positive and finite, got inf")
    args("dt-1000", ["simulate", "--record", good, "--dt", "1000", "--units", "g"],
         r"argument --dt: must be between 0\.0001 and 0\.1 s")
    args("dt-1e-9", ["pulses", "--record", good, "--dt", "1e-9", "--units", "g"],
         r"argument --dt: must be between 0\.0001 and 0\.1 s .*got 1e-9")
    args("stop-huge", ["critical-sa", *rec, "--stop", "1e9"],
         r"argument --stop: must be positive and at most 5 g")
    args("after-failure-negative", ["critical-sa", *rec, "--after-failure", "-1"],
         r"argument --after-failure: must be between 0 and 1000")
    args("workers-huge", ["validate", "--workers", "100000", "--out", out],
         r"argument --workers: must be between 1 and 256")
    args("records-zero", ["validate", "--records", "0", "--out", out],
         r"argument --records: must be positive and finite, got 0")
    args("fem-step-huge", ["validate", "--fem-step", "1", "--out", out],
         r"argument --fem-step: must be positive and at most 0\.1 s")
    args("criteria-five", ["validate", "--criteria", "5"],
         r"argument --criteria: invalid choice: 5")
    args("unknown-set", ["validate", "--set", "japan", "--no-fem", "--out", out],
         r"unknown record set 'japan'; choose from farfield")
    args("fem-pressure-not-run", ["validate", "--manifest", str(files / "good.csv"),
                                  "--pressure", "10", "--fem-pressure", "60", "--out", out],
         r"--fem-pressure 60 is not one of --pressure 10")
    write("good.csv", f"path,dt,units\n{good},0.01,g\n")
    args("kind-sideways", ["simulate", "--kind", "sideways"],
         r"argument --kind: invalid choice: 'sideways'")
    args("unknown-command", ["explode"], r"invalid choice: 'explode'")
    args("no-command", [], r"the following arguments are required: command")
    write("afile", "x")
    args("out-is-a-file", ["simulate", "--out", str(files / "afile")],
         r"cannot write to output folder .*afile")
    args("record-and-nothing", ["pulses"], r"the following arguments are required: --record")
    return cases


if __name__ == "__main__":
    folder = Path(sys.argv[1])
    folder.mkdir(parents=True, exist_ok=True)
    for case in build_corpus(folder):
        print(f"{case.id:28s} exit {case.status}  {' '.join(case.argv)[:90]}")
