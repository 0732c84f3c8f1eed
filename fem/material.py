r"""Plane-strain J2 plasticity with capped linear isotropic hardening at quadrature points: the
material (:class:`Material`), its history, the radial return (one Numba point kernel, real or
complex, shared by the small- and finite-strain models) and the consistent tangent, on Mandel
4-vectors ``[xx, yy, zz, √2·xy]`` with the zz component carried throughout
(docs/theory/finite-elements.md, Eqs. F4–F9).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, NamedTuple

import numpy as np
from numba import njit

if TYPE_CHECKING:  # pragma: no cover - typing only
    from rigid.bearing import DFPBearing

SQRT_2 = math.sqrt(2.0)
SQRT_3_2 = math.sqrt(1.5)

#: Second-order identity as a Mandel vector.
IDENTITY = np.array([1.0, 1.0, 1.0, 0.0])
#: Deviatoric projector P_dev = I − (1/3) 1 ⊗ 1 as a Mandel matrix.
DEVIATORIC_PROJECTOR = np.eye(4) - np.outer(IDENTITY, IDENTITY) / 3.0


@dataclass(frozen=True)
class Material:
    """Isotropic elastoplastic steel, J2 with capped linear isotropic hardening.

    Parameters
    ----------
    youngs_modulus : float [Pa]
        Young's modulus E.
    poisson_ratio : float [-]
        Poisson's ratio ν, 0 ≤ ν < 0.5.
    yield_stress : float [Pa]
        Initial uniaxial yield stress f_y; ``math.inf`` for a linear elastic material
        (:meth:`elastic`).
    ultimate_stress : float [Pa]
        Flow stress at which hardening stops, f_u ≥ f_y; ``math.inf`` for unbounded
        linear hardening.
    hardening_ratio : float [-]
        Post-yield to elastic stiffness ratio E_t/E of the uniaxial curve, 0 ≤ r < 1;
        0 gives perfect plasticity at f_y.
    """

    youngs_modulus: float
    poisson_ratio: float
    yield_stress: float
    ultimate_stress: float
    hardening_ratio: float

    def __post_init__(self):
        if not (math.isfinite(self.youngs_modulus) and self.youngs_modulus > 0):
            raise ValueError(
                f"Material.youngs_modulus must be a positive finite number, "
                f"got {self.youngs_modulus!r}"
            )
        if not self.yield_stress > 0:  # inf allowed: elastic
            raise ValueError(f"Material.yield_stress must be positive, got {self.yield_stress!r}")
        if not 0 <= self.poisson_ratio < 0.5:
            raise ValueError(
                f"Material.poisson_ratio must lie in [0, 0.5), got {self.poisson_ratio!r}"
            )
        if not 0 <= self.hardening_ratio < 1:
            raise ValueError(
                f"Material.hardening_ratio must lie in [0, 1), got {self.hardening_ratio!r}"
            )
        if not self.ultimate_stress >= self.yield_stress:
            raise ValueError(
                f"Material.ultimate_stress ({self.ultimate_stress!r}) must not be below "
                f"yield_stress ({self.yield_stress!r})"
            )

    @classmethod
    def from_bearing(cls, bearing: DFPBearing) -> Material:
        """The rim steel of a :class:`rigid.DFPBearing`.

        Parameters
        ----------
        bearing : rigid.DFPBearing
            Supplies ``youngs_modulus`` [Pa], ``poisson_ratio`` [-], ``yield_stress`` [Pa],
            ``ultimate_stress`` [Pa] and ``hardening_ratio`` [-].
        """
        return cls(
            youngs_modulus=bearing.youngs_modulus,
            poisson_ratio=bearing.poisson_ratio,
            yield_stress=bearing.yield_stress,
            ultimate_stress=bearing.ultimate_stress,
            hardening_ratio=bearing.hardening_ratio,
        )

    def elastic(self) -> Material:
        """The same steel without yield (f_y = f_u = ∞): the return map never leaves the
        elastic branch."""
        return replace(self, yield_stress=math.inf, ultimate_stress=math.inf)

    @property
    def shear_modulus(self) -> float:
        """G = E / (2(1 + ν)) [Pa]."""
        return self.youngs_modulus / (2.0 * (1.0 + self.poisson_ratio))

    @property
    def bulk_modulus(self) -> float:
        """K = E / (3(1 − 2ν)) [Pa]."""
        return self.youngs_modulus / (3.0 * (1.0 - 2.0 * self.poisson_ratio))

    @property
    def tangent_modulus(self) -> float:
        """Post-yield uniaxial tangent modulus E_t = r E [Pa]."""
        return self.hardening_ratio * self.youngs_modulus

    @property
    def plastic_modulus(self) -> float:
        """Plastic modulus H = E E_t / (E − E_t) = dσ_y/dp [Pa]."""
        r = self.hardening_ratio
        return self.youngs_modulus * r / (1.0 - r)

    @property
    def ultimate_plastic_strain(self) -> float:
        """Equivalent plastic strain at the kink, p_u = (f_u − f_y)/H [-] (inf if H = 0)."""
        h = self.plastic_modulus
        if h == 0.0 or math.isinf(self.ultimate_stress):
            return math.inf
        return (self.ultimate_stress - self.yield_stress) / h

    def flow_stress(self, eq_plastic_strain):
        """Current yield stress σ_y(p) = min(f_y + H p, f_u) [Pa] (Eq. F4).

        Parameters
        ----------
        eq_plastic_strain : array_like [-]
            Equivalent plastic strain p ≥ 0.
        """
        p = np.asarray(eq_plastic_strain, dtype=float)
        return np.minimum(self.yield_stress + self.plastic_modulus * p, self.ultimate_stress)

    def elastic_tangent(self) -> np.ndarray:
        """Elasticity matrix C = 3K·(1⊗1)/3 + 2G·P_dev in Mandel form, shape (4, 4) [Pa]
        (Eq. F5)."""
        return (
            self.bulk_modulus * np.outer(IDENTITY, IDENTITY)
            + 2.0 * self.shear_modulus * DEVIATORIC_PROJECTOR
        )


class MaterialState(NamedTuple):
    """History variables at quadrature points (never modified in place).

    Attributes
    ----------
    plastic_strain : ndarray, shape (4, ...) [-]
        Plastic strain ε^p in Mandel form, including ε^p_zz.
    eq_plastic_strain : ndarray, shape (...) [-]
        Equivalent plastic strain p = ∫ √(2/3) ‖dε^p‖.
    """

    plastic_strain: np.ndarray
    eq_plastic_strain: np.ndarray

    @classmethod
    def virgin(cls, shape) -> MaterialState:
        """Zero plastic strain at points of the given shape, e.g. ``(nelems, nqp)``."""
        shape = (shape,) if isinstance(shape, (int, np.integer)) else tuple(shape)
        return cls(np.zeros((4, *shape)), np.zeros(shape))


class ReturnMapResult(NamedTuple):
    """Output of :func:`return_map`, all new arrays.

    Attributes
    ----------
    stress : ndarray, shape (4, ...) [Pa]
        Cauchy stress in Mandel form (σ_zz included).
    tangent : ndarray, shape (4, 4, ...) [Pa]
        Consistent tangent dσ/dε in Mandel form.
    state : MaterialState
        Trial history variables; commit them only once the global iteration has converged.
    plastic : ndarray of bool, shape (...)
        Whether the point is on the plastic branch in this increment.
    """

    stress: np.ndarray
    tangent: np.ndarray
    state: MaterialState
    plastic: np.ndarray


def deviator(tensor: np.ndarray) -> np.ndarray:
    """Deviatoric part of Mandel vectors ``tensor`` of shape (4, ...) (real or complex)."""
    tensor = np.asarray(tensor)
    dev = np.array(tensor, dtype=complex if np.iscomplexobj(tensor) else float, copy=True)
    dev[:3] -= dev[:3].sum(axis=0) / 3.0
    return dev


def von_mises(stress: np.ndarray) -> np.ndarray:
    """Von Mises equivalent stress √(3/2) ‖dev σ‖ [Pa] of Mandel vectors (4, ...)."""
    s = deviator(stress)
    return SQRT_3_2 * np.sqrt(np.einsum("i...,i...->...", s, s))


class RadialReturn(NamedTuple):
    """Output of :func:`radial_return` (all new arrays, real or complex like the input).

    Attributes
    ----------
    stress : ndarray, shape (4, ...) [Pa]
        Stress C : (ε_e^trial − Δε^p) in Mandel form.
    plastic_increment : ndarray, shape (4, ...) [-]
        Δε^p (zero at elastic points).
    eq_plastic_strain : ndarray, shape (...) [-]
        p + Δp.
    plastic : ndarray of bool, shape (...)
        Points on the plastic branch.
    """

    stress: np.ndarray
    plastic_increment: np.ndarray
    eq_plastic_strain: np.ndarray
    plastic: np.ndarray


@njit(cache=True, inline="always")
def radial_point(e0, e1, e2, e3, p_n, G, K, H, f_y, f_u, p_u):
    """Radial return at one point (real or complex elastic trial strain ``e0..e3``, Mandel).

    Returns the stress (4 values), the plastic strain increment (4), p + Δp, whether the point
    is plastic, Δp and q_tr. Eqs. F6–F8; branches are chosen on real parts.
    """
    vol = e0 + e1 + e2
    mean = vol / 3.0
    # Elastic predictor, Eq. F6 (Simo & Hughes 1998, Box 3.2, step 1).
    s0 = 2.0 * G * (e0 - mean)
    s1 = 2.0 * G * (e1 - mean)
    s2 = 2.0 * G * (e2 - mean)
    s3 = 2.0 * G * e3
    norm = np.sqrt(s0 * s0 + s1 * s1 + s2 * s2 + s3 * s3)
    q = SQRT_3_2 * norm
    f = q - min(f_y + H * p_n, f_u)
    zero = 0.0 * e0
    if not f.real > 0.0:
        return (s0 + K * vol, s1 + K * vol, s2 + K * vol, s3, zero, zero, zero, zero,
                p_n + zero, False, zero, q)
    # Plastic corrector, Eq. F7: the consistency condition q_tr − 3GΔp = σ_y(p_n + Δp) is
    # linear on each branch of the capped law (Box 3.2, step 2; de Souza Neto et al. 2008,
    # Box 7.3); hardening branch first, the flat branch if its root passes the kink p_u.
    dp = f / (3.0 * G + H)
    if p_n + dp.real > p_u:
        dp = (q - f_u) / (3.0 * G)
    # Δε^p = Δp √(3/2) N̂, N̂ = s_tr/‖s_tr‖; s = s_tr − 2G Δε^p (Box 3.2, step 3; Eq. F8).
    c = SQRT_3_2 * dp / norm
    d0, d1, d2, d3 = c * s0, c * s1, c * s2, c * s3
    return (s0 - 2.0 * G * d0 + K * vol, s1 - 2.0 * G * d1 + K * vol,
            s2 - 2.0 * G * d2 + K * vol, s3 - 2.0 * G * d3, d0, d1, d2, d3, p_n + dp, True,
            dp, q)


@njit(cache=True)
def _radial_return_points(eps, p_n, G, K, H, f_y, f_u, p_u, stress, d_eps, p_new, plastic,
                          dp, q):
    """:func:`radial_point` at every column of ``eps`` (4, n); fills the output arrays."""
    for i in range(eps.shape[1]):
        (stress[0, i], stress[1, i], stress[2, i], stress[3, i], d_eps[0, i], d_eps[1, i],
         d_eps[2, i], d_eps[3, i], p_new[i], plastic[i], dp[i], q[i]) = radial_point(
            eps[0, i], eps[1, i], eps[2, i], eps[3, i], p_n[i], G, K, H, f_y, f_u, p_u)


def material_constants(material: Material) -> tuple:
    """(G, K, H, f_y, f_u, p_u) of :func:`radial_point` [Pa, Pa, Pa, Pa, Pa, -]."""
    return (material.shear_modulus, material.bulk_modulus, material.plastic_modulus,
            material.yield_stress, material.ultimate_stress, material.ultimate_plastic_strain)


def radial_return(material: Material, elastic_trial: np.ndarray, eq_plastic_strain: np.ndarray,
                  _tangent_data: dict | None = None) -> RadialReturn:
    """Closest-point projection of an elastic trial strain onto the capped J2 yield surface.

    Backward Euler for J2 with capped linear hardening (Simo & Hughes 1998, Box 3.2; de Souza
    Neto et al. 2008, Box 7.3; Eqs. F6–F8), point by point (:func:`radial_point`). The
    small-strain model applies it to ε − ε^p_n; the finite-strain model (:mod:`fem.hencky`)
    to the logarithmic elastic trial strain. Branch decisions use real parts, so a complex
    trial strain (complex-step differentiation) follows the branch of its real part
    analytically.

    Parameters
    ----------
    material : Material
    elastic_trial : ndarray, shape (4, ...) [-]
        Elastic trial strain in Mandel form (real or complex).
    eq_plastic_strain : ndarray, shape (...) [-]
        Equivalent plastic strain p at the start of the increment (real).

    Returns
    -------
    RadialReturn
    """
    eps = np.asarray(elastic_trial)
    dtype = complex if np.iscomplexobj(eps) else float
    shape = eps.shape[1:]
    flat = np.ascontiguousarray(eps.reshape(4, -1), dtype=dtype)
    p_n = np.ascontiguousarray(np.broadcast_to(eq_plastic_strain, shape), dtype=float).ravel()
    n = flat.shape[1]
    stress = np.empty((4, n), dtype=dtype)
    d_eps = np.empty((4, n), dtype=dtype)
    p_new = np.empty(n, dtype=dtype)
    plastic = np.empty(n, dtype=np.bool_)
    dp = np.empty(n, dtype=dtype)
    q = np.empty(n, dtype=dtype)
    _radial_return_points(flat, p_n, *material_constants(material), stress, d_eps, p_new,
                          plastic, dp, q)
    plastic = plastic.reshape(shape)
    if _tangent_data is not None and plastic.any():
        m = plastic.ravel()
        s_dev = deviator(eps).reshape(4, -1)[:, m] * (2.0 * material.shear_modulus)
        _tangent_data.update(
            dp=dp[m], q=q[m], n_hat=s_dev / np.sqrt((s_dev * s_dev).sum(axis=0)),
            h_alg=np.where(p_n[m] + dp[m].real > material.ultimate_plastic_strain, 0.0,
                           material.plastic_modulus))
    return RadialReturn(stress.reshape(4, *shape), d_eps.reshape(4, *shape),
                        p_new.reshape(shape), plastic)


def return_map(
    material: Material, strain: np.ndarray, state: MaterialState
) -> ReturnMapResult:
    """Radial return for a total strain from the last converged state (backward Euler).

    Parameters
    ----------
    material : Material
        Elastoplastic parameters.
    strain : ndarray, shape (4, ...) [-]
        Total strain at the end of the increment, Mandel ``[xx, yy, zz, √2 xy]``; plane strain
        has ``strain[2] == 0``.
    state : MaterialState
        History variables of the last *converged* increment (not modified).

    Returns
    -------
    ReturnMapResult
        Stress [Pa], consistent tangent [Pa], trial state and the plastic mask.
    """
    strain = np.asarray(strain, dtype=float)
    eps_p_n = np.asarray(state.plastic_strain, dtype=float)
    G = material.shear_modulus
    K = material.bulk_modulus
    data: dict = {}
    ret = radial_return(material, strain - eps_p_n, state.eq_plastic_strain, data)
    plastic = ret.plastic
    new_state = MaterialState(eps_p_n + ret.plastic_increment, ret.eq_plastic_strain)
    extra = (1,) * (strain.ndim - 1)
    elastic = material.elastic_tangent().reshape(4, 4, *extra)
    if not plastic.any():  # every point elastic: D = C everywhere (a read-only view)
        tangent = np.broadcast_to(elastic, (4, 4, *strain.shape[1:]))
        return ReturnMapResult(ret.stress, tangent, new_state, plastic)

    # Consistent tangent, Eq. F9 (Simo & Taylor 1985; de Souza Neto et al. 2008, Box 7.4):
    # D = K 1⊗1 + 2G(1 − 3GΔp/q_tr) P_dev + 6G²(Δp/q_tr − 1/(3G + H_alg)) N̂⊗N̂.
    dp, q_m, n_hat, h_alg = data["dp"], data["q"], data["n_hat"], data["h_alg"]
    ratio = dp / q_m
    beta = 6.0 * G * G * (ratio - 1.0 / (3.0 * G + h_alg))
    tangent = np.array(np.broadcast_to(elastic, (4, 4, *strain.shape[1:])))
    dev = 2.0 * G * DEVIATORIC_PROJECTOR
    tangent[:, :, plastic] = (
        (K * np.outer(IDENTITY, IDENTITY))[:, :, None]
        + dev[:, :, None] * (1.0 - 3.0 * G * ratio)
        + beta * n_hat[:, None, :] * n_hat[None, :, :]
    )
    return ReturnMapResult(ret.stress, tangent, new_state, plastic)
