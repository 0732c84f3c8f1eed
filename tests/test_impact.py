"""Impact velocity and impact region spectra (paper §3, Figs. 6–8).

Each test names its oracle and why its tolerance is what it is. Grids are coarse to keep the
suite fast; the resolution study is ``validation/studies/impact_resolution.py``. All sweeps run
in this process (``workers=1``) with a cache in a temporary folder, except the one test of
the process pool.
"""

import dataclasses
import math
import subprocess
import sys

import numpy as np
import pytest

from rigid import (
    G,
    SweepSettings,
    design_chart,
    impact_region_spectrum,
    impact_velocity_spectrum,
    load_spectrum,
    region_at,
    region_boundaries,
    ricker_record,
    save_spectrum,
    simulate,
)
from rigid.impact import (
    bearing_from_attrs,
    grid_boundaries,
    nonmonotonic_periods,
    settings_from_attrs,
)
from rigid.impact.sweep import pulse_record, run_cells
from rigid.motions.spectra import spectral_displacement

# Tb/Tp from 0.9 (Tp = 5 s) to 4.8 in steps of 0.3: the paper's range, coarse
RATIOS = 0.9 + 0.3 * np.arange(14)
STEP = 0.05 * G  # amplitude step of the coarse grids and of the failure scan
GRID_PERIODS = np.array([1.5, 2.0, 3.0])
GRID_AMPS = STEP * np.arange(1, 17)  # 0.05 g … 0.80 g, the same floats as the scan


@pytest.fixture(scope="module")
def cache(tmp_path_factory):
    return tmp_path_factory.mktemp("impact") / "cells.sqlite"


@pytest.fixture(scope="module")
def spectra_08g(cache, heavy, light):
    """Light and heavy bearing, Ap = 0.8 g, both kinds (paper Fig. 6)."""
    out = {}
    for name, b in (("light", light), ("heavy", heavy)):
        for kind in ("symmetric", "antisymmetric"):
            out[name, kind] = impact_velocity_spectrum(
                b, kind, 0.8 * G, b.design_period / RATIOS, workers=1, cache=cache,
                progress=False)
    return out


@pytest.fixture(scope="module")
def grid(cache, light):
    return impact_region_spectrum(light, "symmetric", GRID_PERIODS, GRID_AMPS, workers=1,
                                  cache=cache, progress=False)


@pytest.fixture(scope="module")
def bisected(cache, grid, light):  # after the grid: the scan reuses its cells
    return region_boundaries(light, "symmetric", GRID_PERIODS, amplitude_max=GRID_AMPS[-1],
                             tolerance=0.005 * G, scan_step=STEP, workers=1, cache=cache,
                             progress=False)


@pytest.mark.parametrize("kind", ["symmetric", "antisymmetric"])
def test_light_bearing_at_08g_shows_three_regions(spectra_08g, kind):
    """Paper §3.2: at Ap = 0.8 g the Tb/Tp axis splits into failure (long pulses), impact
    without failure, and no impact (short pulses). Exact categorical checks."""
    ds = spectra_08g["light", kind]
    x, region = ds.frequency_ratio.values, ds.region.values
    assert set(region.tolist()) == {0, 1, 2}
    last_failure, first_clear = x[region == 2].max(), x[region == 0].min()
    assert last_failure < first_clear
    # a band of impacts without failure between the two
    assert np.any((region == 1) & (x > last_failure) & (x < first_clear))
    # short pulses never reach the rims: everything above the first clear ratio is clear
    assert np.all(region[x >= first_clear] == 0)
    clear = region == 0
    assert np.all(ds.max_impact_velocity.values[clear] == 0)
    assert np.all(ds.n_impacts.values[clear] == 0)
    # failures follow an impact; the maximum is the largest |v| of the listed impacts
    failed = ds.failed.values
    assert np.all(ds.failure_time.values[failed] > ds.impact_time.values[failed, 0])
    listed = np.nanmax(np.abs(ds.impact_velocity.values[~clear]), axis=1)
    np.testing.assert_allclose(listed, ds.max_impact_velocity.values[~clear], rtol=1e-12)


@pytest.mark.parametrize("kind", ["symmetric", "antisymmetric"])
def test_heavy_bearing_same_impacts_and_also_fails(spectra_08g, kind, light):
    """60 MPa in the rigid model: before the first impact the bearing is a friction pendulum
    whose period and friction do not depend on the mass, so whether a rim is reached and the
    first impact velocity agree with 10 MPa. Tolerance on v² (v² = ω²(A² − d²) near a rim):
    1 % for the slider's mass (0.15 % of M at 10 MPa), plus 2ω²·d_cap·Δd with Δd = 1.5 mm for
    where first contact happens (the vertex penetrations differ, 1.13 vs 0.34 mm static),
    which matters for grazing impacts only. The rims cannot yield, so the heavy bearing also
    fails by uplift (paper §2.1: in FE it yields first)."""
    light_ds, heavy_ds = spectra_08g["light", kind], spectra_08g["heavy", kind]
    np.testing.assert_array_equal(light_ds.region.values == 0, heavy_ds.region.values == 0)
    hit = light_ds.region.values > 0
    omega2 = (2 * math.pi / light.period) ** 2
    np.testing.assert_allclose(heavy_ds.impact_velocity.values[hit, 0] ** 2,
                               light_ds.impact_velocity.values[hit, 0] ** 2, rtol=0.01,
                               atol=2 * omega2 * light.displacement_capacity * 1.5e-3)
    assert np.any(heavy_ds.region.values == 2)


def test_no_impact_cells_have_no_impact_in_a_direct_simulation(grid, light):
    """Every column's highest no-impact cell (the one most at risk) and lowest impact cell
    against a plain ``simulate`` call on ``ricker_record``'s default record (lead 2·Tp, 10 s
    of free vibration, no early stop): same verdict. Exact (categorical)."""
    region = grid.region.values
    assert np.any(region == 0) and np.any(region > 0)
    for j, tp in enumerate(GRID_PERIODS):
        column = region[:, j]
        top_clear = np.flatnonzero(column == 0).max()
        first_hit = np.flatnonzero(column > 0).min()
        assert first_hit == top_clear + 1  # monotonic column at this resolution
        for i, expect_impact in ((top_clear, False), (first_hit, True)):
            _t, a = ricker_record(GRID_AMPS[i], tp, "symmetric", dt=0.005)
            r = simulate(light, a, 0.005, on_instability="refine")
            assert bool(r.impacts) is expect_impact, (tp, GRID_AMPS[i] / G)


def test_bisected_boundaries_agree_with_the_grid(grid, bisected):
    """Bisection (± 0.005 g) inside the grid's transition interval. The failure scan uses the
    grid's amplitudes (multiples of 0.05 g, same floats), so its bracket must sit in the
    interval below the column's first failure cell. Exact up to round-off in the bracket."""
    tol = 0.005 * G
    region = grid.region.values
    for j in range(len(GRID_PERIODS)):
        for name, k in (("impact", 1), ("failure", 2)):
            lo = float(bisected[f"{name}_lower"][j])
            hi = float(bisected[f"{name}_upper"][j])
            reached = np.flatnonzero(region[:, j] >= k)
            if reached.size == 0:
                assert math.isnan(hi)
                continue
            i = reached[0]
            below = GRID_AMPS[i - 1] if i > 0 else 0.0
            assert below - 1e-9 <= lo < hi <= GRID_AMPS[i] + 1e-9
            assert hi - lo <= 2 * tol * (1 + 1e-6)
            mid = float(bisected[f"{name}_boundary"][j])
            assert float(grid[f"{name}_boundary"][j]) == pytest.approx(mid, abs=STEP / 2 + tol)
    assert np.any(np.isfinite(bisected.failure_boundary.values))  # the check above bites


def test_frictionless_peak_equals_undamped_spectral_displacement(cache, light):
    """μ = 0 below the rims: the bearing is a linear pendulum of period T = bearing.period, so
    the sweep's peak displacement equals the undamped (ξ = 0) spectral displacement of the
    pulse at T, computed by the project's Nigam–Jennings code on ``ricker_record``'s longer
    record. 0.5 %: the slider's inertia and the contact compliance change T by < 0.1 %.
    Amplitudes are set so that the SDOF peak is 0.4 m, below the 0.6 m capacity."""
    b = dataclasses.replace(light, friction=0.0, rim_friction=0.0)
    settings = SweepSettings(stop_when_quiet=False, free=1.5 * b.period)
    cells, expected = [], []
    for kind in ("symmetric", "antisymmetric"):
        for tp in (1.5, 5.0):
            _t, unit = ricker_record(1.0, tp, kind, dt=0.005, free=2 * b.period)
            sd_unit = float(spectral_displacement(unit, 0.005, [b.period], damping=0.0)[0])
            cells.append((kind, tp, 0.4 / sd_unit))
            expected.append(0.4)
    out, _ = run_cells(b, cells, settings, workers=1, cache=cache, progress=False)
    for c, e in zip(out, expected, strict=True):
        assert c.region == 0
        assert c.max_displacement == pytest.approx(e, rel=0.005)


def test_cache_resumes_and_keys_on_every_input(tmp_path, light):
    """An interrupted sweep (here: run on part of the grid) is completed without recomputing;
    results equal an uncached run exactly; changing the bearing or a setting misses."""
    path = tmp_path / "c.sqlite"
    periods, amps = [1.0, 1.25], [0.5 * G, 0.9 * G]
    kw = {"workers": 1, "progress": False}
    part = impact_region_spectrum(light, "antisymmetric", periods[:1], amps, cache=path, **kw)
    assert (part.attrs["cells_computed"], part.attrs["cells_reused"]) == (2, 0)
    full = impact_region_spectrum(light, "antisymmetric", periods, amps, cache=path, **kw)
    assert (full.attrs["cells_computed"], full.attrs["cells_reused"]) == (2, 2)
    fresh = impact_region_spectrum(light, "antisymmetric", periods, amps, cache=False, **kw)
    for name in ("region", "max_impact_velocity", "n_impacts", "max_uplift"):
        np.testing.assert_array_equal(full[name].values, fresh[name].values)
    other = dataclasses.replace(light, friction=0.049)
    miss = impact_region_spectrum(other, "antisymmetric", periods, amps, cache=path, **kw)
    assert miss.attrs["cells_computed"] == 4
    miss = impact_region_spectrum(light, "antisymmetric", periods, amps, cache=path,
                                  settings=SweepSettings(free=21.0), **kw)
    assert miss.attrs["cells_computed"] == 4


def _cached_cells(path):
    from rigid.tasks.store import ResultStore

    if not path.exists():
        return 0
    with ResultStore(path) as store:
        return store.count("impact-cell")


def test_ctrl_c_keeps_finished_cells_and_the_rerun_computes_only_the_rest(tmp_path, light):
    """A sweep in another process is interrupted (SIGINT) once two cells are cached: it stops
    with KeyboardInterrupt, and the rerun computes exactly the cells that were missing."""
    import signal
    import time

    path = tmp_path / "i.sqlite"
    periods, amps = [0.6, 0.65, 0.7, 0.75, 0.8], [G * a for a in (0.1, 0.2, 0.3, 0.4, 0.5, 0.6)]
    code = (
        "import signal; signal.signal(signal.SIGINT, signal.default_int_handler)\n"
        "from rigid import DFPBearing, impact_region_spectrum\n"
        f"impact_region_spectrum(DFPBearing(pressure=10e6), 'symmetric', {periods!r}, "
        f"{amps!r}, workers=1, cache={str(path)!r}, progress=False)\n"
    )
    proc = subprocess.Popen([sys.executable, "-c", code], stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 120
    while _cached_cells(path) < 2:
        assert proc.poll() is None and time.monotonic() < deadline
        time.sleep(0.05)
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode != 0 and "KeyboardInterrupt" in err
    done = _cached_cells(path)
    total = len(periods) * len(amps)
    assert 2 <= done < total
    ds = impact_region_spectrum(light, "symmetric", periods, amps, workers=1, cache=path,
                                progress=False)
    assert (ds.attrs["cells_computed"], ds.attrs["cells_reused"]) == (total - done, done)


def test_process_pool_gives_the_serial_result(tmp_path, light):
    """Two spawned workers, no cache: identical cells (the model is deterministic)."""
    periods, amps = [1.0, 1.25, 1.5], [0.6 * G, 0.9 * G]
    serial = impact_region_spectrum(light, "symmetric", periods, amps, workers=1,
                                    cache=False, progress=False)
    pooled = impact_region_spectrum(light, "symmetric", periods, amps, workers=2,
                                    cache=tmp_path / "p.sqlite", progress=False)
    for name in ("region", "max_impact_velocity", "n_impacts"):
        np.testing.assert_array_equal(serial[name].values, pooled[name].values)
    assert pooled.attrs["cells_computed"] == 6


def test_netcdf_round_trip(grid, bisected, tmp_path, light):
    import xarray as xr

    for ds in (grid, bisected):
        path = tmp_path / "s.nc"
        save_spectrum(ds, path)
        back = load_spectrum(path)
        xr.testing.assert_identical(back, ds)
        assert bearing_from_attrs(back) == light
        assert settings_from_attrs(back) == SweepSettings()
        path.unlink()


def _synthetic(impact, failure, periods=(2.0, 3.0), top=1.0 * G):
    import xarray as xr

    return xr.Dataset(
        {"impact_boundary": ("period", np.asarray(impact) * G),
         "failure_boundary": ("period", np.asarray(failure) * G)},
        coords={"period": ("period", np.asarray(periods))},
        attrs={"design_period": 4.5, "amplitude_max": top},
    )


def test_region_at_interpolates_boundaries_linearly_in_frequency_ratio():
    """Hand-made boundaries: 0.3 g at Tb/Tp = 2.25 and 0.2 g at 1.5, so 0.25 g at 1.875
    (Tp = 2.4 s); the failure boundary is 0.6 g at Tp = 2 s and not reached at 3 s."""
    s = _synthetic([0.3, 0.2], [0.6, np.nan])
    assert region_at(s, 2.4, 0.2499 * G) == 0
    assert region_at(s, 2.4, 0.2501 * G) == 1
    assert region_at(s, 2.0, 0.6 * G) == 2
    assert region_at(s, 2.4, 0.95 * G) == 1  # interpolation with "not reached" is not reached
    assert region_at(s, 2.0, 1.2 * G) == 2  # above the grid, below a known failure boundary
    np.testing.assert_array_equal(region_at(s, [2.0, 3.0, 2.4], [0.1 * G, 0.25 * G, 0.7 * G]),
                                  [0, 1, 1])
    with pytest.raises(ValueError, match="period outside"):
        region_at(s, 1.0, 0.1 * G)
    with pytest.raises(ValueError, match="highest amplitude"):
        region_at(s, 3.0, 1.2 * G)


def test_region_at_reproduces_a_monotonic_grid(grid):
    """At the grid's own periods and amplitudes the lookup returns the cells' regions (the
    grid boundaries sit midway between cells). Exact."""
    region = grid.region.values
    for j, tp in enumerate(GRID_PERIODS):
        if grid.nonmonotonic_failure.values[j] or grid.nonmonotonic_impact.values[j]:
            continue
        np.testing.assert_array_equal(region_at(grid, tp, GRID_AMPS), region[:, j])


def test_nonmonotonic_flags_and_grid_boundaries():
    """Hand-made columns (amplitude ascending downwards)."""
    region = np.array([
        [0, 0, 0, 1, 0],
        [1, 0, 2, 0, 1],
        [2, 1, 1, 1, 2],
        [2, 2, 2, 1, -1],
    ])
    fail, impact = nonmonotonic_periods(region)
    np.testing.assert_array_equal(fail, [False, False, True, False, False])
    np.testing.assert_array_equal(impact, [False, False, False, True, False])
    ib, fb = grid_boundaries(region, [1.0, 2.0, 3.0, 4.0])
    np.testing.assert_array_equal(ib, [1.5, 2.5, 1.5, 0.5, 1.5])
    np.testing.assert_array_equal(fb, [2.5, 3.5, 1.5, np.nan, 2.5])


def test_design_chart_collapses_without_friction(cache, light):
    """μ = 0: the pendulum is linear up to the rims, so impact occurs when Ap·Tp²/d_cap
    reaches Tp²/Sd(Ap = 1) (dimensional analysis), whatever the capacity. Oracle: the
    undamped spectral displacement at T = bearing.period. Tolerance: the bisection bracket
    (± 0.0005 g, as Π: 0.1–0.9 %) plus 1 % for the circular (not parabolic) dish and the rim
    contact geometry at 0.5–0.6 m (measured: 0.2–0.6 % above the oracle)."""
    base = dataclasses.replace(light, friction=0.0, rim_friction=0.0)
    cases = [dataclasses.replace(base, capacity=c) for c in (0.25, 0.30)]
    ratios = np.array([1.5, 3.0])
    settings = SweepSettings(free=3.0)
    chart = design_chart(cases, "antisymmetric", ratios, amplitude_max=1.0 * G,
                         tolerance=0.0005 * G, failure=False, settings=settings, workers=1,
                         cache=cache, progress=False)
    tp = chart.period.values
    for j, p in enumerate(tp):
        _t, unit = ricker_record(1.0, p, "antisymmetric", dt=0.005, free=2 * base.period)
        sd_unit = float(spectral_displacement(unit, 0.005, [base.period], damping=0.0)[0])
        expected = p**2 / sd_unit
        for c, b in enumerate(cases):
            pi = float(chart.impact_pi[c, j])
            tol_pi = 0.0005 * G * p**2 / b.displacement_capacity
            assert pi == pytest.approx(expected, abs=tol_pi + 0.01 * expected), (c, p)


def test_plots_are_written(spectra_08g, grid, bisected, tmp_path):
    from rigid.impact.plots import (
        plot_impact_region_spectrum,
        plot_impact_velocity_spectrum,
        plot_max_impact_velocity_spectra,
        plot_region_boundaries,
    )

    paths = [
        plot_impact_velocity_spectrum(spectra_08g["light", "symmetric"], tmp_path / "f6.png"),
        plot_max_impact_velocity_spectra(grid, tmp_path / "f7.png"),
        plot_impact_region_spectrum(grid, tmp_path / "f8.png", boundaries=bisected),
        plot_region_boundaries(bisected, tmp_path / "b.png"),
    ]
    for p in paths:
        assert p.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and p.stat().st_size > 10_000


def test_pulse_record_is_truncated_where_the_pulse_is_negligible():
    """The sweep's record keeps the whole pulse: its ends are below 1e-5·Ap (§2.1 closed
    forms; the half-widths 1.25·Tp and 1.6·Tp are chosen for that)."""
    for kind in ("symmetric", "antisymmetric"):
        a, duration = pulse_record(kind, 2.0, 1.0, SweepSettings())
        assert max(abs(a[0]), abs(a[-1])) < 1e-5
        assert np.max(np.abs(a)) == pytest.approx(1.0, rel=1e-3)
        assert duration == pytest.approx((a.size - 1) * 0.005 + 20.0)


@pytest.mark.parametrize(
    "call, error",
    [
        (lambda b: impact_region_spectrum(b, "sine", [1.0], [1.0], cache=False), "kind"),
        (lambda b: impact_region_spectrum(b, "symmetric", [-1.0], [1.0], cache=False),
         "periods"),
        (lambda b: impact_region_spectrum(b, "symmetric", [1.0], [1.0, 1.0], cache=False),
         "repeat"),
        (lambda b: impact_velocity_spectrum(b, "symmetric", 0.0, [1.0], cache=False),
         "amplitude"),
        (lambda b: region_boundaries(b, "symmetric", [1.0], tolerance=0.1, scan_step=0.1,
                                   cache=False), "scan_step"),
        (lambda b: SweepSettings(free=0.0), "free"),
        (lambda b: SweepSettings(half_width=0.5), "half_width"),
    ],
)
def test_bad_input(call, error, light):
    with pytest.raises(ValueError, match=error):
        call(light)


def test_import_rigid_does_not_import_the_optional_packages():
    code = (
        "import sys, rigid; heavy = ('xarray', 'tqdm', 'matplotlib', 'netCDF4', "
        "'concurrent.futures.process'); print(','.join(m for m in heavy if m in sys.modules))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True)
    assert out.stdout.strip() == ""


@pytest.mark.parametrize(("options", "message"), [
    ({"tolerance": 0.0}, "must be positive"),
    ({"amplitude_max": -1.0}, "must be positive"),
    ({"tolerance": 0.05 * G, "scan_step": 0.05 * G}, "scan_step must exceed twice"),
])
def test_both_boundary_searches_check_their_arguments(light, options, message):
    """region_boundaries and design_chart share one search (boundaries_many) and so one check
    of its arguments (before, design_chart ran with any)."""
    with pytest.raises(ValueError, match=message):
        region_boundaries(light, "symmetric", [3.0], cache=False, **options)
    with pytest.raises(ValueError, match=message):
        design_chart([light], "symmetric", [1.5], cache=False, **options)
