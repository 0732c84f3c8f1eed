"""The 3-D push's Newton machinery (fem.ring): the linear solver's factorisations, the cylinder
contact's tangent, and the line search that keeps the cylinder push on its schedule."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp
import scipy.sparse.linalg as spla

pytest.importorskip("skfem")
pytest.importorskip("gmsh")

from fem.ring import Load, ring_mesh, ring_push
from fem.ring.linear import TangentSolver, default_backend
from fem.ring.mesh import COARSE
from fem.ring.push import COARSE_STEP, FINE_REACH, FINE_STEP, _Problem, load_patch_widths
from rigid import DFPBearing

BEARING = DFPBearing()
BACKENDS = ["superlu"] + (["pardiso"] if default_backend() == "pardiso" else [])


def _laplacian(n: int, shift: float) -> sp.csr_matrix:
    """The 3-D 7-point Laplacian on n³ points plus ``shift``·I: positive definite for a shift
    above −λ_min, indefinite below."""
    d = sp.diags([-1.0, 2.0, -1.0], [-1, 0, 1], shape=(n, n))
    eye = sp.identity(n)
    A = (sp.kron(sp.kron(d, eye), eye) + sp.kron(sp.kron(eye, d), eye)
         + sp.kron(sp.kron(eye, eye), d))
    return (A + shift * sp.identity(n**3)).tocsr()


@pytest.mark.parametrize("backend", BACKENDS)
def test_tangents_of_one_pattern_are_solved_to_round_off(backend):
    """Three positive definite matrices of one pattern (conditions 6–14) and an indefinite one
    (shifted by −0.7 past the smallest eigenvalue 0.36; condition 1 200): x against SciPy's
    general LU to 1e-10: the round-off, condition × machine epsilon ≈ 3e-13, with a margin of
    300. Only the indefinite one leaves Cholesky."""
    solver = TangentSolver(backend)
    b = np.random.default_rng(1).normal(size=8**3)
    for shift in (0.5, 1.0, 2.0, -0.7):
        A = _laplacian(8, shift)
        x = solver.solve(A, b)
        assert x == pytest.approx(spla.spsolve(A.tocsc(), b), rel=1e-10, abs=1e-10)
    if backend == "pardiso":
        assert solver.indefinite == 1
    b2 = np.column_stack([b, 2 * b])  # several right-hand sides, as the pressure's border
    assert solver.solve(A, b2)[:, 1] == pytest.approx(2 * solver.solve(A, b), rel=1e-12)


@pytest.mark.skipif(default_backend() != "pardiso", reason="pypardiso is not installed")
def test_pardiso_analyses_a_pattern_once(monkeypatch):
    """PARDISO's reordering (phase 11) runs once for matrices of one pattern, and again for a
    new pattern."""
    from fem.ring import linear

    phases = []
    real = linear._Pardiso._phase
    monkeypatch.setattr(linear._Pardiso, "_phase",
                        lambda self, phase, b: phases.append(phase) or real(self, phase, b))
    solver = TangentSolver("pardiso")
    b = np.ones(6**3)
    for shift in (0.5, 1.0, 2.0):
        solver.solve(_laplacian(6, shift), b)
    wider = _laplacian(6, 1.0) + sp.diags([0.1, 0.1], [-2, 2], shape=(6**3, 6**3))
    solver.solve(wider.tocsr(), b)
    assert phases.count(11) == 2 and phases.count(22) == 4


def test_cylinder_contact_tangent_against_central_differences():
    """−∂f/∂u of the cylinder's contact, assembled from its element matrices, against central
    differences of its force at a state with the cylinder 3 mm into the face (three facets of
    the coarse mesh pressed) and a random displacement: the difference quotient's truncation
    error is O(h²) with h = 1e-9 m; the measured error is 1.4e-8, so 1e-6 leaves a margin for
    round-off."""
    mesh = ring_mesh(BEARING, sizes=COARSE, patch_widths=load_patch_widths(BEARING))
    pb = _Problem(mesh, Load("cylinder"), plasticity=True)
    rng = np.random.default_rng(0)
    u = rng.normal(size=pb.solid.ndofs) * 1e-5
    centre = pb.centre0 + 3e-3
    elements, _ = pb.contact.element_matrices(u, centre)
    assert elements.size >= 3
    K = pb.contact.stiffness(u, centre)
    v = rng.normal(size=pb.solid.ndofs) * 1e-9
    fd = -(pb.contact.force(u + v, centre)[0] - pb.contact.force(u - v, centre)[0]) / 2
    assert np.linalg.norm(K @ v - fd) <= 1e-6 * np.linalg.norm(fd)


def test_cylinder_push_keeps_its_schedule():
    """The coarse cylinder push to 5 mm takes its increments as scheduled (0.05 mm to 2 mm,
    then 0.5 mm): no increment is cut. Without the line search Newton cycles on the contact
    points switching and cuts the increments ending at 2.5 and 5 mm."""
    end = 5e-3
    push = ring_push(BEARING, Load("cylinder"), sizes=COARSE, displacement=end)
    scheduled = round(FINE_REACH / FINE_STEP) + round((end - FINE_REACH) / COARSE_STEP)
    assert push.increments == scheduled
    assert np.all(np.diff(push.force) > 0)
