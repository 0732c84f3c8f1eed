"""Newton's linear solver (fem.linear.TangentSolver) against a direct sparse LU of the assembled
tangent (an independent algorithm), on a coarse-mesh state with everything that makes the
tangent differ from the cached elastic one: dish contact (stick), a slider vertex in a rim,
and plastic points in a rim pushed 1 mm sideways.
"""

import numpy as np
import pytest

pytest.importorskip("skfem")
pytest.importorskip("gmsh")

import scipy.sparse as sp
from scipy.sparse.linalg import spsolve

from fem import contact as C
from fem.dfp import build_system
from fem.dynamics import HHTParameters
from fem.geometry import COARSE_MESH
from fem.linear import REFINE_TOL
from rigid.bearing import DFPBearing


@pytest.fixture(scope="module")
def loaded(mesh_cache):
    """A state of the coarse 60 MPa model with contact, a vertex contact and plasticity."""
    from fem.dynamics import Integrator

    bearing = DFPBearing(pressure=60e6)
    model = build_system(bearing, mesh_options=COARSE_MESH, vertex_contact=True,
                         cache_dir=mesh_cache)
    sysm = model.system
    a, state, _ = Integrator(model, lambda t: 0.0).gravity_step()
    d = model.reduction.expand(a)
    # push the +x bottom rim's nodes 1 mm outward, more at the top (bending: yields the root)
    m = model.mesh
    rim = np.unique(m.t[:, m.subdomains["bottom_rim"]])
    rim = rim[m.p[0, rim] > 0]
    z0 = bearing.dish_depth(bearing.rim_radius)
    d[sysm.fe.basis.nodal_dofs[0, rim]] += 1e-3 * (m.p[1, rim] - z0) / bearing.rim_height
    # turn the slider by 0.12 rad, its bottom-right vertex 1.5 mm beyond the +x rim's inner
    # face halfway up the face (1 mm into the face pushed 0.5 mm outward there)
    shape = sysm.shape
    u = C.rotation(0.12) @ shape.vertices[:, 1]
    target = np.array([bearing.rim_radius + 1.5e-3, z0 + 0.5 * bearing.rim_height])
    pose = np.array([*(target - u), 0.12])
    d[sysm.slider_dofs] = pose - sysm.pose
    ev = sysm.evaluate(d, state)
    return model, ev


def direct(model, ev, c0, s, rhs):
    K = model.reduction.reduce_matrix(ev.stiffness) * s + sp.diags(c0 * model.mass)
    return K, spsolve(K.tocsc(), rhs)


def test_state_exercises_every_update(loaded):
    """The fixture's state has active dish nodes, an active vertex and plastic points."""
    _, ev = loaded
    assert ev.contact.active.sum() > 10
    assert ev.vertex is not None and ev.vertex.active.any()
    assert ev.material.plastic.any()


@pytest.mark.parametrize("h", [5e-3, 5e-4])
def test_same_solution_as_direct_lu(loaded, h):
    """For the HHT matrix c₀M + (1 + α)K at two step sizes (two cached factorizations): the
    solution equals the direct LU's to 1e-9 relative (both are backward stable; the matrix's
    condition number here is ≈ 1e6) and the residual is at most REFINE_TOL. A second solve
    with the same active set reuses the cached columns and gives the same answer."""
    from fem.dynamics import Integrator

    model, ev = loaded
    solver = Integrator(model, lambda t: 0.0).solver
    hht = HHTParameters()
    c0, s = 1.0 / (hht.beta * h * h), 1.0 + hht.alpha
    rhs = np.random.default_rng(3).standard_normal(model.reduction.nreduced) * 1e6
    x = solver.solve(ev, c0, s, rhs)
    K, xd = direct(model, ev, c0, s, rhs)
    assert np.linalg.norm(x - xd) <= 1e-9 * np.linalg.norm(xd)
    assert np.linalg.norm(rhs - K @ x) <= REFINE_TOL * np.linalg.norm(rhs)
    assert solver.fallbacks == 0
    again = solver.solve(ev, c0, s, 2 * rhs)
    assert np.linalg.norm(again - 2 * x) <= 1e-12 * np.linalg.norm(2 * x)
    assert solver.factorizations == 1


def test_large_modification_falls_back(loaded):
    """With a capacity below the size of the modified set, the solver solves directly (and
    counts it) and still returns the direct LU's solution."""
    from fem.linear import TangentSolver

    model, ev = loaded
    solver = TangentSolver(model.system, model.reduction, model.mass, capacity=10)
    rhs = np.ones(model.reduction.nreduced)
    x = solver.solve(ev, 1e5, 0.7, rhs)
    _, xd = direct(model, ev, 1e5, 0.7, rhs)
    assert solver.fallbacks == 1
    assert np.allclose(x, xd, rtol=0, atol=1e-12 * np.abs(xd).max())


@pytest.fixture(scope="module")
def turned(mesh_cache):
    """Finite kinematics, the bottom plate turned rigidly by θ about the origin on top of the
    gravity state (every one of its elements elastic with |F − 1| ≈ θ > 0.01), and its +x rim
    then bent outward by ``bend`` [m] at the top (yielding the rim): the evaluation as a
    function of θ and the bend."""
    from fem.dynamics import Integrator

    model = build_system(DFPBearing(pressure=60e6), mesh_options=COARSE_MESH,
                         kinematics="finite", cache_dir=mesh_cache)
    a, state, _ = Integrator(model, lambda t: 0.0).gravity_step()
    d0 = model.reduction.expand(a)
    m = model.mesh
    nodes = np.unique(m.t[:, np.concatenate([m.subdomains[k]
                                             for k in ("bottom_plate", "bottom_rim")])])
    dofs = model.system.fe.basis.nodal_dofs[:, nodes]
    b = model.bearing
    rim = np.unique(m.t[:, m.subdomains["bottom_rim"]])
    rim = rim[m.p[0, rim] > 0]
    z0 = b.dish_depth(b.rim_radius)
    rim_x = model.system.fe.basis.nodal_dofs[0, rim]

    def at(theta, bend=0.0):
        d = d0.copy()
        x = m.p[:, nodes] + d[dofs]
        d[dofs] += C.rotation(theta) @ x - x
        d[rim_x] += bend * ((m.p[1, rim] - z0) / b.rim_height) ** 2
        return model.system.evaluate(d, state)

    return model, at


def _solver_matrix(model, ev, c0, s, replaced, gradient=None):
    """The reduced c₀M + sK the solver stands for at ``ev``: the exact tangent, except the
    elements below ``gradient`` (default ACTIVE_GRADIENT) that do not yield (their small-strain
    elastic block, by design of the low-rank update) and those in ``replaced`` (element → its
    block)."""
    sysm = model.system
    fe, mat = sysm.fe, ev.material
    nel = fe.element_dofs.shape[1]
    blocks = dict(replaced)
    inactive = np.setdiff1d(np.arange(nel), fe.active_elements(mat, gradient))
    for e, k in zip(inactive, fe.element_stiffness(sysm.material.elastic_tangent(), inactive),
                    strict=True):
        blocks.setdefault(int(e), k)
    e = np.array(sorted(blocks))
    delta = np.array([blocks[k] for k in e]) - fe.element_tangent(sysm.material, mat, e)
    dofs = fe.element_dofs[:, e].T
    rows = np.broadcast_to(dofs[:, :, None], delta.shape).ravel()
    cols = np.broadcast_to(dofs[:, None, :], delta.shape).ravel()
    K = ev.stiffness + sp.csr_matrix((delta.ravel(), (rows, cols)), shape=ev.stiffness.shape)
    return model.reduction.reduce_matrix(K) * s + sp.diags(c0 * model.mass)


def test_frozen_tangents(turned, monkeypatch):
    """Eq. F35a. With more elastic elements carrying their own tangent than FREEZE_AFTER
    (lowered to 2 here), the solver refactors with their tangents frozen: at the iterate it
    froze them the solve is the direct LU's of the matrix of the low-rank update without
    freezing (1e-9 relative, as above); at a later iterate, turned further and with the +x rim
    bent until some frozen elements yield, it is the direct LU's of the matrix with the still
    elastic frozen elements' blocks kept from the freeze and the yielding ones exact (1e-9);
    the freezing moves the solution by far more than that (> 1e-4; measured 8e-3). After
    :meth:`thaw` the next solve freezes again, at its own iterate: the unfrozen solution (also
    when no element is left to freeze)."""
    import fem.linear as L
    from fem.dynamics import Integrator

    model, at = turned
    monkeypatch.setattr(L, "FREEZE_AFTER", 2)
    solver = Integrator(model, lambda t: 0.0).solver
    hht = HHTParameters()
    h = 5e-4
    c0, s = 1.0 / (hht.beta * h * h), 1.0 + hht.alpha
    rhs = np.random.default_rng(5).standard_normal(model.reduction.nreduced) * 1e6
    ev = at(0.02)
    x = solver.solve(ev, c0, s, rhs)
    assert solver.freezes == 1
    xd = spsolve(_solver_matrix(model, ev, c0, s, {}).tocsc(), rhs)
    assert np.linalg.norm(x - xd) <= 1e-9 * np.linalg.norm(xd)
    base = solver._bases[(c0, s)]
    frozen = np.flatnonzero(base.frozen)
    assert frozen.size > 2 and not ev.material.plastic[frozen].any()

    later = at(0.03, bend=0.002)
    x2 = solver.solve(later, c0, s, rhs)
    yielding = later.material.plastic[frozen].any(axis=1)
    assert yielding.any() and not yielding.all()
    el = model.system.material.elastic_tangent()
    then = base.blocks + model.system.fe.element_stiffness(el, frozen)
    kept = dict(zip(frozen[~yielding], then[~yielding], strict=True))
    xf = spsolve(_solver_matrix(model, later, c0, s, kept).tocsc(), rhs)
    assert np.linalg.norm(x2 - xf) <= 1e-9 * np.linalg.norm(xf)
    unfrozen = spsolve(_solver_matrix(model, later, c0, s, {}).tocsc(), rhs)
    assert np.linalg.norm(unfrozen - xf) > 1e-4 * np.linalg.norm(xf)
    assert solver.freezes == 1
    # after a thaw (what a failed Newton step calls) the next solve refreezes at its iterate
    solver.thaw()
    x3 = solver.solve(later, c0, s, rhs)
    assert solver.freezes == 2
    assert np.linalg.norm(x3 - unfrozen) <= 1e-9 * np.linalg.norm(unfrozen)
    # and with no elastic element left to freeze, it freezes none
    solver.thaw()
    rest = at(0.0)
    x4 = solver.solve(rest, c0, s, rhs)
    assert solver.freezes == 3 and not solver._bases[(c0, s)].frozen.any()
    x4d = spsolve(_solver_matrix(model, rest, c0, s, {}).tocsc(), rhs)
    assert np.linalg.norm(x4 - x4d) <= 1e-9 * np.linalg.norm(x4d)


def test_torn_solve(turned):
    """Eq. F35b. With elements letting go, the solve is a direct LU of the exact tangent
    except on the elements below TORN_ACTIVE_GRADIENT that do not yield (1e-9 relative, as
    above). The plate is turned by 5e-3 rad, so its elements' gradients (about 7e-3) lie
    between that threshold and ACTIVE_GRADIENT: the matrix with the coarser threshold gives
    a solution farther off than round-off (> 1e-6), so the test tells the two apart. The
    torn solve's sparse entries are the dense low-rank block's, exactly."""
    from fem.dynamics import Integrator
    from fem.linear import TORN_ACTIVE_GRADIENT

    model, at = turned
    sysm = model.system
    fe = sysm.fe
    nel = fe.element_dofs.shape[1]
    intact = (fe.retained, sysm.nodes)
    retained = np.ones(nel)
    rim = model.mesh.subdomains["bottom_rim"]
    retained[rim[:3]] = [0.5, 0.25, 0.0]
    try:
        sysm.erode(retained)
        solver = Integrator(model, lambda t: 0.0).solver
        hht = HHTParameters()
        h = 5e-4
        c0, s = 1.0 / (hht.beta * h * h), 1.0 + hht.alpha
        rhs = np.random.default_rng(6).standard_normal(model.reduction.nreduced) * 1e6
        ev = at(0.005, bend=0.002)
        between = np.setdiff1d(fe.active_elements(ev.material, TORN_ACTIVE_GRADIENT),
                               fe.active_elements(ev.material))
        assert between.size > 10
        x = solver.solve(ev, c0, s, rhs)
        xd = spsolve(_solver_matrix(model, ev, c0, s, {}, TORN_ACTIVE_GRADIENT).tocsc(), rhs)
        assert np.linalg.norm(x - xd) <= 1e-9 * np.linalg.norm(xd)
        coarse = spsolve(_solver_matrix(model, ev, c0, s, {}).tocsc(), rhs)
        assert np.linalg.norm(coarse - xd) > 1e-6 * np.linalg.norm(xd)
        # the torn solve's entries are the dense block's nonzeros, bit for bit and in its order
        S, W, _ = solver.modification(ev, s, gradient=TORN_ACTIVE_GRADIENT)
        S2, rows, cols, values = solver.sparse_modification(ev, s, TORN_ACTIVE_GRADIENT)
        i, j = np.nonzero(W)
        assert S.size > 100 and np.array_equal(S2, S)
        assert np.array_equal(rows, S[i]) and np.array_equal(cols, S[j])
        assert np.array_equal(values, W[i, j])
        # a second solve at the same step size (its elastic part cached) is the same solve
        assert np.array_equal(solver.solve(ev, c0, s, rhs), x)
    finally:
        fe.retained, sysm.nodes = intact
