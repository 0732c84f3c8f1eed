"""What the package installs and declares (pyproject.toml): the studies that write docs/ stay out
of the wheel, and every third-party module they import is declared in the ``studies`` extra (or
in the core dependencies it builds on)."""

from __future__ import annotations

import ast
import re
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PROJECT = ("rigid", "fem", "validation")

try:
    import tomllib
except ModuleNotFoundError:  # Python 3.10
    tomllib = pytest.importorskip("tomli")


def _pyproject() -> dict:
    return tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))


def _name(requirement: str) -> str:
    """The normalised distribution name of a requirement ("scikit-fem>=10" → "scikit-fem")."""
    return re.split(r"[\s\[<>=!~;]", requirement, maxsplit=1)[0].lower().replace("_", "-")


def _closure(extra: str) -> set[str]:
    """Distribution names that ``pip install dfp-failure[extra]`` brings in directly: the core
    dependencies and the extra's, with the extras it names expanded."""
    project = _pyproject()["project"]
    extras = project["optional-dependencies"]
    names, todo, seen = {_name(r) for r in project["dependencies"]}, [extra], set()
    while todo:
        e = todo.pop()
        if e in seen:
            continue
        seen.add(e)
        for r in extras[e]:
            if _name(r) == project["name"]:
                todo.extend(re.search(r"\[(.*)\]", r).group(1).split(","))
            else:
                names.add(_name(r))
    return names


def test_the_studies_are_not_in_the_wheel():
    # the build backend's own search (pyproject: setuptools), as it runs when a wheel is built
    find_namespace_packages = pytest.importorskip("setuptools").find_namespace_packages

    find = _pyproject()["tool"]["setuptools"]["packages"]["find"]
    packages = find_namespace_packages(str(ROOT), include=find["include"],
                                       exclude=find.get("exclude", ()))
    assert "validation.studies" not in packages
    assert {"rigid", "rigid.tasks", "fem", "fem.contact", "validation",
            "validation.report"} <= set(packages)


def _third_party_imports(folder: Path) -> dict[str, set[str]]:
    found: dict[str, set[str]] = {}
    for path in sorted(folder.glob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Import):
                modules = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom) and node.level == 0:
                modules = [node.module]
            else:
                continue
            for m in modules:
                top = m.split(".")[0]
                if top not in sys.stdlib_module_names and top not in PROJECT:
                    found.setdefault(top, set()).add(path.name)
    return found


def test_the_studies_dependencies_are_declared():
    """An import of a study resolves to a distribution of the ``studies`` extra's closure (via
    the installed distributions' top-level names, else the import name itself)."""
    from importlib.metadata import packages_distributions

    installed = packages_distributions()
    declared = _closure("studies")
    imports = _third_party_imports(ROOT / "validation" / "studies")
    assert "pandas" in imports  # the scan sees what the studies import
    missing = {}
    for module, files in imports.items():
        dists = {d.lower().replace("_", "-") for d in installed.get(module, [module])}
        if not dists & declared:
            missing[module] = sorted(files)
    assert missing == {}, f"imported by the studies but not declared: {missing}"
