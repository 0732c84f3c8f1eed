"""Dependency direction: ``fem`` uses ``rigid``; ``import rigid`` never imports ``fem``."""

import subprocess
import sys


def test_rigid_does_not_import_fem():
    """Run in a fresh interpreter so modules imported by other tests do not mask the result."""
    code = (
        "import sys, rigid, rigid.bearing; "
        "bad = [m for m in sys.modules if m == 'fem' or m.startswith('fem.')]; "
        "print(bad); sys.exit(1 if bad else 0)"
    )
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert run.returncode == 0, run.stdout + run.stderr


def test_fem_package_import_is_light():
    """``import fem`` needs only numpy (and rigid): scikit-fem and gmsh load on demand."""
    code = (
        "import sys, fem; "
        "heavy = [m for m in ('skfem', 'gmsh', 'meshio', 'pyvista') if m in sys.modules]; "
        "print(heavy); sys.exit(1 if heavy else 0)"
    )
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert run.returncode == 0, run.stdout + run.stderr
