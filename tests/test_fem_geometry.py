"""The parametric DFP mesh (meshes/dfp.geo through fem.geometry): groups, dimensions, cache.

Every expected number is computed here from the DFPBearing fields and elementary geometry
(rectangles and circular segments), never from the mesh generator.
"""

import dataclasses
import math

import numpy as np
import pytest

pytest.importorskip("skfem")
pytest.importorskip("gmsh")

from skfem import Basis, ElementQuad1, MeshQuad1

from fem.geometry import BOUNDARIES, SUBDOMAINS, build_mesh
from rigid.bearing import DFPBearing

BEARING = DFPBearing()
SIZES = {"rim_size": 0.01, "coarse_size": 0.04, "block_height": 0.1}  # coarse: fast
TOL = 1e-9  # [m] coordinates are written with 16 significant digits


@pytest.fixture(scope="module")
def dfp(tmp_path_factory):
    return build_mesh(BEARING, cache_dir=tmp_path_factory.mktemp("meshes"), **SIZES)


def facet_points(mesh, name):
    """Coordinates of the vertices of a named facet set, shape (2, 2, nfacets)."""
    return mesh.p[:, mesh.facets[:, mesh.boundaries[name]]]


def segment_area(radius, chord):
    """Area between a chord and its arc: R²(α − sin α)/2, α = 2 asin(c/2R)."""
    alpha = 2 * math.asin(chord / (2 * radius))
    return radius**2 * (alpha - math.sin(alpha)) / 2


def test_groups_and_element_type(dfp):
    """Exactly the documented physical groups, all non-empty; all quads, positive Jacobians."""
    m = dfp.mesh
    assert isinstance(m, MeshQuad1)
    assert set(m.subdomains) == set(SUBDOMAINS)
    assert set(m.boundaries) == set(BOUNDARIES)
    assert all(len(m.subdomains[k]) > 0 for k in SUBDOMAINS)
    assert all(len(m.boundaries[k]) > 0 for k in BOUNDARIES)
    # The subdomains partition the mesh.
    cells = np.concatenate([m.subdomains[k] for k in SUBDOMAINS])
    assert np.array_equal(np.sort(cells), np.arange(m.nelements))
    assert (Basis(m, ElementQuad1(), intorder=2).dx > 0).all()


def test_dimensions_from_bearing(dfp):
    """Extents, rim faces and dish arcs against the DFPBearing numbers (to 1e-9 m)."""
    m, b = dfp.mesh, BEARING
    R, r_in, r_out = b.radius, b.rim_radius, b.plate_radius
    h, t, hb = b.slider_height, b.plate_thickness, SIZES["block_height"]
    z_r = b.dish_depth(r_in)
    z_t = z_r + b.rim_height
    assert r_out == pytest.approx(r_in + b.rim_thickness)
    assert m.p[0].min() == pytest.approx(-r_out, abs=TOL)
    assert m.p[0].max() == pytest.approx(r_out, abs=TOL)
    assert m.p[1].min() == pytest.approx(-t, abs=TOL)
    assert m.p[1].max() == pytest.approx(h + t + hb, abs=TOL)

    x, y = facet_points(m, "support")
    assert np.allclose(y, -t, atol=TOL) and np.ptp(x) == pytest.approx(2 * r_out, abs=TOL)
    x, y = facet_points(m, "block_top")
    assert np.allclose(y, h + t + hb, atol=TOL)
    for plate, centre, sign in (("bottom", R, 1), ("top", h - R, -1)):
        x, y = facet_points(m, f"{plate}_dish")
        assert np.allclose(np.hypot(x, y - centre), R, atol=TOL)  # vertices on the dish circle
        assert x.min() == pytest.approx(-r_in, abs=TOL) and x.max() == pytest.approx(r_in, abs=TOL)
        x, y = facet_points(m, f"{plate}_rim_inner")
        assert np.allclose(np.abs(x), r_in, atol=TOL)
        y_root, y_top = (z_r, z_t) if sign > 0 else (h - z_r, h - z_t)
        assert min(y.min(), y.max()) == pytest.approx(min(y_root, y_top), abs=TOL)
        assert max(y.min(), y.max()) == pytest.approx(max(y_root, y_top), abs=TOL)
        x, y = facet_points(m, f"{plate}_rim_top")
        assert np.allclose(y, y_top, atol=TOL)
        assert np.all((np.abs(x) >= r_in - TOL) & (np.abs(x) <= r_out + TOL))
        x, y = facet_points(m, f"{plate}_rim_root")
        assert np.allclose(y, y_root, atol=TOL)
        # The rim root is an interior line: each of its facets is shared by two elements.
        assert (m.f2t[1, m.boundaries[f"{plate}_rim_root"]] >= 0).all()
        # Rim facets no longer than the requested size (structured rim mesh).
        x, y = facet_points(m, f"{plate}_rim_inner")
        assert np.hypot(*(np.array([x[1] - x[0], y[1] - y[0]]))).max() <= SIZES["rim_size"] + TOL


def test_subdomain_areas(dfp):
    """Areas per unit depth against closed forms, to 1e-9 relative.

    Rims and block are rectangles. Each plate is the rectangle 2 r_out (t + z_r) minus the
    circular segment of the dish (chord 2 r_in); the mesh replaces the arc by chords whose
    vertices lie on the circle, so its area exceeds the exact one by the sum of the small
    segments cut off by each dish facet, which is added here exactly.
    """
    m, b = dfp.mesh, BEARING
    dx = Basis(m, ElementQuad1(), intorder=2).dx.sum(axis=1)

    def area(name):
        return dx[m.subdomains[name]].sum()

    R, r_in, r_out, t = b.radius, b.rim_radius, b.plate_radius, b.plate_thickness
    z_r = b.dish_depth(r_in)
    for plate in ("bottom", "top"):
        assert area(f"{plate}_rim") == pytest.approx(2 * b.rim_thickness * b.rim_height, rel=1e-9)
        x, y = facet_points(m, f"{plate}_dish")
        chords = np.hypot(x[1] - x[0], y[1] - y[0])
        facet_segments = sum(segment_area(R, c) for c in chords)
        exact = 2 * r_out * (t + z_r) - segment_area(R, 2 * r_in)
        assert facet_segments > 0
        assert area(f"{plate}_plate") == pytest.approx(exact + facet_segments, rel=1e-9)
    assert area("block") == pytest.approx(2 * r_out * SIZES["block_height"], rel=1e-9)


def test_dish_normals_face_the_slider(dfp):
    """Outward normals of the plates on the dishes point into the slider gap: up on the bottom
    dish, down on the top dish (needed by the contact code). Mean |n_y| > 0.99 since the dish
    slopes at most asin(r_in/R) = 11.8°."""
    from skfem import FacetBasis

    m = dfp.mesh
    for name, sign in (("bottom_dish", 1), ("top_dish", -1)):
        fb = FacetBasis(m, ElementQuad1(), facets=m.boundaries[name])
        ny = np.asarray(fb.normals)[1]
        assert (sign * ny > 0).all() and sign * ny.mean() > 0.99


def test_cache_reuse_and_keys(dfp, tmp_path):
    """Same inputs reuse the cached file; any change of bearing, sizes or .geo text re-meshes."""
    cache = dfp.path.parent
    again = build_mesh(BEARING, cache_dir=cache, **SIZES)
    assert again.from_cache and again.path == dfp.path and again.key == dfp.key
    assert np.array_equal(again.mesh.t, dfp.mesh.t)

    taller = dataclasses.replace(BEARING, rim_height=0.030)
    other = build_mesh(taller, cache_dir=cache, **SIZES)
    assert not other.from_cache and other.key != dfp.key
    _, y = facet_points(other.mesh, "bottom_rim_top")
    assert np.allclose(y, taller.dish_depth(taller.rim_radius) + 0.030, atol=TOL)

    finer = build_mesh(BEARING, cache_dir=cache, **{**SIZES, "rim_size": 0.005})
    assert finer.key != dfp.key and finer.mesh.nelements > dfp.mesh.nelements

    geo = tmp_path / "dfp.geo"
    from fem.geometry import GEO_FILE

    geo.write_text(GEO_FILE.read_text() + "\n// edited\n")
    edited = build_mesh(BEARING, cache_dir=cache, geo_file=geo, **SIZES)
    assert edited.key != dfp.key and not edited.from_cache
