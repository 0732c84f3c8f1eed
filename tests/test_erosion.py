"""Torn rim elements let go (fem/fracture/erosion.py, fem.system.CoupledSystem.erode;
docs/theory/finite-elements.md, Eqs. F67–F69): the damage per rim on the real mesh against
today's rupture, the release schedule, an element's force and tangent scaled by what it
retains, the contact surface leaving with it, and a dynamic run that tears a rim with its
energy balance closed."""

import math

import numpy as np
import pytest

import fem
from fem.dfp import build_system
from fem.fracture import RimFracture, StressModifiedStrain
from fem.geometry import COARSE_MESH
from fem.limit_states import RIMS, rim_gauge_average
from rigid import G

UNIAXIAL = np.array([345e6, 0.0, 0.0, 0.0])  # Mandel [Pa], T = 1/3


@pytest.fixture(scope="module")
def model(mesh_cache, heavy):
    return build_system(heavy, mesh_options=COARSE_MESH, kinematics="finite",
                        cache_dir=mesh_cache)


def _ramp(model, rate, steps):
    """Plastic strain growing at ``rate`` (nelems, nqp) per step, uniaxial stress."""
    shape = model.system.fe.point_shape
    stress = np.broadcast_to(UNIAXIAL[:, None, None], (4, *shape))
    return [(k * rate, stress) for k in range(1, steps + 1)]


def test_without_triaxiality_the_first_tear_is_todays_rupture(model, heavy):
    """Exponent 0, nothing released: each rim's largest damage is its largest gauge-averaged
    plastic strain over the rupture strain (Eqs. F51–F52, F66–F67) at every step, and the
    first element tears at the step where today's rupture is reached. Round-off tolerance:
    the same sums in another order."""
    fe, mesh = model.system.fe, model.mesh
    rng = np.random.default_rng(3)
    rate = rng.uniform(0.0, 0.01, fe.point_shape)
    frac = RimFracture(StressModifiedStrain(heavy.rupture_strain, 0.0), fe, mesh,
                       heavy.rim_thickness, steps=0)
    gauges = [rim_gauge_average(fe, mesh, r, heavy.rim_thickness) for r in RIMS]
    rupture_step = None
    for k, (p, stress) in enumerate(_ramp(model, rate, 40)):
        assert not frac.update(float(k), p, stress)  # steps=0: nothing lets go
        regular = [float((A @ p[e].ravel()).max()) for e, A in gauges]
        assert frac.rim_damage == pytest.approx(
            [r / heavy.rupture_strain for r in regular], rel=1e-12)
        if rupture_step is None and max(regular) >= heavy.rupture_strain:
            rupture_step = k
    assert rupture_step is not None
    assert frac.first_tear[0] == rupture_step
    assert (frac.retained == 1.0).all()


def test_a_torn_element_lets_go_over_its_steps_and_stops_straining_the_gauges(model, heavy):
    """With N = 4 an element torn at step k keeps 3/4, 1/2, 1/4, 0 at steps k … k+3 (Eq.
    F68); once every element has torn the damage grows no more (torn points add no strain,
    Eq. F67)."""
    fe, mesh = model.system.fe, model.mesh
    frac = RimFracture(StressModifiedStrain(heavy.rupture_strain, 1.5), fe, mesh,
                       heavy.rim_thickness, steps=4)
    rate = np.full(fe.point_shape, 0.05)
    history = []
    for k, (p, stress) in enumerate(_ramp(model, rate, 12)):
        frac.update(float(k), p, stress)
        history.append(frac.retained.copy())
    e, (when, _) = next(iter(frac.torn.items()))
    k = int(when)
    assert [h[e] for h in history[k:k + 4]] == pytest.approx([0.75, 0.5, 0.25, 0.0],
                                                              abs=1e-15)
    rims = np.concatenate(frac.elements)
    assert (frac.retained[rims] == 0.0).all()  # uniform strain: every rim element tore
    before = list(frac.rim_damage)
    frac.update(99.0, 20 * rate, _ramp(model, rate, 1)[0][1])
    assert frac.rim_damage == before


def test_an_element_gives_what_it_retains(model):
    """At a fixed displacement the material force is linear in the retained fractions (Eq.
    F68; exact up to round-off), and the tangent is the derivative of the force with
    elements partly and wholly let go (central differences, h = 1e-8 m: truncation and
    round-off about 1e-8 of the largest entry, hence 1e-6)."""
    sysm, mesh = model.system, model.mesh
    rim = mesh.subdomains["bottom_rim"][:6]
    rng = np.random.default_rng(0)
    d = np.zeros(sysm.size)
    d[:sysm.n_plate] = 5e-5 * rng.standard_normal(sysm.n_plate)
    state = sysm.initial_state()

    def force(retained):
        sysm.erode(retained)
        return sysm.evaluate(d, state).material_force

    none, part, full = (np.ones(mesh.t.shape[1]) for _ in range(3))
    none[rim] = 0.0
    part[rim[:3]], part[rim[3:]] = 0.4, 0.0
    mixed = 0.6 * force(np.where(np.isin(np.arange(none.size), rim[:3]), 0.0, part)) \
        + 0.4 * force(np.where(np.isin(np.arange(none.size), rim[:3]), 1.0, part))
    assert np.abs(force(part) - mixed).max() <= 1e-12 * np.abs(force(full)).max()
    sysm.erode(part)
    K = sysm.tangent(sysm.evaluate(d, state)).toarray()
    h = 1e-8
    for j in sysm.fe.element_dofs[:, rim].ravel()[::3]:
        dp, dm = d.copy(), d.copy()
        dp[j] += h
        dm[j] -= h
        fd = (sysm.evaluate(dp, state).internal_force
              - sysm.evaluate(dm, state).internal_force) / (2 * h)
        assert np.abs(fd - K[:, j]).max() <= 1e-6 * np.abs(K[:, j]).max()
    sysm.erode(full)


def test_an_inverted_element_stops_a_step_unless_it_is_letting_go(model):
    """Elements turned inside out make the plates' force NaN (Newton cuts the step); the
    same elements letting go are dropped instead, and the force stays finite."""
    sysm, mesh = model.system, model.mesh
    e = mesh.subdomains["bottom_rim"][0]
    d = np.zeros(sysm.size)
    a, c = mesh.t[0, e], mesh.t[2, e]  # a corner pushed past the opposite one
    d[sysm.fe.basis.nodal_dofs[:, a]] = 1.5 * (mesh.p[:, c] - mesh.p[:, a])
    inverted = (sysm.fe.deformation(d[:sysm.n_plate])[1] <= 0.0).any(axis=1)
    assert inverted[e]
    state = sysm.initial_state()
    retained = np.ones(mesh.t.shape[1])
    sysm.erode(retained)
    assert np.isnan(sysm.evaluate(d, state).material_force[:sysm.n_plate]).all()
    retained[inverted] = 0.5
    sysm.erode(retained)
    assert np.isfinite(sysm.evaluate(d, state).internal_force).all()
    sysm.erode(np.ones_like(retained))


def test_the_contact_surface_leaves_with_its_elements(model):
    """A contact node keeps the largest fraction its elements retain of its tributary
    length: nothing while one of them is intact, and none once all have gone."""
    sysm, mesh = model.system, model.mesh
    nodes = sysm.nodes
    full = nodes.length.copy()
    retained = np.zeros(mesh.t.shape[1])
    sysm.erode(retained)
    assert (sysm.nodes.length == 0.0).all()
    node = nodes.nodes[0]
    owners = np.flatnonzero((mesh.t == node).any(axis=0))
    retained[owners[0]] = 1.0
    sysm.erode(retained)
    assert sysm.nodes.length[0] == full[0]
    sysm.erode(np.ones(mesh.t.shape[1]))
    assert (sysm.nodes.length == full).all()


def test_a_piece_cut_off_a_rim_lets_go_and_its_corner_moves_to_what_is_left(model, heavy):
    """When the elements of the bottom +x rim's root row have gone, the rest of that rim is
    joined to no plate: it lets go over the same N steps as a torn element (Eq. F68b), and
    nothing else does. The containment check then measures that rim where its inner face met
    the dish: a slider vertex just outside the inner face, between the root and the old
    corner height, has got past it through its tear; with the rim whole it has not."""
    from fem.limit_states import LimitStates

    fe, mesh = model.system.fe, model.mesh
    frac = RimFracture(StressModifiedStrain(heavy.rupture_strain, 1.5), fe, mesh,
                       heavy.rim_thickness, steps=4)
    rim = frac.elements[RIMS.index("bottom +x")]
    z_root = heavy.dish_depth(heavy.rim_radius)
    root_row = rim[np.isclose(mesh.p[1, mesh.t[:, rim]].min(axis=0), z_root, atol=1e-6)]
    rest = np.setdiff1d(rim, root_row)
    assert root_row.size and rest.size
    p, stress = np.zeros(fe.point_shape), _ramp(model, 0.0, 1)[0][1]
    frac.retained[root_row] = 0.5  # letting go: 1/4 of it left after the next step
    frac.update(0.0, p, stress)
    assert not frac.loose  # the root row still holds some stiffness
    frac.update(1.0, p, stress)
    assert sorted(frac.loose) == rest.tolist()
    assert set(frac.loose.values()) == {(1.0, "bottom +x")}
    others = np.setdiff1d(np.arange(frac.retained.size), rim)
    assert (frac.retained[rest] == 0.75).all() and (frac.retained[others] == 1.0).all()
    for t in (1.1, 1.2, 1.3):
        frac.update(t, p, stress)
    assert (frac.retained[rim] == 0.0).all() and (frac.retained[others] == 1.0).all()

    # the +x bottom vertex 5 mm outside the inner face, 10 mm above the root
    vertex = model.system.shape.vertices[:, 1]
    pose = (heavy.rim_radius + 0.005 - vertex[0], z_root + 0.01 - vertex[1], 0.0)
    d = np.zeros(model.system.size)
    for fracture in (None, frac):
        watch = LimitStates(heavy, model, fracture=fracture)
        watch.update(2.0, d, pose, np.zeros(fe.point_shape))
        if fracture is None:
            assert watch.times["containment"] is None
        else:
            assert watch.times["containment"] == 2.0 and watch.mode == "yielding"
            assert watch.detail.endswith("bottom +x rim (through its tear)")


def test_bad_fracture_options_are_refused(heavy):
    a = np.zeros(10)
    with pytest.raises(ValueError, match="fracture must be one of"):
        fem.simulate(heavy, a, 0.01, fracture="brittle")
    with pytest.raises(TypeError, match="StressModifiedStrain"):
        fem.simulate(heavy, a, 0.01, fracture=0.19)
    with pytest.raises(ValueError, match="finite"):
        fem.simulate(heavy, a, 0.01, fracture="median", kinematics="small")


def _pulse_run(bearing, cache_dir, limit_state: str, duration: float):
    """The heavy bearing's one-second sine pulse (tests/test_fem_failure.py) with the median
    criterion on the coarse mesh, run on past its failure to ``duration`` [s]."""
    dt = 0.01
    t = np.arange(0.0, 2.0 + dt / 2, dt)
    a = np.where(t < 1.0, 3.0 * np.sin(np.pi * t), 0.0)
    return fem.simulate(bearing, a, dt, max_step=0.02, mesh_options=COARSE_MESH,
                        limit_state=limit_state, stop_at_failure=False, duration=duration,
                        fracture="median", cache_dir=cache_dir)


@pytest.fixture(scope="module")
def tearing_run(mesh_cache, heavy):
    """The pulse run 50 ms past the first tear."""
    return _pulse_run(heavy, mesh_cache, "rupture", 1.06)


def test_a_rim_tears_and_lets_go_with_the_energy_booked(tearing_run):
    """The run tears rim elements, rupture is the first tear, and the elements torn more than
    10 steps before the end have let go entirely. The energy balance: the residual stays
    within 1 % of the input (the issue's bound on an unexplained jump), and what the torn
    elements released is booked, positive, under ``fracture``."""
    res = tearing_run
    assert res.torn_elements, res.summary()
    first_time, first_rim = next(iter(res.torn_elements.values()))
    assert res.limit_states["rupture"] == first_time
    assert res.failed and "tore" in res.failure_detail and first_rim in res.failure_detail
    gone = [e for e, (t, _) in res.torn_elements.items()
            if np.searchsorted(res.time, t) + 10 < res.time.size]
    assert gone and (res.retained[gone] == 0.0).all()
    e = res.energy
    scale = np.abs(e.input).max()
    assert np.abs(e.residual).max() <= 0.01 * scale
    assert np.abs(np.diff(e.residual)).max() <= 0.01 * scale
    # booked releases never negative, to round-off: each is a difference of two sums of the
    # strain energy at one configuration (one came out at -8.6e-12 J of a 7e5 J input)
    assert e.fracture[-1] > 0.0 and np.all(np.diff(e.fracture) >= -1e-15 * scale)
    assert res.rim_damage.shape == (res.time.size, 4)
    assert math.isclose(res.rim_damage[-1].max(), res.rim_damage.max())


@pytest.fixture(scope="module")
def cut_off_run(mesh_cache, heavy):
    """The same pulse run on to 2 s at the containment: the slider gets through the torn rim
    at 1.07 s and what the tear cut off the rim falls free of the bearing."""
    return _pulse_run(heavy, mesh_cache, "containment", 2.0)


def test_torn_off_material_falls_free_and_its_kinetic_energy_is_booked_apart(cut_off_run,
                                                                             model):
    """Material that no element holds any more keeps its lumped mass and weight, so it falls
    (Eq. F69b); ``loose_kinetic`` books its kinetic energy. Checked against the closed form
    of a free fall: once the ground is still (after 1 s) and every piece is off (the last
    tear is at 1.06 s), E = Σ ½ mᵢ |vᵢ + g t ẑ|² is a parabola in t with the leading
    coefficient ½ m g², m the lumped mass of the vertices no element holds (from the mesh,
    not from the run). HHT's Newmark updates are exact under a constant force, so the fit
    on 1.5–2 s is held to 1e-8 (it comes out at 1e-10: the round-off of the fit).
    Before any vertex is loose it is exactly 0, and it never exceeds the whole kinetic
    energy."""
    res, sysm = cut_off_run, model.system
    e = res.energy
    keep = np.zeros(model.mesh.p.shape[1])
    for corner in model.mesh.t:
        np.maximum.at(keep, corner, res.retained)
    loose = np.flatnonzero(keep == 0.0)
    assert loose.size  # the run cuts something off, or this test checks nothing
    red = model.reduction.reduce(np.isin(np.arange(sysm.size),
                                         sysm.fe.basis.nodal_dofs[1, loose]).astype(float))
    mass = float(model.mass[red > 0].sum()) * res.depth  # [kg]
    late = res.time >= 1.5
    curvature = np.polyfit(res.time[late], e.loose_kinetic[late], 2)[0]
    assert curvature == pytest.approx(0.5 * mass * G**2, rel=1e-8)
    first_gone = min(t for t, _ in res.torn_elements.values())
    assert (e.loose_kinetic[res.time <= first_gone] == 0.0).all()
    assert (e.loose_kinetic <= e.kinetic).all()
