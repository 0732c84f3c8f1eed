"""Rigid-slider penalty contact (fem.contact, fem.system, fem.dfp): geometry, tangent, Hertz,
the slider at rest, and the quasi-static friction pendulum.

Oracles are written here: the section geometry by hand, the tangent by central finite
differences, plane-strain Hertz (Johnson 1985, §5.6: a = √(4PR/(πE*)), p(x) = p0 √(1 − x²/a²),
p0 = 2P/(πa)), rigid-body statics of the slider, and the friction-pendulum equilibrium of a rigid
slider with concentric spherical faces (derived in the docstring of the last test).
"""

import math

import numpy as np
import pytest

pytest.importorskip("skfem")

from fem import contact as C
from rigid.bearing import DFPBearing, G

SHAPE = C.SliderShape(radius=2.5, half_width=0.2, half_height=0.1)
ROUNDED = C.SliderShape(radius=2.5, half_width=0.2, half_height=0.1, edge_radius=0.01)


def test_penetration_geometry():
    """Depth and face for hand-placed body-frame points (exact to 1e-12 m)."""
    sag = 2.5 - math.sqrt(2.5**2 - 0.2**2)
    pts = np.array(
        [
            [0.0, 0.0, 0.0, 0.199, -0.2 - 1e-3, 0.0],
            [-0.1 - 1e-3, -0.1 + 2e-3, 0.1 - 5e-4, 0.0, 0.0, 0.5],
        ]
    )
    depth, face, normal, _ = C.penetration(SHAPE, pts)
    assert depth[0] == pytest.approx(-1e-3, abs=1e-12)  # below the bottom apex: outside
    assert face[0] == C.BOTTOM and normal[:, 0] == pytest.approx([0.0, -1.0])
    assert depth[1] == pytest.approx(2e-3, abs=1e-12) and face[1] == C.BOTTOM
    assert depth[2] == pytest.approx(5e-4, abs=1e-12) and face[2] == C.TOP
    assert depth[3] == pytest.approx(1e-3, abs=1e-12) and face[3] == C.RIGHT
    assert depth[4] == pytest.approx(-1e-3, abs=1e-12) and face[4] == C.LEFT
    assert depth[5] < 0  # far above the top face
    assert SHAPE.sag == pytest.approx(sag, rel=1e-14)
    # Vertices lie on both a face circle and a side.
    v = SHAPE.vertices
    d, _, _, _ = C.penetration(SHAPE, v)
    assert np.abs(d).max() < 1e-14


def test_rounded_edges_geometry():
    """Rounded edges (Eq. F14a), against the geometry written here: a point a depth t inside
    an edge arc, along its normal at angle φ between the side's and the face's normals, has
    depth t, the arc's normal and ρ = r − t (1e-12 m: round-off on coordinates of 0.2 m); the
    depth is continuous where the arc meets a face (1e-12 m); the sharp vertex is outside by
    |v − f| − r; the rounded section lies inside the sharp one; and r = 0 is the sharp
    section bit for bit."""
    r = ROUNDED.edge_radius
    f = ROUNDED.edge_centres
    cb, ct = ROUNDED.centres
    for k, (sx, centre) in enumerate(((-1, cb), (1, cb), (-1, ct), (1, ct))):
        n_side = np.array([sx, 0.0])
        n_face = (f[:, k] - centre) / np.linalg.norm(f[:, k] - centre)
        a_side, a_face = (math.atan2(n[1], n[0]) for n in (n_side, n_face))
        if a_face - a_side > math.pi:
            a_face -= 2 * math.pi
        elif a_side - a_face > math.pi:
            a_side -= 2 * math.pi
        phi = np.linspace(a_side, a_face, 9)[1:-1]  # the ends belong to either face
        t = np.linspace(-2e-3, 3e-3, 7)
        nu = np.array([np.cos(phi), np.sin(phi)])
        pts = f[:, k, None] + (r - t) * nu
        depth, face, normal, rho = C.penetration(ROUNDED, pts)
        assert np.abs(depth - t).max() < 1e-12
        assert (face == C.EDGES[k]).all()
        assert np.abs(normal - nu).max() < 1e-12 and np.abs(rho - (r - t)).max() < 1e-12
        # across the two ends of the arc: a point just inside the wedge and one just outside
        for n_end in (n_side, n_face):
            tangent = np.array([-n_end[1], n_end[0]])
            p0 = f[:, k] + (r - 1e-3) * n_end
            pair = np.stack([p0 + 1e-9 * tangent, p0 - 1e-9 * tangent], axis=1)
            d_pair, face_pair, _, _ = C.penetration(ROUNDED, pair)
            assert abs(d_pair[0] - d_pair[1]) < 1e-12 and set(face_pair) != {C.EDGES[k]}
    v = ROUNDED.vertices
    d_v, _, _, _ = C.penetration(ROUNDED, v)
    assert np.abs(d_v - (r - np.linalg.norm(v - f, axis=0))).max() < 1e-12
    rng = np.random.default_rng(1)
    pts = rng.uniform([-0.25, -0.12], [0.25, 0.12], (4000, 2)).T
    sharp, _, _, _ = C.penetration(SHAPE, pts)
    rounded, _, _, _ = C.penetration(ROUNDED, pts)
    assert (rounded <= sharp + 1e-15).all() and (rounded < sharp - 1e-4).any()
    zero = C.SliderShape(radius=2.5, half_width=0.2, half_height=0.1, edge_radius=0.0)
    for a, b in zip(C.penetration(SHAPE, pts), C.penetration(zero, pts), strict=True):
        assert np.array_equal(a, b)
    with pytest.raises(ValueError, match="edge_radius"):
        C.SliderShape(radius=2.5, half_width=0.2, half_height=0.1, edge_radius=0.1)


def _random_contacts(friction, n=24, seed=0, shape=SHAPE):
    """Nodes a few µm inside each face of a tilted, shifted slider (and inside each rounded
    edge, if ``shape`` has them)."""
    rng = np.random.default_rng(seed)
    pose = np.array([0.03, 0.101, 0.02])
    cb, ct = SHAPE.centres
    k = n // 4
    ang = rng.uniform(-0.07, 0.07, 2 * k)
    inset = rng.uniform(1e-7, 1e-5, n)
    xi = np.zeros((2, n))
    xi[:, :k] = cb[:, None] + (2.5 - inset[:k]) * np.array([np.sin(ang[:k]), -np.cos(ang[:k])])
    xi[:, k : 2 * k] = ct[:, None] + (2.5 - inset[k : 2 * k]) * np.array(
        [np.sin(ang[k:]), np.cos(ang[k:])]
    )
    xi[:, 2 * k : 3 * k] = [0.2 - inset[2 * k : 3 * k], rng.uniform(-0.08, 0.08, k)]
    xi[:, 3 * k :] = [-0.2 + inset[3 * k :], rng.uniform(-0.08, 0.08, n - 3 * k)]
    if shape.edge_radius > 0:  # one node inside each rounded edge, at the arc's middle
        f = shape.edge_centres
        mid = np.array([np.sign(f[0]), np.sign(f[1])]) / math.sqrt(2)
        edge = f + (shape.edge_radius - rng.uniform(1e-7, 1e-5, 4)) * mid
        xi = np.concatenate([xi, edge], axis=1)
        n += 4
    x = C.rotation(pose[2]) @ xi + pose[:2, None]
    nodes = C.ContactNodes(np.arange(n), np.full(n, 0.01), np.full(n, friction), np.zeros(n, int))
    return x, pose, nodes


@pytest.mark.parametrize("shape", [SHAPE, ROUNDED], ids=["sharp", "rounded"])
@pytest.mark.parametrize("friction", [0.0, 0.05])
def test_tangent_against_finite_differences(friction, shape):
    """K = −∂F/∂d against central differences (step 1e-9 m), for every node's 5 × 5 block,
    with sharp and with rounded edges (nodes on the edge arcs too).

    Frictionless: normal penalty plus the exact curvature term. With friction, every node sticks
    with zero traction at the base point (ξ_n = ξ), where the omitted T·∂τ terms vanish, so the
    tangent must be exact there too. Tolerance 1e-5 relative to the largest entry: central
    differences on forces of ~1e6 N/m with δ ~ µm give truncation ~1e-7.
    """
    x, pose, nodes = _random_contacts(friction, shape=shape)
    xi = C.body_coordinates(x, pose)
    _, face, _, _ = C.penetration(shape, xi)
    if shape.edge_radius > 0:
        assert set(C.EDGES) <= set(face)
    state = C.ContactState(xi, np.zeros(xi.shape[1]), face)
    offset = np.zeros(xi.shape[1])
    base = C.evaluate(shape, nodes, x, pose, state, offset, 2e14, 2e13)
    assert base.active.all()
    assert base.stick.all() == (friction > 0)
    h = 1e-9

    def local_force(i, d):
        xx = x.copy()
        xx[:, i] = d[:2]
        r = C.evaluate(shape, nodes, xx, d[2:], state, offset, 2e14, 2e13)
        # the slider force of node i alone: subtract the others' (unchanged for x-columns)
        return np.concatenate([r.node_force[:, i], r.slider_force])

    worst = 0.0
    for i in range(x.shape[1]):
        d0 = np.concatenate([x[:, i], pose])
        fd = np.zeros((5, 2))
        for j in range(2):  # columns of the node's own dofs: only node i changes
            e = np.zeros(5)
            e[j] = h
            fd[:, j] = -(local_force(i, d0 + e) - local_force(i, d0 - e)) / (2 * h)
        K = base.stiffness[:, :, i]
        worst = max(worst, np.abs(fd - K[:, :2]).max() / np.abs(K).max())
    # slider columns: all nodes respond; compare the summed 3 × 3 block
    fd = np.zeros((3, 3))
    for j in range(3):
        e = np.zeros(3)
        e[j] = h
        fp = C.evaluate(shape, nodes, x, pose + e, state, offset, 2e14, 2e13).slider_force
        fm = C.evaluate(shape, nodes, x, pose - e, state, offset, 2e14, 2e13).slider_force
        fd[:, j] = -(fp - fm) / (2 * h)
    K = base.stiffness[2:, 2:].sum(axis=-1)
    worst = max(worst, np.abs(fd - K).max() / np.abs(K).max())
    assert worst < 1e-5


def test_coulomb_return_map():
    """One node on the slider's flat side: stick while |ε_T L s| ≤ μN, then T = μN opposing
    the slip (closed form, 1e-12 relative)."""
    pose = np.zeros(3)
    L, mu, eps_n, eps_t = 0.01, 0.3, 1e14, 1e13
    nodes = C.ContactNodes(np.array([0]), np.array([L]), np.array([mu]), np.array([0]))
    x0 = np.array([[0.2 - 1e-6], [0.0]])  # 1 µm inside the right side
    state, offset = C.initial_state(SHAPE, x0, pose, adjust=0.0)
    N = eps_n * L * 1e-6
    for slip in (1e-8, -2e-8, 1e-6, -1e-6):
        x = x0 + np.array([[0.0], [slip]])  # move along the side (τ = (0, 1) on the right)
        r = C.evaluate(SHAPE, nodes, x, pose, state, offset, eps_n, eps_t)
        assert r.normal[0] == pytest.approx(N, rel=1e-9)
        trial = -eps_t * L * slip
        expected = trial if abs(trial) <= mu * N else math.copysign(mu * N, trial)
        assert r.tangential[0] == pytest.approx(expected, rel=1e-9)
        assert r.stick[0] == (abs(trial) <= mu * N)
        assert r.node_force[1, 0] == pytest.approx(expected, rel=1e-9)  # along +z


@pytest.mark.parametrize("carry", [False, True])
def test_friction_history_across_a_rounded_edge(carry):
    """A node stuck on the bottom face slips across the tangent boundary onto the rounded edge
    (docs/theory/finite-elements.md, Eqs. F16, F16a): with ``carry_across_edges`` its
    tangential force goes on from the converged one, T = T_n − ε_T L ΔS, else it starts again,
    T = −ε_T L ΔS (closed form, 1e-9 relative: the slips are 1e-7 of the 1e-4 m positions)."""
    pose = np.zeros(3)
    L, mu, eps_n, eps_t = 0.01, 0.3, 1e14, 1e13
    nodes = C.ContactNodes(np.array([0]), np.array([L]), np.array([mu]), np.array([0]))
    centre = ROUNDED.centres[0]  # of the bottom face's circle
    n_f = ROUNDED.edge_centres[:, 1] - centre  # bottom-right edge: its boundary with the face
    boundary = math.atan2(n_f[1], n_f[0])
    depth = 1e-6

    def at(angle):  # a point ``depth`` inside the bottom face's circle (or the edge) at angle
        return (centre + (ROUNDED.radius - depth) * np.array([math.cos(angle),
                                                              math.sin(angle)]))[:, None]

    step = 2e-8 / ROUNDED.radius  # 20 nm along the face
    state, offset = C.initial_state(ROUNDED, at(boundary - step), pose, adjust=0.0)
    first = C.evaluate(ROUNDED, nodes, at(boundary - 2 * step), pose, state, offset, eps_n,
                       eps_t, carry_across_edges=carry)  # converged: stuck on the face
    assert first.state.face[0] == C.BOTTOM and first.stick[0] and first.tangential[0] != 0
    across = C.evaluate(ROUNDED, nodes, at(boundary + step), pose, first.state, offset, eps_n,
                        eps_t, carry_across_edges=carry)
    assert across.state.face[0] == C.EDGES[1] and across.stick[0]
    kept = first.tangential[0] if carry else 0.0
    assert across.tangential[0] == pytest.approx(kept - eps_t * L * across.slip[0], rel=1e-9)
    # the boundary is tangent-continuous only where the edges are rounded
    assert C.tangent_continuous(ROUNDED)[C.EDGES[1], [C.BOTTOM, C.RIGHT]].all()
    assert not C.tangent_continuous(ROUNDED)[C.EDGES[1], [C.TOP, C.LEFT, C.EDGES[0]]].any()
    assert (C.tangent_continuous(SHAPE) == np.eye(8, dtype=bool)).all()


def test_hertz_plane_strain():
    """Rigid cylinder (the slider's bottom face, R = 50 mm) on an elastic half-plane.

    Half model (symmetry at x = 0), graded tensor mesh, h = a/20 under the contact, domain 40a ×
    40a, frictionless, load P = 3.733 MN/m (docs/theory/finite-elements.md, "Oracles used by the
    tests"). Oracle: plane-strain Hertz with E* = E/(1 − ν²) evaluated at the FE's own total normal
    force P (an exact identity of the load). Tolerances (finite-elements.md, "Oracles": 3 %): p(0)
    within 2 % of p0; nodal pressures within 2 % of p0 up to 0.9a (the finite depth and the penalty
    penetration p0/ε_N ≈ 6e-8 m ≪ a shift p by well under 1 %); the last loaded node within one
    element of a.
    """
    from skfem import MeshQuad

    from fem.assembly import PlaneStrainQ1
    from fem.material import Material
    from fem.system import CoupledSystem, Reduction, solve_static

    E, nu, R, P = 200e9, 0.3, 0.05, 3.733e6
    e_star = E / (1 - nu**2)
    a_guess = math.sqrt(4 * P * R / (math.pi * e_star))
    h = a_guess / 20

    def graded(length, n_fine, ratio=1.2):
        x = list(np.arange(n_fine + 1) * h)
        step = h
        while x[-1] < length:
            step *= ratio
            x.append(x[-1] + step)
        return np.array(x)

    ys = -graded(40 * a_guess, 10)[::-1]
    mesh = MeshQuad.init_tensor(graded(40 * a_guess, 30), ys).with_boundaries(
        {
            "top": lambda p: np.isclose(p[1], 0.0),
            "bottom": lambda p: np.isclose(p[1], ys[0]),
            "sym": lambda p: np.isclose(p[0], 0.0),
        }
    )
    fe = PlaneStrainQ1(mesh)
    elastic = Material(E, nu, 1e15, 1e15, 0.0)
    shape = C.SliderShape(R, 0.01, 0.02)
    nodes = C.ContactNodes.from_mesh(mesh, {"top": 0.0})
    system = CoupledSystem(fe, elastic, shape, nodes, [0.0, 0.02, 0.0], 10 * E / h, E / h)
    fixed = np.concatenate(
        [
            fe.basis.get_dofs("bottom").flatten(),
            fe.basis.get_dofs("sym").nodal["u^1"],
            system.slider_dofs[[0, 2]],
        ]
    )
    reduction = Reduction(system.size, fixed=fixed)
    d, state = np.zeros(system.size), system.initial_state()
    f = np.zeros(system.size)
    for k in range(1, 4):  # three load steps: the contact zone grows from one node
        f[system.slider_dofs[1]] = -P / 2 * k / 3
        res = solve_static(system, reduction, d, state, f)
        assert res.converged, res.residuals
        d, state = res.displacement, res.state
    con = res.evaluation.contact
    total = 2 * con.normal.sum()
    # equilibrium of the slider; 1e-3 because Newton's test is relative to the norm of all
    # nodal forces, not to P (the oracle below uses the FE's own total anyway)
    assert total == pytest.approx(P, rel=1e-3)
    a = math.sqrt(4 * total * R / (math.pi * e_star))
    p0 = 2 * total / (math.pi * a)
    x = system.reference[0]
    p = con.normal / nodes.length
    assert p[np.argmin(x)] == pytest.approx(p0, rel=0.02)
    inside = x < 0.9 * a
    exact = p0 * np.sqrt(1 - (x[inside] / a) ** 2)
    assert np.abs(p[inside] - exact).max() < 0.02 * p0
    assert abs(x[con.normal > 0].max() - a) <= h * 1.0001


@pytest.fixture(scope="module")
def heavy_system(mesh_cache):
    from fem.dfp import build_system

    return build_system(
        DFPBearing(),
        mesh_options={"rim_size": 0.01, "coarse_size": 0.04},
        cache_dir=mesh_cache,
    )


def _full_load(model, reduced):
    """A full load vector whose reduction is ``reduced`` (spread evenly over tied dofs)."""
    red = model.reduction
    counts = np.asarray(red.P.sum(axis=0)).ravel()
    return red.P @ (reduced / np.maximum(counts, 1))


def _gravity_step(model):
    from fem.system import solve_static

    system = model.system
    res = solve_static(
        system, model.reduction, np.zeros(system.size), system.initial_state(),
        _full_load(model, model.gravity),
    )
    assert res.converged, res.residuals
    return res


def test_slider_at_rest(heavy_system):
    """Gravity on the 60 MPa bearing (static step). Rigid-body equilibrium of the slider:
    the bottom dish carries W + m_s g, the top dish W (per unit depth, W/depth = p·b), both to
    1e-7 relative (Newton rtol 1e-8); no net horizontal force or moment on the slider (1e-7 of
    W and W·b); by symmetry the slider neither shifts (< 1 µm) nor tilts (< 1e-6 rad). The
    static penetration is of order p/ε_N: the slider sinks by less than 0.1 mm."""
    _check_at_rest(heavy_system)


def test_slider_with_rounded_edges_at_rest(heavy_system, mesh_cache):
    """The same equilibrium, to the same tolerances, with the slider's edges rounded to 20 mm
    (Eq. F14a): the dish nodes under the edges lose contact, the others carry the load on the
    spherical faces."""
    from fem.dfp import build_system

    model = build_system(DFPBearing(), mesh_options={"rim_size": 0.01, "coarse_size": 0.04},
                         edge_radius=0.02, cache_dir=mesh_cache)
    faces = _check_at_rest(model)
    assert set(faces) == {C.BOTTOM, C.TOP}
    assert faces.size < _check_at_rest(heavy_system).size


def _check_at_rest(model):
    """The assertions of :func:`test_slider_at_rest`; returns the faces in contact."""
    b = model.bearing
    res = _gravity_step(model)
    con = res.evaluation.contact
    bottom = model.system.nodes.plate == 0
    W = b.weight / model.depth
    assert W == pytest.approx(b.pressure * b.slider_diameter, rel=1e-12)
    ws = b.slider_mass * G / model.depth
    assert con.node_force[1, bottom].sum() == pytest.approx(-(W + ws), rel=1e-7)
    assert con.node_force[1, ~bottom].sum() == pytest.approx(W, rel=1e-7)
    f = con.slider_force
    assert abs(f[0]) < 1e-7 * W and abs(f[2]) < 1e-7 * W * b.slider_diameter
    pose = model.system.slider_pose(res.displacement)
    assert abs(pose[0]) < 1e-6 and abs(pose[2]) < 1e-6
    assert 0 < b.slider_height / 2 - pose[1] < 1e-4
    return con.state.face[con.active]


def test_friction_pendulum_quasi_static(heavy_system):
    r"""Top plate pushed to u = 0.02 … 0.20 m (displacement control of the superstructure),
    slider free, μ = 0.05 on both dishes, gravity on.

    Oracle (rigid slider, both faces sliding and concentric with their dishes; derived here):
    normal pressures on a face act through its dish centre, the friction tractions μp act
    tangentially at radius R from it. Moments about the bottom dish centre O_b for the slider
    (the top dish centre O_t = O_b + (u, h − 2R), the force of the top plate on the slider
    (H, −W)) give

        (2R − h) H − W u − μR(N_b + N_t) = 0  ⇒  H = W u/(2R − h) + μ W · 2R/(2R − h),

    with N_b ≈ N_t ≈ W. The friction term is 2R/(2R − h) = 1.042 times μW: the friction
    couple μW·h of a rigid slider is carried by the dish reactions (the rigid model's
    vertex-lumped slider gives ≈ 1.045). The Fenz & Constantinou (2006) form W u/R_eff + μW
    assumes an articulated slider and is 2–4 % lower here.

    Each step starts from the exact sliding kinematics (tilt φ = asin(u/(2R − h)), the top
    plate rising 2(R − h/2)(1 − cos φ)), so Newton only corrects µm-level penetrations.
    Tolerance 1 %: N_b + N_t differ from 2W by the slider weight and by cos φ terms (≤ 0.3 %)
    and the dish nodes entering under the slider edge make H ripple by a few 0.1 %.
    """
    from fem.system import solve_static

    model = heavy_system
    b = model.bearing
    system, red = model.system, model.reduction
    res = _gravity_step(model)
    d, state = res.displacement, res.state
    fg = _full_load(model, model.gravity)
    mesh = model.mesh
    nd = system.fe.basis.nodal_dofs
    above = np.unique(
        mesh.t[:, np.concatenate([mesh.subdomains[k] for k in ("top_plate", "top_rim", "block")])]
    )
    arm = b.radius - b.slider_height / 2
    W = b.weight / model.depth
    previous = np.zeros(4)
    for u in np.linspace(0.01, 0.2, 20):
        phi = math.asin(u / (2 * arm))
        now = np.array([u, 2 * arm * (1 - math.cos(phi)), u / 2, arm * (1 - math.cos(phi))])
        guess = d.copy()
        guess[nd[0, above]] += now[0] - previous[0]
        guess[nd[1, above]] += now[1] - previous[1]
        guess[system.slider_dofs] += [now[2] - previous[2], now[3] - previous[3], 0.0]
        guess[system.slider_dofs[2]] = phi
        res = solve_static(system, red, guess, state, fg, {model.top_x: u})
        assert res.converged, (u, res.residuals)
        d, state, previous = res.displacement, res.state, now
        H = red.reduce(res.evaluation.internal_force)[model.top_x]
        expected = W * u / b.effective_radius + b.friction * W * 2 * b.radius / b.effective_radius
        assert H == pytest.approx(expected, rel=0.01), u
        # the slider settles at half the travel (both surfaces slide alike), within 1 mm
        assert system.slider_pose(d)[0] == pytest.approx(u / 2, abs=1e-3)


def test_rounded_edges_are_checked_before_meshing(tmp_path):
    """An edge radius too large for the slider, or rounded edges with vertex contact (which
    needs the sharp vertices), is refused with a clear error before any mesh is built."""
    from fem.dfp import build_system

    with pytest.raises(ValueError, match="edge_radius"):
        build_system(DFPBearing(), edge_radius=0.5, cache_dir=tmp_path)
    with pytest.raises(ValueError, match="vertex_contact needs sharp slider edges"):
        build_system(DFPBearing(), edge_radius=0.01, vertex_contact=True, cache_dir=tmp_path)
    assert not any(tmp_path.iterdir())
