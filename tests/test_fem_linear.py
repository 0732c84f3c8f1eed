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
