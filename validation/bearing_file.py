"""A user's own bearing: a TOML file with any of :class:`rigid.DFPBearing`'s fields in the
units of docs/bearing.md (MPa, m, mm for the friction's elastic slip, GPa for Young's
modulus), checked field by field, and the commented template that ``dfp bearing --template``
writes.

Call :func:`read_bearing_file` for the fields of a file in SI units (a ``dict`` for
``DFPBearing(**fields)``), :func:`bearing_from` to build the bearing of a command from a file
and the command line's options, :func:`template` for the template's text. Every error is a
:class:`ValueError` of one line naming the field, the value and the allowed range.
"""

from __future__ import annotations

import dataclasses
import difflib
import math
from pathlib import Path
from typing import NamedTuple

from rigid import DFPBearing

__all__ = ["FIELDS", "OPTIONS", "UNITS", "Field", "bearing_from", "check_field",
           "describe_variant", "option_range", "overrides", "read_bearing_file", "template"]


class Field(NamedTuple):
    """How a :class:`rigid.DFPBearing` field is written in a bearing file: its unit there,
    the factor from SI to that unit, the plausible range in that unit (``low_open``: the
    low end excluded), where the default comes from and what it is."""

    unit: str
    factor: float
    low: float
    high: float
    source: str
    text: str
    low_open: bool = False


#: Every field of :class:`rigid.DFPBearing` as a bearing file writes it; the ranges are what
#: sliding bearings are built with, wide enough for any design and narrow enough to catch a
#: value in the wrong unit (a radius in mm, a pressure in Pa).
FIELDS: dict[str, Field] = {
    "pressure": Field("MPa", 1e-6, 1, 200, "paper", "slider pressure of the supported load "
                      "(paper: 60 heavy, 10 light)"),
    "radius": Field("m", 1, 0.5, 10, "paper", "radius of each sliding surface R"),
    "friction": Field("-", 1, 0, 0.3, "paper", "friction coefficient μ of the sliding surfaces"),
    "slider_diameter": Field("m", 1, 0.05, 2, "assumed", "slider diameter b"),
    "slider_height": Field("m", 1, 0.02, 1, "assumed", "slider height h, face to face"),
    "capacity": Field("m", 1, 0.02, 1.5, "assumed", "travel on one surface until the slider "
                      "touches the rim (the bearing's displacement capacity is twice this)"),
    "rim_height": Field("m", 1, 0.005, 0.2, "assumed", "rim height above the dish"),
    "rim_thickness": Field("m", 1, 0.005, 0.5, "assumed", "rim radial thickness"),
    "contact_stiffness": Field("N/m^1.5", 1, 1e8, 1e13, "assumed",
                               "Hertz stiffness k of every contact (paper Eqs. 1-2)"),
    "restitution": Field("-", 1, 0, 1, "paper", "coefficient of restitution e (paper Eq. 4)",
                         low_open=True),
    "impact_mass": Field("", 1, math.nan, math.nan, "assumed", "colliding masses of paper "
                         "Eq. 3 (docs/theory/rigid-body.md, Eq. R19)"),
    "rim_friction": Field("-", 1, 0, 0.5, "assumed", "friction between the slider and the rims"),
    "friction_yield_slip": Field("mm", 1e3, 0.001, 10, "assumed",
                                 "elastic slip Y before sliding starts"),
    "design_period": Field("s", 1, 0.5, 10, "paper", "period Tb at which records are scaled, "
                           "SA(Tb)"),
    "steel_density": Field("kg/m³", 1, 1000, 20000, "assumed", "density of the slider"),
    "youngs_modulus": Field("GPa", 1e-9, 10, 400, "assumed", "steel Young's modulus (FE model)"),
    "poisson_ratio": Field("-", 1, 0, 0.5, "assumed", "steel Poisson's ratio (FE model)",
                           low_open=True),
    "yield_stress": Field("MPa", 1e-6, 100, 1500, "paper", "rim steel yield stress f_y"),
    "ultimate_stress": Field("MPa", 1e-6, 100, 2000, "paper", "rim steel ultimate stress f_u"),
    "hardening_ratio": Field("-", 1, 0, 0.5, "paper", "post-yield stiffness ratio E_t/E",
                             low_open=True),
    "plate_thickness": Field("m", 1, 0.01, 0.5, "assumed", "plate thickness under the dish "
                             "(FE model)"),
    "rupture_strain": Field("-", 1, 0.01, 1, "assumed", "plastic strain at which the rim steel "
                            "ruptures (ln(1 + 0.21), ASTM A572 Gr. 50)"),
}

#: Unit and factor from SI of each field, as the report and the bearing file show it.
UNITS = {name: (f.unit, f.factor) for name, f in FIELDS.items()}


def _loads(text: str) -> dict:
    try:
        import tomllib
    except ModuleNotFoundError:  # Python 3.10
        import tomli as tomllib
    return tomllib.loads(text)


def _bounds(f: Field) -> str:
    low = f"{f.low:g}" if not f.low_open else f"above {f.low:g}"
    unit = f" {f.unit}" if f.unit not in ("", "-") else ""
    return f"{low} to {f.high:g}{unit}" if not f.low_open else f"{low} and at most {f.high:g}{unit}"


def check_field(name: str, value, where: str = "") -> float | str:
    """``value`` of field ``name`` in the file's unit, checked; returned in SI units.
    ValueError of one line (``where``: the file, as its prefix) names the field, the value and
    the allowed range; an unknown field gets the nearest known name."""
    prefix = f"{where}: " if where else ""
    if name not in FIELDS:
        near = difflib.get_close_matches(name, FIELDS, n=1)
        hint = f" (did you mean {near[0]}?)" if near else f"; fields: {', '.join(FIELDS)}"
        raise ValueError(f"{prefix}unknown field {name!r}{hint}")
    f = FIELDS[name]
    if name == "impact_mass":
        if value not in ("supported", "slider"):
            raise ValueError(f"{prefix}impact_mass = {str(value)[:40]!r}: allowed \"supported\" "
                             "or \"slider\"")
        return value
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise ValueError(f"{prefix}{name} = {str(value)[:40]!r}: must be a number in "
                         f"{_bounds(f)}")
    ok = math.isfinite(value) and (value > f.low if f.low_open else value >= f.low) \
        and value <= f.high
    if not ok:
        unit = f" {f.unit}" if f.unit not in ("", "-") else ""
        raise ValueError(f"{prefix}{name} = {value:g}{unit} is outside the allowed range "
                         f"{_bounds(f)}")
    return value / f.factor


def read_bearing_file(path) -> dict:
    """The fields of a bearing file in SI units, each checked (:func:`check_field`); the
    bearing as a whole is checked when built (:func:`bearing_from`).

    Parameters
    ----------
    path : str or Path
        A TOML file: ``name = value`` lines at the top level (or under ``[bearing]``), in the
        units of :data:`FIELDS` (``dfp bearing --template`` writes one).
    """
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise ValueError(f"bearing file {path} does not exist") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise ValueError(f"bearing file {path}: cannot read it ({exc})") from None
    try:
        data = _loads(text)
    except Exception as exc:  # tomllib.TOMLDecodeError: its message names the line
        raise ValueError(f"bearing file {path}: not valid TOML: {exc}") from None
    if set(data) == {"bearing"} and isinstance(data["bearing"], dict):
        data = data["bearing"]
    return {name: check_field(name, value, str(path)) for name, value in data.items()}


#: The command line's options for the common fields: option → (field, the option's unit,
#: factor from that unit to SI). ``--displacement-capacity`` is the bearing's, twice the field
#: ``capacity``; rims are given in mm as before.
OPTIONS = {
    "pressure": ("pressure", "MPa", 1e6), "radius": ("radius", "m", 1.0),
    "friction": ("friction", "", 1.0), "slider_diameter": ("slider_diameter", "m", 1.0),
    "displacement_capacity": ("capacity", "m", 0.5),
    "rim_thickness": ("rim_thickness", "mm", 1e-3), "rim_height": ("rim_height", "mm", 1e-3),
    "yield_stress": ("yield_stress", "MPa", 1e6),
    "ultimate_stress": ("ultimate_stress", "MPa", 1e6),
}


def option_range(option: str) -> tuple[float, float, str, bool]:
    """The allowed range of a command-line option in its own unit: (low, high, unit,
    low_open), from its field's range in :data:`FIELDS`."""
    name, unit, factor = OPTIONS[option]
    f = FIELDS[name]
    to_option = 1.0 / (f.factor * factor)
    return f.low * to_option, f.high * to_option, unit, f.low_open


def overrides(args) -> dict:
    """The bearing's fields in SI units from ``--bearing FILE`` and the options given (an
    option, already checked by the parser against :func:`option_range`, wins over the
    file); the pressure included when given as one number."""
    fields = read_bearing_file(args.bearing) if getattr(args, "bearing", None) else {}
    for option, (name, _, factor) in OPTIONS.items():
        value = getattr(args, option, None)
        if value is None or isinstance(value, list):  # validate's --pressure is a list
            continue
        fields[name] = value * factor
    return fields


def bearing_from(fields: dict, **changes) -> DFPBearing:
    """A :class:`rigid.DFPBearing` from fields in SI units (and ``changes``); a combination
    that is no bearing (rims that leave no clearance, a capacity too large for the radius) is
    a one-line ValueError."""
    try:
        return DFPBearing(**{**fields, **changes})
    except ValueError as exc:
        raise ValueError(f"bearing: {exc}") from None


def describe_variant(fields) -> str:
    """The fields that differ from the baseline, as the report's settings show them
    (``rim thickness 80 mm``; rims in mm, the others in their file units)."""
    parts = []
    for name, value in dict(fields).items():
        if name == "impact_mass":
            parts.append(f"impact mass {value}")
            continue
        unit, factor = ("mm", 1e3) if name in ("rim_height", "rim_thickness") else UNITS[name]
        parts.append(f"{name.replace('_', ' ')} {value * factor:g}"
                     + (f" {unit}" if unit not in ("", "-") else ""))
    return ", ".join(parts)


def template(pressure: float | None = None) -> str:
    """The text of a commented bearing file with every field at the baseline's value
    (``pressure`` [Pa]: another pressure)."""
    base = DFPBearing() if pressure is None else DFPBearing(pressure=pressure)
    lines = [
        "# A double friction pendulum bearing for dfp (--bearing FILE).",
        "# Every field is optional: a field left out (or commented out) keeps the value shown.",
        "# Units as in docs/bearing.md: MPa, m, s; each field is checked against its range.",
        "# 'paper': Bao & Becker (2016); 'assumed': the paper's Figure 1 is not available.",
        "",
    ]
    for f in dataclasses.fields(DFPBearing):
        spec = FIELDS[f.name]
        value = getattr(base, f.name)
        if f.name == "impact_mass":
            shown, bounds = f'"{value}"', "\"supported\" or \"slider\""
        else:
            shown, bounds = f"{value * spec.factor:.6g}", _bounds(spec)
            if "e" in shown and "." not in shown.split("e")[0]:
                shown = shown.replace("e", ".0e")  # TOML floats need a dot before e
        unit = f" [{spec.unit}]" if spec.unit else ""
        lines.append(f"# {spec.text}{unit}; {bounds}; {spec.source}")
        lines.append(f"{f.name} = {shown}")
        lines.append("")
    return "\n".join(lines)
