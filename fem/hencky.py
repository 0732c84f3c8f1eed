r"""Finite-strain J2 plasticity at quadrature points (plane strain): Hencky elasticity with the
exponential-map return, which applies the small-strain radial return of :mod:`fem.material`
unchanged to logarithmic strains, and its consistent tangent by complex-step differentiation
(docs/theory/finite-elements.md, Eqs. F43–F50). Arrays are components first, then any trailing
shape: 2 × 2 tensors ``(2, 2, ...)``, the history C_p⁻¹ as components ``[xx, yy, zz, xy]``,
strains and stresses in Mandel form ``[xx, yy, zz, √2 xy]``.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit

from .material import SQRT_2, Material, material_constants, radial_point

__all__ = ["FiniteState", "HenckyResult", "exp_sym2", "log_sym2", "tangent", "update"]

#: Step of the complex-step derivative [-]: the derivative is exact to O(h²) and has no
#: cancellation error, so any tiny h works; 1e-20 keeps h² far below round-off.
COMPLEX_STEP = 1e-20
#: Below this value of s (the squared relative deviator, see :func:`log_sym2`) the closed forms
#: use their Taylor series; the series' first omitted term is then below 1e-24.
_SERIES = 1e-4


class FiniteState(NamedTuple):
    """Plastic history at quadrature points (never modified in place).

    Attributes
    ----------
    elastic_inverse : ndarray, shape (4, ...) [-]
        C_p⁻¹ = F_p⁻¹ F_p⁻ᵀ as components ``[xx, yy, zz, xy]`` (identity when virgin).
    eq_plastic_strain : ndarray, shape (...) [-]
        Equivalent plastic strain p (logarithmic).
    """

    elastic_inverse: np.ndarray
    eq_plastic_strain: np.ndarray

    @classmethod
    def virgin(cls, shape) -> FiniteState:
        """No plastic deformation at points of the given shape, e.g. ``(nelems, nqp)``."""
        shape = (shape,) if isinstance(shape, (int, np.integer)) else tuple(shape)
        c = np.zeros((4, *shape))
        c[:3] = 1.0
        return cls(c, np.zeros(shape))


class HenckyResult(NamedTuple):
    """Output of :func:`update`.

    Attributes
    ----------
    first_piola : ndarray, shape (2, 2, ...) [Pa]
        P* = (J/J̄) τ̄ F⁻ᵀ, conjugate to the in-plane displacement gradient (per reference
        volume).
    kirchhoff : ndarray, shape (4, ...) [Pa]
        τ̄ in Mandel form (zz included).
    cauchy : ndarray, shape (4, ...) [Pa]
        σ̄ = τ̄/J̄ in Mandel form.
    elastic_strain : ndarray, shape (4, ...) [-]
        ε_e = ½ ln b_e in Mandel form (the Hencky strain of the stress).
    state : FiniteState
        Trial history; commit only once the global iteration has converged.
    plastic : ndarray of bool, shape (...)
    """

    first_piola: np.ndarray
    kirchhoff: np.ndarray
    cauchy: np.ndarray
    elastic_strain: np.ndarray
    state: FiniteState
    plastic: np.ndarray


@njit(cache=True, inline="always")
def _even(s, kind: int):
    """atanh(√s)/√s (kind 0), cosh √s (1) or sinh(√s)/√s (2), analytic in s (real or
    complex): their Taylor series in s below :data:`_SERIES`."""
    if abs(s) < _SERIES:
        if kind == 0:  # Σ s^k/(2k + 1)
            return 1.0 + s / 3.0 + s * s / 5.0
        if kind == 1:  # Σ s^k/(2k)!
            return 1.0 + s / 2.0 + s * s / 24.0
        return 1.0 + s / 6.0 + s * s / 120.0  # Σ s^k/(2k + 1)!
    r = np.sqrt(s)
    if kind == 0:
        return np.arctanh(r) / r
    if kind == 1:
        return np.cosh(r)
    return np.sinh(r) / r


@njit(cache=True)
def log_sym2(xx, yy, xy):
    """ln b of a symmetric positive definite 2 × 2 tensor b = [[xx, xy], [xy, yy]], Eq. F48.

    With m = (xx + yy)/2, the deviator d = b − m·1 and s = (((xx − yy)/2)² + xy²)/m² (so that the
    eigenvalues are m(1 ± √s)):  ln b = ½ ln(det b)·1 + [atanh(√s)/(√s·m)]·d  (derived from the
    spectral form; analytic in the components, real or complex).

    Returns
    -------
    (xx, yy, xy) of ln b [-]
    """
    m = 0.5 * (xx + yy)
    e = 0.5 * (xx - yy)
    iso = 0.5 * np.log(xx * yy - xy * xy)
    g = _even((e * e + xy * xy) / (m * m), 0) / m
    return iso + g * e, iso - g * e, g * xy


@njit(cache=True)
def exp_sym2(xx, yy, xy):
    """exp a of a symmetric 2 × 2 tensor a = [[xx, xy], [xy, yy]], Eq. F48.

    With m = (xx + yy)/2, d = a − m·1 and s = ((xx − yy)/2)² + xy² (d·d = s·1):
    exp a = e^m [cosh(√s)·1 + (sinh(√s)/√s)·d]. Analytic in the components.

    Returns
    -------
    (xx, yy, xy) of exp a [-]
    """
    m = 0.5 * (xx + yy)
    e = 0.5 * (xx - yy)
    s = e * e + xy * xy
    em = np.exp(m)
    c = em * _even(s, 1)
    k = em * _even(s, 2)
    return c + k * e, c - k * e, k * xy


@njit(cache=True)
def _update_points(F, jbar, cinv, p_n, G, K, H, f_y, f_u, p_u, P, tau, eps_e, cnew, p_new,
                   plastic):
    """The exponential-map update (Eqs. F43–F47) at every point (columns) of F (4, n) in the
    order [11, 12, 21, 22]; fills the output arrays."""
    for i in range(F.shape[1]):
        f00, f01, f10, f11 = F[0, i], F[1, i], F[2, i], F[3, i]
        J = f00 * f11 - f01 * f10
        i00, i01, i10, i11 = f11 / J, -f01 / J, -f10 / J, f00 / J
        a2 = (jbar[i] / J) ** (2.0 / 3.0)  # α² of F̄ = αF, its zz stretch α (Eq. F43)
        c0, c1, c2, c3 = cinv[0, i], cinv[1, i], cinv[2, i], cinv[3, i]
        # b_e^tr = F̄ C_p⁻¹ F̄ᵀ (Eq. F44)
        g00 = f00 * c0 + f01 * c3
        g01 = f00 * c3 + f01 * c1
        g10 = f10 * c0 + f11 * c3
        g11 = f10 * c3 + f11 * c1
        lxx, lyy, lxy = log_sym2(a2 * (g00 * f00 + g01 * f01), a2 * (g10 * f10 + g11 * f11),
                                 a2 * (g00 * f10 + g01 * f11))
        e0, e1, e2, e3 = 0.5 * lxx, 0.5 * lyy, 0.5 * np.log(a2 * c2), SQRT_2 * 0.5 * lxy
        # the small-strain return map on the logarithmic trial strain (Eq. F45)
        (t0, t1, t2, t3, d0, d1, d2, d3, p_new[i], plastic[i], _, _) = radial_point(
            e0, e1, e2, e3, p_n[i], G, K, H, f_y, f_u, p_u)
        e0, e1, e2, e3 = e0 - d0, e1 - d1, e2 - d2, e3 - d3
        # b_e = exp(2 ε_e), C_p⁻¹ = F̄⁻¹ b_e F̄⁻ᵀ (Eq. F46)
        bxx, byy, bxy = exp_sym2(2.0 * e0, 2.0 * e1, SQRT_2 * e3)
        h00 = i00 * bxx + i01 * bxy
        h01 = i00 * bxy + i01 * byy
        h10 = i10 * bxx + i11 * bxy
        h11 = i10 * bxy + i11 * byy
        cnew[0, i] = (h00 * i00 + h01 * i01) / a2
        cnew[1, i] = (h10 * i10 + h11 * i11) / a2
        cnew[2, i] = np.exp(2.0 * e2) / a2
        cnew[3, i] = (h00 * i10 + h01 * i11) / a2
        # P* = (J/J̄) τ̄ F⁻ᵀ, P_iJ = (J/J̄) τ_ik (F⁻¹)_Jk (Eq. F47)
        scale = J / jbar[i]
        txy = t3 / SQRT_2
        P[0, i] = (t0 * i00 + txy * i01) * scale
        P[1, i] = (t0 * i10 + txy * i11) * scale
        P[2, i] = (txy * i00 + t1 * i01) * scale
        P[3, i] = (txy * i10 + t1 * i11) * scale
        tau[0, i], tau[1, i], tau[2, i], tau[3, i] = t0, t1, t2, t3
        eps_e[0, i], eps_e[1, i], eps_e[2, i], eps_e[3, i] = e0, e1, e2, e3


def update(material: Material, F, mean_dilatation, state: FiniteState) -> HenckyResult:
    """Stress and trial history for in-plane deformation gradients F from the last converged
    history (the exponential-map return; module docstring).

    Parameters
    ----------
    material : fem.material.Material
    F : ndarray, shape (2, 2, ...) [-]
        In-plane deformation gradient F = 1 + ∇_X u (real, or complex for the tangent).
    mean_dilatation : ndarray, shape (...) [-]
        J̄ of the mean-dilatation element at each point (F̄ = (J̄/J)^{1/3} F); pass J itself
        (``det F``) for the plain, unmodified gradient.
    state : FiniteState
        Converged history (not modified).

    Returns
    -------
    HenckyResult
    """
    F = np.asarray(F)
    jbar = np.asarray(mean_dilatation)
    complex_ = np.iscomplexobj(F) or np.iscomplexobj(jbar)
    dtype = complex if complex_ else float
    shape = F.shape[2:]
    n = int(np.prod(shape))
    Ff = np.ascontiguousarray(F.reshape(4, n), dtype=dtype)
    jf = np.ascontiguousarray(np.broadcast_to(jbar, shape), dtype=dtype).ravel()
    cf = np.ascontiguousarray(np.broadcast_to(state.elastic_inverse, (4, *shape)).reshape(4, n),
                              dtype=float)
    pf = np.ascontiguousarray(np.broadcast_to(state.eq_plastic_strain, shape), dtype=float).ravel()
    P, tau, eps_e, cnew = (np.empty((4, n), dtype=dtype) for _ in range(4))
    p_new = np.empty(n, dtype=dtype)
    plastic = np.empty(n, dtype=np.bool_)
    _update_points(Ff, jf, cf, pf, *material_constants(material), P, tau, eps_e, cnew, p_new,
                   plastic)
    tau = tau.reshape(4, *shape)
    new = FiniteState(cnew.reshape(4, *shape), p_new.reshape(shape))
    return HenckyResult(P.reshape(2, 2, *shape), tau, tau / jf.reshape(shape),
                        eps_e.reshape(4, *shape), new, plastic.reshape(shape))


def tangent(material: Material, F, mean_dilatation, state: FiniteState):
    """Consistent tangent of :func:`update` by complex-step differentiation (the five partial
    derivatives in one vectorised evaluation).

    Returns
    -------
    dP_dF : ndarray, shape (4, 4, ...) [Pa]
        ∂P*_iJ/∂F_kL at fixed J̄, rows and columns in the order ``[11, 12, 21, 22]``.
    dP_dJbar : ndarray, shape (4, ...) [Pa]
        ∂P*_iJ/∂J̄ at fixed F.
    """
    F = np.asarray(F, dtype=float)
    shape = F.shape[2:]
    h = COMPLEX_STEP
    Fc = np.repeat(F[..., None], 5, axis=-1).astype(complex)  # last axis: the 5 directions
    jc = np.repeat(np.asarray(mean_dilatation, dtype=float)[..., None], 5, axis=-1).astype(complex)
    for k in range(4):
        Fc[k // 2, k % 2, ..., k] += 1j * h
    jc[..., 4] += 1j * h
    wide = FiniteState(
        np.repeat(np.asarray(state.elastic_inverse)[..., None], 5, axis=-1),
        np.repeat(np.asarray(state.eq_plastic_strain)[..., None], 5, axis=-1),
    )
    dP = update(material, Fc, jc, wide).first_piola.reshape(4, *shape, 5).imag / h
    return np.moveaxis(dP[..., :4], -1, 1), dP[..., 4]
