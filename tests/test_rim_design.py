"""The rim design space's bookkeeping (validation/studies/rim_design*.py): what fails first,
the map's shares and the design chart's percentiles, on hand-made rungs and rows whose
answers are known; and the FE table's statistics against a hand count."""

from __future__ import annotations

import math

import pytest

from rigid import G
from rigid.collapse.ladder import CriticalSA, Rung
from validation.studies.rim_design import design_chart, mode_map
from validation.studies.rim_design_case import governing_mode
from validation.studies.rim_design_fem import statistics_rows


def _rung(j, *, failed=False, mode=None, states=()):
    return Rung(index=j, sa=j * 0.01 * G, scale=1.0, failed=failed, numerical_failure=False,
                failure_time=None, impacts=1, max_impact_velocity=0.3, max_uplift=0.0,
                failure_mode=mode, limit_states=tuple(states))


def _ladders(rungs, answers):
    """{limit state: CriticalSA} over the same rungs, ``answers`` the critical rung of each."""
    return {state: CriticalSA(sa=None if j is None else j * 0.01 * G, scale=None, name="r",
                              record_sa=G, period=4.5, start=0.01 * G, step=0.01 * G,
                              stop=3 * G, search="fast", rungs=tuple(rungs), rims="yielding",
                              limit_state=state)
            for state, j in answers.items()}


@pytest.mark.parametrize(("rungs", "answers", "expected"), [
    # the rim hinges at rung 20, ruptures at 25, lets the slider through at 30
    ([_rung(20, states=("hinge",)), _rung(25, states=("hinge", "rupture")),
      _rung(30, failed=True, mode="yielding", states=("hinge", "rupture", "containment"))],
     {"hinge": 20, "rupture": 25, "containment": 30}, "hinge"),
    # a squat rim: no hinge; it ruptures first
    ([_rung(25, states=("rupture",)),
      _rung(30, failed=True, mode="yielding", states=("rupture", "containment"))],
     {"hinge": 30, "rupture": 25, "containment": 30}, "rupture"),
    # the slider climbs over a rim that has not yielded
    ([_rung(40, failed=True, mode="uplift", states=("containment",))],
     {"hinge": 40, "rupture": 40, "containment": 40}, "uplift"),
    # nothing up to the top
    ([_rung(300)], {"hinge": None, "rupture": None, "containment": None}, "none"),
])
def test_what_fails_first(rungs, answers, expected):
    assert governing_mode(_ladders(rungs, answers)) == expected


def _row(t, p, mode, hinge):
    return {"rim_thickness_mm": t, "pressure_mpa": p, "governing_mode": mode,
            "hinge_sa_g": hinge, "rupture_sa_g": hinge, "containment_sa_g": hinge,
            "hinge_mode": "rim", "rupture_mode": "rim", "containment_mode": "uplift",
            "hinge_uncertain": False, "rupture_uncertain": False,
            "containment_uncertain": hinge is None, "rigid_sa_g": 1.0,
            "rigid_uncertain": False, "first_touch_sa_g": 0.2}


def test_the_map_counts_shares_per_thickness_and_pressure():
    rows = [_row(40, 60, "hinge", 0.2)] * 3 + [_row(40, 60, "uplift", 0.5)]
    (cell,) = mode_map(rows)
    assert cell["records"] == 4 and cell["share_hinge"] == 0.75 and cell["share_uplift"] == 0.25
    assert sum(cell[f"share_{m}"] for m in ("hinge", "rupture", "containment", "uplift",
                                            "none")) == pytest.approx(1.0)


def test_the_chart_percentiles_count_a_case_without_failure_as_above_the_top():
    # 10 records: 0.1 … 0.9 g and one without failure; the median is the 5th value (inverted
    # CDF: no interpolation), the 84th percentile the 9th, and the 16th the 2nd
    rows = [_row(80, 10, "hinge", round(0.1 * k, 1)) for k in range(1, 10)]
    rows.append(_row(80, 10, "none", None))
    chart = {r["model"]: r for r in design_chart(rows)}
    hinge = chart["yielding_hinge"]
    assert (hinge["p16_g"], hinge["median_g"], hinge["p84_g"]) == (0.2, 0.5, 0.9)
    assert hinge["no_failure"] == 1 and hinge["records"] == 10
    rows.append(_row(80, 10, "none", None))  # 2 of 11 without failure: the 84th is above
    chart = {r["model"]: r for r in design_chart(rows)}
    assert math.isinf(chart["yielding_hinge"]["p84_g"])
    # the containment of the two is numerical (uncertain): unknown, not above the top
    assert chart["yielding_containment"]["unknown"] == 2
    assert chart["yielding_containment"]["no_failure"] == 0
    assert chart["yielding_containment"]["p84_g"] == 0.8  # the 8th of the 9 known


def test_fem_statistics_count_the_discriminating_cases_apart():
    def case(fe, yielding, touch):
        return {"rim_thickness_mm": 160.0, "limit_state": "hinge", "fem_sa_g": str(fe),
                "yielding_sa_g": str(yielding), "first_touch_sa_g": touch,
                "fem_over_first_touch": fe / touch}

    rows = [case(0.20, 0.20, 0.20),   # not discriminating (FE = first touch)
            case(0.40, 0.38, 0.20),   # discriminating; yielding within 20 %, touch not
            case(0.30, 0.20, 0.22)]   # discriminating; neither within 20 %
    stats = {s["cases"]: s for s in statistics_rows(rows)}
    assert stats["all"]["n"] == 3 and stats["discriminating"]["n"] == 2
    d = stats["discriminating"]
    assert d["yielding_within_20"] == 0.5 and d["first_touch_within_20"] == 0.0
    assert d["median_fem_over_yielding"] == pytest.approx((0.40 / 0.38 + 0.30 / 0.20) / 2)


def test_containment_with_tearing_checks_the_issue_targets():
    """validation/studies/containment_tearing.py: containment rows only; the median FE/rigid
    within ±15 %, at least 80 % within ±35 %, and more cases within ±20 % of the rigid model
    than of the first touch. Five cases: FE/rigid 1.0, 1.1, 0.9, 1.3, 2.0 (median 1.1; four
    of five within 35 %, three within 20 %); FE/first touch 1.0, 1.5, 1.5, 1.5, 1.5."""
    from validation.studies.containment_tearing import statistics_rows as tearing

    def case(fe, rigid, touch, state="containment"):
        return {"rim_thickness_mm": 40.0, "limit_state": state, "fem_sa_g": str(fe),
                "yielding_sa_g": str(rigid), "first_touch_sa_g": touch,
                "fem_over_first_touch": fe / touch, "uncertain": "False",
                "numerical_runs": "0"}

    rows = [case(0.2, 0.2, 0.2), case(0.33, 0.3, 0.22), case(0.27, 0.3, 0.18),
            case(0.39, 0.3, 0.26), case(0.6, 0.3, 0.4), case(0.9, 0.1, 0.1, "hinge")]
    s = {s["cases"]: s for s in tearing(rows)}["all"]
    assert (s["n"], s["of"]) == (5, 5)
    assert s["median_fem_over_yielding"] == pytest.approx(1.1)
    assert (s["yielding_within_20"], s["yielding_within_35"]) == (0.6, 0.8)
    assert (s["first_touch_within_20"], s["first_touch_within_35"]) == (0.2, 0.2)
    assert s["target_median"] and s["target_within_35"] and s["target_beats_first_touch"]
    rows[1] = case(0.33, 0.2, 0.22)  # FE/rigid 1.65: three of five within 35 %
    s = {s["cases"]: s for s in tearing(rows)}["all"]
    assert not s["target_within_35"]
    # the same cases run with crushing are another validation, with statistics of their own
    crushed = [{**r, "crush_jacobian": 0.1} for r in rows[:2]]
    stats = [s for s in tearing(rows + crushed) if s["cases"] == "all"]
    assert [(s["crush_jacobian"], s["n"]) for s in stats] == [("", 5), (0.1, 2)]


def test_the_containment_figure_has_a_panel_per_validation(tmp_path):
    """validation/studies/containment_tearing_figure.py: a panel per (thickness, crushing),
    thinner first and uncrushed before crushed, only containment cases with both answers;
    its legend counts the cases within ±20 % as the statistics do (FE/rigid 1.1 and 1.3: one;
    FE/first touch 1.5 twice: none)."""
    from rigid.collapse.comparison import write_csv
    from validation.studies.containment_tearing_figure import _within, draw, panels

    def case(t, crush, fe, rigid, touch, state="containment"):
        return {"crush_jacobian": crush, "rim_thickness_mm": t, "limit_state": state,
                "fem_sa_g": fe, "yielding_sa_g": rigid, "first_touch_sa_g": touch,
                "run_finished": "True"}

    rows = [case(80, "", 0.33, 0.3, 0.22), case(40, 0.1, 0.39, 0.3, 0.26),
            case(40, "", 0.33, 0.3, 0.22), case(40, "", 0.39, 0.3, 0.26),
            case(40, "", 0.5, "", 0.3), case(40, "", 0.5, 0.5, 0.3, "hinge")]
    write_csv(rows, tmp_path / "c.csv")
    groups = panels([{k: str(v) for k, v in r.items()} for r in rows])
    assert [(t, c, len(g)) for (t, c), g in groups.items()] == [
        (40.0, "", 2), (40.0, "0.1", 1), (80.0, "", 1)]
    assert _within(groups[40.0, ""], "yielding_sa_g") == 1
    assert _within(groups[40.0, ""], "first_touch_sa_g") == 0
    assert draw(tmp_path / "c.csv", tmp_path / "c.png").stat().st_size > 10_000

def test_the_slider_lifts_where_the_rims_upward_force_passes_the_weight():
    """validation/studies/slider_lift.py: W = p·πd²/4 (0.4 m slider: 1.257 MN at 10 MPa,
    7.540 MN at 60 MPa); the first set at which the upward force reaches W, none at 60 MPa
    here; the largest force and where; the push's tear and end."""
    from types import SimpleNamespace

    from validation.studies.slider_lift import lift_rows

    curve = [{"rim_thickness_mm": 120.0, "set_mm": d, "vertical_mn": f}
             for d, f in ((10.0, 0.5), (20.0, 1.3), (30.0, 2.0), (40.0, 1.0))]
    at10, at60 = lift_rows(curve, SimpleNamespace(fracture_displacement=0.035), (10, 60))
    assert at10["weight_mn"] == pytest.approx(1.2566, rel=1e-4)
    assert at60["weight_mn"] == pytest.approx(7.5398, rel=1e-4)
    assert (at10["lifted_from_mm"], at60["lifted_from_mm"]) == (20.0, "")
    assert (at10["largest_upward_mn"], at10["largest_at_mm"]) == (2.0, 30.0)
    assert (at10["first_tear_mm"], at10["push_end_mm"]) == (pytest.approx(35.0), 40.0)

def test_fracture_sensitivity_sets_each_set_beside_the_median(tmp_path):
    """validation/studies/fracture_sensitivity.py: per record each set's SA and its ratio to
    the median set's, read from a finished run's fem_comparison.csv or from the finished rows
    of a run's status.csv (other limit states and pressures left out); then the median,
    smallest and largest ratio. Two records, steep FE/median 0.8 and 1.0, mild 1.5 and 1.2."""
    import csv

    from validation.studies.fracture_sensitivity import table

    columns = ["finished", "record", "pressure_mpa", "limit_state", "fem_sa_g",
               "yielding_sa_g"]

    def folder(name, file, rows):
        path = tmp_path / name
        path.mkdir()
        with open(path / file, "w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(columns)
            w.writerows(rows)
        return path

    folders = {
        "steep": folder("steep", "fem_comparison.csv", [
            ["True", "a", "60", "containment", "0.16", "0.2"],
            ["True", "b", "60", "containment", "0.3", "0.3"],
            ["True", "b", "10", "containment", "0.9", "0.9"]]),
        "median": folder("median", "status.csv", [
            ["True", "a", "60", "containment", "0.2", "0.2"],
            ["True", "b", "60", "containment", "0.3", "0.3"],
            ["False", "b", "60", "hinge", "0.1", "0.1"]]),
        "mild": folder("mild", "fem_comparison.csv", [
            ["True", "a", "60", "containment", "0.3", "0.25"],
            ["True", "b", "60", "containment", "0.36", "0.3"]]),
    }
    rows = table(folders)
    assert [r["record"] for r in rows[:2]] == ["a", "b"]
    assert rows[0]["fem_steep_over_median"] == pytest.approx(0.8)
    assert rows[1]["fem_mild_over_median"] == pytest.approx(1.2)
    assert rows[0]["rigid_mild_over_median"] == pytest.approx(1.25)
    median, low, high = rows[2:]
    assert median["fem_mild_over_median"] == pytest.approx(1.35)
    assert (low["fem_steep_over_median"], high["fem_steep_over_median"]) == pytest.approx(
        (0.8, 1.0))


def test_keep_stored_laws_needs_rekey_from(capsys):
    """The design space's --keep-stored-laws without --rekey-from is refused before anything
    runs (argparse's exit 2, the reason on stderr)."""
    from validation.studies.rim_design import main

    with pytest.raises(SystemExit) as exit_:
        main(["--keep-stored-laws", "--records", "1"])
    assert exit_.value.code == 2
    assert "--keep-stored-laws needs --rekey-from" in capsys.readouterr().err
