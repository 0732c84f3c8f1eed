"""The report in a real browser (headless Chromium, when installed; CI machines have none and
skip): at 800, 1000 and 1400 px no table is cut off, every table is fully visible or inside a
box that scrolls horizontally; the Summary is on the first 1280 × 800 screen; printed (the
print style sheet at A4 width) no table is cut (validation/studies/report_screenshots.py does
the same for the example report and takes the screenshots in docs/images).

Oracle: the browser's own layout (each table's right edge against the window, its box's
computed overflow). To show the check can fail, the same page with the scrolling boxes
switched off must report the wide table as cut at 800 px.
"""

import pytest

from validation.report.html import Report
from validation.studies.report_screenshots import find_chromium, layout

CHROMIUM = find_chromium()
pytestmark = pytest.mark.skipif(CHROMIUM is None, reason="no chromium (apt-get install chromium)")


def _page(tmp_path):
    report = Report("layout")
    wide = [{f"column {k} [unit]": 1000.0 + k for k in range(30)} for _ in range(3)]
    report.table(wide, caption="a table far wider than 800 px")
    report.table([{"setting": "pressures", "value": "60, 10", "unit": "MPa"}], caption="narrow")
    return report.write(tmp_path / "report.html")


@pytest.mark.parametrize("width", [800, 1400])
def test_no_table_is_cut_off(tmp_path, width):
    data = layout(_page(tmp_path), width, CHROMIUM)
    wide, narrow = data["tables"]
    assert not [t for t in data["tables"] if t["cut"]]
    assert wide["scrolls"] and wide["box_scroll_width"] > wide["box_width"]  # it does scroll
    assert narrow["table_right"] <= narrow["view"]


def test_the_check_sees_a_cut_table(tmp_path):
    page = _page(tmp_path)
    page.write_text(page.read_text().replace("overflow-x: auto", "overflow-x: visible"))
    wide, _narrow = layout(page, 800, CHROMIUM)["tables"]
    assert wide["cut"]


# -- a whole report: the Summary on the first screen, nothing cut at 1000 px or in print -------


@pytest.fixture(scope="module")
def report_page(tmp_path_factory):
    """A report as dfp validate writes it: two Ricker-pulse records at 60 and 10 MPa (rigid
    ladders and predictions, run here in a few seconds) and an FE section with the widest
    table of all (every FE run, 19 columns), the FE answers made up around the rigid ones."""
    from rigid import G, GroundMotion, ricker_record
    from validation.fem_search import FECritical, FESettings
    from validation.report import write_report
    from validation.run import Settings, run_rigid

    out = tmp_path_factory.mktemp("report")
    motions = []
    for k, (amplitude, period) in enumerate(((0.25, 2.5), (0.2, 3.0))):
        _, a = ricker_record(amplitude * G, period, "antisymmetric", dt=0.01, free=8.0)
        motions.append(GroundMotion(name=f"pulse {k} with a long name_{k:03d}", dt=0.01,
                                    acceleration=a))
    settings = Settings(pressures=(60e6, 10e6), criteria=(3, 4), stop=1.2 * G,
                        fem=FESettings())
    results = run_rigid(motions, settings, out, workers=1, progress=False)
    probes = [{"sa": sa * G, "scale": 2.0, "failed": sa > 0.2, "failure_mode": "yielding",
               "failure_time": 4.2, "numerical_failure": False, "start": 1.0,
               "strong_end": 9.0, "end": 4.2, "quiet": True, "energy_end": 1e5,
               "reach_energy": 2e5, "steps": 900, "newton_iterations": 2000, "dofs": 905,
               "max_plastic_strain": 0.03, "max_rim_force": 2.0e6, "cpu_seconds": 30.0}
              for sa in (0.25, 0.2, 0.21)]
    fem = {60e6: [FECritical(m.name, 60e6, a.sa, 0.21 * G, 0.2 * G, "yielding", 4.2, probes)
                  for m, a in zip(motions, results[60e6].actual, strict=True)]}
    return write_report(results, motions, settings, out, elapsed=60.0, title="layout",
                        record_set="two Ricker pulses", fem=fem)


def test_the_summary_is_on_the_first_screen(report_page):
    """In a 1280 × 800 window the Summary (what ran, the answers' table, the verdicts and
    the key figure) ends above 800 px; the check sees a summary pushed below the screen."""
    data = layout(report_page, 1280, CHROMIUM, height=800)
    assert data["summary"]["figure"] and data["summary"]["table"]
    assert data["summary"]["bottom"] <= 800, data["summary"]
    pushed = report_page.parent / "pushed.html"
    pushed.write_text(report_page.read_text().replace(
        '<div class="summary">', '<div style="height: 900px"></div><div class="summary">', 1))
    assert layout(pushed, 1280, CHROMIUM, height=800)["summary"]["bottom"] > 800


def test_nothing_overflows_at_1000_px(report_page):
    data = layout(report_page, 1000, CHROMIUM)
    assert [t["index"] for t in data["tables"] if t["cut"]] == []
    assert data["page_width"] <= data["view"]  # no horizontal scroll of the page


def test_print_cuts_no_table(report_page, tmp_path):
    """With the print style sheet at an A4 page's printable width, where nothing can scroll,
    every table fits the page; without it the FE runs' table is cut. Chromium prints the
    page to a PDF of several A4 pages."""
    from validation.studies.report_screenshots import A4_PRINT_WIDTH, print_pdf

    data = layout(report_page, A4_PRINT_WIDTH, CHROMIUM, media="print")
    assert [t["index"] for t in data["tables"] if t["cut"]] == []
    assert data["page_width"] <= data["view"]
    bare = tmp_path / "bare.html"
    bare.write_text(report_page.read_text().replace("@media print", "@media nothing"))
    assert any(t["cut"] for t in layout(bare, A4_PRINT_WIDTH, CHROMIUM, media="print")["tables"])
    pdf = print_pdf(report_page, tmp_path / "report.pdf", CHROMIUM).read_bytes()
    pages = pdf.count(b"/Type /Page") - pdf.count(b"/Type /Pages")
    assert pdf.startswith(b"%PDF") and pages > 1
