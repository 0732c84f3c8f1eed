"""A self-contained HTML report: text, tables and PNG figures embedded as data URIs."""

from __future__ import annotations

import base64
import html
from pathlib import Path

_STYLE = """
body { font-family: system-ui, sans-serif; max-width: 70em; margin: 2em auto; color: #222;
       line-height: 1.45; padding: 0 1em; }
h1 { font-size: 1.6em; } h2 { font-size: 1.25em; border-bottom: 1px solid #ccc; margin-top: 2em; }
.table-scroll { overflow-x: auto; max-width: 100%; margin: 1em 0; }
table { border-collapse: collapse; font-size: 0.9em; margin: 0; }
.table-caption { font-size: 0.9em; color: #555; margin-top: 1em; }
th, td { border: 1px solid #ccc; padding: 0.25em 0.6em; text-align: right; }
th { background: #f3f3f3; } td.text { text-align: left; }
figure { margin: 1em 0; } figcaption { font-size: 0.9em; color: #555; }
img { max-width: 100%; } .note { background: #fff8e0; padding: 0.6em 1em; }
code { background: #f3f3f3; padding: 0 0.2em; }
"""


class Report:
    """Build the page piece by piece, then :meth:`write` it.

    Parameters
    ----------
    title : str
    """

    def __init__(self, title: str):
        self.title = title
        self.parts: list[str] = []

    def heading(self, text: str) -> None:
        self.parts.append(f"<h2>{html.escape(text)}</h2>")

    def paragraph(self, text: str, note: bool = False) -> None:
        """A paragraph of plain text (escaped); ``note`` highlights it."""
        cls = ' class="note"' if note else ""
        self.parts.append(f"<p{cls}>{html.escape(text)}</p>")

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
        cap = (f'<div class="table-caption">{html.escape(caption)}</div>' if caption else "")
        # wide tables scroll inside their box instead of being cut at the page's width; the
        # caption stays outside the box, so it wraps instead of scrolling away
        self.parts.append(f'{cap}<div class="table-scroll"><table><tr>{head}</tr>'
                          f"{''.join(body)}</table></div>")

    def figure(self, png, caption: str = "") -> None:
        """Embed a PNG file."""
        data = base64.b64encode(Path(png).read_bytes()).decode()
        cap = f"<figcaption>{html.escape(caption)}</figcaption>" if caption else ""
        self.parts.append(f'<figure><img src="data:image/png;base64,{data}" '
                          f'alt="{html.escape(caption)}">{cap}</figure>')

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
