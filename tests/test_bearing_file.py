"""A user's bearing file (validation/bearing_file.py): the template covers every DFPBearing
field and reads back as the baseline bearing; each field is checked on its own with a
one-line error naming the field, the value and the allowed range; the command line's options
win over the file."""

import argparse
import dataclasses
import math

import pytest

from rigid import DFPBearing
from validation.bearing_file import (
    FIELDS,
    OPTIONS,
    bearing_from,
    option_range,
    overrides,
    read_bearing_file,
    template,
)

NUMERIC = [name for name in FIELDS if name != "impact_mass"]


def test_every_field_of_the_bearing_has_a_unit_and_range():
    """No DFPBearing field can be added without saying how a file writes it."""
    assert list(FIELDS) == [f.name for f in dataclasses.fields(DFPBearing)]


@pytest.mark.parametrize("name", NUMERIC)
def test_the_baseline_lies_in_every_range(name):
    """The paper's bearing (both pressures) is accepted: a range that excluded it would be
    wrong."""
    f = FIELDS[name]
    for pressure in (10e6, 60e6):
        value = getattr(DFPBearing(pressure=pressure), name) * f.factor
        assert (value > f.low if f.low_open else value >= f.low) and value <= f.high


def test_the_template_reads_back_as_the_baseline(tmp_path):
    """Every field is written, in the file's units, and read back to the SI value it came
    from (6 significant digits written: rel 1e-6)."""
    path = tmp_path / "bearing.toml"
    path.write_text(template(), encoding="utf-8")
    fields = read_bearing_file(path)
    baseline = dataclasses.asdict(DFPBearing())
    assert set(fields) == set(baseline)
    for name, value in baseline.items():
        assert fields[name] == (value if isinstance(value, str)
                                else pytest.approx(value, rel=1e-6)), name
    built = dataclasses.asdict(bearing_from(fields))
    for name, value in baseline.items():  # field by field: approx takes no text (pytest 9.2)
        assert built[name] == (value if isinstance(value, str)
                               else pytest.approx(value, rel=1e-6)), name


@pytest.mark.parametrize("name", NUMERIC)
def test_a_value_out_of_range_names_field_value_and_range(tmp_path, name):
    f = FIELDS[name]
    bad = f.high * 10 + 1
    path = tmp_path / "b.toml"
    path.write_text(f"{name} = {bad!r}\n")
    with pytest.raises(ValueError) as info:
        read_bearing_file(path)
    message = str(info.value)
    assert "\n" not in message
    assert f"{name} = {bad:g}" in message and f"{f.high:g}" in message and "b.toml" in message


def test_unknown_field_wrong_type_and_bad_toml(tmp_path):
    path = tmp_path / "b.toml"
    path.write_text("frictoin = 0.04\n")
    with pytest.raises(ValueError, match="did you mean friction"):
        read_bearing_file(path)
    path.write_text('radius = "2.5"\n')
    with pytest.raises(ValueError, match=r"radius = '2\.5': must be a number"):
        read_bearing_file(path)
    path.write_text('impact_mass = "superstructure"\n')
    with pytest.raises(ValueError, match="impact_mass = 'superstructure'"):
        read_bearing_file(path)
    path.write_text("radius = \n")
    with pytest.raises(ValueError, match="not valid TOML"):
        read_bearing_file(path)
    with pytest.raises(ValueError, match="does not exist"):
        read_bearing_file(tmp_path / "none.toml")


def test_a_bearing_section_is_accepted(tmp_path):
    path = tmp_path / "b.toml"
    path.write_text("[bearing]\nradius = 3.0\nyield_stress = 355\n")
    assert read_bearing_file(path) == {"radius": 3.0, "yield_stress": pytest.approx(355e6)}


def test_fields_that_make_no_bearing_are_one_line_errors():
    """Each field in range, together no bearing: 150 mm rims leave no clearance."""
    with pytest.raises(ValueError, match="no clearance") as info:
        bearing_from({"rim_height": 0.15})
    assert "\n" not in str(info.value)


def test_options_win_over_the_file_in_their_own_units(tmp_path):
    """--rim-thickness is in mm, --displacement-capacity is twice the field capacity."""
    path = tmp_path / "b.toml"
    path.write_text("rim_thickness = 0.05\nfriction = 0.04\npressure = 30\n")
    args = argparse.Namespace(bearing=str(path), rim_thickness=70.0, displacement_capacity=0.5,
                              pressure=None)
    fields = overrides(args)
    assert fields == {"rim_thickness": pytest.approx(0.07), "friction": 0.04,
                      "pressure": pytest.approx(30e6), "capacity": pytest.approx(0.25)}


@pytest.mark.parametrize("option", list(OPTIONS))
def test_option_ranges_are_the_fields_ranges(option):
    """An option's range, taken back to SI, is its field's range in SI."""
    name, _, factor = OPTIONS[option]
    f = FIELDS[name]
    low, high, _, _ = option_range(option)
    assert math.isclose(low * factor, f.low / f.factor) and math.isclose(high * factor,
                                                                          f.high / f.factor)
