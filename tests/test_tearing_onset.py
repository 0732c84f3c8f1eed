"""The tearing-onset study's helpers: which rim an impact loads in series with the torn one,
and the energy of the impact in which a rim tore (validation/studies/tearing_onset.py)."""

from types import SimpleNamespace

import numpy as np
import pytest

from rigid.model import RIM_NAMES
from validation.studies.tearing_onset import impact_energy, partner


def test_the_partner_is_the_other_plates_rim_on_the_other_side():
    assert partner("top -x") == "bottom +x"
    assert partner("bottom -x") == "top +x"
    assert {partner(r) for r in RIM_NAMES} == set(RIM_NAMES)
    assert all(partner(partner(r)) == r for r in RIM_NAMES)


def _history():
    """Two impacts (0.3–0.4 s and from 0.7 s) on a 0.1 s grid; kinetic energy falling by 10 J
    a sample, plastic work growing by 10 J a sample while a rim is loaded."""
    time = np.round(np.arange(11) * 0.1, 10)
    force = np.where(((time >= 0.3) & (time <= 0.4)) | (time >= 0.7), 5e6, 0.0)
    kinetic = 1000.0 - 10.0 * np.arange(11)
    plastic = np.cumsum(np.where(force > 0, 10.0, 0.0))
    return time, force, SimpleNamespace(kinetic=kinetic, plastic=plastic)


def test_the_impact_starts_at_the_last_unloaded_sample_before_the_tear():
    time, force, energy = _history()
    got = impact_energy(time, force, 0.9, energy, {"kinetic": "kinetic", "plastic": "plastic"})
    # the second impact starts after 0.6 s (index 6), the tear is at index 9: three samples
    # loaded, 30 J of plastic work; the kinetic energy read at the start, 1000 − 60 J
    assert got == pytest.approx({"impact_kinetic_kj": 0.94, "impact_plastic_kj": 0.03})


def test_a_tear_between_impacts_changes_nothing():
    time, force, energy = _history()
    got = impact_energy(time, force, 0.6, energy, {"plastic": "plastic"})
    assert got == {"impact_plastic_kj": 0.0}
