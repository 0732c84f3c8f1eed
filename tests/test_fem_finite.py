"""Finite deformation of the FE model: the Hencky/exponential-map update (fem.hencky) and the
mean-dilatation element (fem.finite_element), docs/theory/finite-elements.md, Eqs. F43–F50.

Oracles: SciPy's ``logm``/``expm`` for the closed-form 2 × 2 logarithm and exponential; central
finite differences for the complex-step tangents; the B-bar elastic stiffness (the element's
exact linearisation at u = 0); the small-strain return map along the same logarithmic strain
path (the model's exact reduction for fixed principal axes, Simo 1992); frame indifference
under rigid rotations; and, in dynamics, the small-strain model before the first hinge.
"""

import math

import numpy as np
import pytest
import scipy.linalg as sl

pytest.importorskip("skfem")

from skfem import MeshQuad

from fem.finite_element import FiniteStrainQ1
from fem.hencky import FiniteState, exp_sym2, log_sym2, tangent, update
from fem.material import SQRT_2, Material, MaterialState, return_map

STEEL = Material(200e9, 0.3, 345e6, 450e6, 0.01)  # the bearing's steel (paper values)
RNG = np.random.default_rng(2026)


def sym(xx, yy, xy):
    return np.array([[xx, xy], [xy, yy]])


@pytest.mark.filterwarnings("ignore:logm result may be inaccurate")  # its estimate: ≤ 5e-13
@pytest.mark.parametrize("scale", [1e-7, 0.3, 1.0])
def test_log_and_exp_match_scipy(scale):
    """F48 against SciPy's Padé/Schur ``logm`` and ``expm`` on random symmetric positive
    definite tensors, from nearly isotropic (where the closed form switches to its series) to
    log-eigenvalues of ±3 (stretches of 20, far beyond any use here). Tolerance 1e-12 relative
    (1e-13 absolute near zero): both methods lose accuracy in proportion to the condition
    λ_max/λ_min of b (≤ e^12 here), so a few 1e-13 is their round-off."""
    for _ in range(20):
        a = scale * RNG.normal(size=(2, 2))
        b = sl.expm(a + a.T)  # SPD with log-eigenvalues of size `scale`
        log = sl.logm(b).real
        np.testing.assert_allclose(sym(*log_sym2(b[0, 0], b[1, 1], b[0, 1])), log, rtol=1e-12,
                                   atol=1e-13)
        np.testing.assert_allclose(sym(*exp_sym2(log[0, 0], log[1, 1], log[0, 1])), b,
                                   rtol=1e-13, atol=1e-13)


def _random_gradients(shape, size):
    return np.eye(2).reshape(2, 2, *([1] * len(shape))) + size * RNG.normal(size=(2, 2, *shape))


def test_complex_step_tangent_matches_finite_differences():
    """F50: the complex-step derivatives of P* with respect to F and J̄ against central
    differences (h = 1e-7), on points that yield (5 % random gradients of virgin steel, all
    plastic). Tolerance 1e-6 of the largest modulus: the differences' own truncation and
    round-off error (measured 1e-8)."""
    F = _random_gradients((3, 4), 0.05)
    J = F[0, 0] * F[1, 1] - F[0, 1] * F[1, 0]
    state = FiniteState.virgin((3, 4))
    assert update(STEEL, F, J, state).plastic.all()
    dP_dF, dP_dJ = tangent(STEEL, F, J, state)
    h = 1e-7
    for k in range(4):
        Fp, Fm = F.copy(), F.copy()
        Fp[k // 2, k % 2] += h
        Fm[k // 2, k % 2] -= h
        fd = (update(STEEL, Fp, J, state).first_piola
              - update(STEEL, Fm, J, state).first_piola).reshape(4, 3, 4) / (2 * h)
        np.testing.assert_allclose(dP_dF[:, k], fd, atol=1e-6 * np.abs(dP_dF).max())
    fd = (update(STEEL, F, J + h, state).first_piola
          - update(STEEL, F, J - h, state).first_piola).reshape(4, 3, 4) / (2 * h)
    np.testing.assert_allclose(dP_dJ, fd, atol=1e-6 * np.abs(dP_dJ).max())


def test_fixed_principal_axes_reduce_to_the_small_strain_model_in_log_strains():
    """For stretches along fixed axes the exponential-map model *is* the small-strain model
    written in logarithmic strains (Simo 1992): along a non-proportional path of principal
    stretches (to 40 % strain, unloading included) the Kirchhoff stress equals the small-strain
    return map's stress for the strains ln λ, and the plastic strains agree, step by step.
    Tolerance 1e-9 relative: round-off in ln/exp."""
    path = [(1.002, 0.999), (1.02, 0.99), (1.1, 0.95), (1.25, 0.9), (1.4, 0.95), (1.3, 1.0),
            (1.35, 0.8)]
    finite = FiniteState.virgin(1)
    small = MaterialState.virgin(1)
    for l1, l2 in path:
        F = np.array([[l1, 0.0], [0.0, l2]]).reshape(2, 2, 1)
        res = update(STEEL, F, F[0, 0] * F[1, 1], finite)
        ref = return_map(STEEL, np.array([[math.log(l1)], [math.log(l2)], [0.0], [0.0]]), small)
        np.testing.assert_allclose(res.kirchhoff, ref.stress, rtol=1e-9, atol=1e-9 * 345e6)
        np.testing.assert_allclose(res.state.eq_plastic_strain, ref.state.eq_plastic_strain,
                                   rtol=1e-9, atol=1e-12)
        finite, small = res.state, ref.state
    assert small.eq_plastic_strain[0] > 0.3  # the path went deep into the plastic range


def test_rigid_rotations_rotate_the_stress():
    """Frame indifference: σ(QF) = Q σ(F) Qᵀ for rotations of 0.3, 1 and 3 rad after a plastic
    deformation (from a history that is itself plastic). Tolerance 1e-11 of the stress: the
    update only sees F̄ C_p⁻¹ F̄ᵀ, so only round-off separates the two."""
    F1 = _random_gradients((5,), 0.05)
    J1 = F1[0, 0] * F1[1, 1] - F1[0, 1] * F1[1, 0]
    history = update(STEEL, F1, J1, FiniteState.virgin(5)).state
    F = F1 + 0.02 * RNG.normal(size=(2, 2, 5))
    J = F[0, 0] * F[1, 1] - F[0, 1] * F[1, 0]
    base = update(STEEL, F, J, history)
    assert base.plastic.all()

    def full(s):
        return np.array([[s[0], s[3] / SQRT_2], [s[3] / SQRT_2, s[1]]])

    for angle in (0.3, 1.0, 3.0):
        Q = np.array([[math.cos(angle), -math.sin(angle)], [math.sin(angle), math.cos(angle)]])
        rotated = update(STEEL, np.einsum("ij,jkn->ikn", Q, F), J, history)
        expected = np.einsum("ij,jkn,lk->iln", Q, full(base.cauchy), Q)
        np.testing.assert_allclose(full(rotated.cauchy), expected,
                                   atol=1e-11 * np.abs(base.cauchy).max())
        np.testing.assert_allclose(rotated.cauchy[2], base.cauchy[2],
                                   atol=1e-11 * np.abs(base.cauchy).max())


@pytest.fixture(scope="module")
def patch():
    """A distorted 3 × 3 patch of Q1 elements, 40 × 35 mm (the rim's size)."""
    m = MeshQuad.init_tensor(np.linspace(0, 0.04, 4), np.linspace(0, 0.035, 4))
    p = m.p.copy()
    inner = (p[0] > 0) & (p[0] < 0.04) & (p[1] > 0) & (p[1] < 0.035)
    p[:, inner] += 0.002 * np.random.default_rng(1).normal(size=(2, inner.sum()))
    return FiniteStrainQ1(MeshQuad(p, m.t))


def test_element_linearises_to_b_bar(patch):
    """F43: at u = 0 the mean-dilatation element's consistent tangent is the small-strain B-bar
    elastic stiffness, entry by entry (tolerance 1e-12 of the largest entry: round-off), and
    there is no internal force."""
    ev, f = patch.evaluate(STEEL, np.zeros(patch.ndofs), FiniteState.virgin(patch.point_shape))
    K = patch.finite_stiffness(STEEL, ev).toarray()
    K_bbar = patch.stiffness(STEEL.elastic_tangent()).toarray()
    np.testing.assert_allclose(K, K_bbar, atol=1e-12 * np.abs(K_bbar).max())
    assert not f.any()


def test_element_tangent_is_the_derivative_of_the_force(patch):
    """F49 against central differences of the internal force (h = 1e-9 m) after a rotation of
    0.6 rad, a 30 % shear and a random perturbation, every point yielding. Tolerance 1e-6 of the
    largest entry (the differences' own error; measured 2e-9)."""
    X = patch.mesh.p
    Q = np.array([[math.cos(0.6), -math.sin(0.6)], [math.sin(0.6), math.cos(0.6)]])
    x = Q @ np.array([[1.0, 0.3], [0.0, 1.1]]) @ X
    nd = patch.basis.nodal_dofs
    u = np.zeros(patch.ndofs)
    u[nd[0]], u[nd[1]] = x[0] - X[0], x[1] - X[1]
    u += 1e-4 * np.random.default_rng(3).normal(size=u.size)
    state = FiniteState.virgin(patch.point_shape)
    ev, _ = patch.evaluate(STEEL, u, state)
    assert ev.plastic.all()
    K = patch.finite_stiffness(STEEL, ev).toarray()
    h = 1e-9
    for j in range(patch.ndofs):
        up, um = u.copy(), u.copy()
        up[j] += h
        um[j] -= h
        fd = (patch.evaluate(STEEL, up, state)[1] - patch.evaluate(STEEL, um, state)[1]) / (2 * h)
        np.testing.assert_allclose(K[:, j], fd, atol=1e-6 * np.abs(K).max())
