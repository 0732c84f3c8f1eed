"""The rim push of :mod:`fem.ring.push` as a CalculiX deck on the same mesh: the same vertices
and edge mid-points as 20-node bricks with 2 × 2 × 2 Gauss points (C3D20R), the same capped
bilinear J2 steel (``*PLASTIC``), supports and punch; small strain or ``NLGEOM``. Used by the
check with CalculiX (``validation/studies/rim3d_ccx.py``) and the deck-equivalence test.

:func:`write_deck` writes it, :func:`run_ccx` runs ``ccx`` (Debian's ``calculix-ccx``) and
reads the punch's force and the hinge section's plastic strain at every increment.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .mesh import RingMesh
from .push import Load, _force_scale

__all__ = ["CcxPush", "ccx_available", "run_ccx", "write_deck"]

#: Abaqus/CalculiX C3D20 mid-side nodes 9–20: the edges of corners 1–8 they sit on.
EDGES = ((0, 1), (1, 2), (2, 3), (3, 0), (4, 5), (5, 6), (6, 7), (7, 4), (0, 4), (1, 5),
         (2, 6), (3, 7))


def ccx_available() -> bool:
    """Whether CalculiX's ``ccx`` is on the PATH."""
    return shutil.which("ccx") is not None


def _num(x: float) -> str:
    return f"{x:.12g}"


def _lines(ids, per_line=8):
    ids = [str(i) for i in sorted(int(i) for i in ids)]
    return "\n".join(", ".join(ids[k:k + per_line]) for k in range(0, len(ids), per_line))


def quadratic_nodes(mesh: RingMesh):
    """Vertices and edge mid-points (3, n) [m] and the C3D20 connectivity (20, nelems), both
    1-based-ready (add 1)."""
    ends = [mesh.hexes[list(a)] for a in zip(*EDGES, strict=True)]
    edges = np.sort(np.stack(ends), axis=0)  # (2, 12, nelems)
    flat = edges.reshape(2, -1)
    unique, inverse = np.unique(flat, axis=1, return_inverse=True)
    mids = 0.5 * (mesh.points[:, unique[0]] + mesh.points[:, unique[1]])
    n0 = mesh.points.shape[1]
    conn = np.concatenate([mesh.hexes, n0 + inverse.reshape(12, -1)])
    return np.concatenate([mesh.points, mids], axis=1), conn


def write_deck(path, mesh: RingMesh, load: Load, steps, *, nlgeom: bool = False) -> None:
    """Write the push of ``mesh`` by ``load`` (a punch or the strip; CalculiX gets no contact)
    as ``path`` (.inp) [m, N, Pa]: one CalculiX step per ``(delta [m], increments)`` of
    ``steps``, each ramping the punch linearly to its δ in equal increments."""
    if load.kind not in ("punch", "strip"):
        raise ValueError("the CalculiX deck has the punch loads only (punch or strip)")
    if mesh.sweep not in ("half", "slab") or not mesh.plate:
        raise ValueError("the CalculiX deck is written for the half ring or the slab, with "
                         "the plate")
    b = mesh.bearing
    x, conn = quadratic_nodes(mesh)
    tol = 1e-7
    r1, zmid = b.rim_radius, b.dish_depth(b.rim_radius) + 0.5 * b.rim_height
    radius = np.hypot(x[0], x[1]) if mesh.kind == "ring" else x[0]
    bottom = np.flatnonzero(np.abs(x[2] + b.plate_thickness) < tol)
    symmetry = (np.flatnonzero(np.abs(x[1]) < tol) if mesh.kind == "ring"
                else np.arange(x.shape[1]))
    # the pushed face: corner nodes on it, and the mid-points of edges joining two of them
    corners = np.zeros(mesh.points.shape[1], bool)
    on = (np.abs(radius[:corners.size] - r1) < 1e-9 * r1) & (x[2, :corners.size] > zmid - tol)
    if load.kind == "punch":
        theta = np.arctan2(x[1, :corners.size], x[0, :corners.size])
        on &= np.abs(theta) <= 0.5 * load.width / r1 + 1e-9
    corners[on] = True
    pushed = set(np.flatnonzero(corners))
    for k, (a, c) in enumerate(EDGES):
        both = corners[conn[a]] & corners[conn[c]]
        pushed.update(conn[8 + k][both].tolist())
    hinge = mesh.elements(mesh.root_quads, layers=mesh.load_layers)
    E, nu = b.youngs_modulus, b.poisson_ratio
    H = E * b.hardening_ratio / (1 - b.hardening_ratio)
    p_u = (b.ultimate_stress - b.yield_stress) / H
    text = ["*HEADING", f"rim push ({mesh.kind}, {load.label}) written by fem.ring.ccx", "*NODE"]
    text += [f"{i + 1}, {_num(a)}, {_num(c)}, {_num(d)}" for i, (a, c, d) in enumerate(x.T)]
    text.append("*ELEMENT, TYPE=C3D20R, ELSET=EALL")
    for e, row in enumerate(conn.T):
        ids = [str(int(i) + 1) for i in row]
        text.append(f"{e + 1}, " + ", ".join(ids[:15]) + ",")
        text.append(", ".join(ids[15:]))
    text += ["*NSET, NSET=NBOTTOM", _lines(bottom + 1), "*NSET, NSET=NSYM", _lines(symmetry + 1),
             "*NSET, NSET=NPUSH", _lines(np.array(sorted(pushed)) + 1),
             "*ELSET, ELSET=EHINGE", _lines(hinge + 1),
             "*MATERIAL, NAME=STEEL", "*ELASTIC", f"{_num(E)}, {_num(nu)}", "*PLASTIC",
             f"{_num(b.yield_stress)}, 0.0", f"{_num(b.ultimate_stress)}, {_num(p_u)}",
             "*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL",
             "*BOUNDARY", "NBOTTOM, 1, 3, 0.0", "NSYM, 2, 2, 0.0"]
    for delta, increments in steps:
        dt = 1.0 / increments
        text += [f"*STEP{', NLGEOM' if nlgeom else ''}, INC=10000", "*STATIC",
                 f"{_num(dt)}, 1.0, {_num(dt * 1e-4)}, {_num(dt)}",
                 "*BOUNDARY", f"NPUSH, 1, 1, {_num(delta)}",
                 "*NODE PRINT, NSET=NPUSH, TOTALS=ONLY", "RF",
                 "*EL PRINT, ELSET=EHINGE", "PEEQ", "*END STEP"]
    text.append("")
    Path(path).write_text("\n".join(text))


@dataclass(frozen=True)
class CcxPush:
    """CalculiX's push: the punch's displacement [m], its force [N] (the half model doubled,
    or per unit depth [N/m] for the strip) and the hinge section's yielded fraction [-] at
    every increment, and the CPU time [s]."""

    displacement: np.ndarray
    force: np.ndarray
    root_yielded: np.ndarray
    cpu_time: float


def run_ccx(mesh: RingMesh, load: Load, steps, *, nlgeom: bool = False, workdir=None,
            threads: int = 1) -> CcxPush:
    """Write the deck (:func:`write_deck`), run ``ccx`` and read its results.

    Parameters
    ----------
    mesh : RingMesh
    load : Load
        A punch or the strip.
    steps : sequence of (float [m], int)
        The punch's displacement at the end of each step and the step's equal increments
        (CalculiX may cut them back).
    nlgeom : bool
        Geometric nonlinearity (CalculiX's finite-strain plasticity).
    workdir : path-like, optional
        Where the deck and results go; default a temporary folder, removed after.
    threads : int
        ``OMP_NUM_THREADS`` of the run.
    """
    if not ccx_available():
        raise FileNotFoundError("CalculiX's ccx is not on the PATH (Debian: apt-get install "
                                "calculix-ccx)")
    tmp = None if workdir is not None else tempfile.TemporaryDirectory()
    folder = Path(workdir if workdir is not None else tmp.name)
    folder.mkdir(parents=True, exist_ok=True)
    try:
        write_deck(folder / "push.inp", mesh, load, steps, nlgeom=nlgeom)
        env = dict(os.environ, OMP_NUM_THREADS=str(threads), CCX_NPROC_EQUATION_SOLVER=str(threads))
        before = os.times()
        proc = subprocess.run(["ccx", "-i", "push"], cwd=folder, env=env, capture_output=True,
                              text=True)
        after = os.times()
        dat = folder / "push.dat"
        if proc.returncode != 0 or not dat.exists():
            tail = (proc.stdout + proc.stderr).strip().splitlines()[-5:]
            raise RuntimeError("ccx failed: " + " | ".join(tail))
        times, forces, yielded = _read_dat(dat.read_text())
    finally:
        if tmp is not None:
            tmp.cleanup()
    scale = _force_scale(mesh)
    # the total time runs 0 → 1 in the first step, 1 → 2 in the second, …
    ends = np.concatenate([[0.0], [d for d, _ in steps]])
    displacement = np.interp(times, np.arange(ends.size), ends)
    return CcxPush(np.concatenate([[0.0], displacement]),
                   np.concatenate([[0.0], forces * scale]), np.concatenate([[0.0], yielded]),
                   (after.children_user + after.children_system)
                   - (before.children_user + before.children_system))


def _read_dat(text: str):
    """Times, the total x-force of the pushed set and the yielded fraction of the hinge
    elements' Gauss points, per increment, from CalculiX's .dat file."""
    times, forces, yielded = [], [], []
    blocks = re.split(r"\n(?=\s*(?:total force|equivalent plastic strain))", text)
    for block in blocks:
        head = [line for line in block.strip().splitlines() if line.strip()]
        if not head:
            continue
        m = re.search(r"time\s+([0-9.Ee+-]+)", head[0])
        if head[0].startswith("total force") and m:
            values = [float(v) for v in head[1].split()]
            times.append(float(m.group(1)))
            forces.append(values[0])
        elif head[0].startswith("equivalent plastic strain") and m:
            peeq = np.array([float(line.split()[-1]) for line in head[1:]])
            yielded.append(float((peeq > 0).mean()) if peeq.size else 0.0)
    return np.array(times), np.array(forces), np.array(yielded)
