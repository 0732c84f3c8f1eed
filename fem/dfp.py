r"""The DFP bearing as a plane-strain FE system: mesh, plates and rims (small strain or finite
deformation), the rigid slider and its contacts, the supported block tied to two master dofs,
lumped masses, weights and the ground's influence vector, all per unit out-of-plane depth
πb/4 (docs/theory/finite-elements.md, Eqs. F1–F3, F21–F22).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from rigid.bearing import DFPBearing, G

from . import contact as C
from .contact.exposed import with_rim_vertices

CONTACT_BOUNDARIES = ("dish", "rim_inner", "rim_top")
#: Kinematics of the plates and rims: small strain or finite deformation.
KINEMATICS = ("small", "finite")


@dataclass
class DFPSystem:
    """Everything the time integrator needs for one bearing (see :func:`build_system`).

    Attributes
    ----------
    bearing : rigid.DFPBearing
    depth : float [m]
        Out-of-plane thickness.
    mesh : skfem.MeshQuad1
    system : fem.system.CoupledSystem
    reduction : fem.system.Reduction
    mass : ndarray, shape (nreduced,) [kg/m, kg·m²/m]
        Lumped (diagonal) mass of the reduced dofs.
    gravity : ndarray, shape (nreduced,) [N/m]
        Weight vector −M r_z g (reduced).
    influence : ndarray, shape (nreduced,) [-]
        Ground influence vector r_x: 1 on horizontal translations, 0 elsewhere; the ground
        load is −M r_x a_g.
    top_x, top_z : int
        Reduced indices of the superstructure masters.
    slider : ndarray of int, shape (3,)
        Reduced indices of (X, Z, Θ).
    rim_roots : dict
        Rim name ("bottom -x", "bottom +x", "top -x", "top +x") → indices of the elements
        of the first row above that rim's root, across its thickness (hinge criterion).
    """

    bearing: DFPBearing
    depth: float
    mesh: object
    system: object
    reduction: object
    mass: np.ndarray
    gravity: np.ndarray
    influence: np.ndarray
    top_x: int
    top_z: int
    slider: np.ndarray
    rim_roots: dict


def out_of_plane_depth(bearing: DFPBearing) -> float:
    """Depth of the plane-strain model, A/b = πb/4 [m] (p·b·depth = W; Eqs. F1–F2)."""
    return bearing.slider_area / bearing.slider_diameter


def build_system(
    bearing: DFPBearing,
    *,
    mesh_options: dict | None = None,
    penalty_factor: float = 10.0,
    tangential_ratio: float = 0.1,
    vertex_contact: bool = False,
    plasticity: bool = True,
    kinematics: str = "small",
    edge_radius: float = 0.0,
    rim_depth: float | None = None,
    uncovered_rims: bool = False,
    cache_dir=None,
) -> DFPSystem:
    """Assemble the plane-strain DFP model of a bearing.

    Parameters
    ----------
    bearing : rigid.DFPBearing
    mesh_options : dict, optional
        Keyword arguments of :func:`fem.geometry.build_mesh` (``rim_size``, ``contact_size``,
        ``coarse_size``, ``block_height`` [m]).
    penalty_factor : float [-]
        ε_N = factor · E / h_c, h_c the mean dish facet length (docs/theory/finite-elements.md,
        Eq. F15).
    tangential_ratio : float [-]
        ε_T / ε_N (Eq. F16).
    vertex_contact : bool
        Also make the slider's four vertices contact points against the rims' inner faces and
        tops (:func:`fem.contact.vertex_contact`). Off by default: see :mod:`fem.model`.
    plasticity : bool
        The bearing's elastoplastic steel (default); False keeps it linear elastic
        (:meth:`fem.material.Material.elastic`), the FE counterpart of the rigid model's rims
        that cannot yield.
    edge_radius : float [m]
        Radius of the slider's rounded edges (:class:`fem.contact.SliderShape`; 0: sharp).
        Not with ``vertex_contact``, which makes the sharp vertices contact points.
    kinematics : {"small", "finite"}
        Small strain (Q1 B-bar, :mod:`fem.assembly`) or finite deformation of the plates and
        rims (mean-dilatation Q1 with Hencky J2, :mod:`fem.finite_element`).
    rim_depth : float [m], optional
        Out-of-plane depth of the rims' steel, when it differs from the model's depth πb/4:
        the 3-D rim's effective depth (:func:`fem.effective_rim_depth`; Eq. F59).
    uncovered_rims : bool
        Make every vertex of the rims a contact node, so that the faces which eroded rim
        elements uncover carry contact (:mod:`fem.contact.exposed`, Eq. F68c); default False:
        the rims' inner faces and tops only.
    cache_dir : path-like, optional
        Mesh cache.

    Returns
    -------
    DFPSystem
    """

    from .assembly import PlaneStrainQ1
    from .finite_element import FiniteStrainQ1
    from .geometry import build_mesh
    from .material import Material
    from .system import CoupledSystem, Reduction

    if edge_radius > 0.0 and vertex_contact:
        raise ValueError("vertex_contact needs sharp slider edges (edge_radius = 0)")
    shape = C.SliderShape.from_bearing(bearing, edge_radius)  # checked before meshing
    dfp = build_mesh(bearing, cache_dir=cache_dir, **(mesh_options or {}))
    m = dfp.mesh
    if kinematics not in KINEMATICS:
        raise ValueError(f"kinematics must be 'small' or 'finite', got {kinematics!r}")
    depth = out_of_plane_depth(bearing)
    thickness = _rim_thickness_factors(m, depth, rim_depth)
    fe = (FiniteStrainQ1(m, thickness=thickness) if kinematics == "finite"
          else PlaneStrainQ1(m, thickness=thickness))

    boundaries = {}
    for plate in ("bottom", "top"):
        for name in CONTACT_BOUNDARIES:
            mu = bearing.friction if name == "dish" else bearing.rim_friction
            boundaries[f"{plate}_{name}"] = mu
    rims = [f"{plate}_{name}" for plate in ("bottom", "top") for name in ("rim_inner", "rim_top")]
    nodes = C.ContactNodes.from_mesh(
        m, boundaries, vertex_boundaries=rims if vertex_contact else ()
    )
    surface = None
    if uncovered_rims:
        nodes, surface = with_rim_vertices(m, nodes, boundaries, bearing.rim_friction)
    dish = m.facets[:, m.boundaries["bottom_dish"]]
    h_c = float(np.mean(np.linalg.norm(m.p[:, dish[1]] - m.p[:, dish[0]], axis=0)))
    eps_n = penalty_factor * bearing.youngs_modulus / h_c
    steel = Material.from_bearing(bearing)
    system = CoupledSystem(
        fe, steel if plasticity else steel.elastic(), shape, nodes,
        pose=[0.0, bearing.slider_height / 2, 0.0],
        penalty=eps_n, tangential_penalty=tangential_ratio * eps_n,
        vertex_depth=bearing.rim_thickness / 2, surface=surface,
    )

    nd = fe.basis.nodal_dofs
    support = np.unique(m.facets[:, m.boundaries["support"]])
    top = np.unique(m.facets[:, m.boundaries["block_top"]])
    reduction = Reduction(system.size, fixed=nd[:, support].ravel(), ties=(nd[0, top], nd[1, top]))

    mass, gravity, influence = _mass_and_loads(bearing, m, fe, system, reduction, depth)
    top_x, top_z = (int(k) for k in reduction.masters)
    slider = np.array([reduction.index(k) for k in system.slider_dofs])

    return DFPSystem(
        bearing, depth, m, system, reduction, mass, gravity, influence, top_x, top_z, slider,
        rim_root_rows(m, bearing),
    )


def _rim_thickness_factors(mesh, depth: float, rim_depth: float | None):
    """Relative thickness of every element (Eq. F59): rim_depth/depth in both plates' rims, 1
    elsewhere; None when the rims have the model's depth."""
    if rim_depth is None:
        return None
    if not (math.isfinite(rim_depth) and rim_depth > 0):
        raise ValueError(f"rim_depth must be a positive length [m], got {rim_depth!r}")
    thickness = np.ones(mesh.t.shape[1])
    for sub in ("bottom_rim", "top_rim"):
        thickness[mesh.subdomains[sub]] = rim_depth / depth
    return thickness


def rim_root_rows(mesh, bearing: DFPBearing, plates=("bottom", "top")) -> dict:
    """Elements of the first row above each rim root (inside the rim), per rim (the hinge
    criterion's section, docs/theory/finite-elements.md, Eq. F36).

    The rims are meshed structured (``meshes/dfp.geo``), so the first row is the set of rim
    elements whose centroid lies within one row height of the root line.

    Parameters
    ----------
    mesh : skfem.MeshQuad1
        With the subdomains ``bottom_rim`` and/or ``top_rim``.
    bearing : rigid.DFPBearing
    plates : sequence of {"bottom", "top"}

    Returns
    -------
    dict
        Rim name ("bottom -x", "bottom +x", "top -x", "top +x") → element indices.
    """
    z_root = bearing.dish_depth(bearing.rim_radius)
    out = {}
    for plate, sub, level, sign in (
        ("bottom", "bottom_rim", z_root, 1.0),
        ("top", "top_rim", bearing.slider_height - z_root, -1.0),
    ):
        if plate not in plates:
            continue
        elems = mesh.subdomains[sub]
        ys = sign * (mesh.p[1, mesh.t[:, elems]] - level)  # height above the root, into the rim
        row = np.min(np.where(ys > 1e-12, ys, np.inf))
        centroid = mesh.p[:, mesh.t[:, elems]].mean(axis=1)
        first = sign * (centroid[1] - level) < row
        for side, name in ((-1.0, "-x"), (1.0, "+x")):
            out[f"{plate} {name}"] = elems[first & (np.sign(centroid[0]) == side)]
    return out


def _mass_and_loads(bearing, m, fe, system, reduction, depth):
    """The reduced lumped mass [kg/m] (plates' steel, the slider, the supported mass less the
    steel above on the top plate's masters; Eq. F3), the weights [N/m] and the horizontal
    influence vector of the ground motion (Eq. F23), per unit depth ``depth`` [m]; ``m`` the
    mesh, ``fe`` its element (small or finite strain)."""
    from skfem import LinearForm, asm

    nd = fe.basis.nodal_dofs
    # Lumped (row-sum) steel mass of the plates: ∫ρ φ_a dx per dof (Eq. F3).
    rho = bearing.steel_density
    plate_mass = asm(LinearForm(lambda v, w: rho * (v[0] + v[1])), fe.basis)
    full_mass = np.concatenate([plate_mass, np.array([1.0, 1.0, 1.0])])
    full_mass[system.slider_dofs] = np.array(
        [bearing.slider_mass, bearing.slider_mass, bearing.slider_inertia]
    ) / depth
    mass = np.asarray(reduction.PT @ full_mass).ravel()
    top_x, top_z = (int(k) for k in reduction.masters)
    above = np.concatenate([m.subdomains[k] for k in ("top_plate", "top_rim", "block")])
    steel_above = rho * float(fe.basis.dx[above].sum())
    extra = bearing.supported_mass / depth - steel_above
    if extra <= 0:
        raise ValueError("the top plate and block outweigh the supported mass; lower block_height")
    mass[top_x] += extra
    mass[top_z] += extra

    # Influence vectors: horizontal translation dofs (plate x dofs, slider X, master X).
    rx = np.zeros(system.size)
    rx[nd[0]] = 1.0
    rx[system.slider_dofs[0]] = 1.0
    rz = np.zeros(system.size)
    rz[nd[1]] = 1.0
    rz[system.slider_dofs[1]] = 1.0
    influence = np.minimum(np.asarray(reduction.PT @ rx).ravel(), 1.0)
    vertical = np.minimum(np.asarray(reduction.PT @ rz).ravel(), 1.0)
    gravity = -mass * vertical * G
    return mass, gravity, influence
