"""The rim pushed by the slider (validation/studies/rim_slider_push.py, Eq. F71): the pendulum
path keeps the slider's spherical face concentric with the dish, and the first touch is found
where the slider's flat side reaches the rim's face. Geometry only: the push itself is a study
(docs/fe-companion.md, "The rim pushed by the slider")."""

import math

import numpy as np
import pytest

from fem.contact import SliderShape, body_coordinates
from rigid import DFPBearing
from validation.studies.rim_slider_push import slider_pose, touching_angle

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
