"""A self-contained HTML report: text, tables and PNG figures embedded as data URIs."""

from __future__ import annotations

import base64
import html
import re
from pathlib import Path

_STYLE = """
body { font-family: system-ui, sans-serif; max-width: 70em; margin: 1em auto; color: #222;
       line-height: 1.4; padding: 0 1em; }
h1 { font-size: 1.5em; margin: 0.3em 0; }
h2 { font-size: 1.25em; border-bottom: 1px solid #ccc; margin-top: 2em; }
.summary h2 { margin-top: 0.4em; }
.summary { display: grid; grid-template-columns: minmax(0, 1fr) minmax(0, 26em); gap: 0 1.5em; }
.summary p, .summary ul { margin: 0.35em 0; } .summary ul { padding-left: 1.2em; }
.summary figure { margin: 0.4em 0; }
@media (max-width: 60em) { .summary { grid-template-columns: minmax(0, 1fr); } }
.table-scroll { overflow-x: auto; max-width: 100%; margin: 1em 0; }
.summary .table-scroll { margin: 0.4em 0; }
table { border-collapse: collapse; font-size: 0.9em; margin: 0; }
.table-caption { font-size: 0.9em; color: #555; margin-top: 1em; }
th, td { border: 1px solid #ccc; padding: 0.2em 0.5em; text-align: right; }
th { background: #f3f3f3; } td.text { text-align: left; }
figure { margin: 1em 0; } figcaption { font-size: 0.9em; color: #555; }
img { max-width: 100%; } .note { background: #fff8e0; padding: 0.6em 1em; }
.warn { color: #8a4b00; }
code { background: #f3f3f3; padding: 0 0.2em; }
dl.glossary dt { font-weight: 600; margin-top: 0.5em; } dl.glossary dd { margin-left: 1.5em; }
a { color: #1a5fb4; }
@media print {
  @page { size: A4; margin: 12mm; }
  body { max-width: none; margin: 0; padding: 0; font-size: 9pt; }
  .summary { grid-template-columns: minmax(0, 1fr); }
  .table-scroll { overflow: visible; }
  table { width: 100%; table-layout: fixed; font-size: 7pt; page-break-inside: auto; }
  th, td { overflow-wrap: anywhere; padding: 0.1em 0.2em; }
  tr, figure { page-break-inside: avoid; }
  h2 { page-break-after: avoid; }
  a { color: inherit; text-decoration: none; }
}
"""

#: ``[[term]]`` or ``[[term|shown text]]`` in a paragraph: a link to the term's definition in
#: the glossary (:mod:`validation.report.glossary`); ``[[#id|text]]``: to the element ``id``.
_LINK = re.compile(r"\[\[([^\]|]+)(?:\|([^\]]+))?\]\]")


def _linked(text: str) -> str:
    """``text`` escaped, its ``[[term]]`` marks turned into links to the glossary."""
    from .glossary import anchor

    out, last = [], 0
    for m in _LINK.finditer(text):
        out.append(html.escape(text[last:m.start()]))
        shown = m.group(2) or m.group(1)
        target = m.group(1) if m.group(1).startswith("#") else "#" + anchor(m.group(1))
        out.append(f'<a href="{html.escape(target)}">{html.escape(shown)}</a>')
        last = m.end()
    out.append(html.escape(text[last:]))
    return "".join(out)


class Report:
    """Build the page piece by piece, then :meth:`write` it.

    Parameters
    ----------
    title : str
    """

    def __init__(self, title: str):
        self.title = title
        self.parts: list[str] = []

    def heading(self, text: str, id: str | None = None) -> None:
        """A section heading (``id``: its anchor)."""
        at = f' id="{html.escape(id)}"' if id else ""
        self.parts.append(f"<h2{at}>{_linked(text)}</h2>")

    def paragraph(self, text: str, note: bool = False, cls: str = "") -> None:
        """A paragraph of plain text (escaped; ``[[term]]`` links to the glossary); ``note``
        highlights it, ``cls`` is its CSS class."""
        cls = " ".join(c for c in ("note" if note else "", cls) if c)
        attr = f' class="{cls}"' if cls else ""
        self.parts.append(f"<p{attr}>{_linked(text)}</p>")

    def items(self, texts: list[str]) -> None:
        """A bulleted list of plain-text items (``[[term]]`` links)."""
        self.parts.append("<ul>" + "".join(f"<li>{_linked(t)}</li>" for t in texts) + "</ul>")

    def open(self, cls: str) -> None:
        """Open a ``<div class=cls>`` (close it with :meth:`close`)."""
        self.parts.append(f'<div class="{html.escape(cls)}">')

    def close(self) -> None:
        self.parts.append("</div>")

    def glossary(self, terms: dict) -> None:
        """Definitions, each with its anchor (:func:`validation.report.glossary.anchor`)."""
        from .glossary import anchor

        self.parts.append('<dl class="glossary">' + "".join(
            f'<dt id="{anchor(t)}">{html.escape(t)}</dt><dd>{_linked(d)}</dd>'
            for t, d in terms.items()) + "</dl>")

    def table(self, rows: list[dict], columns: dict | None = None, caption: str = "") -> None:
        """A table of dict rows; ``columns`` maps keys to headers (default: the first row's
        keys). Floats are shown with 4 significant digits, None as an em dash."""
        if not rows:
            self.paragraph(f"{caption}: no rows." if caption else "No rows.")
            return
        columns = columns or {k: k for k in rows[0]}
        head = "".join(f"<th>{html.escape(str(h))}</th>" for h in columns.values())
        body = []
        for row in rows:
            cells = []
            for key in columns:
                value = row.get(key)
                text = value if isinstance(value, str) else _format(value)
                cls = ' class="text"' if isinstance(value, str) else ""
                cells.append(f"<td{cls}>{html.escape(text)}</td>")
            body.append("<tr>" + "".join(cells) + "</tr>")
        cap = (f'<div class="table-caption">{_linked(caption)}</div>' if caption else "")
        # wide tables scroll inside their box instead of being cut at the page's width; the
        # caption stays outside the box, so it wraps instead of scrolling away
        self.parts.append(f'{cap}<div class="table-scroll"><table><tr>{head}</tr>'
                          f"{''.join(body)}</table></div>")

    def figure(self, png, caption: str = "") -> None:
        """Embed a PNG file."""
        data = base64.b64encode(Path(png).read_bytes()).decode()
        cap = f"<figcaption>{_linked(caption)}</figcaption>" if caption else ""
        alt = _LINK.sub(lambda m: m.group(2) or m.group(1), caption)
        self.parts.append(f'<figure><img src="data:image/png;base64,{data}" '
                          f'alt="{html.escape(alt)}">{cap}</figure>')

    def html(self) -> str:
        return (f"<!DOCTYPE html>\n<html lang='en'><head><meta charset='utf-8'>"
                f"<title>{html.escape(self.title)}</title><style>{_STYLE}</style></head>"
                f"<body><h1>{html.escape(self.title)}</h1>\n" + "\n".join(self.parts)
                + "\n</body></html>\n")

    def write(self, path) -> Path:
        """Write the page to ``path`` through a temporary file renamed over it, so a failed
        write leaves the previous page."""
        from rigid.tasks import atomic_write

        path = Path(path)
        with atomic_write(path, "w", encoding="utf-8") as fh:
            fh.write(self.html())
        return path


def _format(value) -> str:
    """A cell: floats with 4 significant digits, NaN and None as a dash, booleans as yes/no,
    sequences joined by commas (never Python notation)."""
    import math

    if value is None:
        return "—"
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, float):
        return "—" if not math.isfinite(value) else f"{value:.4g}"
    if isinstance(value, dict):
        return "; ".join(f"{k}: {_format(v)}" for k, v in value.items())
    if isinstance(value, (list, tuple)):
        return ", ".join(_format(v) for v in value)
    if hasattr(value, "item"):  # numpy scalars
        return _format(value.item())
    return str(value)
