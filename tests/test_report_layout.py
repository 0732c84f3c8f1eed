"""The report in a real browser (headless Chromium, when installed; CI machines have none and
skip): at 800 and 1400 px no table is cut off, every table is fully visible or inside a box
that scrolls horizontally (validation/studies/report_screenshots.py does the same for the
example report and takes the screenshots in docs/images).

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
