"""Element technology checks: fem.assembly against scikit-fem's own forms, and patch tests.

The einsum assembly with Mandel B-arrays is compared with matrices assembled by scikit-fem
from forms written in tensor notation (an independent implementation of the same operator).
"""

import numpy as np
import pytest

pytest.importorskip("skfem")

from skfem import BilinearForm, MeshQuad, asm
from skfem.helpers import ddot, sym_grad, trace
from skfem.models.elasticity import lame_parameters, linear_elasticity

from fem.assembly import PlaneStrainQ1
from fem.material import Material, MaterialState, return_map

E, NU = 200e9, 0.3
ELASTIC = Material(E, NU, 1e30, 1e30, 0.0)


def distorted_mesh(seed=3):
    """A 5 × 4 mesh on [0, 0.5] × [0, 0.3] m with interior nodes moved by up to 30 % of h."""
    m = MeshQuad.init_tensor(np.linspace(0, 0.5, 6), np.linspace(0, 0.3, 5))
    rng = np.random.default_rng(seed)
    p = m.p.copy()
    interior = np.flatnonzero(
        (p[0] > 1e-9) & (p[0] < 0.5 - 1e-9) & (p[1] > 1e-9) & (p[1] < 0.3 - 1e-9)
    )
    p[:, interior] += rng.uniform(-0.3, 0.3, size=(2, interior.size)) * 0.075
    return MeshQuad(p, m.t)


def relative_difference(K1, K2):
    return abs(K1 - K2).max() / abs(K2).max()


def test_full_integration_matches_skfem_linear_elasticity():
    """Without B-bar, K = ∫ Bᵀ C B equals skfem's ``linear_elasticity`` (2 × 2 Gauss) on a
    distorted mesh. In 2-D, skfem's 3-D Lamé parameters *are* plane strain. Tolerance 1e-12
    relative to the largest entry (round-off of two different summation orders)."""
    fe = PlaneStrainQ1(distorted_mesh(), bbar=False)
    K = fe.stiffness(ELASTIC.elastic_tangent())
    K_ref = asm(linear_elasticity(*lame_parameters(E, NU)), fe.basis)
    assert relative_difference(K, K_ref) < 1e-12


@BilinearForm
def mean_dilatation_elasticity(u, v, w):
    """B-bar bilinear form in tensor notation: 2μ dev ε(u) : dev ε(v) + K θ̄(u) θ̄(v), where the
    deviator is the 3-D one of the plane-strain strain (ε_zz = 0) and θ̄ is the element mean of
    div u (docs/theory/finite-elements.md, Eq. F11: cell average with the quadrature weights
    ``dxw``)."""
    lam, mu = lame_parameters(E, NU)
    bulk = lam + 2 * mu / 3
    eu, ev = sym_grad(u), sym_grad(v)
    dxw = np.asarray(w.dxw)

    def mean(x):
        return (x * dxw).sum(-1, keepdims=True) / dxw.sum(-1, keepdims=True)

    dev_dev = ddot(eu, ev) - trace(eu) * trace(ev) / 3
    return 2 * mu * dev_dev + bulk * mean(trace(eu)) * mean(trace(ev))


def test_bbar_matches_mean_dilatation_form():
    """With B-bar, K equals the mean-dilatation form assembled by scikit-fem. Tolerance 1e-12."""
    fe = PlaneStrainQ1(distorted_mesh(), bbar=True)
    K = fe.stiffness(ELASTIC.elastic_tangent())
    K_ref = asm(mean_dilatation_elasticity, fe.basis, dxw=fe.dx)
    assert relative_difference(K, K_ref) < 1e-12
    # ... and it differs from the fully integrated matrix (the test can tell them apart).
    K_full = PlaneStrainQ1(distorted_mesh(), bbar=False).stiffness(ELASTIC.elastic_tangent())
    assert relative_difference(K, K_full) > 1e-3


@pytest.mark.parametrize("bbar", [True, False])
def test_patch_test(bbar):
    """A linear displacement field gives its constant strain at every Gauss point (ε_zz = 0 for
    B-bar too) and zero internal forces at interior nodes of a distorted mesh. Tolerances 1e-12
    relative (round-off): the patch test is passed exactly or not at all."""
    fe = PlaneStrainQ1(distorted_mesh(), bbar=bbar)
    x, y = fe.mesh.p
    grad = np.array([[2e-3, -1e-3], [3e-3, 5e-4]])
    nd = fe.basis.nodal_dofs
    u = np.zeros(fe.ndofs)
    u[nd[0]] = grad[0, 0] * x + grad[0, 1] * y + 1e-4
    u[nd[1]] = grad[1, 0] * x + grad[1, 1] * y - 2e-4
    eps = fe.strain(u)
    expected = np.array([grad[0, 0], grad[1, 1], 0.0, (grad[0, 1] + grad[1, 0]) / np.sqrt(2)])
    assert np.allclose(eps, expected[:, None, None], rtol=0, atol=1e-12 * np.abs(grad).max())
    stress = return_map(ELASTIC, eps, MaterialState.virgin(fe.point_shape)).stress
    f = fe.internal_force(stress)
    boundary = fe.mesh.boundary_nodes()
    interior = np.setdiff1d(np.arange(fe.mesh.nvertices), boundary)
    scale = np.abs(f).max()
    assert scale > 0
    assert np.abs(f[nd[:, interior]]).max() < 1e-12 * scale
    # Internal forces are work-conjugate to the strain: uᵀ f_int = ∫ σ : ε dx.
    energy = np.einsum("ieq,ieq,eq->", stress, eps, fe.dx)
    assert u @ f == pytest.approx(energy, rel=1e-12)


def test_stiffness_is_derivative_of_internal_force():
    """Global tangent = d f_int / d u by central differences, in a plastic state (B-bar, capped
    hardening). Tolerance 1e-6 relative, as for the material tangent: this checks the assembly
    and the scatter of a point-varying (4, 4, nel, nqp) tangent."""
    steel = Material(E, NU, 345e6, 450e6, 0.01)
    fe = PlaneStrainQ1(distorted_mesh(), bbar=True)
    rng = np.random.default_rng(0)
    u = rng.normal(size=fe.ndofs) * 2e-3 * 0.1  # strains of a few 1e-3: widespread yield
    state = MaterialState.virgin(fe.point_shape)
    res = return_map(steel, fe.strain(u), state)
    assert res.plastic.mean() > 0.3
    K = fe.stiffness(res.tangent).toarray()
    h = 1e-10
    cols = rng.choice(fe.ndofs, size=12, replace=False)
    for j in cols:
        du = np.zeros(fe.ndofs)
        du[j] = h
        fp = fe.internal_force(return_map(steel, fe.strain(u + du), state).stress)
        fm = fe.internal_force(return_map(steel, fe.strain(u - du), state).stress)
        fd = (fp - fm) / (2 * h)
        assert np.linalg.norm(fd - K[:, j]) / np.linalg.norm(K[:, j]) < 1e-6
