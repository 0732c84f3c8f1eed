"""Crushed rim elements let go, and the faces that eroded elements uncover carry contact
(fem.fracture.RimFracture's ``crush_jacobian``, fem.contact.exposed; docs/theory/
finite-elements.md, Eqs. F67b and F68c)."""

import numpy as np
import pytest

from fem.contact import body_coordinates, penetration
from fem.dfp import build_system
from fem.fracture import RimFracture, StressModifiedStrain
from fem.geometry import COARSE_MESH
from fem.limit_states import RIMS

UNIAXIAL = np.array([345e6, 0.0, 0.0, 0.0])  # Mandel [Pa], T = 1/3


@pytest.fixture(scope="module")
def plain(mesh_cache, heavy):
    return build_system(heavy, mesh_options=COARSE_MESH, kinematics="finite",
                        cache_dir=mesh_cache)


@pytest.fixture(scope="module")
def uncovered(mesh_cache, heavy):
    return build_system(heavy, mesh_options=COARSE_MESH, kinematics="finite",
                        cache_dir=mesh_cache, uncovered_rims=True)


def _fracture(model, heavy, crush):
    return RimFracture(StressModifiedStrain(heavy.rupture_strain, 1.5), model.system.fe,
                       model.mesh, heavy.rim_thickness, steps=4, crush_jacobian=crush)


def test_a_collapsed_rim_element_is_crushed_and_lets_go(plain, heavy):
    """A rim element with one point below J_c is crushed (Eq. F67b): torn, recorded as
    crushed, and letting go as a torn element does (Eq. F68); a plate element as collapsed,
    a rim element just above J_c, and every element without ``crush_jacobian`` are not."""
    fe = plain.system.fe
    shape = fe.point_shape
    p, stress = np.zeros(shape), np.broadcast_to(UNIAXIAL[:, None, None], (4, *shape))
    rim = None
    for name, elems in zip(RIMS, _fracture(plain, heavy, 0.1).elements, strict=True):
        if name == "bottom +x":
            rim = elems
    plate = np.setdiff1d(np.arange(shape[0]), np.concatenate(
        _fracture(plain, heavy, 0.1).elements))
    jacobian = np.ones(shape)
    jacobian[rim[0], 2] = 0.05
    jacobian[rim[1], 0] = 0.1000001
    jacobian[plate[0], 1] = 0.01
    frac = _fracture(plain, heavy, 0.1)
    assert frac.update(1.5, p, stress, jacobian)
    assert frac.crushed == {int(rim[0]): (1.5, "bottom +x")}
    assert frac.torn == frac.crushed
    assert frac.retained[rim[0]] == 0.75
    assert (np.delete(frac.retained, rim[0]) == 1.0).all()
    frac.update(1.6, p, stress, jacobian)  # already letting go: not crushed again
    assert frac.retained[rim[0]] == 0.5 and len(frac.crushed) == 1
    off = _fracture(plain, heavy, None)
    assert not off.update(1.5, p, stress, jacobian) and not off.torn
    for bad in (0.0, 1.0, -0.2, 1.5):
        with pytest.raises(ValueError, match="crush_jacobian"):
            _fracture(plain, heavy, bad)


def _edges(mesh, element):
    """The element's four edges as (a, b) vertex pairs, each with whether another element
    shares it (from the connectivity alone, not the mesh's facet tables)."""
    corners = mesh.t[:, element]
    out = []
    for k in range(4):
        a, b = corners[k], corners[(k + 1) % 4]
        holders = np.flatnonzero((mesh.t == a).any(axis=0) & (mesh.t == b).any(axis=0))
        out.append((a, b, holders.size > 1))
    return out


def test_intact_rims_keep_todays_contact_and_an_eroded_element_uncovers_its_faces(
        plain, uncovered):
    """With every rim vertex a contact node, the intact lengths are today's on today's
    nodes and 0 on the added ones (Eq. F68c). When a bottom +x rim element is gone, each of
    its edges that another element shares becomes surface (½ ℓ to each end) and each that was
    an original contact face stops being one; the other nodes keep their lengths.
    Tolerance: the same half-lengths summed in another order."""
    base, sysm, mesh = plain.system.nodes, uncovered.system, uncovered.mesh
    nodes = sysm.nodes
    n0 = len(base)
    assert (nodes.nodes[:n0] == base.nodes).all()
    assert (nodes.length[:n0] == base.length).all() and (nodes.length[n0:] == 0.0).all()
    assert set(np.unique(mesh.t[:, mesh.subdomains["bottom_rim"]])) <= set(nodes.nodes)
    face = set(base.nodes)
    rim = mesh.subdomains["bottom_rim"]
    element = rim[np.argmax(mesh.p[0, mesh.t[:, rim]].mean(axis=0))]  # at the +x edge
    retained = np.ones(mesh.t.shape[1])
    retained[element] = 0.0
    sysm.erode(retained)
    index = {int(v): k for k, v in enumerate(nodes.nodes)}
    expected = nodes.length.copy()
    for a, b, shared in _edges(mesh, element):
        half = 0.5 * np.hypot(*(mesh.p[:, b] - mesh.p[:, a]))
        if shared:
            expected[[index[a], index[b]]] += half
        elif a in face and b in face:  # an original contact face (inner face or top)
            expected[[index[a], index[b]]] -= half
    assert sysm.nodes.length == pytest.approx(expected, rel=1e-12, abs=1e-15)
    sysm.erode(np.ones(mesh.t.shape[1]))
    assert sysm.nodes.length == pytest.approx(nodes.length, rel=1e-12, abs=1e-15)


def test_a_node_uncovered_inside_the_slider_starts_at_zero_force(mesh_cache, heavy):
    """A node uncovered where the slider already overlaps it takes that overlap as its gap
    adjustment δ₀ (Eq. F68c): it pushes only on what the slider presses further, so
    uncovering it adds no force at that configuration, and 1 mm more of overlap (the slider's
    flat side moved 1 mm) gives the penalty ε_N L · 1 mm; tolerance 1e-9: the overlap is a
    difference of positions of about 0.5 m, whose round-off is 1e-16 m against 1 mm."""
    model = build_system(heavy, mesh_options=COARSE_MESH, kinematics="finite",
                         cache_dir=mesh_cache, uncovered_rims=True)
    sysm, mesh = model.system, model.mesh
    rim = mesh.subdomains["bottom_rim"]
    right = rim[mesh.p[0, mesh.t[:, rim]].mean(axis=0) > 0]
    inner = right[np.argmin(mesh.p[0, mesh.t[:, right]].mean(axis=0))]  # on the inner face
    corners = mesh.t[:, inner]
    far = corners[np.argmax(mesh.p[0, corners])]  # a vertex behind the inner face
    k = int(np.flatnonzero(sysm.nodes.nodes == far)[0])
    assert sysm.nodes.length[k] == 0.0
    # the slider moved so that its +x side lies 2 mm beyond that vertex
    half_width = sysm.shape.vertices[0].max()
    d = np.zeros(sysm.size)
    d[sysm.slider_dofs[0]] = mesh.p[0, far] + 0.002 - half_width - sysm.pose[0]
    xi = body_coordinates(sysm.slave_positions(d)[:, [k]], sysm.slider_pose(d))
    overlap = float(penetration(sysm.shape, xi)[0][0])
    assert overlap > 0.0
    retained = np.ones(mesh.t.shape[1])
    retained[inner] = 0.0
    state = sysm.initial_state()
    sysm.erode(retained, d)
    assert sysm.nodes.length[k] > 0.0
    assert sysm.offset[k] == pytest.approx(overlap, rel=1e-12)
    assert sysm.evaluate(d, state).contact.normal[k] == 0.0
    d[sysm.slider_dofs[0]] += 0.001
    normal = sysm.evaluate(d, state).contact.normal[k]
    assert normal == pytest.approx(sysm.penalty * sysm.nodes.length[k] * 0.001, rel=1e-9)


def test_crushing_keys_the_runs_and_the_laws_only_when_set(heavy):
    """``crush_jacobian`` keys an FE run and a rim law only when given, so every stored run
    and law without it keeps its key; without fracture it is refused."""
    from rigid.rims import rim_law_cache_file
    from validation.fem_search import FESettings

    assert "crush_jacobian" not in FESettings(fracture="median").run_options()
    assert FESettings(fracture="median", crush_jacobian=0.1).run_options()[
        "crush_jacobian"] == 0.1
    for bad in ({"crush_jacobian": 0.1}, {"fracture": "median", "crush_jacobian": 1.0}):
        with pytest.raises(ValueError, match="crush_jacobian"):
            FESettings(**bad)
    plain = rim_law_cache_file(heavy, fracture="median", edge_radius=0.02)
    assert rim_law_cache_file(heavy, fracture="median", edge_radius=0.02,
                              crush_jacobian=None) == plain
    assert rim_law_cache_file(heavy, fracture="median", edge_radius=0.02,
                              crush_jacobian=0.1) != plain
    with pytest.raises(ValueError, match="crushing"):
        rim_law_cache_file(heavy, crush_jacobian=0.1)


def test_dfp_validate_refuses_crushing_without_fracture(tmp_path, capsys):
    from validation import cli

    for extra in ([], ["--no-fem", "--fem-fracture", "median"]):
        code = cli.main(["validate", "--quick", "--fem-crush", "0.1", *extra,
                         "--out", str(tmp_path / "out")])
        assert code == 2
        assert "--fem-crush goes with FE runs and --fem-fracture" in capsys.readouterr().err
    assert cli.main(["validate", "--fem-crush", "1", "--out", str(tmp_path / "o")]) == 2
    assert "at most 0.99" in capsys.readouterr().err
