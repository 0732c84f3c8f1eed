"""The foundation pieces together on the bearing's own mesh (bottom plate and rims).

Built from the default DFPBearing with fem.geometry, loaded statically, solved with fem.newton
and the capped rim steel. Checks are exact equilibrium identities and the location of the
plastic hinge; the full DFP model (slider contact, dynamics) is not part of this.
"""

import numpy as np
import pytest

pytest.importorskip("skfem")
pytest.importorskip("gmsh")

from skfem import ElementQuad1, ElementVector, FacetBasis, LinearForm, asm
from skfem.helpers import dot

from fem.assembly import PlaneStrainQ1
from fem.geometry import build_mesh
from fem.material import Material, MaterialState, von_mises
from fem.newton import solve_increment
from rigid.bearing import DFPBearing

BEARING = DFPBearing()


@pytest.fixture(scope="module")
def bottom(mesh_cache):
    dfp = build_mesh(
        BEARING, cache_dir=mesh_cache, rim_size=0.005, coarse_size=0.04
    )
    m = dfp.mesh
    sub = m.restrict(np.concatenate([m.subdomains["bottom_plate"], m.subdomains["bottom_rim"]]))
    fe = PlaneStrainQ1(sub)
    element = ElementVector(ElementQuad1())

    def unit_pressure(boundary):
        fb = FacetBasis(sub, element, facets=sub.boundaries[boundary], intorder=2)
        return asm(LinearForm(lambda v, w: -dot(w.n, v)), fb)

    support = fe.basis.get_dofs(sub.boundaries["support"]).flatten()
    support_nodes = np.unique(sub.facets[:, sub.boundaries["support"]])
    return sub, fe, unit_pressure, support, support_nodes


def test_dish_pressure_equilibrium(bottom):
    """60 MPa on the dish, back face fixed: the support reactions balance p times the dish chord
    2 r_in (the resultant of a uniform pressure on any arc is p times its chord, and the
    polygonal dish has its vertices on the arc). Tolerance 1e-8 relative (Newton rtol 1e-9).
    The plate stays elastic: 60 MPa of bearing pressure is far below 345 MPa."""
    _, fe, unit_pressure, support, support_nodes = bottom
    material = Material.from_bearing(BEARING)
    p = 60e6
    res = solve_increment(
        fe, material, MaterialState.virgin(fe.point_shape), np.zeros(fe.ndofs),
        p * unit_pressure("bottom_dish"), support,
    )
    assert res.converged and res.iterations == 1  # linear response: one Newton step
    nd = fe.basis.nodal_dofs
    chord_force = p * 2 * BEARING.rim_radius
    assert res.internal_force[nd[1, support_nodes]].sum() == pytest.approx(chord_force, rel=1e-8)
    assert abs(res.internal_force[nd[0, support_nodes]].sum()) < 1e-8 * chord_force
    assert not res.state.eq_plastic_strain.any()
    assert von_mises(res.stress).max() < 0.5 * BEARING.yield_stress


def test_rim_push_forms_hinge_at_root(bottom):
    """Both rims pushed outward by a pressure on their inner faces, 50 → 200 MPa.

    The plastic zone must start at the re-entrant corner where the dish meets the rim's inner
    face (a stress singularity) and grow with the load. At 200 MPa the root section (thickness
    t = 40 mm, rim height h = 35 mm) carries V = q h = 0.88 V_p and M = q h²/2 = 0.77 M_p at
    once (V_p = k t, k = f_y/√3; M_p = (2/√3) f_y t²/4, per unit depth), well beyond a
    shear–moment interaction for a Mises rectangle (the approximate M/M_p ≤ 1 − (V/V_p)² allows
    0.23), so the whole root section must be plastic: the rim-yielding mechanism of the
    paper's Figure 3.
    Location tolerance: one rim element (5 mm) from the corner.
    """
    _, fe, unit_pressure, support, _ = bottom
    material = Material.from_bearing(BEARING)
    load = unit_pressure("bottom_rim_inner")
    r_in, r_out = BEARING.rim_radius, BEARING.plate_radius
    z_root = BEARING.dish_depth(r_in)
    x, y = np.asarray(fe.basis.global_coordinates())
    root_section = (np.abs(y - z_root) < 5e-3) & (np.abs(x) > r_in) & (np.abs(x) < r_out)
    state = MaterialState.virgin(fe.point_shape)
    u = np.zeros(fe.ndofs)
    peak = []
    for q in (50e6, 100e6, 150e6, 200e6):
        res = solve_increment(fe, material, state, u, q * load, support)
        assert res.converged, res.residuals
        u, state = res.displacement, res.state
        p = state.eq_plastic_strain
        peak.append(p.max())
        if p.max() > 0:
            i = np.unravel_index(p.argmax(), p.shape)
            assert np.hypot(abs(x[i]) - r_in, y[i] - z_root) < 5e-3
        # Nothing yields far from the rims (plate bottom, dish centre).
        assert not p[np.abs(x) < r_in - 0.05].any()
    assert np.all(np.diff(peak) > 0)
    assert (state.eq_plastic_strain[root_section] > 0).all()
