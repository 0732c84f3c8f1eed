"""The rim push (fem.rim_pushover) against CalculiX, an independent FE program with geometric
nonlinearity, on the same mesh and boundary conditions.

The CalculiX curves are stored numbers: ``docs/results/rim_pushover.csv``, written by
``validation/studies/rim_pushover_ccx.py`` (which runs ``ccx``; CalculiX is not needed here).
This test recomputes the project's side and compares.
"""

import csv
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("skfem")
pytest.importorskip("gmsh")

from fem.pushover import rim_pushover

STORED = Path(__file__).resolve().parents[1] / "docs" / "results" / "rim_pushover.csv"


def stored():
    with open(STORED) as fh:
        rows = list(csv.DictReader(fh))
    return {k: np.array([float(r[k]) for r in rows]) for k in rows[0]}


@pytest.fixture(scope="module")
def push(heavy, mesh_cache):
    return rim_pushover(heavy, kinematics="finite", cache_dir=mesh_cache)


def test_rim_push_agrees_with_calculix(push):
    """Finite deformation against CalculiX with NLGEOM, CPE8R (quadratic, reduced integration)
    and C3D8I (incompatible modes), to a deflection of half the rim height (17.5 mm): within 5 %
    for δ ≥ 2 mm (past the hinge and the knee; the issue's tolerance; measured ≤ 3.3 % and
    ≤ 2.1 %). The three element technologies differ most in how they avoid volumetric locking
    under plastic flow, which is why they do not coincide; CalculiX's fully integrated CPE4,
    which locks, is 25 % stiffer and is not compared."""
    ref = stored()
    d = ref["displacement_mm"] * 1e-3
    ours = np.interp(d, push.displacement, push.force) / 1e6
    beyond = d >= 2e-3
    assert push.displacement[-1] == pytest.approx(0.0175)
    for element in ("CPE8R", "C3D8I"):
        ccx = ref[f"force_MN_ccx_{element}"]
        np.testing.assert_array_less(np.abs(ours[beyond] / ccx[beyond] - 1), 0.05)


def test_rim_push_reproduces_its_stored_curve(push):
    """The project's side of the stored comparison is what the code computes now: within 0.2 %
    (the adaptive increments and Newton's tolerance of 1e-8 leave less than that)."""
    ref = stored()
    d = ref["displacement_mm"] * 1e-3
    ours = np.interp(d, push.displacement, push.force) / 1e6
    np.testing.assert_allclose(ours[1:], ref["force_MN_ours_finite"][1:], rtol=2e-3)


def test_hinge_before_the_plateau(push):
    """The root row is fully plastic (the hinge, Eq. F36) before δ = 1 mm, at a force between
    0.7 and 0.95 of the force at 17.5 mm: the rim goes on carrying load after its first hinge
    (hardening and the guided push), so the hinge is a conservative limit state."""
    assert push.hinge_displacement is not None and push.hinge_displacement < 1e-3
    assert 0.7 < push.hinge_force / push.force[-1] < 0.95


def test_rupture_measure_is_regularised(push, heavy, mesh_cache):
    """The rupture measure (Eq. F52: plastic strain averaged over a disc of the rim's thickness)
    is a property of the rim, not of the mesh: from 4 to 8 elements across the rim (the medium
    and the default mesh) the averaged peak changes by less than 10 % while the local peak, at
    the re-entrant corner of the root, grows by more than 20 % (measured: 4 % and 24 %; the
    study over 2–16 elements, docs/results/rupture_mesh.csv, shows the local peak still
    growing and the average within 8 % of its mean)."""
    from validation.studies.rupture_mesh import regularised_peak

    medium = rim_pushover(heavy, mesh_options={"rim_size": 0.01}, cache_dir=mesh_cache)
    averaged = [regularised_peak(p, heavy) for p in (medium, push)]
    local = [float(p.final_plastic_strain.max()) for p in (medium, push)]
    assert abs(averaged[1] / averaged[0] - 1) < 0.10
    assert local[1] / local[0] - 1 > 0.20


def test_a_push_tears_where_todays_rupture_is_reached(heavy, mesh_cache):
    """Without a triaxiality term (c = 0) the push tears at the step at which the gauge
    strain reaches the rupture strain (Eqs. F51, F66–F67), its damage that strain over ε_r
    (round-off: the same sums in another order); the median criterion tears it too, since the
    gauge there is in shear-tension (T̄ > −1/3), and records that T̄."""
    from fem.fracture import StressModifiedStrain

    flat = rim_pushover(heavy, mesh_options={"rim_size": 0.02}, displacement=0.016, steps=60,
                        fracture=StressModifiedStrain(heavy.rupture_strain, 0.0),
                        cache_dir=mesh_cache)
    assert flat.damage == pytest.approx(flat.averaged_plastic_strain / heavy.rupture_strain,
                                        rel=1e-12, abs=1e-15)
    k = int(np.argmax(flat.averaged_plastic_strain >= heavy.rupture_strain))
    assert k > 0 and flat.fracture_displacement == flat.displacement[k]
    median = rim_pushover(heavy, mesh_options={"rim_size": 0.02}, displacement=0.016,
                          steps=60, fracture="median", cache_dir=mesh_cache)
    assert median.fracture_displacement is not None
    assert -1 / 3 < median.triaxiality[-1] < 1 / 3


def test_a_push_with_erosion_tears_the_rim_off(heavy, mesh_cache):
    """With erosion (Eq. F68 over accepted increments) the push is the push without it, bit
    for bit, up to the first tear (nothing has been let go before it); after it the force
    falls as the torn elements go, and the push ends once it is below 2 % of its peak
    (``SEPARATED``), well past the tear, with elements torn. Coarse mesh (two elements across
    the 40 mm rim): the cheapest mesh that tears through."""
    from fem.pushover import SEPARATED

    options = {"mesh_options": {"rim_size": 0.02}, "fracture": "median",
               "cache_dir": mesh_cache}  # increments of 0.25 mm at most in both
    whole = rim_pushover(heavy, displacement=0.016, steps=64, **options)
    torn = rim_pushover(heavy, displacement=0.04, steps=160, erosion_steps=10,
                        stop_short=True, **options)
    assert torn.fracture_displacement == whole.fracture_displacement is not None
    k = int(np.searchsorted(whole.displacement, whole.fracture_displacement)) + 1
    np.testing.assert_array_equal(torn.force[:k], whole.force[:k])
    assert torn.force[-1] < SEPARATED * torn.force.max()
    assert torn.displacement[-1] > torn.fracture_displacement + 0.005
    assert torn.torn_elements > whole.torn_elements > 0


def test_erosion_needs_fracture_and_finite_kinematics(heavy):
    """Erosion without a criterion, or at small strain (whose element has no weights to let
    go), is refused before anything is pushed."""
    for options in ({"erosion_steps": 10}, {"erosion_steps": 10, "fracture": "median",
                                             "kinematics": "small"}):
        with pytest.raises(ValueError, match="erosion_steps needs fracture"):
            rim_pushover(heavy, **options)


def test_the_tear_begins_where_calculix_says(heavy, mesh_cache):
    """The median criterion's damage in the push (default mesh, to 14 mm) against the same
    damage accumulated from CalculiX's C3D8I points (docs/results/rim_fracture_ccx.csv,
    written by validation/studies/rim_fracture_ccx.py): D = 1 within 10 % of CalculiX's
    displacement (the issue's tolerance; measured 0.4 %), and the damage within 5 % from
    1.5 mm on (measured ≤ 2 %: the two programs' plastic strains differ by about that much,
    as their forces do)."""
    from validation.studies.rim_fracture_ccx import crossing

    path = STORED.parent / "rim_fracture_ccx.csv"
    with open(path) as fh:
        rows = list(csv.DictReader(fh))
    ref = {k: np.array([float(r[k]) for r in rows]) for k in rows[0]}
    d = ref["displacement_mm"] * 1e-3
    push = rim_pushover(heavy, displacement=0.014, steps=60, fracture="median",
                        cache_dir=mesh_cache)
    ours = np.interp(d, push.displacement, push.damage)
    ccx = ref["damage_calculix"]
    assert crossing(push.displacement, push.damage) == pytest.approx(crossing(d, ccx),
                                                                      rel=0.10)
    beyond = d >= 1.5e-3
    np.testing.assert_array_less(np.abs(ours[beyond] / ccx[beyond] - 1), 0.05)
