"""Newton–Raphson for one quasi-static load increment of elastoplastic plates (small strain or
finite deformation), from the last converged history, whose trial update the caller commits
once converged; with the consistent tangent (docs/theory/finite-elements.md, Eqs. F9, F49) it
converges quadratically (Simo & Hughes 1998, §3.3, Box 3.1)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from skfem import condense, solve

from fem.assembly import PlaneStrainQ1
from fem.material import Material, MaterialState, return_map


@dataclass(frozen=True)
class NewtonResult:
    """Outcome of :func:`solve_increment`.

    Attributes
    ----------
    displacement : ndarray, shape (ndofs,) [m]
        Displacement at the last iterate.
    state : MaterialState or fem.hencky.FiniteState
        Trial history at the last iterate; commit it only if ``converged``.
    stress : ndarray, shape (4, nelems, nqp) [Pa]
        Mandel (Cauchy) stress at the last iterate.
    internal_force : ndarray, shape (ndofs,) [N/m]
        f_int at the last iterate; on constrained dofs it is the reaction.
    converged : bool
        Whether the residual test was met within ``max_iter`` iterations.
    iterations : int
        Number of linear solves performed.
    residuals : tuple of float
        Relative residual norm ‖r_free‖ / max(‖f_ext‖, ‖f_int‖) at each iterate.
    """

    displacement: np.ndarray
    state: MaterialState
    stress: np.ndarray
    internal_force: np.ndarray
    converged: bool
    iterations: int
    residuals: tuple[float, ...]


def solve_increment(
    discretisation: PlaneStrainQ1,
    material: Material,
    state: MaterialState,
    displacement: np.ndarray,
    external_force: np.ndarray,
    fixed_dofs: np.ndarray,
    fixed_values: np.ndarray | float = 0.0,
    *,
    rtol: float = 1e-9,
    max_iter: int = 25,
) -> NewtonResult:
    """Solve f_int(u) = f_ext with Dirichlet values for one load increment.

    Parameters
    ----------
    discretisation : PlaneStrainQ1 or fem.finite_element.FiniteStrainQ1
        Element technology and assembly (small strain, or finite deformation).
    material : Material
        Elastoplastic parameters (the same at every quadrature point).
    state : MaterialState or fem.hencky.FiniteState
        Converged history at the start of the increment, arrays of shape (…, nelems, nqp)
        (:class:`~fem.hencky.FiniteState` with finite deformation).
    displacement : ndarray, shape (ndofs,) [m]
        Converged displacement at the start of the increment (initial iterate).
    external_force : ndarray, shape (ndofs,) [N/m]
        Consistent nodal forces at the end of the increment, per unit thickness.
    fixed_dofs : ndarray of int
        Constrained degrees of freedom.
    fixed_values : ndarray or float [m]
        Their prescribed displacements at the end of the increment.
    rtol : float [-]
        Convergence when ‖r_free‖ ≤ rtol · max(‖f_ext‖, ‖f_int‖) (the second norm includes
        reactions, so displacement-controlled increments have a scale too).
    max_iter : int
        Maximum number of Newton iterations.

    Returns
    -------
    NewtonResult
    """
    fixed_dofs = np.asarray(fixed_dofs, dtype=np.int64)
    u = np.array(displacement, dtype=float, copy=True)
    # First iterate imposes the Dirichlet increment through the tangent (consistent predictor).
    du_fixed = np.zeros_like(u)
    du_fixed[fixed_dofs] = np.broadcast_to(fixed_values, fixed_dofs.shape) - u[fixed_dofs]
    pending_bc = bool(np.any(du_fixed[fixed_dofs] != 0.0))
    free = np.setdiff1d(np.arange(u.size), fixed_dofs)
    f_ext_norm = np.linalg.norm(external_force)
    residuals = []
    iterations = 0
    finite = getattr(discretisation, "kinematics", "small") == "finite"
    while True:
        if finite:
            res, f_int = discretisation.evaluate(material, u, state)
        else:
            res = return_map(material, discretisation.strain(u), state)
            f_int = discretisation.internal_force(res.stress)
        r = external_force - f_int
        scale = max(f_ext_norm, np.linalg.norm(f_int))
        if not np.isfinite(f_int).all():  # an invalid iterate (inverted elements): diverged
            rel = math.inf
        else:
            rel = np.linalg.norm(r[free]) / scale if scale > 0 else 0.0
        residuals.append(float(rel))
        converged = not pending_bc and rel <= rtol
        if converged or iterations >= max_iter or not np.isfinite(rel):
            return NewtonResult(
                u, res.state, res.stress, f_int, bool(converged), iterations, tuple(residuals)
            )
        K = (discretisation.finite_stiffness(material, res) if finite
             else discretisation.stiffness(res.tangent))
        u = u + solve(*condense(K, r, x=du_fixed, D=fixed_dofs))
        du_fixed[:] = 0.0
        pending_bc = False
        iterations += 1
