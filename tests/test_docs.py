"""Documents that cannot drift from the code: the theory index (docs/theory/README.md) names, for
each file, the range of equations it holds, checked here against the equations numbered in the
files; and the Layout section (docs/architecture.md) is checked against the tree."""

from __future__ import annotations

import re
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
THEORY = ROOT / "docs" / "theory"

#: An equation as numbered in a theory file: **(R17)**, **(R34b)** on its own paragraph.
NUMBERED = re.compile(r"\*\*\((?P<letter>[A-Z])(?P<number>\d+)(?P<suffix>[a-z]?)\)\*\*")
#: An index entry: * [rigid-body.md](rigid-body.md), Eqs. R1–R54 (...)
ENTRY = re.compile(r"^\* \[(?P<file>[\w-]+\.md)\]\((?P=file)\), Eqs\. "
                   r"(?P<letter>[A-Z])(?P<first>\d+)–(?P=letter)(?P<last>\d+)\b", re.MULTILINE)


def _index() -> dict:
    text = (THEORY / "README.md").read_text(encoding="utf-8")
    return {m["file"]: (m["letter"], int(m["first"]), int(m["last"]))
            for m in ENTRY.finditer(text)}


def _numbered(path: Path) -> tuple[set[str], set[int]]:
    found = NUMBERED.findall(path.read_text(encoding="utf-8"))
    return {letter for letter, _, _ in found}, {int(n) for _, n, _ in found}


def test_every_theory_file_is_in_the_index():
    files = {p.name for p in THEORY.glob("*.md") if p.name != "README.md"}
    assert set(_index()) == files


@pytest.mark.parametrize("name", sorted(p.name for p in THEORY.glob("*.md")
                                        if p.name != "README.md"))
def test_the_index_gives_each_files_equation_range(name):
    """The index's range of a file is exactly its equations: one letter, numbered from 1 to
    the last without a gap (lettered variants such as R34b and F35a belong to their number)."""
    letter, first, last = _index()[name]
    letters, numbers = _numbered(THEORY / name)
    assert letters == {letter}, f"{name} numbers equations with {letters}, index says {letter}"
    assert (first, last) == (1, max(numbers)), (
        f"the index says {letter}{first}–{letter}{last}, {name} holds "
        f"{letter}{min(numbers)}–{letter}{max(numbers)}")
    assert numbers == set(range(1, last + 1)), f"{name} skips {set(range(1, last + 1)) - numbers}"


def test_the_index_checker_reads_the_index():
    """The parser above finds the five files (a changed index format must not make the range
    test pass vacuously)."""
    assert len(_index()) == len([p for p in THEORY.glob("*.md") if p.name != "README.md"]) == 5


# -- the Layout (docs/architecture.md) ---------------------------------------------------

PACKAGES = ("rigid", "fem", "validation")


#: The document whose Layout section lists the repository (the README's until issue #32).
LAYOUT = ROOT / "docs" / "architecture.md"


def _layout() -> dict[str, str]:
    """The Layout block of :data:`LAYOUT`, by top-level entry: {"rigid/": its lines, ...}."""
    text = LAYOUT.read_text(encoding="utf-8")
    block = re.search(r"^## Layout\n[^`]*?^```\n(.*?)^```", text, re.MULTILINE | re.DOTALL)
    assert block, f"{LAYOUT.name} has no Layout code block"
    sections: dict[str, str] = {}
    current = None
    for line in block.group(1).splitlines():
        if line and not line[0].isspace():
            current = line.split()[0]
            sections[current] = ""
        assert current is not None, f"Layout starts with an indented line: {line!r}"
        sections[current] += line + "\n"
    return sections


def _names(section: str) -> set[str]:
    """Every file or folder name (``x.py``, ``x/``, ``x.geo``) written in a section."""
    return set(re.findall(r"(?<![\w./-])([\w.-]+/|[\w-]+\.(?:py|geo|md))(?![\w/])", section))


def _top_level() -> set[str]:
    """The repository's top-level folders: those git tracks files in (outside a git checkout,
    the non-empty folders on disk but hidden ones, caches and build output)."""
    try:
        files = subprocess.run(["git", "ls-files"], cwd=ROOT, capture_output=True, text=True,
                               check=True).stdout.splitlines()
        return {f.split("/")[0] + "/" for f in files if "/" in f}
    except (OSError, subprocess.CalledProcessError):
        return {p.name + "/" for p in ROOT.iterdir()
                if p.is_dir() and (not p.name.startswith(".") or p.name == ".ci")
                and p.name != "__pycache__" and not p.name.endswith(".egg-info")
                and any(p.rglob("*"))}


def test_the_layout_lists_every_top_level_folder_and_only_those():
    listed = set(_layout())
    tracked = _top_level()
    assert tracked - listed == set(), f"missing from the Layout: {tracked - listed}"
    assert listed - tracked == set(), f"in the Layout but not in the tree: {listed - tracked}"


def _where(top: str, name: str) -> Path | None:
    """The file or folder ``name`` written in the section of ``top``: below ``top`` at any
    depth (the Layout nests ``formats/`` in ``motions/``), or a file at the top (a section may
    name the README or BENCHMARKS.md); None if there is none."""
    base = ROOT / top.rstrip("/")
    bare = name.rstrip("/")
    for p in [base / bare, *base.rglob(bare), ROOT / bare]:
        if p.exists() and (p.is_dir() == name.endswith("/")):
            return p
    return None


def test_every_name_in_the_layout_exists():
    missing = sorted(f"{top}{name}" for top, section in _layout().items()
                     for name in _names(section)
                     if name != top and _where(top, name) is None)
    assert missing == []


@pytest.mark.parametrize("package", PACKAGES)
def test_the_layout_names_every_subpackage_and_module(package):
    """Every subpackage (a folder with __init__.py, at any depth) of the package is written in
    its section as ``name/``, and every module directly in the package as ``name.py`` or, in a
    section that lists modules by name, as ``name``."""
    section = _layout()[f"{package}/"]
    names = _names(section)
    base = ROOT / package
    subpackages = {p.parent.name + "/" for p in base.rglob("__init__.py") if p.parent != base}
    assert subpackages - names == set(), f"{package}: {subpackages - names} not in the Layout"
    modules = {p.stem for p in base.glob("*.py") if p.stem != "__init__"}
    unnamed = {m for m in modules
               if f"{m}.py" not in names and not re.search(rf"(?<![\w/.]){m}(?![\w/])", section)}
    assert unnamed == set(), f"{package}: modules {unnamed} not in the Layout"


def test_the_layout_names_every_docs_folder():
    section = _layout()["docs/"]
    folders = {p.name + "/" for p in (ROOT / "docs").iterdir() if p.is_dir()}
    assert folders - _names(section) == set()
