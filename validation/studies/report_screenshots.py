"""The validation report as a reader sees it: headless Chromium renders ``report.html`` at 800
and 1400 px, writes full-page screenshots (``docs/images/report_800px.png``,
``report_1400px.png``) and checks in the page that no table is cut off: every table is
either fully inside the window or inside a box that scrolls horizontally.

Needs a Chromium or Chrome executable (Debian: ``apt-get install chromium``); CI machines have
none, so this is a script (and ``tests/test_report_layout.py`` skips without it)::

    python -m validation.studies.report_screenshots [--report docs/example-report/report.html]

Exit status 1 if a table is cut off at any width.
"""

from __future__ import annotations

import argparse
import json
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

from . import DOCS, IMAGES

#: Flags for a quiet, offline, throw-away headless Chromium.
FLAGS = ("--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync",
         "--hide-scrollbars", "--mute-audio")

#: Runs in the page after layout: for each table, its width, its box's width and whether the
#: box scrolls horizontally; the result goes into <pre id="layout-check"> for --dump-dom.
_CHECK = """
<script>
(function () {
  var view = document.documentElement.clientWidth, out = [];
  document.querySelectorAll('table').forEach(function (t, i) {
    var box = t.parentElement, style = getComputedStyle(box);
    var scrolls = (style.overflowX === 'auto' || style.overflowX === 'scroll');
    var r = t.getBoundingClientRect(), b = box.getBoundingClientRect();
    var cap = t.querySelector('caption');
    out.push({index: i, caption: cap ? cap.textContent.slice(0, 60) : '',
              table_right: r.right, table_width: t.scrollWidth, box_right: b.right,
              box_width: box.clientWidth, box_scroll_width: box.scrollWidth,
              scrolls: scrolls, view: view});
  });
  var s = document.querySelector('.summary'), summary = null;
  if (s) {
    summary = {bottom: s.getBoundingClientRect().bottom + window.scrollY,
               figure: !!s.querySelector('img'), table: !!s.querySelector('table')};
  }
  var pre = document.createElement('pre');
  pre.id = 'layout-check';
  pre.textContent = JSON.stringify({height: document.documentElement.scrollHeight,
                                    page_width: document.documentElement.scrollWidth,
                                    view: view, summary: summary, tables: out});
  document.body.appendChild(pre);
})();
</script>
"""


def find_chromium() -> str | None:
    """Path of a Chromium or Chrome executable, or None."""
    for name in ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable"):
        path = shutil.which(name)
        if path:
            return path
    return None


def _run(chromium: str, args: list[str], timeout: float = 120) -> str:
    with tempfile.TemporaryDirectory(prefix="dfp-chromium-") as profile:
        result = subprocess.run([chromium, *FLAGS, f"--user-data-dir={profile}", *args],
                                capture_output=True, text=True, timeout=timeout)
    if result.returncode != 0:
        raise RuntimeError(f"chromium failed ({result.returncode}): {result.stderr[-500:]}")
    return result.stdout


#: Width [CSS px] of an A4 page's printable area with the report's 12 mm margins:
#: (210 − 2 × 12) mm at 96 px per inch.
A4_PRINT_WIDTH = round((210 - 2 * 12) / 25.4 * 96)


def layout(report: Path, width: int, chromium: str, *, height: int = 1000,
           media: str = "screen") -> dict:
    """Tables of ``report`` laid out in a ``width`` × ``height`` px window: ``{"height": page
    height [px], "page_width": its scroll width [px], "view": the window's width, "summary":
    the Summary's bottom [px] and whether it holds a figure and a table (None without one),
    "tables": [...]}``, each table with its right edge and width, its box's right edge, width
    and scroll width, and whether the box scrolls horizontally; ``"cut"`` is added: the table
    reaches beyond the window and no scrolling box holds it. ``media="print"`` lays the page
    out with its print style sheet (at ``width``: :data:`A4_PRINT_WIDTH` for A4), where no box
    can scroll: a table is cut when it reaches beyond the page."""
    page = Path(report).read_text(encoding="utf-8")
    if media == "print":  # the print rules, applied on screen
        page = page.replace("@media print", "@media all")
    checked = page.replace("</body>", _CHECK + "</body>")
    with tempfile.TemporaryDirectory(prefix="dfp-layout-") as tmp:
        copy = Path(tmp) / "report.html"
        copy.write_text(checked, encoding="utf-8")
        dom = _run(chromium, [f"--window-size={width},{height}", "--dump-dom", copy.as_uri()])
    m = re.search(r'<pre id="layout-check">(.*?)</pre>', dom, re.S)
    if not m:
        raise RuntimeError("the layout check did not run in the page")
    text = m.group(1).replace("&quot;", '"').replace("&lt;", "<").replace("&gt;", ">")
    data = json.loads(text.replace("&amp;", "&"))
    for t in data["tables"]:
        inside = t["table_right"] <= t["view"] + 0.5
        scrolls = t["scrolls"] and media != "print"
        t["cut"] = not inside and not (scrolls and t["box_right"] <= t["view"] + 0.5)
    return data


def print_pdf(report: Path, pdf: Path, chromium: str) -> Path:
    """``report`` printed to ``pdf`` by Chromium (its print style sheet, A4)."""
    _run(chromium, [f"--print-to-pdf={pdf}", "--no-pdf-header-footer",
                    Path(report).resolve().as_uri()])
    return pdf


def screenshot(report: Path, width: int, png: Path, chromium: str, height: int) -> Path:
    """A screenshot of the whole page (``height`` px tall) at ``width`` px."""
    png.parent.mkdir(parents=True, exist_ok=True)
    _run(chromium, [f"--window-size={width},{height}", f"--screenshot={png}",
                    Path(report).resolve().as_uri()])
    return png


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--report", default=str(DOCS / "example-report/report.html"))
    parser.add_argument("--out", default=str(IMAGES),
                        help="folder of report_<width>px.png")
    parser.add_argument("--widths", type=int, nargs="+", default=[800, 1400])
    args = parser.parse_args(argv)
    chromium = find_chromium()
    if chromium is None:
        print("no chromium found (apt-get install chromium)", file=sys.stderr)
        return 2
    status = 0
    for width in args.widths:
        data = layout(Path(args.report), width, chromium)
        cut = [t for t in data["tables"] if t["cut"]]
        scrolling = [t for t in data["tables"] if t["box_scroll_width"] > t["box_width"]]
        png = screenshot(Path(args.report), width, Path(args.out) / f"report_{width}px.png",
                         chromium, data["height"])
        print(f"{width} px: {len(data['tables'])} tables, {len(scrolling)} scroll "
              f"horizontally, {len(cut)} cut off; page {data['height']} px -> {png}")
        for t in cut:
            print(f"  cut: table {t['index']} {t['caption']!r} ({t['table_width']:.0f} px)")
        status = status or (1 if cut else 0)
    return status


if __name__ == "__main__":
    sys.exit(main())
