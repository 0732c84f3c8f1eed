"""Output of FE results: VTU files for ParaView (meshio) and pictures (pyvista, off-screen).

pyvista renders through Mesa EGL without a display (no X server or Xvfb needed); the variable
``VTK_DEFAULT_OPENGL_WINDOW=vtkEGLRenderWindow`` is set before pyvista is imported. Heavy
imports stay inside the functions so ``import fem`` stays light.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from .contact import SliderShape, rotation
from .material import von_mises

FIELDS = {
    "von_mises": "von Mises stress [MPa]",
    "eq_plastic_strain": "equivalent plastic strain [-]",
}


def cell_fields(stress: np.ndarray, plastic_strain: np.ndarray) -> dict:
    """Element averages of the von Mises stress [Pa] and equivalent plastic strain [-].

    Parameters
    ----------
    stress : ndarray, shape (4, nelems, nqp) [Pa]
    plastic_strain : ndarray, shape (nelems, nqp) [-]
    """
    return {
        "von_mises": von_mises(stress).mean(axis=-1),
        "eq_plastic_strain": np.asarray(plastic_strain).mean(axis=-1),
    }


def nodal_displacement(mesh, d_full: np.ndarray) -> np.ndarray:
    """Plate displacements per mesh vertex, shape (2, nvertices) [m] (scikit-fem's vector Q1
    numbers the dofs node by node: x, z)."""
    n = mesh.p.shape[1]
    return d_full[: 2 * n].reshape(n, 2).T


def slider_outline(shape: SliderShape, pose, n: int = 48) -> np.ndarray:
    """Closed outline of the slider section at a pose, shape (2, m) [m], with its rounded
    edges if it has them."""
    R, r = shape.radius, shape.edge_radius
    cb, ct = shape.centres
    f = shape.edge_centres
    # each face arc ends where it meets its edge arc (at the sharp vertex if r = 0)
    a = np.arcsin(f[0, 1] / (R - r)) if r > 0 else np.arcsin(shape.half_width / R)
    s = np.linspace(-a, a, n)
    bottom = cb[:, None] + R * np.array([np.sin(s), -np.cos(s)])
    top = ct[:, None] + R * np.array([np.sin(s[::-1]), np.cos(s[::-1])])
    parts = [bottom]
    if r > 0:  # counter-clockwise: bottom right, top right edges; top face; top left, bottom left
        parts += [_edge(f[:, 1], r, a - np.pi / 2, 0.0, n // 4),
                  _edge(f[:, 3], r, 0.0, np.pi / 2 - a, n // 4)]
    parts.append(top)
    if r > 0:
        parts += [_edge(f[:, 2], r, np.pi / 2 + a, np.pi, n // 4),
                  _edge(f[:, 0], r, np.pi, 1.5 * np.pi - a, n // 4)]
    xi = np.concatenate([*parts, bottom[:, :1]], axis=1)
    return rotation(pose[2]) @ xi + np.asarray(pose[:2])[:, None]


def _edge(centre, r, start, stop, n):
    """Points of a rounded edge's arc from angle ``start`` to ``stop`` [rad]."""
    t = np.linspace(start, stop, n)
    return centre[:, None] + r * np.array([np.cos(t), np.sin(t)])


def write_vtu(path, mesh, d_full, stress, plastic_strain) -> Path:
    """Write the deformed-state fields to a VTU file (ParaView).

    Parameters
    ----------
    path : path-like
    mesh : skfem.MeshQuad1
    d_full : ndarray
        Full dof vector (plates first) [m].
    stress : ndarray, shape (4, nelems, nqp) [Pa]
    plastic_strain : ndarray, shape (nelems, nqp) [-]

    Returns
    -------
    pathlib.Path
    """
    import meshio

    u = nodal_displacement(mesh, d_full)
    points = np.column_stack([mesh.p.T, np.zeros(mesh.p.shape[1])])
    cells = cell_fields(stress, plastic_strain)
    out = meshio.Mesh(
        points,
        [("quad", mesh.t.T.astype(np.int64))],
        point_data={"displacement": np.column_stack([u.T, np.zeros(u.shape[1])])},
        cell_data={k: [v] for k, v in cells.items()},
    )
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    meshio.write(str(path), out)
    return path


def _pyvista():
    os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")
    import pyvista

    pyvista.OFF_SCREEN = True
    return pyvista


def _add_state(plotter, pv, mesh, shape, d_full, pose, stress, plastic, field, scale, clim):
    u = nodal_displacement(mesh, d_full)
    pts = np.column_stack([(mesh.p + scale * u).T, np.zeros(mesh.p.shape[1])])
    faces = np.column_stack([np.full(mesh.t.shape[1], 4), mesh.t.T]).ravel()
    grid = pv.PolyData(pts, faces)
    values = cell_fields(stress, plastic)[field]
    if field == "von_mises":
        values = values / 1e6
    grid.cell_data[FIELDS[field]] = values
    plotter.add_mesh(
        grid, scalars=FIELDS[field], cmap="turbo", clim=clim, show_edges=False,
        scalar_bar_args={"title": FIELDS[field], "vertical": False, "n_labels": 4},
    )
    outline = slider_outline(shape, pose)
    line = np.column_stack([outline.T, np.full(outline.shape[1], 0.001)])
    plotter.add_lines(np.repeat(line, 2, axis=0)[1:-1], color="black", width=3)
    plotter.view_xy()


def render_state(
    path,
    mesh,
    shape: SliderShape,
    d_full,
    pose,
    stress,
    plastic_strain,
    *,
    title: str = "",
    scale: float = 1.0,
    focus=None,
    clims=None,
    window=(1600, 1000),
) -> Path:
    """PNG of von Mises stress (top) and equivalent plastic strain (bottom) on the deformed
    shape, with the slider's outline.

    Parameters
    ----------
    path : path-like
    mesh : skfem.MeshQuad1
    shape : SliderShape
    d_full : ndarray
        Full dof vector [m].
    pose : sequence of 3 floats [m, m, rad]
        Slider pose.
    stress, plastic_strain : ndarray
        (4, nelems, nqp) [Pa] and (nelems, nqp) [-].
    title : str
    scale : float [-]
        Displacement magnification of the plates (the slider is drawn at its true pose).
    focus : (x, z, half_width) [m], optional
        Zoom the camera on a region (e.g. a rim).
    clims : dict, optional
        Field → (min, max) colour limits (MPa for stress).
    window : (int, int)
        Image size in pixels.
    """
    pv = _pyvista()
    clims = clims or {}
    plotter = pv.Plotter(off_screen=True, shape=(2, 1), window_size=list(window))
    for row, field in enumerate(("von_mises", "eq_plastic_strain")):
        plotter.subplot(row, 0)
        _add_state(
            plotter, pv, mesh, shape, d_full, pose, stress, plastic_strain, field, scale,
            clims.get(field),
        )
        if row == 0 and title:
            plotter.add_text(title, font_size=12, color="black")
        if focus is not None:
            x, z, w = focus
            plotter.camera.focal_point = (x, z, 0.0)
            plotter.camera.position = (x, z, 10.0)
            plotter.camera.parallel_projection = True
            plotter.camera.parallel_scale = w
            plotter.reset_camera_clipping_range()
        plotter.set_background("white")
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    plotter.screenshot(str(path))
    plotter.close()
    return path


def slider_pose(bearing, d: np.ndarray) -> np.ndarray:
    """The slider's pose (X, Z, Θ) [m, m, rad] of the :class:`rigid.DFPBearing` ``bearing`` at
    the displacements ``d`` [m, rad] of its FE model (the slider's three dofs last)."""
    return np.array([0.0, bearing.slider_height / 2, 0.0]) + d[-3:]


def final_pose(result) -> np.ndarray:
    """The slider's pose (X, Z, Θ) [m, m, rad] at the end of an :class:`fem.FEMResult`."""
    return slider_pose(result.bearing, result.final_displacement)


def render_result(path, result, **kwargs) -> Path:
    """:func:`render_state` of an :class:`fem.FEMResult`'s final state, without the elements
    that have let go altogether (Eq. F68; their vertices fall free, Eq. F69b)."""
    from skfem import MeshQuad1

    shape = SliderShape.from_bearing(result.bearing, result.edge_radius)
    held = (np.ones(result.mesh.t.shape[1], dtype=bool) if result.retained is None
            else result.retained > 0.0)
    return render_state(
        path, MeshQuad1(result.mesh.p, result.mesh.t[:, held]), shape,
        result.final_displacement, final_pose(result), result.final_stress[:, held],
        result.final_plastic_strain[held], **kwargs,
    )


def render_movie(path, result, *, fps: int = 10, **kwargs) -> Path:
    """Animated GIF of the snapshots of an :class:`fem.FEMResult` (``snapshot_every`` > 0).

    Colour limits are fixed over the movie (0 … the run's largest value) unless given.
    """
    import imageio.v2 as imageio

    if not result.snapshots:
        raise ValueError("the result has no snapshots; run fem.simulate with snapshot_every > 0")
    shape = SliderShape.from_bearing(result.bearing, result.edge_radius)
    vm_max = max(float(von_mises(s[3]).max()) for s in result.snapshots) / 1e6
    p_max = max(float(s[2].max()) for s in result.snapshots) or 1e-6
    kwargs.setdefault("clims", {"von_mises": (0.0, vm_max), "eq_plastic_strain": (0.0, p_max)})
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    frames = []
    tmp = path.with_suffix(".frame.png")
    title = kwargs.pop("title", "")
    for t, d, p, s in result.snapshots:
        render_state(
            tmp, result.mesh, shape, d, slider_pose(result.bearing, d), s, p,
            title=f"{title}  t = {t:.3f} s", **kwargs,
        )
        frames.append(imageio.imread(tmp))
    tmp.unlink(missing_ok=True)
    imageio.mimsave(path, frames, duration=1.0 / fps, loop=0)
    return path
