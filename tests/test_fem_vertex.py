"""The slider's vertices as contact points against the rims (fem.contact.vertex_contact).

Oracles written here: the vertex-to-facet penalty force N = ε_N ℓ₀ δ for a hand-placed vertex
(δ from the geometry), rigid-body statics of the slider under that force, and the tangent by
central finite differences. The rim geometry comes from the coarse bearing mesh
(rim elements 20 mm, so the rim's inner face has nodes 17.5 mm apart).
"""

import math

import numpy as np
import pytest

pytest.importorskip("skfem")
pytest.importorskip("gmsh")

from fem import contact as C
from fem.geometry import COARSE_MESH
from rigid.bearing import DFPBearing

EPS_N = 2e14  # [N/m³], the order of the model's ε_N = 10 E / h_c


@pytest.fixture(scope="module")
def rim(mesh_cache):
    """Slave nodes of the bottom plate's rims (inner faces and tops) with their facets."""
    from fem.geometry import build_mesh

    bearing = DFPBearing()
    mesh = build_mesh(bearing, cache_dir=mesh_cache, **COARSE_MESH).mesh
    names = ("bottom_rim_inner", "bottom_rim_top")
    nodes = C.ContactNodes.from_mesh(mesh, dict.fromkeys(names, 0.05), vertex_boundaries=names)
    return bearing, mesh, nodes


def tilted_pose(bearing, nodes, x, depth, theta=0.12):
    """Pose with the bottom-right vertex ``depth`` [m] inside the +x rim's inner face, midway
    between its two lowest nodes, the slider turned by ``theta`` [rad] (counter-clockwise, so
    that this vertex is the slider's rightmost point)."""
    shape = C.SliderShape.from_bearing(bearing)
    r_in = bearing.rim_radius
    face = np.flatnonzero(np.isclose(x[0], r_in) & (x[1] < bearing.rim_top - 1e-9))
    z = np.sort(x[1, face])
    z_mid = 0.5 * (z[0] + z[1])
    u = C.rotation(theta) @ shape.vertices[:, 1]
    return shape, np.array([r_in + depth - u[0], z_mid - u[1], theta]), u


def test_tilted_vertex_is_held_by_the_rim(rim):
    """A vertex 0.5 mm inside the rim, midway between two rim nodes 17.5 mm apart, the slider
    turned by 0.12 rad (its tilt at rim contact): its side recedes from the face by
    0.12 × 8.75 mm = 1.05 mm at the next node up, so no rim node is inside the slider and
    node-to-surface contact alone exerts nothing (the defect this fixes). The vertex contact
    pushes the slider back with N = ε_N ℓ₀ δ along the face's outward normal (−x), δ = 0.5 mm,
    ℓ₀ the facet's length, with the moment u × F about the centroid, and the plate takes the
    opposite force. Tolerance 1e-9 relative (round-off; the facet is exactly vertical)."""
    bearing, mesh, nodes = rim
    x = mesh.p[:, nodes.nodes]
    depth = 5e-4
    shape, pose, u = tilted_pose(bearing, nodes, x, depth)
    xi = C.body_coordinates(x, pose)
    state = C.ContactState(xi, np.zeros(len(nodes)), np.full(len(nodes), -1))
    plain = C.evaluate(shape, nodes, x, pose, state, np.zeros(len(nodes)), EPS_N, 0.1 * EPS_N)
    assert not plain.active.any()
    assert np.all(plain.slider_force == 0.0)

    vc = C.vertex_contact(shape, nodes, x, pose, EPS_N, bearing.rim_thickness / 2)
    assert vc.active.tolist() == [False, True, False, False]
    ends = nodes.segments[vc.segment[1]]
    ell = float(np.hypot(*(x[:, ends[1]] - x[:, ends[0]])))
    assert vc.gap[1] == pytest.approx(depth, rel=1e-9)
    N = EPS_N * ell * depth
    assert vc.normal[1] == pytest.approx(N, rel=1e-9)
    merged = C.add_vertices(plain, vc)
    F = merged.slider_force
    assert F[0] == pytest.approx(-N, rel=1e-9)
    assert abs(F[1]) <= 1e-9 * N
    assert F[2] == pytest.approx(u[0] * F[1] - u[1] * F[0], rel=1e-9)  # moment u × F
    assert merged.node_force.sum(axis=1) == pytest.approx([N, 0.0], abs=1e-9 * N)
    assert merged.active[ends].all()
    assert merged.normal_energy == pytest.approx(0.5 * N * depth, rel=1e-9)


def test_vertex_off_the_rim_is_free(rim):
    """The same vertex 1 mm outside the rim face, or 30 mm deep in it (beyond the search
    depth of half the rim thickness: it belongs to no facet), has no contact."""
    bearing, mesh, nodes = rim
    x = mesh.p[:, nodes.nodes]
    for depth in (-1e-3, 0.03):
        shape, pose, _ = tilted_pose(bearing, nodes, x, depth)
        vc = C.vertex_contact(shape, nodes, x, pose, EPS_N, bearing.rim_thickness / 2)
        assert not vc.active.any()


def test_vertex_tangent_against_finite_differences(rim):
    """K = −∂F/∂d on the seven dofs (x_a, z_a, x_b, z_b, X, Z, Θ) against central differences
    (step 1e-9 m or rad), with the facet's end nodes displaced off the vertical so that every
    term of the second variation of δ is exercised. Tolerance 1e-6 relative to the largest
    entry (the issue's tangent criterion): the truncation error is ~ (1e-9/1e-3)² of forces
    ~1e9 N/m, and the geometric terms N∇²δ are ~1e-2 of the largest entry."""
    bearing, mesh, nodes = rim
    x = mesh.p[:, nodes.nodes].copy()
    shape, pose, _ = tilted_pose(bearing, nodes, x, 2e-3, theta=0.08)
    vc = C.vertex_contact(shape, nodes, x, pose, EPS_N, 0.02)
    a, b = nodes.segments[vc.segment[1]]
    x[:, a] += [3e-4, -2e-4]
    x[:, b] += [-1e-4, 1e-4]
    vc = C.vertex_contact(shape, nodes, x, pose, EPS_N, 0.02)
    assert vc.active[1]
    K = vc.stiffness[:, :, 1]
    h = 1e-9

    def force(d):
        xx = x.copy()
        xx[:, a] += d[0:2]
        xx[:, b] += d[2:4]
        return C.vertex_contact(shape, nodes, xx, pose + d[4:], EPS_N, 0.02).force[:, 1]

    fd = np.zeros((7, 7))
    for j in range(7):
        e = np.zeros(7)
        e[j] = h
        fd[:, j] = -(force(e) - force(-e)) / (2 * h)
    assert np.abs(fd - K).max() <= 1e-6 * np.abs(K).max()
    assert math.isfinite(vc.normal[1]) and vc.normal[1] > 0


def test_rim_impact_keeps_vertices_out(mesh_cache):
    """The heavy bearing driven into its rims (3 m/s² half-sine of 1 s, 1 s of it, as in
    test_fem_failure): with vertex contacts the leading vertex stays on the rim faces, its
    penetration at most the penalty's F/(ε_N ℓ₀) for the whole rim force F on the shortest
    rim facet (measured 11 µm); with node contacts only it sinks more than ten times that into
    the rim between two rim nodes (measured 3.1 mm), the defect vertex contacts remove."""
    import fem
    from fem.dfp import build_system

    bearing = DFPBearing(pressure=60e6)
    dt = 0.01
    t = np.arange(0.0, 2.0 + dt / 2, dt)
    a = np.where(t < 1.0, 3.0 * np.sin(np.pi * t), 0.0)
    sysm = build_system(bearing, mesh_options=COARSE_MESH, vertex_contact=True,
                        cache_dir=mesh_cache).system

    def sink(res):
        return max(
            C.vertex_contact(sysm.shape, sysm.nodes, sysm.slave_positions(d),
                             sysm.slider_pose(d), sysm.penalty, sysm.vertex_depth).gap.max()
            for _, d, _, _ in res.snapshots
        )

    runs = {
        on: fem.simulate(bearing, a, dt, duration=1.0, max_step=0.02, mesh_options=COARSE_MESH,
                         snapshot_every=1, vertex_contact=on, cache_dir=mesh_cache)
        for on in (True, False)
    }
    held = runs[True]
    assert not held.numerical_failure and held.rim_force.max() > 0
    bound = held.rim_force.max() / held.depth / (sysm.penalty * sysm.nodes.segment_length.min())
    assert 0 < sink(held) <= bound
    assert sink(runs[False]) > 10 * bound
