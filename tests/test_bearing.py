"""DFPBearing: derived quantities against closed forms, and parameter validation."""

import dataclasses
import math

import pytest

from rigid import DFPBearing, G, jankowski_damping_ratio


def test_baseline_loads_and_masses():
    b = DFPBearing()
    area = math.pi * 0.2**2
    # exact arithmetic identities: tolerance is float round-off
    assert b.weight == pytest.approx(60e6 * area, rel=1e-12)
    assert b.supported_mass == pytest.approx(60e6 * area / G, rel=1e-12)
    assert b.slider_mass == pytest.approx(7850 * area * 0.2, rel=1e-12)
    assert b.slider_inertia == pytest.approx(b.slider_mass * (3 * 0.04 + 0.04) / 12, rel=1e-12)
    # docs/theory/rigid-body.md, table after Eq. R14 (rounded to 3-4 digits there)
    assert b.supported_mass == pytest.approx(768.6e3, rel=1e-3)
    assert b.slider_mass == pytest.approx(197, rel=2e-3)
    assert DFPBearing(pressure=10e6).supported_mass == pytest.approx(128.1e3, rel=1e-3)


def test_rim_is_where_the_leading_vertex_arrives_at_capacity():
    """Independent check of r_in: rotate the slider to the capacity by rigid-body kinematics."""
    b = DFPBearing()
    arm = b.radius - b.slider_height / 2  # centroid path radius about the dish centre (0, R)
    phi = math.asin(b.capacity / arm)
    cx, cz = arm * math.sin(phi), b.radius - arm * math.cos(phi)
    # bottom-leading vertex (b/2, −h_e/2) in the body frame, rotated by φ
    vx = cx + math.cos(phi) * b.slider_diameter / 2 + math.sin(phi) * b.edge_height / 2
    vz = cz + math.sin(phi) * b.slider_diameter / 2 - math.cos(phi) * b.edge_height / 2
    assert vx == pytest.approx(b.rim_radius, abs=1e-12)
    assert vz == pytest.approx(b.dish_depth(vx), abs=1e-12)  # and it lies on the dish
    # rigid-body.md, Eq. R6 and the table after R14 (c0 ≈ 25 mm)
    assert b.rim_radius == pytest.approx(0.5099, abs=1e-4)
    assert b.rim_clearance == pytest.approx(0.0249, abs=1e-4)


def test_period_and_damping_ratio():
    b = DFPBearing()
    assert b.period == pytest.approx(2 * math.pi * math.sqrt((5.0 - 0.2) / G), rel=1e-12)
    # rigid-body.md, Eq. R11 (a prototype measured 4.3957 s)
    assert b.period == pytest.approx(4.395, abs=1e-3)
    assert b.design_period == 4.5
    assert jankowski_damping_ratio(0.65) == pytest.approx(0.3728, abs=1e-4)  # Eq. R18
    assert jankowski_damping_ratio(1.0) == 0.0
    # static penetration (W/2k)^(2/3): 1.125 mm / 0.341 mm, rigid-body.md table after R14
    assert b.static_penetration == pytest.approx(1.125e-3, rel=2e-3)
    assert DFPBearing(pressure=10e6).static_penetration == pytest.approx(0.341e-3, rel=2e-3)


@pytest.mark.parametrize(
    "field, value",
    [
        ("pressure", -1.0),
        ("radius", 0.0),
        ("slider_diameter", -0.4),
        ("rim_height", -0.01),
        ("rim_thickness", 0.0),
        ("contact_stiffness", float("nan")),
        ("friction", 1.0),
        ("friction", -0.1),
        ("rim_friction", 1.5),
        ("restitution", 0.0),
        ("restitution", 1.2),
        ("rim_height", 0.08),  # leaves no clearance between the rims
        ("capacity", 2.0),
        ("slider_height", 0.01),  # thinner than the two face sags
        ("hardening_ratio", 1.0),
        ("poisson_ratio", 0.5),
        ("ultimate_stress", 300e6),
    ],
)
def test_invalid_parameters_name_the_parameter(field, value):
    with pytest.raises(ValueError, match=field):
        DFPBearing(**{field: value})


def test_frozen_and_replace():
    b = DFPBearing()
    with pytest.raises(dataclasses.FrozenInstanceError):
        b.friction = 0.1
    light = dataclasses.replace(b, pressure=10e6)
    assert light.weight == pytest.approx(b.weight / 6, rel=1e-12)
    assert "rim_radius" in b.describe()
