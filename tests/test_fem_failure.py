"""Failure of the FE model (fem.simulate): the heavy bearing driven into its rims forms a plastic
hinge at a rim root; the light bearing whose rims cannot yield is thrown out by uplift.

Input: a 3 m/s² half-sine of 1 s, which the rigid model (same bearing) takes to the rims at a
relative velocity of 1.05 m/s (first impact at t = 0.972 s) without failing (it cannot yield).
Coarsest mesh (905 dofs, two elements across the rim) so the run takes ~20 s. The oracle for the
failure itself is the rim's plastic capacity (docs/theory/finite-elements.md, Eqs. F40–F41): the
root section, t = 40 mm thick, carries at most V_p = t·f_y/√3 per unit depth in shear, 2.5 MN for
the model's depth — far below the ~40 MN peak force of the rigid model's Hertz contact at that
velocity, so the rim cannot stay elastic.
"""

import math

import numpy as np
import pytest

pytest.importorskip("skfem")
pytest.importorskip("gmsh")

import fem
import rigid
from fem.geometry import COARSE_MESH
from rigid import G, ricker_record
from rigid.bearing import DFPBearing

DT = 0.01


def pulse():
    t = np.arange(0.0, 2.0 + DT / 2, DT)
    return np.where(t < 1.0, 3.0 * np.sin(np.pi * t), 0.0)


@pytest.fixture(scope="module")
def heavy_run(mesh_cache, heavy):
    bearing = heavy
    res = fem.simulate(
        bearing, pulse(), DT, max_step=0.02, mesh_options=COARSE_MESH,
        cache_dir=mesh_cache,
    )
    return bearing, res


def test_heavy_bearing_fails_by_rim_yielding(heavy_run):
    """The run ends in yielding: a hinge across a rim root, that rim's root row entirely
    plastic, and the rim force at failure at most the shear capacity with the ultimate stress,
    V_u = t·f_u/√3·depth (the hinge cannot carry more), and at least half of V_p (a hinge
    cannot form under a force much below the section's capacity: the moment arm of a load at
    the root is small). The energy balance still closes to 1 %."""
    bearing, res = heavy_run
    assert res.failed and res.failure_mode == "yielding", res.summary()
    rim = res.failure_detail.split("of the ")[1].split(" rim")[0]
    k = fem.model.RIMS.index(rim)
    assert res.rim_root_yielded_fraction[-1, k] == 1.0
    assert res.hinge_times[rim] == pytest.approx(res.failure_time)
    v_p = bearing.rim_thickness * bearing.yield_stress / math.sqrt(3) * res.depth
    v_u = bearing.rim_thickness * bearing.ultimate_stress / math.sqrt(3) * res.depth
    peak = res.rim_force[:, k].max()
    assert 0.5 * v_p < peak <= v_u
    e = res.energy
    assert np.abs(e["residual"]).max() <= 0.01 * np.abs(e["input"]).max()


def test_hinge_is_at_the_rim_root(heavy_run):
    """The largest plastic strain sits at a rim root (within one element, 20 mm, of the
    re-entrant corner where the dish meets the rim's inner face) and nothing yields in the
    plates away from the rims (|x| < r_in − 50 mm)."""
    bearing, res = heavy_run
    from skfem import Basis, ElementQuad1

    x, z = Basis(res.mesh, ElementQuad1(), intorder=2).global_coordinates()
    p = res.final_plastic_strain
    i = np.unravel_index(np.argmax(p), p.shape)
    r_in = bearing.rim_radius
    z_root = bearing.dish_depth(r_in)
    # reference coordinates: each rim's root corner is at |x| = r_in on its plate
    z_corner = z_root if z[i] < bearing.slider_height / 2 else bearing.slider_height - z_root
    assert math.hypot(abs(x[i]) - r_in, z[i] - z_corner) < COARSE_MESH["rim_size"]
    assert not p[np.abs(x) < r_in - 0.05].any()


def test_rims_reached_when_the_rigid_model_says(heavy_run):
    """The FE slider reaches the rims when the rigid model's does (first contact within 2 %
    of the elapsed time: the approach is the same pendulum, checked by the period test)."""
    bearing, res = heavy_run
    rb = rigid.simulate(bearing, pulse(), DT)
    assert rb.impacts and not rb.failed
    first = res.time[np.flatnonzero(res.rim_force.sum(axis=1) > 0)[0]]
    assert first == pytest.approx(rb.impacts[0].time, rel=0.02)


def test_containment_and_its_mode(mesh_cache):
    """The containment check on hand-made states of the coarse model (geometry from DFPBearing;
    docs/theory/finite-elements.md, Eqs. F37, F53): a bottom vertex beyond the +x bottom rim's
    corner and above it is uplift (it climbed over); the same vertex past a corner pushed 10 mm
    outward and down, but below the undeformed corner, is yielding (the rim let go); a slider
    turned by more than 45° is uplift; at rest nothing happens."""
    from fem.dfp import build_system
    from fem.limit_states import LimitStates

    bearing = DFPBearing()
    model = build_system(bearing, mesh_options=COARSE_MESH, cache_dir=mesh_cache)
    watch = LimitStates(bearing, model)
    nd = model.system.fe.basis.nodal_dofs
    vertices = model.system.shape.vertices
    d = np.zeros(model.system.size)
    half_b, half_e = vertices[0, 1], vertices[1, 3]  # right vertices; top z = +half_e
    r_in, z_top = bearing.rim_radius, bearing.rim_top

    def mode(pose, disp=d):
        return watch._containment(disp, np.asarray(pose))[0]

    assert mode([0.0, bearing.slider_height / 2, 0.0]) is None
    # bottom-right vertex 5 mm outside and 5 mm above the corner (θ = 0)
    assert mode([r_in + 0.005 - half_b, z_top + 0.005 + half_e, 0.0]) == "uplift"
    # rim corner pushed 10 mm outward and 10 mm down; the vertex is past it but 5 mm below
    # the undeformed corner
    pushed = d.copy()
    node = watch.corners["bottom +x"]
    pushed[nd[0, node]] = 0.010
    pushed[nd[1, node]] = -0.010
    past = [r_in + 0.015 - half_b, z_top - 0.005 + half_e, 0.0]
    assert mode(past, pushed) == "yielding"
    assert mode(past) is None  # the rim where it was: the vertex is still held
    assert mode([0.0, bearing.slider_height / 2, 0.9]) == "uplift"  # overturned


def test_containment_over_a_top_rim_of_a_displaced_top_plate(mesh_cache):
    """Eq. F37's side is the rim's, not the sign of its deformed corner's x: with the top plate
    displaced 0.62 m (more than the rim radius, 0.51 m; as when the slider bears on a rim of
    each plate), the top −x rim's corner lies at x > 0. A top vertex 5 mm to that corner's −x
    side and 5 mm past it vertically has climbed over it (uplift); the same vertex 5 mm to its
    +x side is held. Taking the side from the corner's x (a fault of an earlier version) gets
    both wrong."""
    from fem.dfp import build_system
    from fem.limit_states import LimitStates

    bearing = DFPBearing()
    model = build_system(bearing, mesh_options=COARSE_MESH, cache_dir=mesh_cache)
    watch = LimitStates(bearing, model)
    nd = model.system.fe.basis.nodal_dofs
    p = model.mesh.p
    half_b, half_e = model.system.shape.vertices[0, 1], model.system.shape.vertices[1, 3]
    shift = 0.62
    d = np.zeros(model.system.size)
    top_plate = p[1] > bearing.slider_height / 2  # the top plate's nodes
    d[nd[0, top_plate]] = shift
    corner = watch.corners["top -x"]
    cx, cz = p[0, corner] + shift, p[1, corner]
    assert cx > 0.0
    z = cz - 0.005 - half_e  # the top vertices 5 mm below the corner: past it vertically
    past = [cx - 0.005 + half_b, z, 0.0]  # top-left vertex 5 mm to the corner's -x side
    held = [cx + 0.005 + half_b, z, 0.0]  # 5 mm to its +x side
    mode, detail = watch._containment(d, np.asarray(past))
    assert (mode, detail) == ("uplift", "a top slider vertex got past the top -x rim "
                                        "(climbed over it)")
    assert watch._containment(d, np.asarray(held)) == (None, None)


def test_limit_state_verdicts(mesh_cache):
    """Under each criterion the run fails at the first of that limit state and containment:
    a hinge at 1 s and containment at 2 s fail a "hinge" run at 1 s by yielding and a
    "containment" run at 2 s by the containment's mode; a containment before any hinge fails
    even a "hinge" run, at its time and with its mode; nothing reached, no failure."""
    from fem.dfp import build_system
    from fem.limit_states import LimitStates

    bearing = DFPBearing()
    watch = LimitStates(bearing, build_system(bearing, mesh_options=COARSE_MESH,
                                              cache_dir=mesh_cache))
    assert watch.verdict("hinge") == (False, None, None, None)
    watch.times.update(hinge=1.0, containment=2.0)
    watch.hinge_rim, watch.mode, watch.detail = "bottom +x", "uplift", "climbed"
    assert watch.verdict("hinge")[:3] == (True, 1.0, "yielding")
    assert watch.verdict("rupture")[:3] == (True, 2.0, "uplift")
    assert watch.verdict("containment")[:3] == (True, 2.0, "uplift")
    watch.times.update(hinge=3.0)
    assert watch.verdict("hinge")[:3] == (True, 2.0, "uplift")


# -- uplift: the light bearing with rims that cannot yield --------------------------------------
# Antisymmetric Ricker pulse, Tp = 1 s, Ap = 1.2 g, 10 MPa: the FE model with the assumed steel
# rims forms a rim-root hinge at the first rim impact (2.13 s); with elastic steel the same
# impact throws the superstructure up and the slider out. The rigid model (unyielding rims)
# fails by uplift with e ≥ 0.8 and survives with the paper's e = 0.65
# (validation/studies/fem_elastic_rims.py).


def light_pulse():
    return ricker_record(1.2 * G, 1.0, "antisymmetric", dt=0.005, free=3.0)[1]


def light_run(cache, **kwargs):
    """The light bearing's uplift runs at small strain: they are about the mechanism and the
    energy step control; with finite deformation the same flight and landing costs 5–10 times
    more and closes its energy balance less well (docs/fe-companion.md, "Finite deformation")."""
    return fem.simulate(DFPBearing(pressure=10e6), light_pulse(), 0.005, mesh_options=COARSE_MESH,
                        max_step=0.01, duration=3.0, cache_dir=cache, kinematics="small",
                        **kwargs)


@pytest.fixture(scope="module")
def light_elastic(mesh_cache):
    return light_run(mesh_cache, plasticity=False)


def pendulum_rise(b):
    """Top-plate rise [m] when both surfaces are at their capacity (the pendulum path's top)."""
    return 2 * (b.radius - math.sqrt(b.radius**2 - b.capacity**2))


def test_light_bearing_with_unyielding_rims_fails_by_uplift(light_elastic):
    """Elastic steel: failure by uplift, nothing yields, and the superstructure was thrown up
    by more than the rim height above the top of its pendulum path (the mechanism of uplift:
    the rim couple tips the slider and lifts the supported load). The energy-balance error is
    below 5 % of the work of that lift, W × (largest rise): a numerical energy gain cannot
    have caused it (measured: 1.5 %)."""
    res = light_elastic
    b = res.bearing
    assert res.failed and res.failure_mode == "uplift", res.summary()
    assert res.max_plastic_strain == 0.0
    rise = res.top_plate_rise.max()
    assert rise > pendulum_rise(b) + b.rim_height
    assert np.abs(res.energy["residual"]).max() < 0.05 * b.weight * rise


def test_energy_control_is_what_closes_the_uplift_balance(light_elastic, mesh_cache):
    """Without the energy step control (energy_tolerance=inf) the light slider rattling
    between the airborne plates makes energy out of penalty contacts that open and close
    within a step: the same run's energy error is more than 10 × larger (measured: 70 × the
    input energy against 0.8 %)."""
    loose = light_run(mesh_cache, plasticity=False, energy_tolerance=math.inf)
    assert (np.abs(loose.energy["residual"]).max()
            > 10 * np.abs(light_elastic.energy["residual"]).max())


def test_same_pulse_with_steel_rims_fails_by_yielding(light_elastic, mesh_cache):
    """The assumed steel rims (f_y = 345 MPa, 40 mm) cannot hold the impact that throws the
    elastic model's slider out: a hinge forms at a rim root first, before the elastic run's
    uplift (tipping needs a rim force W·b/h = 2.51 MN, the root's plastic shear capacity is
    2.50 MN; fem/model.py), and the superstructure has not been lifted off its pendulum path
    by a rim height (measured: 2.4 mm above it)."""
    res = light_run(mesh_cache)
    assert res.failed and res.failure_mode == "yielding", res.summary()
    assert res.failure_time < light_elastic.failure_time
    assert res.top_plate_rise.max() < pendulum_rise(res.bearing) + res.bearing.rim_height
