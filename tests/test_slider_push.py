"""The rim pushed by the slider (fem/slider_push.py, Eq. F71): the pendulum
path keeps the slider's spherical face concentric with the dish, and the first touch is found
where the slider's flat side reaches the rim's face. Geometry only: the push itself is a study
(docs/fe-companion.md, "The rim pushed by the slider")."""

import math

import numpy as np
import pytest

from fem.contact import SliderShape, body_coordinates
from fem.slider_push import slider_pose, touching_angle
from rigid import DFPBearing

BEARING = DFPBearing(pressure=60e6)


@pytest.mark.parametrize("angle", [0.0, 0.05, 0.15])
def test_the_path_keeps_the_slider_on_the_dish(angle):
    """The centre of the slider's lower spherical face, R − h/2 above its centroid in the
    body frame, stays at the dish's centre (0, R) on the whole path: the slider rides the
    dish without gap or overlap. Round-off: 1e-12 m on metres."""
    x, z, theta = slider_pose(BEARING, angle)
    arm = BEARING.radius - BEARING.slider_height / 2
    centre = np.array([x - math.sin(theta) * arm, z + math.cos(theta) * arm])
    np.testing.assert_allclose(centre, [0.0, BEARING.radius], atol=1e-12)


def test_the_sharp_slider_first_touches_the_face_with_its_flat_side():
    """A sharp slider reaches a point of the rim's inner face 10 mm above its root when the
    point lies on the slider's right side, ξ_x = b/2 in the body frame (Eq. F13); the
    bisection stops within 1e-12 rad, which moves the point by less than 1e-11 m."""
    shape = SliderShape.from_bearing(BEARING)
    point = np.array([[BEARING.rim_radius], [BEARING.dish_depth(BEARING.rim_radius) + 0.01]])
    angle = touching_angle(BEARING, shape, point)
    xi = body_coordinates(point, slider_pose(BEARING, angle))
    assert xi[0, 0] == pytest.approx(shape.half_width, abs=1e-11)
    assert abs(xi[1, 0]) < shape.half_height - shape.sag  # on the flat side, not a corner
    with pytest.raises(ValueError, match="clear of the rim"):
        touching_angle(BEARING, shape, point - np.array([[0.5], [0.0]]))


def test_the_slider_and_the_plate_s_support_carry_the_same_force():
    """Newton's third law through the contact: in an elastic push by the slider the force
    reported on the slider (its contact force times the depth πb/4) is the reaction of the
    plate's fixed back face. Both sides are assembled independently (the slider's resultant
    in fem.contact, the plate's internal forces in fem.finite_element); Newton stops at 1e-8
    of the force scale, so 1e-6 is round-off with margin."""
    from fem.finite_element import FiniteStrainQ1
    from fem.hencky import FiniteState
    from fem.material import Material
    from fem.slider_push import rim_slider_push

    push = rim_slider_push(BEARING, displacement=1e-4, steps=2, plasticity=False)
    assert push.force[-1] > 0.0  # the rim pushes the slider back, outward
    fe = FiniteStrainQ1(push.plate.mesh)
    _, f_int = fe.evaluate(Material.from_bearing(BEARING).elastic(), push.final_displacement,
                           FiniteState.virgin(fe.point_shape))
    reaction = f_int[fe.basis.nodal_dofs[0, push.plate.support]].sum() * push.plate.depth
    assert -reaction == pytest.approx(push.force[-1], rel=1e-6)


def test_a_law_from_the_slider_is_a_law_through_tearing_with_its_own_key(tmp_path, monkeypatch):
    """``fem.rim_law(punch="slider")`` needs the fracture set (the slider's push is there to
    tear the rim), and its cache key holds the slider's edge radius, so that the face push's
    laws keep theirs."""
    import fem
    from rigid.rims import rim_law_cache_file

    monkeypatch.setenv("DFP_CACHE_DIR", str(tmp_path))
    with pytest.raises(ValueError, match="give fracture"):
        fem.rim_law(BEARING, punch="slider")
    with pytest.raises(ValueError, match="punch must be one of"):
        fem.rim_law(BEARING, fracture="median", punch="cylinder")
    face = rim_law_cache_file(BEARING, fracture="median")
    slider = {r: rim_law_cache_file(BEARING, fracture="median", edge_radius=r)
              for r in (0.02, 0.01)}
    assert len({face, *slider.values()}) == 3
    with pytest.raises(ValueError, match="give fracture"):
        rim_law_cache_file(BEARING, edge_radius=0.02)


def test_dfp_validate_asks_for_the_slider_s_law(tmp_path, monkeypatch):
    """``dfp validate --rim-punch slider`` asks fem.rim_law for the law through tearing
    pushed by the slider, with --fem-edge-radius's edges or 20 mm, and the report says so;
    without a fracture set it is refused in one line. The FE pushes are replaced by a
    stand-in law (the push is tested above; the law through tearing in
    test_tearing_rims.py)."""
    from test_cli import _pulse_manifest
    from test_tearing_rims import _law

    import fem
    from validation import cli

    law, _ = _law()
    asked = []

    def fake_rim_law(bearing, model="plane-strain", fracture=None, punch="face",
                     edge_radius=None, cache=True):
        asked.append((fracture, punch, edge_radius))
        return law

    monkeypatch.setattr(fem, "rim_law", fake_rim_law)
    monkeypatch.setenv("DFP_CACHE_DIR", str(tmp_path / "cache"))
    common = ["validate", "--manifest", str(_pulse_manifest(tmp_path)), "--pressure", "60",
              "--criteria", "4", "--stop", "1.2", "--workers", "1", "--no-progress",
              "--no-fem", "--rims", "yielding", "--limit-state", "containment",
              "--rim-punch", "slider"]
    assert cli.main([*common, "--out", str(tmp_path / "refused")]) == 2
    out = tmp_path / "out"
    assert cli.main([*common, "--rim-fracture", "median", "--out", str(out)]) == 0
    # the law through tearing: once to keep it in the store, once for the ladders (the plain
    # law is kept in the store beside it)
    assert [a for a in asked if a[0]] == [("median", "slider", 0.02)] * 2
    assert "by the slider (edges 20 mm), through tearing (median)" in (
        out / "report.html").read_text()
