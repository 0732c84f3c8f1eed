"""The rims' out-of-plane depth (docs/theory/finite-elements.md, Eq. F59): per-element thickness
of the plane-strain element, the FE rims given the ring's effective depth, the yielding rims'
law from the 3-D push, and the command line that asks for them.

Oracles: Euler-Bernoulli's stepped cantilever for the thickness; the definition of Eq. F59
on synthetic pushes for the effective depth and the law (the 3-D push itself is checked in
tests/test_ring.py, its cost keeps it out of here).
"""

import math
import subprocess
import sys
from types import SimpleNamespace

import numpy as np
import pytest
import scipy.sparse.linalg as spla
from skfem import MeshQuad

from fem.assembly import PlaneStrainQ1
from fem.material import Material, MaterialState, return_map
from rigid import DFPBearing

E, NU = 200e9, 0.3


def _tip_deflection(thickness_of):
    """Tip deflection [m] of a plane-strain cantilever 2 m × 0.1 m (80 × 4 elements, clamped
    at x = 0) under a unit shear load at x = 2 m, with element thickness ``thickness_of(x)``."""
    mesh = MeshQuad.init_tensor(np.linspace(0, 2.0, 81), np.linspace(0, 0.1, 5))
    centroid = mesh.p[0, mesh.t].mean(axis=0)
    fe = PlaneStrainQ1(mesh, thickness=thickness_of(centroid))
    elastic = Material(E, NU, 1e30, 1e30, 0.0)
    tangent = return_map(elastic, np.zeros((4, *fe.point_shape)),
                         MaterialState.virgin(fe.point_shape)).tangent
    K = fe.stiffness(tangent).tocsc()
    nd = fe.basis.nodal_dofs
    x = mesh.p[0]
    fixed = nd[:, x < 1e-9].ravel()
    free = np.setdiff1d(np.arange(fe.ndofs), fixed)
    tip = np.flatnonzero(x > 2.0 - 1e-9)
    f = np.zeros(fe.ndofs)
    f[nd[1, tip]] = 1.0 / tip.size
    u = np.zeros(fe.ndofs)
    u[free] = spla.spsolve(K[free][:, free], f[free])
    return float(u[nd[1, tip]].mean())


def test_stepped_cantilever():
    # Bending stiffness c(x)·EI: δ = P/EI ∫(L−x)²/c dx, so relative thicknesses c1 on the root
    # half and c2 on the tip half give δ/δ₀ = 7/(8c1) + 1/(8c2) (Euler-Bernoulli). Shear
    # deformation (≈ (h/L)² of δ here) and Q1's shear locking, both scaled the same way by
    # c, leave it within 1 %; a uniform factor is exact to round-off (linearity).
    base = _tip_deflection(np.ones_like)
    assert _tip_deflection(lambda x: np.full_like(x, 0.32)) == pytest.approx(base / 0.32,
                                                                           rel=1e-9)
    c1, c2 = 0.32, 2.0
    stepped = _tip_deflection(lambda x: np.where(x < 1.0, c1, c2))
    assert stepped / base == pytest.approx(7 / (8 * c1) + 1 / (8 * c2), rel=0.01)


def test_thickness_is_checked():
    mesh = MeshQuad.init_tensor(np.linspace(0, 1, 3), np.linspace(0, 1, 2))
    with pytest.raises(ValueError, match="one positive factor per element"):
        PlaneStrainQ1(mesh, thickness=[1.0, -1.0])
    with pytest.raises(ValueError, match="one positive factor per element"):
        PlaneStrainQ1(mesh, thickness=[1.0])


def test_rims_get_the_depth_asked_for(mesh_cache):
    # Both plates' rims, and only they, carry rim_depth/depth of each element's weight.
    from fem.dfp import build_system, out_of_plane_depth

    options = {"rim_size": 0.01, "coarse_size": 0.04}
    b = DFPBearing()
    plain = build_system(b, mesh_options=options, cache_dir=mesh_cache)
    ring = build_system(b, mesh_options=options, cache_dir=mesh_cache, rim_depth=0.1)
    rims = np.concatenate([plain.mesh.subdomains[k] for k in ("bottom_rim", "top_rim")])
    ratio = ring.system.fe.dx / plain.system.fe.dx
    expected = np.ones(ratio.shape[0])
    expected[rims] = 0.1 / out_of_plane_depth(b)
    assert np.allclose(ratio, expected[:, None], rtol=1e-14, atol=0)
    with pytest.raises(ValueError, match="rim_depth"):
        build_system(b, mesh_options=options, cache_dir=mesh_cache, rim_depth=-1.0)


def _law(scale, rupture=True):
    """A synthetic law: a push curve 0 → 2 mm of force scale·(1 − e^(−δ/0.5 mm)) [N], hinge at
    0.5 mm, rupture at 1.5 mm (inf without)."""
    from rigid.rims import RimLaw

    d = np.linspace(0.0, 2e-3, 81)
    f = scale * (1.0 - np.exp(-d / 5e-4))
    return RimLaw(stiffness=scale / 5e-4, plastic_set=np.array([0.0, 1e-3]),
                  force=np.array([f[10], f[-1]]), first_yield_force=f[5],
                  hinge_displacement=5e-4, hinge_force=float(np.interp(5e-4, d, f)),
                  hinge_set=1e-4, rupture_displacement=1.5e-3 if rupture else math.inf,
                  rupture_set=1e-3, lever=0.026, push_displacement=d, push_force=f)


def test_effective_depth_is_eq_f59(monkeypatch):
    # d_eff = F_ring(state)/F_plane(state)·πb/4 at the hinge, the rupture and the largest
    # force: with the ring's curve 0.3 times the plane one it is 0.3·πb/4 at each (1e-12).
    import fem.rim_laws as laws

    b = DFPBearing()
    monkeypatch.setattr(laws, "rim_law", lambda bearing, model="plane-strain", cache=True:
                        _law(0.3e6 if model == "ring" else 1e6))
    for state in ("hinge", "rupture", "containment"):
        assert laws.effective_rim_depth(b, state) == pytest.approx(
            0.3 * math.pi * b.slider_diameter / 4, rel=1e-12)
    monkeypatch.setattr(laws, "rim_law", lambda bearing, model="plane-strain", cache=True:
                        _law(1e6, rupture=model != "ring"))
    with pytest.raises(ValueError, match="rupture"):
        laws.effective_rim_depth(b, "rupture")


def test_law_from_the_ring_push(monkeypatch):
    # The 3-D push's curve, hinge and gauge strain become the law's: a push whose gauge
    # strain reaches the rupture strain (0.1906) at 1.2 mm gives that rupture displacement;
    # the hinge is the push's; the stiffness is the elastic push's secant.
    import fem.rim_laws as laws
    import fem.ring

    d = np.linspace(0.0, 17.5e-3, 71)
    force = 2e6 * (1.0 - np.exp(-d / 1e-3))
    gauge = np.maximum(0.0, d - 2e-4) * 0.1906 / 1.0e-3

    def fake_push(bearing, load, displacement=None, plasticity=True):
        if not plasticity:
            return SimpleNamespace(displacement=np.array([0.0, 1e-4]),
                                   force=np.array([0.0, 2e6 * 1e-4 / 1e-3]))
        return SimpleNamespace(displacement=d, force=force, gauge_plastic_strain=gauge,
                               hinge_displacement=5e-4,
                               hinge_force=float(np.interp(5e-4, d, force)))

    monkeypatch.setattr(fem.ring, "ring_push", fake_push)
    law = laws.rim_law(DFPBearing(), model="ring", cache=False)
    assert law.stiffness == pytest.approx(2e9, rel=1e-12)
    assert law.hinge_displacement == 5e-4
    assert law.hinge_force == pytest.approx(float(np.interp(5e-4, d, force)), rel=1e-12)
    assert law.rupture_displacement == pytest.approx(1.2e-3, rel=1e-9)
    np.testing.assert_array_equal(law.push_force, force)


def test_ring_rims_need_one_limit_state(tmp_path):
    # The ring's effective depth differs between limit states, so a run searches one: asked
    # for two, the command stops in one line before running anything.
    r = subprocess.run([sys.executable, "-m", "validation.cli", "validate", "--quick",
                        "--rim-model", "ring", "--limit-state", "hinge", "rupture",
                        "--out", str(tmp_path / "o")], capture_output=True, text=True,
                       timeout=300)
    assert r.returncode != 0
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and "one --limit-state" in lines[0], r.stderr
    assert not (tmp_path / "o" / "report.html").exists()
