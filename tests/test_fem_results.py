"""The FE model's typed results and records (fem.model.FEEnergy, fem.observer): attributes
instead of string keys, with the energy still readable as a mapping as before."""

from __future__ import annotations

import numpy as np
import pytest

from fem.model import FEEnergy
from fem.observer import History, Verdict

NAMES = ("input", "kinetic", "strain", "plastic", "contact", "friction", "fracture",
         "loose_kinetic", "residual")


def test_fe_energy_reads_as_attributes_and_as_a_mapping():
    e = FEEnergy(**{name: np.full(3, float(i)) for i, name in enumerate(NAMES)})
    assert tuple(e) == NAMES and len(e) == 9 and set(e.keys()) == set(NAMES)
    for i, name in enumerate(NAMES):
        assert e[name] is getattr(e, name) and e[name][0] == i
    assert dict(e.items())["friction"] is e.friction
    with pytest.raises(KeyError):
        e["potential"]


def test_history_arrays_keep_every_field():
    h = History()
    h.t.extend([0.0, 0.1])
    h.rim.extend([[1.0, 2.0, 3.0, 4.0]] * 2)
    a = h.arrays()
    assert isinstance(a.t, np.ndarray) and a.t.tolist() == [0.0, 0.1]
    assert a.rim.shape == (2, 4) and a.x.shape == (0,)


@pytest.mark.parametrize(("fields", "reached"), [
    ({}, False), ({"time": 1.0}, True), ({"numerical": "why"}, True),
    ({"mode": "uplift"}, False),
])
def test_a_verdict_is_reached_by_a_failure_time_or_a_numerical_end(fields, reached):
    assert Verdict(**fields).reached is reached
