"""The import rule of docs/architecture.md, checked on the source: dependencies point one way,
``validation`` → ``fem`` → ``rigid`` (physics) → the neutral base; and the rigid model runs
with yielding rims from a given law while ``fem``, scikit-fem and gmsh cannot be imported."""

from __future__ import annotations

import ast
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("rigid", "fem", "validation")

#: The modules of the neutral base (docs/architecture.md): below both models, they import no
#: other module of the library.
BASE = ("rigid.units", "rigid.bearing", "rigid.limits", "rigid.limit_states", "rigid.inputs",
        "rigid.tasks")

#: Imports that break the rule on purpose, each with its reason: the deprecated fallback of
#: a yielding-rim run without a law (for one release; rigid.rims.resolve_rim_law and the
#: deprecated alias rigid.rims.rim_law), a lazy import reached only on that path.
EXCEPTIONS = {("rigid.rims", "fem.rim_laws")}


def _module_name(path: Path) -> str:
    parts = list(path.relative_to(ROOT).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def _imports(path: Path) -> set[str]:
    """Every module ``path`` imports, anywhere in it (lazy imports in functions included),
    as absolute dotted names (relative imports resolved)."""
    name = _module_name(path)
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    found = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"), str(path))):
        if isinstance(node, ast.Import):
            found.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")
                base = base[:len(base) - (node.level - 1)]
                module = ".".join(base + ([node.module] if node.module else []))
            else:
                module = node.module
            found.add(module)
            found.update(f"{module}.{alias.name}" for alias in node.names)  # submodules
    return found


def _modules(package: str):
    for path in sorted((ROOT / package).rglob("*.py")):
        yield _module_name(path), _imports(path)


def _within(module: str, prefixes) -> bool:
    return any(module == p or module.startswith(p + ".") for p in prefixes)


def _violations(package: str, forbidden) -> list[str]:
    return sorted(f"{name} imports {imp}" for name, imports in _modules(package)
                  for imp in imports
                  if _within(imp, forbidden) and (name, imp) not in EXCEPTIONS
                  and not any(name == a and imp.startswith(b) for a, b in EXCEPTIONS))


def test_the_scan_sees_lazy_and_relative_imports():
    """The scan itself: a lazy import inside a function and a relative import are found."""
    pkg = ROOT / "rigid" / "collapse" / "ladder.py"
    imports = _imports(pkg)
    assert "rigid.tasks" in imports and "rigid.rims" in imports  # top level and lazy


def test_rigid_imports_neither_fem_nor_validation():
    assert _violations("rigid", ("fem", "validation")) == []


def test_fem_does_not_import_validation():
    assert _violations("fem", ("validation",)) == []


def test_the_neutral_base_imports_nothing_above_it():
    """The base (bearing, units, limit-state names, input checks, tasks) imports only the
    base: the physics of ``rigid`` (its model, kernel, motions, sweeps), ``fem`` and
    ``validation`` build on it, never the other way."""
    bad = sorted(f"{name} imports {imp}" for name, imports in _modules("rigid")
                 if _within(name, BASE)
                 for imp in imports
                 if _within(imp, PACKAGES) and not _within(imp, BASE) and imp != "rigid")
    assert bad == []


def test_the_exceptions_are_still_needed():
    """Each allowed exception is still in the source (drop it from EXCEPTIONS with the code)."""
    imports = dict(_modules("rigid"))
    for module, target in EXCEPTIONS:
        assert any(i.startswith(target) for i in imports[module]), (module, target)


#: Longest module [lines] (issue #33: small single-purpose modules); the Numba kernel, one
#: compiled unit, is the exception.
MAX_MODULE_LINES = 500
LONG_MODULES = {"rigid/_kernel.py"}


def test_every_module_is_short():
    long = sorted(f"{p.relative_to(ROOT)}: {n} lines"
                  for package in PACKAGES for p in (ROOT / package).rglob("*.py")
                  if str(p.relative_to(ROOT)) not in LONG_MODULES
                  and (n := len(p.read_text(encoding="utf-8").splitlines())) > MAX_MODULE_LINES)
    assert long == []


BLOCKED_RUN = textwrap.dedent("""
    import importlib.abc, sys, warnings

    BLOCKED = ("fem", "skfem", "gmsh", "meshio", "pyvista", "validation")

    class Block(importlib.abc.MetaPathFinder):
        def find_spec(self, name, path=None, target=None):
            if name.split(".")[0] in BLOCKED:
                raise ImportError(f"{name} is blocked in this test")
            return None

    sys.meta_path.insert(0, Block())
    import numpy as np
    import rigid
    from rigid.rims import RimLaw

    law = RimLaw(stiffness=6e9, plastic_set=np.array([0.0, 0.02]),
                 force=np.array([1.5e6, 2.5e6]), first_yield_force=1.5e6,
                 hinge_displacement=5e-4, hinge_force=1.8e6, hinge_set=2e-4,
                 rupture_displacement=1e-2, rupture_set=9e-3, lever=0.02625,
                 push_displacement=np.zeros(2), push_force=np.zeros(2))
    b = rigid.DFPBearing(pressure=60e6)
    _, a = rigid.ricker_record(1.0 * rigid.G, 2.0, dt=0.005, free=3.0)
    r = rigid.simulate(b, a, 0.005, rims="yielding", rim_law=law, limit_state="containment")
    loaded = sorted(m for m in sys.modules if m.split(".")[0] in BLOCKED)
    print("loaded", loaded)
    print("ran", r.rims, r.limit_state, max(r.rim_sets) > 0, r.energy.relative_error < 0.01)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            rigid.simulate(b, a, 0.005, rims="yielding")
        except RuntimeError as exc:
            print("without a law:", exc)
    print("warned", [w.category.__name__ for w in caught])
""")


def test_rigid_runs_yielding_rims_from_a_given_law_without_fem():
    """In a fresh interpreter where fem, scikit-fem, gmsh (and validation) cannot be imported:
    ``import rigid`` works, a yielding-rim run from a given law bends a rim and closes its
    energy balance (the 1 % of test_yielding_rims), nothing blocked got loaded, and a
    yielding run without a law says how to get one (fem.rim_law) after a
    DeprecationWarning."""
    env = {**os.environ, "PYTHONPATH": str(ROOT), "OMP_NUM_THREADS": "1"}
    out = subprocess.run([sys.executable, "-c", BLOCKED_RUN], capture_output=True, text=True,
                         env=env, cwd=ROOT, timeout=600)
    assert out.returncode == 0, out.stderr
    lines = out.stdout.splitlines()
    assert "loaded []" in lines, out.stdout
    assert "ran yielding containment True True" in lines, out.stdout
    message = next(line for line in lines if line.startswith("without a law:"))
    assert "fem.rim_law(bearing)" in message and "rim_law=" in message
    assert "warned ['DeprecationWarning']" in lines, out.stdout


@pytest.mark.parametrize("old", ["failure_criterion"])
def test_old_limit_state_names_still_work_with_a_warning(old):
    import rigid

    b = rigid.DFPBearing()
    _, a = rigid.ricker_record(0.1 * rigid.G, 2.0, dt=0.01, free=1.0)
    with pytest.warns(DeprecationWarning, match=f"{old}= is deprecated"):
        r = rigid.simulate(b, a, 0.01, **{old: "containment"})
    assert r.limit_state == "containment"
    with pytest.warns(DeprecationWarning, match="failure_criterion is deprecated"):
        assert r.failure_criterion == "containment"
    with pytest.raises(TypeError, match="got both limit_state"):
        rigid.simulate(b, a, 0.01, limit_state="containment", **{old: "containment"})
