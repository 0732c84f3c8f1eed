"""HTML report builder: self-contained page, escaped text, embedded figures, formatted tables."""

import base64

from validation.report.html import Report

# the 8-byte PNG signature plus an IHDR-like tail: enough to check the embedding round-trips
PNG = b"\x89PNG\r\n\x1a\n" + b"\x00" * 16


def test_report_is_self_contained_and_escaped(tmp_path):
    png = tmp_path / "fig.png"
    png.write_bytes(PNG)
    report = Report("Validation <quick>")
    report.heading("Critical SA & prediction")
    report.paragraph("SA(4.5 s) < 0.2 g", note=True)
    report.table([{"record": "RSN1084 <a>", "sa": 0.123456, "failed": True, "none": None}],
                 caption="ladder")
    report.figure(png, caption="Figure 12")
    text = report.write(tmp_path / "report.html").read_text()
    assert "<quick>" not in text and "Validation &lt;quick&gt;" in text
    assert "SA(4.5 s) &lt; 0.2 g" in text and 'class="note"' in text
    assert "RSN1084 &lt;a&gt;" in text and "0.1235" in text and "yes" in text and "—" in text
    embedded = text.split("data:image/png;base64,")[1].split('"')[0]
    assert base64.b64decode(embedded) == PNG
    assert "src=\"http" not in text and "<link" not in text  # nothing fetched from elsewhere


def test_empty_table_says_so(tmp_path):
    report = Report("r")
    report.table([], caption="impacts")
    assert "impacts: no rows." in report.html()


def test_glossary_links_resolve_and_terms_are_defined_once(tmp_path):
    """Every [[term]] a page links resolves to a definition on the page, and an unknown term
    is caught (its link has no target)."""
    import re

    from validation.report.glossary import GLOSSARY, anchor

    report = Report("r")
    report.paragraph("The [[critical SA]] of a [[ladder|ladder's]] rung; see [[#glossary|it]].")
    report.heading("Glossary", id="glossary")
    report.glossary(GLOSSARY)
    page = report.html()
    targets = set(re.findall(r'href="#([^"]+)"', page))
    ids = re.findall(r'id="([^"]+)"', page)
    assert len(ids) == len(set(ids)) == len(GLOSSARY) + 1  # each defined once
    assert targets <= set(ids) and {"g-critical-sa", "g-ladder", "glossary"} <= targets
    assert ">ladder&#x27;s</a>" in page
    linked = {m for d in GLOSSARY.values() for m in re.findall(r"\[\[([^\]|]+)", d)}
    assert {anchor(t) for t in linked} <= set(ids)  # the glossary's own links resolve
    report.paragraph("an [[unknown term]]")  # the check above catches a dangling link
    assert not set(re.findall(r'href="#([^"]+)"', report.html())) <= set(ids)


def test_precision_follows_the_number_of_records():
    """A median from fewer than 10 records gets two significant digits, from 10 three."""
    from validation.report.summary import FEW_RECORDS, significant

    assert FEW_RECORDS == 10
    assert significant(0.45678, 4) == "0.46" and significant(0.45678, 10) == "0.457"
    assert significant(float("nan"), 4) == "—"
