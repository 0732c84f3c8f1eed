"""fem.output: slider outline geometry, VTU round trip through meshio, an off-screen PNG."""

import numpy as np
import pytest

pytest.importorskip("skfem")
pytest.importorskip("gmsh")
meshio = pytest.importorskip("meshio")

from fem import contact as C  # noqa: E402
from fem.assembly import PlaneStrainQ1  # noqa: E402
from fem.geometry import COARSE_MESH, build_mesh  # noqa: E402
from fem.material import von_mises  # noqa: E402
from fem.output import cell_fields, nodal_displacement, slider_outline, write_vtu  # noqa: E402
from rigid.bearing import DFPBearing  # noqa: E402

BEARING = DFPBearing()


@pytest.fixture(scope="module")
def state(mesh_cache):
    mesh = build_mesh(
        BEARING, cache_dir=mesh_cache,
        **COARSE_MESH,
    ).mesh
    fe = PlaneStrainQ1(mesh)
    rng = np.random.default_rng(1)
    d = np.concatenate([rng.normal(size=fe.ndofs) * 1e-3, [0.05, 0.001, 0.02]])
    stress = rng.normal(size=(4, *fe.point_shape)) * 1e8
    plastic = np.abs(rng.normal(size=fe.point_shape)) * 1e-3
    return mesh, fe, d, stress, plastic


@pytest.mark.parametrize("edge_radius", [0.0, 0.025])
def test_slider_outline_on_the_section(edge_radius):
    """Every outline point lies on the section boundary (|depth| < 1e-12 m), it closes, and
    with rounded edges every edge arc has points on it."""
    shape = C.SliderShape.from_bearing(BEARING, edge_radius)
    pose = np.array([0.1, 0.12, 0.05])
    pts = slider_outline(shape, pose)
    depth, face, _, _ = C.penetration(shape, C.body_coordinates(pts, pose))
    assert np.abs(depth).max() < 1e-12
    assert np.allclose(pts[:, 0], pts[:, -1])
    if edge_radius:
        assert set(C.EDGES) <= set(face)


def test_nodal_displacement_order(state):
    """The reshape used for output agrees with scikit-fem's nodal dof numbering."""
    mesh, fe, d, _, _ = state
    assert np.array_equal(nodal_displacement(mesh, d), d[fe.basis.nodal_dofs])


def test_vtu_round_trip(state, tmp_path):
    """Points, quads, displacement and cell averages survive meshio's VTU writer (exactly for
    the topology, 1e-12 relative for the floating-point fields)."""
    mesh, fe, d, stress, plastic = state
    path = write_vtu(tmp_path / "state.vtu", mesh, d, stress, plastic)
    back = meshio.read(path)
    assert np.array_equal(back.cells_dict["quad"], mesh.t.T)
    assert np.allclose(back.points[:, :2], mesh.p.T, rtol=1e-12, atol=0)
    u = back.point_data["displacement"]
    assert np.allclose(u[:, :2].T, d[fe.basis.nodal_dofs], rtol=1e-12, atol=1e-18)
    vm = back.cell_data["von_mises"][0]
    assert np.allclose(vm, von_mises(stress).mean(axis=-1), rtol=1e-12)
    assert np.allclose(back.cell_data["eq_plastic_strain"][0], plastic.mean(axis=-1), rtol=1e-12)
    assert set(cell_fields(stress, plastic)) == {"von_mises", "eq_plastic_strain"}


def test_png_renders(state, tmp_path):
    """An off-screen render (pyvista through EGL) writes a non-blank PNG."""
    pytest.importorskip("pyvista")
    from PIL import Image

    from fem.output import render_state

    mesh, _, d, stress, plastic = state
    shape = C.SliderShape.from_bearing(BEARING)
    pose = np.array([0.05, BEARING.slider_height / 2 + 0.001, 0.02])
    path = render_state(
        tmp_path / "state.png", mesh, shape, d, pose, stress, plastic, window=(400, 300)
    )
    img = np.asarray(Image.open(path).convert("L"), dtype=float)
    assert img.shape == (300, 400)
    assert img.std() > 5  # not a blank frame


def test_result_figure_leaves_out_the_elements_let_go(state, monkeypatch):
    """render_result draws the elements that keep any of their stiffness (Eq. F68) with their
    own fields, none of those that have let go altogether, and the slider at the final pose."""
    from types import SimpleNamespace

    import fem.output as output

    mesh, _, d, stress, plastic = state
    retained = np.ones(mesh.t.shape[1])
    retained[[3, 7]] = 0.0  # let go
    retained[5] = 0.4  # letting go: still drawn
    result = SimpleNamespace(bearing=BEARING, edge_radius=0.0, mesh=mesh, final_displacement=d,
                             final_stress=stress, final_plastic_strain=plastic,
                             retained=retained)
    drawn = {}
    monkeypatch.setattr(output, "render_state",
                        lambda path, m, shape, dd, pose, s, p, **kw: drawn.update(
                            t=m.t, pose=pose, stress=s, plastic=p))
    output.render_result("unused.png", result)
    kept = np.setdiff1d(np.arange(mesh.t.shape[1]), [3, 7])
    assert np.array_equal(drawn["t"], mesh.t[:, kept])
    assert np.array_equal(drawn["stress"], stress[:, kept])
    assert np.array_equal(drawn["plastic"], plastic[kept])
    assert np.allclose(drawn["pose"], [0.05, BEARING.slider_height / 2 + 0.001, 0.02])
