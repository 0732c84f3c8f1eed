"""The rigid model's rims through tearing (docs/theory/rigid-body.md, Eqs. R55b, R56c, R64):
the law built from a push that tears the rim off, the rim element along its falling force,
the corner at the pushed height, and the loss of containment when a torn rim comes off. The
laws here are synthetic (a push of the 40 mm rim's shape and size), so that every number
checked is known beforehand; the FE push through tearing is tested in test_fem_pushover.py."""

from __future__ import annotations

import dataclasses
import math
from types import SimpleNamespace

import numpy as np
import pytest

import rigid
from rigid import DFPBearing, G, ricker_record
from rigid import _kernel as K
from rigid.model import kernel_parameters
from rigid.rims import rim_law_through_tearing

BEARING = DFPBearing(pressure=60e6)
K_EL = 6e9  # [N/m], the 40 mm rim's elastic push
ROOT = BEARING.dish_depth(BEARING.rim_radius)


def _push(d, f, height, tear=None, separated=False, hinge=2e-4):
    """A push as fem.rim_pushover returns it, with the fields the law reads."""
    corner = np.column_stack([BEARING.rim_radius + d, ROOT + height])
    hinged = hinge if hinge <= d[-1] else None
    return SimpleNamespace(
        displacement=d, force=f, corner=corner,
        averaged_plastic_strain=np.zeros_like(d),
        hinge_displacement=hinged,
        hinge_force=None if hinged is None else float(np.interp(hinge, d, f)),
        fracture_displacement=tear,
        fracture_force=None if tear is None else float(np.interp(tear, d, f)),
        separated=separated)


def _law(separated=True, bearing=BEARING):
    """Elastic to 0.4 MN, hardening to 2.4 MN at 6 mm, a slight fall to the tear at 10 mm,
    then down to 1 % of the peak at 38 mm; the corner rising from 35 to 39 mm."""
    fine_d = np.linspace(0.0, 1.5e-3, 61)
    torn_d = np.linspace(0.0, 0.038, 153)

    def force(d):
        rise = 0.4e6 + 2.0e6 * (1.0 - np.exp(-d / 1.5e-3))
        fall = np.where(d > 6e-3, 0.05e6 * (d - 6e-3) / 4e-3, 0.0)
        tear = np.where(d > 0.01, 2.35e6 * np.clip((d - 0.01) / 0.028, 0, 0.99), 0.0)
        return np.minimum(K_EL * d, rise - fall - tear)

    def height(d):
        return 0.035 + 0.004 * d / 0.038

    fine = _push(fine_d, force(fine_d), height(fine_d))
    torn = _push(torn_d, force(torn_d), height(torn_d), tear=0.01, separated=separated)
    return rim_law_through_tearing(bearing, K_EL, fine, torn), torn


def test_the_law_follows_the_push_through_the_tear():
    """The backbone is the push's force at u_p = δ − F/k_el (Eq. R56), non-decreasing up to
    the first tear and the push's own falling force past it (R56c); the corner's height is
    the push's at each row (R55b); the first tear is the rupture, and the last row, where
    the push ended with the rim off, is the off set (R64). Round-off tolerances: every
    number is the push's own, interpolated at most once."""
    law, torn = _law()
    up = torn.displacement - torn.force / K_EL
    before = law.plastic_set < law.tear_set
    assert np.all(np.diff(law.force[before]) >= 0.0)
    after = ~before
    np.testing.assert_allclose(law.force[after], np.interp(law.plastic_set[after], up,
                                                           torn.force), rtol=1e-9)
    assert law.force[-1] < 0.02 * law.force.max() < law.force[after][0]
    assert np.all(np.diff(up) > 0)  # so that the push's heights can be read at a set
    rows = law.plastic_set > np.interp(1.5e-3, torn.displacement, up)  # past the fine push
    np.testing.assert_allclose(law.corner_height[rows], np.interp(
        law.plastic_set[rows], up, torn.corner[:, 1] - ROOT), rtol=1e-9)
    assert law.tear_set == law.rupture_set == pytest.approx(
        0.01 - torn.fracture_force / K_EL, rel=1e-12)
    assert law.off_set == law.plastic_set[-1]


def test_a_push_stopped_short_goes_on_to_the_plate_edge():
    """A push that Newton stopped short of the rim's coming off (Eq. R64b): the law keeps the
    push's rows and adds one at u_p = t_r, where the rim is off, of zero force if the rim
    had torn and of the last force if not, with the last corner height. Exact: the added
    row is copied, not computed."""
    law, _ = _law()
    short, torn = _law(separated=False)
    n = law.plastic_set.size
    np.testing.assert_array_equal(short.plastic_set[:n], law.plastic_set)
    np.testing.assert_array_equal(short.force[:n], law.force)
    assert short.plastic_set[-1] == short.off_set == BEARING.rim_thickness
    assert short.force[-1] == 0.0 and short.corner_height[-1] == short.corner_height[-2]
    untorn = SimpleNamespace(**{**vars(torn), "fracture_displacement": None,
                                "fracture_force": None})
    fine_d = np.linspace(0.0, 1.5e-3, 61)
    fine = _push(fine_d, np.interp(fine_d, torn.displacement, torn.force), np.full(61, 0.035))
    held = rim_law_through_tearing(BEARING, K_EL, fine, untorn)
    assert held.off_set == held.plastic_set[-1] == BEARING.rim_thickness
    assert held.force[-1] == held.force[-2] and held.tear_set == math.inf


def test_a_push_past_the_plate_edge_is_cut_there():
    """A push that went on past u_p = t_r, as the slider's push ploughs through a crushed
    thick rim (Eq. R64c): the law keeps the rows before t_r and ends with one at t_r, its force
    and corner height interpolated there, where the rim is off. The same push stopped at 38 mm
    of a 40 mm rim keeps all its rows. Round-off tolerances: one interpolation."""
    law, _ = _law()
    cut, _ = _law(bearing=dataclasses.replace(BEARING, rim_thickness=0.030))  # ends past it
    assert cut.off_set == cut.plastic_set[-1] == 0.030
    before = law.plastic_set < 0.030
    n = int(before.sum())
    np.testing.assert_array_equal(cut.plastic_set[:n], law.plastic_set[before])
    np.testing.assert_array_equal(cut.force[:n], law.force[before])
    assert cut.plastic_set.size == n + 1
    assert cut.force[-1] == pytest.approx(np.interp(0.030, law.plastic_set, law.force),
                                          rel=1e-12)
    assert cut.corner_height[-1] == pytest.approx(
        np.interp(0.030, law.plastic_set, law.corner_height), rel=1e-12)
    assert law.off_set == law.plastic_set[-1] < BEARING.rim_thickness  # not cut at 40 mm


def test_the_rim_element_softens_along_the_backbone():
    """The kernel's rim (Eqs. R57–R59) pushed quasi-statically through one rigid contact past
    the tear: in plastic flow its force is the backbone's at its set, falling past the tear;
    the series solve converges to 1e-12 of the force, so 1e-9 holds."""
    law, _ = _law()
    table = law.table
    buf = np.zeros((K.B_CONTACTS, K.B_FIELDS))
    buf[0, K.B_SHARE] = 1.0
    up, forces, sets = 0.0, [], []
    for deflection in np.linspace(1e-3, 0.035, 200):
        buf[0, K.B_GAP] = deflection - up
        _, force, step = K.rim_response(buf, 1, 1e30, K_EL, table, up)
        up += step
        forces.append(force)
        sets.append(up)
    np.testing.assert_allclose(forces, np.interp(sets, law.plastic_set, law.force), rtol=1e-9)
    assert forces[-1] < 0.2 * max(forces)


def test_the_corner_is_where_the_push_put_it():
    """Eq. R55b: with a law through tearing the rim's face keeps the corner height of its
    table at the set (exactly: a linear interpolation of the table); without one it turns
    about its root (R55, h_r·cos φ, sin φ = u_p/L)."""
    law, _ = _law()
    p, q = kernel_parameters(BEARING), np.zeros(5)
    p[K.P_HR], p[K.P_LEVER] = BEARING.rim_height, law.lever
    up = 0.02
    p[K.P_CORNER] = 1.0
    assert K.rim_geometry(p, q, 1, up, law.table)[2] == pytest.approx(
        np.interp(up, law.plastic_set, law.corner_height), rel=1e-12)
    p[K.P_CORNER] = 0.0
    assert K.rim_geometry(p, q, 1, up, law.table)[2] == pytest.approx(
        BEARING.rim_height * math.sqrt(1.0 - (up / law.lever) ** 2), rel=1e-12)


def test_a_torn_rim_comes_off_and_the_slider_is_out():
    """A pulse that drives the slider through the rim: with the law through tearing the run
    fails by yielding when the rim's set reaches the off set (R64), after the rupture (the
    first tear); the same law with no off set does not say so."""
    _, a = ricker_record(0.6 * G, 2.0, "antisymmetric", dt=0.005, lead=3.0, free=4.0)
    law, _ = _law()
    run = rigid.simulate(BEARING, a, 0.005, rims="yielding", rim_law=law,
                         limit_state="containment")
    assert run.failure_mode == "yielding" and run.failure_detail == "a torn rim came off"
    assert max(run.rim_sets) >= law.off_set
    assert run.limit_states["rupture"] <= run.limit_states["containment"]
    assert abs(run.energy.relative_error) < 0.01
    kept = rigid.simulate(BEARING, a, 0.005, rims="yielding", limit_state="containment",
                          rim_law=dataclasses.replace(law, off_set=math.inf))
    assert kept.failure_detail != "a torn rim came off"


def test_dfp_validate_gives_the_rigid_model_the_law_through_tearing(tmp_path, monkeypatch):
    """``dfp validate --rim-fracture median`` asks for the law through tearing, keeps it in
    the run's store, runs the yielding-rim ladders with it and says so in the report. The FE
    pushes are replaced by the synthetic law (they take a minute; the law they give is
    tested above and in test_fem_pushover.py)."""
    from test_cli import _pulse_manifest

    import fem
    from validation import cli

    law, _ = _law()
    untorn = dataclasses.replace(law, corner_height=np.zeros(0), off_set=math.inf)
    asked = []

    def fake_rim_law(bearing, model="plane-strain", fracture=None, cache=True):
        asked.append(fracture)
        return law if fracture else untorn

    monkeypatch.setattr(fem, "rim_law", fake_rim_law)
    monkeypatch.setenv("DFP_CACHE_DIR", str(tmp_path / "cache"))
    out = tmp_path / "out"
    assert cli.main(["validate", "--manifest", str(_pulse_manifest(tmp_path)), "--pressure", "60",
                     "--criteria", "4", "--stop", "1.2", "--workers", "1", "--no-progress",
                     "--no-fem", "--rims", "yielding", "--limit-state", "containment",
                     "--rim-fracture", "median", "--out", str(out)]) == 0
    assert asked.count("median") == 2  # one to keep it in the store, one for the ladders
    assert "through tearing (median)" in (out / "report.html").read_text()


def test_a_law_without_tearing_keeps_its_key():
    """The fields of a law through tearing key a stored run only when set, so the runs of
    the laws without them keep their keys (and can be carried over to new code); set, each
    changes the key."""
    from rigid.tasks.store import _canonical, task_key

    law, _ = _law()
    plain = dataclasses.replace(law, corner_height=np.zeros(0), tear_set=math.inf,
                                off_set=math.inf)
    fields = {f.name for f in dataclasses.fields(plain)}
    assert set(_canonical(plain)) == fields - {"corner_height", "tear_set", "off_set"} | {
        "__type__"}
    keys = {task_key("t", ("rigid",), law=x) for x in (
        plain, law, dataclasses.replace(plain, off_set=law.off_set),
        dataclasses.replace(plain, tear_set=law.tear_set),
        dataclasses.replace(plain, corner_height=law.corner_height))}
    assert len(keys) == 5
