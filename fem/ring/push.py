"""Static push of the rim as a ring (3-D) or as the plane-strain strip of the same section, to
beyond its limit load: the hinge section's first yield, the hinge, the force at the rupture
strain and the limit load (docs/theory/finite-elements.md, "The rim as a ring", Eqs. F54–F58).

Call :func:`ring_push` with a :class:`Load`: the slider as a rigid cylinder of diameter b in
penalty contact (``Load("cylinder")``), a rigid punch or a uniform pressure on a patch of the
rim's inner face (``Load("punch", width)``, ``Load("pressure", width)``), or the plane-strain
strip under the 2-D push's punch (``Load("strip")``, forces per unit depth).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from rigid.bearing import DFPBearing

from .linear import TangentSolver
from .mesh import DEFAULT, MeshSizes, RingMesh, ring_mesh
from .solid import elastic_matrix, return_map_3d, von_mises_6

__all__ = ["LOADS", "Load", "RingPush", "load_patch_widths", "ring_push"]

#: The push's displacement schedule [m]: increments of 0.05 mm to 2 mm (the hinge section's
#: first yield and the hinge of the 40 mm rim come at 0.2–1 mm), then of 0.5 mm (halved when
#: Newton fails) to the end.
FINE_REACH, FINE_STEP, COARSE_STEP = 2.0e-3, 5.0e-5, 5.0e-4
#: Penalty of the cylinder contact as a multiple of E / (element length at the face) (Eq. F56).
PENALTY_FACTOR = 10.0
#: Newton: the free dofs' residual relative to the reactions, and the iterations of a try.
RTOL, MAX_ITER = 1e-7, 12
#: Halvings of a Newton step in the cylinder's line search.
LINE_SEARCH = 4

LOADS = ("cylinder", "punch", "pressure", "strip")


@dataclass(frozen=True)
class Load:
    """How the rim is pushed.

    Parameters
    ----------
    kind : {"cylinder", "punch", "pressure", "strip"}
        The slider as a rigid cylinder; a rigid punch of the given width guided along x (the
        2-D push's load in 3-D); a uniform radial pressure on a patch of the given width, its
        magnitude controlled by the patch's mean radial displacement; the plane-strain strip
        under the 2-D push's punch.
    width : float [m]
        Punch and pressure: arc length at the inner face, centred on the plane of symmetry.
    full_height : bool
        Load the whole height of the rim's inner face, not its upper half (the free ring's
        closed-form check: a load through the section's centroid).
    """

    kind: str
    width: float = 0.0
    full_height: bool = False

    def __post_init__(self):
        if self.kind not in LOADS:
            raise ValueError(f"Load.kind must be one of {LOADS}, got {self.kind!r}")
        if self.patch and not (math.isfinite(self.width) and self.width > 0):
            raise ValueError(f"a {self.kind} load needs a positive width [m], "
                             f"got {self.width!r}")

    @property
    def patch(self) -> bool:
        """Whether the load acts on a patch of :attr:`width` (punch or pressure)."""
        return self.kind in ("punch", "pressure")

    @property
    def label(self) -> str:
        """E.g. ``cylinder``, ``punch 100 mm``, ``pressure 314 mm``, ``strip``."""
        return f"{self.kind} {self.width * 1e3:.0f} mm" if self.patch else self.kind


def load_patch_widths(bearing: DFPBearing) -> tuple[float, float, float]:
    """The sensitivity patches' widths b/4, πb/4 and b [m] (b the slider diameter)."""
    b = bearing.slider_diameter
    return (b / 4, math.pi * b / 4, b)


@dataclass
class RingPush:
    """A static push's curve and its points (:func:`ring_push`).

    Attributes
    ----------
    load : Load
    displacement : ndarray [m]
        Displacement δ of the punch, the cylinder or the pressure patch (its mean), from 0.
    force : ndarray [N]
        The push's resultant along x: the whole ring's (the half or quarter model's doubled),
        or per unit depth [N/m] for the strip.
    max_plastic_strain, gauge_plastic_strain : ndarray [-]
        The rim's largest equivalent plastic strain at each step, and its largest average
        over a ball of the rim's thickness (the rupture gauge, Eq. F52 in 3-D).
    root_yielded : ndarray [-]
        Fraction of the hinge section's Gauss points that have yielded at each step (Eq. F58).
    first_yield_force, hinge_force, rupture_force, limit_force : float [N or N/m]
        At the hinge section's first yield (its last elastic state scaled to f_y), at the hinge
        (the first step with the hinge section wholly plastic), where the gauge average
        reaches the rupture strain (interpolated; nan if never) and the push's largest force.
    hinge_displacement, rupture_displacement : float [m]
    plastic_arc : float [m]
        Arc length of the rim's root, at its inner face, plastic through the whole section at
        the last step (the 3-D hinge line, the whole ring's; the strip: its depth).
    dofs, increments, factorizations : int
    cpu_time, wall_time : float [s]
    final : dict
        The last step's displacements ``u`` [m], plastic strains ``eq_plastic_strain`` [-] and
        the ``mesh`` (for pictures).
    """

    load: Load
    displacement: np.ndarray
    force: np.ndarray
    max_plastic_strain: np.ndarray
    gauge_plastic_strain: np.ndarray
    root_yielded: np.ndarray
    first_yield_force: float
    hinge_force: float
    hinge_displacement: float
    rupture_force: float
    rupture_displacement: float
    limit_force: float
    plastic_arc: float
    dofs: int
    increments: int
    factorizations: int
    cpu_time: float
    wall_time: float
    final: dict = field(default_factory=dict, repr=False)


def _gauge_operator(solid, elements, radius):
    """Row-normalised average over balls of the given radius [m] of the rim's Gauss points
    (Eq. F52 in 3-D): ``op @ field[elements].ravel()``."""
    x = np.asarray(solid.basis.global_coordinates())[:, elements].reshape(3, -1)
    w = solid.weights[elements].ravel()
    rows, cols = [], []
    for i in range(x.shape[1]):
        near = np.flatnonzero(((x - x[:, i:i + 1]) ** 2).sum(axis=0) <= radius * radius)
        rows.append(np.full(near.size, i))
        cols.append(near)
    rows, cols = np.concatenate(rows), np.concatenate(cols)
    op = sp.csr_matrix((w[cols], (rows, cols)), shape=(x.shape[1], x.shape[1]))
    return sp.diags(1.0 / np.asarray(op.sum(axis=1)).ravel()) @ op


def _radius(x, kind):
    """Distance from the bearing's axis (ring) or the x coordinate (slab) [m]."""
    return np.hypot(x[0], x[1]) if kind == "ring" else x[0]


def _facets_on(mesh, where):
    """Boundary facets all of whose vertices satisfy ``where(x)`` (x of shape (3, n) [m]); a
    facet's midpoint would not do: the ring's faceted inner face lies inside r_in between its
    vertices."""
    facets = mesh.boundary_facets()
    ok = where(mesh.p[:, mesh.facets[:, facets].ravel()]).reshape(mesh.facets.shape[0], -1)
    return facets[ok.all(axis=0)]


def _force_scale(mesh: RingMesh) -> float:
    """What the model's push force is multiplied by: 2 for a half or quarter ring (the other
    half of the load acts on the mirror image), 1 for the whole ring, 1/depth for the slab."""
    if mesh.kind == "slab":
        return 1.0 / (mesh.angles[-1] - mesh.angles[0])
    return 1.0 if mesh.sweep == "full" else 2.0


@dataclass
class _Pressure:
    """A unit pressure on a patch: its nodal forces [N/Pa], the patch's area [m²] (a·u with
    a = forces/area is the patch's mean radial displacement), the forces' x resultant [N/Pa]
    and the current pressure [Pa]."""

    forces: np.ndarray
    area: float
    resultant: float
    value: float = 0.0


def _unit_pressure(solid, facets, kind: str) -> _Pressure:
    """Consistent nodal forces of a unit radial pressure on the facets (away from the axis;
    along +x on the slab)."""
    from skfem import FacetBasis

    fb = FacetBasis(solid.mesh, solid.basis.elem, facets=facets, intorder=5)
    N = np.array([np.asarray(phi[0]) for phi in fb.basis])  # (60, 3, nf, nq)
    X = np.asarray(fb.global_coordinates())
    zero = np.zeros_like(X[0])
    if kind == "ring":
        rho = np.hypot(X[0], X[1])
        direction = np.stack([X[0] / rho, X[1] / rho, zero])
    else:
        direction = np.stack([zero + 1.0, zero, zero])
    dx = np.asarray(fb.dx)
    fe = np.einsum("aieq,ieq->ae", N, direction * dx)
    forces = np.bincount(np.asarray(fb.element_dofs).ravel(), fe.ravel(),
                         minlength=solid.ndofs)
    return _Pressure(forces, float(dx.sum()), float((direction[0] * dx).sum()))


class _Problem:
    """The discrete push: solid, supports, load and the linear solver."""

    def __init__(self, mesh: RingMesh, load: Load, plasticity: bool, backend=None):
        from fem.material import Material

        from .contact import CylinderContact
        from .solid import Solid, SolidState

        b = mesh.bearing
        self.mesh, self.load = mesh, load
        sk = mesh.skfem()
        self.solid = Solid(sk)
        steel = Material.from_bearing(b)
        self.steel = steel if plasticity else steel.elastic()
        self.elastic = elastic_matrix(self.steel)
        self.state = SolidState.virgin(self.solid.point_shape)
        basis = self.solid.basis
        r1, z_root = b.rim_radius, b.dish_depth(b.rim_radius)
        tol = 1e-7
        z_low = z_root + (0.0 if load.full_height else 0.5 * b.rim_height)
        empty = np.array([], dtype=int)
        fixed_x = fixed_y = empty
        if mesh.plate:  # the plate's back face fixed (the 2-D push's support)
            bottom = sk.facets_satisfying(lambda x: np.abs(x[2] + b.plate_thickness) < tol,
                                          boundaries_only=True)
            fixed_all = basis.get_dofs(bottom).all()
        else:  # the free ring: its vertical translation held at one vertex
            fixed_all = basis.nodal_dofs[2, :1]
        if mesh.kind == "slab":  # plane strain: no displacement out of the section's plane
            fixed_y = basis.get_dofs().all(["u^2"])
        elif mesh.sweep in ("half", "quarter"):  # the plane of the push: symmetry
            fixed_y = basis.get_dofs(_facets_on(sk, lambda x: np.abs(x[1]) < tol)).all(["u^2"])
        if mesh.sweep == "quarter":  # the plane normal to the push: symmetry
            fixed_x = basis.get_dofs(_facets_on(sk, lambda x: np.abs(x[0]) < tol)).all(["u^1"])
        half = 0.5 * load.width / r1 + 1e-9 if load.patch else math.inf
        face = _facets_on(sk, lambda x: (np.abs(_radius(x, mesh.kind) - r1) < 1e-9 * r1)
                          & (x[2] > z_low - tol) & (np.abs(np.arctan2(x[1], x[0])) <= half))
        self.contact = self.pressure = None
        self.pushed = empty
        if load.kind == "cylinder":
            size = b.rim_height / mesh.root_quads.size  # element length at the face
            self.contact = CylinderContact(self.solid, face, 0.5 * b.slider_diameter,
                                           PENALTY_FACTOR * b.youngs_modulus / size,
                                           (z_low, b.rim_top))
        elif load.kind == "pressure":
            self.pressure = _unit_pressure(self.solid, face, mesh.kind)
        else:
            self.pushed = basis.get_dofs(face).all(["u^1"])
        self.fixed = np.unique(np.concatenate([fixed_all, fixed_y, fixed_x, self.pushed]))
        self.free = np.setdiff1d(np.arange(self.solid.ndofs), self.fixed)
        self.scale = _force_scale(mesh)
        self.centre0 = r1 - 0.5 * b.slider_diameter
        self.rim = mesh.elements(mesh.rim_quads)
        self.gauge = _gauge_operator(self.solid, self.rim, 0.5 * b.rim_thickness)
        self.hinge_section = mesh.elements(mesh.root_quads, layers=mesh.load_layers)
        self.linear = TangentSolver(backend)
        self._free = None

    def residual(self, u, delta, state, pressure=0.0):
        """Out-of-balance forces [N] and the material's answer at ``u`` [m]."""
        stress, tangent, trial, plastic = return_map_3d(self.steel, self.solid.strain(u), state)
        r = self.solid.internal_force(stress)
        force = None
        if self.contact is not None:
            fc, force = self.contact.force(u, self.centre0 + delta)
            r = r - fc
        elif self.pressure is not None:
            r = r - pressure * self.pressure.forces
            force = pressure * self.pressure.resultant
        else:
            force = float(r[self.pushed].sum())
        return r, tangent, trial, plastic, stress, force

    def newton(self, u, delta, state, guess=None):
        """One increment to ``delta`` [m] from the converged ``u``. The first iterate is
        ``guess`` (the last increment's displacements extrapolated) where given; else the
        prescribed increment enters the first iteration through the converged tangent
        (K_ff Δu_f = −r_f − K_fc Δu_c). A pressure's magnitude is the extra unknown of a
        bordered system (its patch's mean radial displacement = δ). Returns (converged, u,
        state, plastic, stress, force)."""
        u = u.copy() if guess is None else guess.copy()
        du_fixed = np.zeros(self.fixed.size)
        if self.pushed.size:
            du_fixed = np.where(np.isin(self.fixed, self.pushed), delta, 0.0) - u[self.fixed]
        p = self.pressure
        lam = p.value if p is not None else 0.0
        reference = None
        answer = self.residual(u, delta, state, lam)
        for it in range(MAX_ITER + 1):
            r, tangent, trial, plastic, stress, force = answer
            rf = r[self.free]
            norm = np.linalg.norm(rf)
            gap = 0.0 if p is None else p.forces @ u / p.area - delta
            if it > 0:
                reference = reference or max(np.linalg.norm(r[self.fixed]),
                                             abs(force or 0.0), 1.0)
                if norm <= RTOL * reference and abs(gap) <= 1e-9 * max(abs(delta), 1e-9):
                    if p is not None:
                        p.value = lam
                    return True, u, trial, plastic, stress, force
                if norm > 1e3 * reference:  # diverging: the caller cuts the increment
                    break
            extra = (None if self.contact is None
                     else self.contact.element_matrices(u, self.centre0 + delta))
            K = self.solid.stiffness(tangent, plastic, self.elastic, extra)
            Kff = self._free_block(K)
            if it == 0 and self.pushed.size and guess is None:
                rf = rf + K[self.free][:, self.fixed] @ du_fixed
                u[self.fixed] += du_fixed
            if p is None:
                du = self.linear.solve(Kff, -rf)
            else:  # bordered: K du − dλ f = −r, a·du = −gap
                f, a = p.forces[self.free], p.forces[self.free] / p.area
                x = self.linear.solve(Kff, np.column_stack([-rf, f]))
                dlam = (-gap - a @ x[:, 0]) / (a @ x[:, 1])
                du = x[:, 0] + dlam * x[:, 1]
                lam += dlam
            if not np.all(np.isfinite(du)):
                break
            if self.contact is not None:
                u, answer = self._line_search(u, du, delta, state, norm)
            else:
                u[self.free] += du
                answer = self.residual(u, delta, state, lam)
        return False, u, state, None, None, None

    def _free_block(self, K: sp.csr_matrix) -> sp.csr_matrix:
        """K_ff: the free rows and columns of K (whose pattern never changes), their
        positions in K.data found at the first call."""
        if self._free is None:
            marker = sp.csr_matrix((np.arange(1.0, K.nnz + 1), K.indices, K.indptr),
                                   shape=K.shape)[self.free][:, self.free].tocsr()
            marker.sort_indices()
            self._free = (marker.indptr, marker.indices, marker.data.astype(np.int64) - 1)
        indptr, indices, where = self._free
        n = self.free.size
        return sp.csr_matrix((K.data[where], indices, indptr), shape=(n, n))

    def _line_search(self, u, du, delta, state, norm):
        """``u`` [m] moved by the Newton step ``du`` [m], halved until the free residual falls
        below ``norm`` [N] (at most :data:`LINE_SEARCH` times; else the full step), and the
        residual there. The cylinder's contact points switch on and off between iterates; a
        full step that switches many makes Newton cycle (Eq. F57)."""
        step, full = 1.0, None
        for _ in range(LINE_SEARCH + 1):
            trial = u.copy()
            trial[self.free] += step * du
            answer = self.residual(trial, delta, state)
            full = full or (trial, answer)
            if np.linalg.norm(answer[0][self.free]) < norm:
                return trial, answer
            step *= 0.5
        return full


def ring_push(bearing: DFPBearing, load: Load = Load("cylinder"), *,
              sizes: MeshSizes = DEFAULT, displacement: float | None = None,
              plasticity: bool = True, patch_widths=None, mesh: RingMesh | None = None,
              inner_width: float | None = None, backend: str | None = None) -> RingPush:
    """Push the bottom rim outward, statically, at small strain (Eqs. F54–F58).

    Parameters
    ----------
    bearing : DFPBearing
        Rim geometry and steel [m, Pa]; slider diameter b [m].
    load : Load
        ``Load("cylinder")`` (the slider), ``Load("punch", width)``,
        ``Load("pressure", width)`` or ``Load("strip")``.
    sizes : MeshSizes
        The mesh (:data:`fem.ring.mesh.DEFAULT`; ``COARSE``, ``FINE`` for convergence).
    displacement : float [m], optional
        Final δ; default half the rim height (as the 2-D push).
    plasticity : bool
        False keeps the steel elastic.
    patch_widths : sequence of float [m], optional
        Patch edges the ring's mesh is built around; default :func:`load_patch_widths`, so
        that every load of a study runs on one mesh.
    mesh : RingMesh, optional
        A mesh made by :func:`fem.ring.mesh.ring_mesh` (overrides ``sizes``).
    inner_width : float [m], optional
        Width of the plate strip inside the rim (:func:`fem.ring.mesh.ring_mesh`).
    backend : {"pardiso", "superlu"}, optional
        The factorisation (:class:`fem.ring.linear.TangentSolver`).

    Returns
    -------
    RingPush
    """
    cpu0, wall0 = time.process_time(), time.perf_counter()
    delta_end = 0.5 * bearing.rim_height if displacement is None else float(displacement)
    if not (math.isfinite(delta_end) and delta_end > 0):
        raise ValueError(f"displacement must be a positive length [m], got {displacement!r}")
    if mesh is None:
        widths = load_patch_widths(bearing) if patch_widths is None else patch_widths
        mesh = ring_mesh(bearing, sizes=sizes, kind="slab" if load.kind == "strip" else "ring",
                         patch_widths=widths, inner_width=inner_width)
    wanted = "slab" if load.kind == "strip" else "ring"
    if mesh.kind != wanted:
        raise ValueError(f"a {load.kind} load needs a {wanted} mesh, got a {mesh.kind} mesh")
    pb = _Problem(mesh, load, plasticity, backend)
    u = np.zeros(pb.solid.ndofs)
    state = pb.state
    out = {k: [0.0] for k in ("d", "f", "p", "avg", "root")}
    first_yield, q_last = math.nan, 0.0
    hinge = (math.nan, math.nan)
    delta, increments, previous = 0.0, 0, None
    while delta < delta_end * (1 - 1e-12):
        fine = delta < FINE_REACH * (1 - 1e-9)
        target = min(delta + (FINE_STEP if fine else COARSE_STEP), delta_end,
                     FINE_REACH if fine else delta_end)
        while True:
            guess = None
            if previous is not None:  # extrapolate the last increment's displacements
                guess = u + (u - previous[1]) * (target - delta) / (delta - previous[0])
            ok, u_new, trial, plastic, stress, force = pb.newton(u, target, state, guess)
            if not ok and guess is not None:  # then the tangent predictor
                ok, u_new, trial, plastic, stress, force = pb.newton(u, target, state)
            if ok:
                break
            if target - delta < 1e-4 * FINE_STEP:
                raise RuntimeError(f"ring push ({load.label}): Newton did not converge beyond "
                                   f"δ = {delta * 1e3:.4g} mm")
            target = delta + 0.5 * (target - delta)
        increments += 1
        force *= pb.scale
        section_plastic = bool(plastic[pb.hinge_section].any())
        if math.isnan(first_yield) and section_plastic and q_last > 0:
            # the hinge section's last elastic state scaled to f_y (exact where the response
            # is linear up to there)
            first_yield = out["f"][-1] * bearing.yield_stress / q_last
        if not section_plastic:
            q_last = float(von_mises_6(stress[:, pb.hinge_section]).max())
        previous = (delta, u)
        delta, u, state = target, u_new, trial
        p = state.eq_plastic_strain
        frac = float((p[pb.hinge_section] > 0).mean())
        out["d"].append(delta)
        out["f"].append(force)
        out["p"].append(float(p[pb.rim].max()))
        out["avg"].append(float((pb.gauge @ p[pb.rim].ravel()).max()))
        out["root"].append(frac)
        if math.isnan(hinge[0]) and frac >= 1.0:
            hinge = (delta, force)
    d, f, avg = (np.array(out[k]) for k in ("d", "f", "avg"))
    rupture = (math.nan, math.nan)
    if avg.max() >= bearing.rupture_strain:
        k = int(np.flatnonzero(avg >= bearing.rupture_strain)[0])
        rd = float(np.interp(bearing.rupture_strain, avg[k - 1:k + 1], d[k - 1:k + 1]))
        rupture = (rd, float(np.interp(rd, d, f)))
    return RingPush(
        load=load, displacement=d, force=f, max_plastic_strain=np.array(out["p"]),
        gauge_plastic_strain=avg, root_yielded=np.array(out["root"]),
        first_yield_force=float(first_yield), hinge_force=float(hinge[1]),
        hinge_displacement=float(hinge[0]), rupture_force=rupture[1],
        rupture_displacement=rupture[0], limit_force=float(f.max()),
        plastic_arc=_plastic_arc(pb, state), dofs=pb.solid.ndofs, increments=increments,
        factorizations=pb.linear.factorizations, cpu_time=time.process_time() - cpu0,
        wall_time=time.perf_counter() - wall0,
        final={"u": u, "eq_plastic_strain": state.eq_plastic_strain, "mesh": mesh},
    )


def _plastic_arc(pb: _Problem, state) -> float:
    """Arc length [m] at the rim's inner face over which the root row is plastic at every
    Gauss point (the whole ring's; the slab: its depth)."""
    mesh = pb.mesh
    section = mesh.elements(mesh.root_quads).reshape(mesh.layers, -1)
    whole = (state.eq_plastic_strain[section] > 0).all(axis=(1, 2))
    widths = np.diff(mesh.angles)[whole].sum()
    if mesh.kind == "ring":
        return float(pb.scale * mesh.bearing.rim_radius * widths)
    return float(widths)
