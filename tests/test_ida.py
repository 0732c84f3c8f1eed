"""Critical SA by time history (rigid.collapse.ladder): ladder bookkeeping, fast search, cache,
pool.

Records are short synthetic Ricker pulses (with and without noise) on coarse 0.05 g ladders,
so each ladder costs a few seconds. Outcomes (failed / survived) are compared exactly: the
model is deterministic, so the same scaled record must give the same verdict.
"""

from dataclasses import replace

import numpy as np
import pytest

import rigid.collapse.ladder as ida
from rigid import DFPBearing, G, pseudo_acceleration, simulate
from rigid.collapse.ladder import CriticalSA, Rung, critical_sa, critical_sas

DT = 0.01
STEP = 0.05 * G


@pytest.fixture(scope="module")
def shared_cache(tmp_path_factory):
    """One rung cache for the tests that ladder the same record (each rung is simulated once;
    the verdicts are deterministic, so reading them back changes nothing)."""
    return tmp_path_factory.mktemp("ida-cache")


def _sim(bearing, acc, scale):
    return simulate(bearing, acc * scale, DT, stop_when_quiet=True, on_instability="refine")


def test_ladder_rungs_scaling_and_first_failure(shared_cache, light, pulse_motion):
    """Rungs are start + j·step, each scaled to its SA(4.5 s) (N-J spectrum, rel 1e-9:
    PSA is linear in the record, so only round-off separates the two), all below the critical
    rung survive, and simulate() on the scaled record agrees at the critical rung and below."""
    acc = pulse_motion().acceleration
    res = critical_sa(light, acc, STEP, dt=DT, cache=shared_cache)
    assert res.sa is not None
    idx = [r.index for r in res.rungs]
    assert idx == list(range(len(idx)))
    for r in res.rungs:
        assert r.sa == pytest.approx(STEP * (r.index + 1), rel=1e-12)
    assert [r.failed for r in res.rungs] == [False] * (len(idx) - 1) + [True]
    crit, below = res.rungs[-1], res.rungs[-2]
    assert res.sa == crit.sa and res.scale == crit.scale
    psa = float(pseudo_acceleration(acc * crit.scale, DT, [light.design_period])[0])
    assert psa == pytest.approx(crit.sa, rel=1e-9)
    assert _sim(light, acc, crit.scale).failed
    assert not _sim(light, acc, below.scale).failed
    assert res.record_sa == pytest.approx(crit.sa / crit.scale, rel=1e-12)


@pytest.mark.parametrize(
    "kind, period, noise",
    [("symmetric", 2.0, 0.0), ("antisymmetric", 2.5, 0.3), ("symmetric", 3.0, 0.3)],
)
def test_fast_search_finds_the_full_ladders_first_failure(kind, period, noise, shared_cache, light,
                                                          pulse_motion):
    """The fast search (0.2 g coarse rungs) returns the same critical rung as the full ladder.

    The rung cache is shared, so the fast search re-reads the full ladder's verdicts and this
    checks the search logic at the cost of one ladder. The third record resurrects above its
    first failure in our runs (0.95 g fails, 1.0-1.25 g survive), the case a plain coarse
    search gets wrong.
    """
    seed = int(10 * period) if noise else 0
    acc = pulse_motion(kind, period, noise=noise, seed=seed).acceleration
    full = critical_sa(light, acc, STEP, dt=DT, cache=shared_cache)
    fast = critical_sa(light, acc, STEP, dt=DT, cache=shared_cache, search="fast", coarse=4)
    assert full.sa is not None
    assert fast.sa == full.sa
    assert fast.search == "fast" and len(fast.rungs) < len(full.rungs) + 4


def test_cache_reuse_and_resume(tmp_path, monkeypatch, light, pulse_motion):
    """A ladder cut short (stop below the failure) resumes: only the new rungs run; a rerun
    runs nothing and returns identical rungs."""
    acc = pulse_motion("antisymmetric", 2.5).acceleration
    calls = []
    run = ida._run_rung
    monkeypatch.setattr(ida, "_run_rung", lambda *a: calls.append(a[3]) or run(*a))
    part = critical_sa(light, acc, STEP, dt=DT, cache=tmp_path, stop=0.3 * G)
    assert part.sa is None and len(calls) == 6
    whole = critical_sa(light, acc, STEP, dt=DT, cache=tmp_path)
    assert len(calls) == len(whole.rungs) and whole.sa is not None
    again = critical_sa(light, acc, STEP, dt=DT, cache=tmp_path)
    assert len(calls) == len(whole.rungs)
    assert again.rungs == whole.rungs
    # a different bearing is a different ladder
    critical_sa(DFPBearing(pressure=10e6, friction=0.06), acc, STEP, dt=DT, cache=tmp_path,
                stop=0.05 * G)
    assert len(calls) == len(whole.rungs) + 1


def test_cache_false_disables_the_cache(tmp_path, monkeypatch, light, pulse_motion):
    """``cache=False`` behaves as None: the ladder runs and nothing is written to the default
    cache directory (it used to be taken for a path and raise)."""
    monkeypatch.setenv("DFP_CACHE_DIR", str(tmp_path / "default"))
    res = critical_sa(light, pulse_motion().acceleration, STEP, dt=DT, cache=False, stop=0.1 * G)
    assert len(res.rungs) == 2
    assert not (tmp_path / "default").exists()


def _rung(j, failed):
    return Rung(j, (j + 1) * STEP, 1.0, failed, False, None, 1, 1.0, 0.0)


def test_resurrections_listed():
    """Every surviving rung above the critical one is a resurrection; none without failure."""
    rungs = tuple(_rung(j, f) for j, f in enumerate([False, True, False, True, False]))
    res = CriticalSA(rungs[1].sa, 1.0, "x", 1.0, 4.5, STEP, STEP, 5 * STEP, "full", rungs)
    assert res.resurrected
    assert [r.index for r in res.resurrections] == [2, 4]
    none = CriticalSA(None, None, "x", 1.0, 4.5, STEP, STEP, 5 * STEP, "full",
                      tuple(_rung(j, False) for j in range(3)))
    assert not none.resurrected and not none.failed


def test_after_failure_runs_extra_rungs(shared_cache, light, pulse_motion):
    """``after_failure=k`` runs exactly k rungs above the first failure (all kept)."""
    acc = pulse_motion().acceleration
    kw = {"dt": DT, "search": "fast", "coarse": 4, "cache": shared_cache}
    base = critical_sa(light, acc, STEP, **kw)
    more = critical_sa(light, acc, STEP, after_failure=2, **kw)
    top = max(r.index for r in more.rungs)
    crit = round(more.sa / STEP) - 1
    assert more.sa == base.sa
    assert {crit + 1, crit + 2} <= {r.index for r in more.rungs}
    assert top == max(crit + 2, max(r.index for r in base.rungs))


def test_parallel_matches_serial(light, pulse_motion):
    """Two records in a 2-process pool give the same rungs as in this process (short ladders
    of two 0.15 g rungs: this checks the plumbing, not the physics)."""
    motions = [replace(pulse_motion(), name="r0"),
               replace(pulse_motion("antisymmetric", 2.5), name="r1")]
    kw = {"step": 0.15 * G, "stop": 0.3 * G, "cache": None, "progress": False}
    par = critical_sas(light, motions, processes=2, **kw)
    ser = critical_sas(light, motions, processes=1, **kw)
    assert [r.name for r in par] == ["r0", "r1"]
    assert [r.rungs for r in par] == [r.rungs for r in ser]


def test_bad_input(light, pulse_motion):
    acc = pulse_motion().acceleration
    with pytest.raises(ValueError, match="search"):
        critical_sa(light, acc, STEP, dt=DT, search="bisect")
    with pytest.raises(ValueError, match="zero SA"):
        critical_sa(light, np.zeros(100), STEP, dt=DT)
    with pytest.raises(ValueError, match="step"):
        critical_sa(light, acc, -1.0, dt=DT)
    with pytest.raises(TypeError, match="dt"):
        critical_sa(light, acc, STEP)
    with pytest.raises(ValueError, match="after_failure"):
        critical_sa(light, acc, STEP, dt=DT, after_failure=-1)
    with pytest.raises(ValueError, match="free"):
        critical_sa(light, acc, STEP, dt=DT, free=-1.0)
