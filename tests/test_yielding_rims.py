"""The rigid model's yielding rims (docs/theory/rigid-body.md, "Yielding rims", Eqs. R55–R63):
the rim element against the FE push it is derived from, the energy balance with plastic work,
the limit states, and the rigid rims left as they were."""

from __future__ import annotations

import numpy as np
import pytest

import rigid
from fem import rim_law
from rigid import DFPBearing, G, ricker_record
from rigid import _kernel as K


@pytest.fixture(scope="module")
def law(tmp_path_factory):
    """The baseline rim's law, from the FE pushes (about 20 s), in a cache of this module."""
    import os

    old = os.environ.get("DFP_CACHE_DIR")
    os.environ["DFP_CACHE_DIR"] = str(tmp_path_factory.mktemp("rim-law"))
    try:
        return rim_law(DFPBearing(pressure=60e6))
    finally:
        if old is None:
            del os.environ["DFP_CACHE_DIR"]
        else:
            os.environ["DFP_CACHE_DIR"] = old


def _pulse(ap_g, tp=2.0, kind="symmetric"):
    _, a = ricker_record(ap_g * G, tp, kind, dt=0.005, lead=1.5 * tp, free=4.0)
    return a


def element_force(law, deflection):
    """The kernel's rim element pushed quasi-statically to each deflection [m] in turn through
    one stiff contact (Hertz k = 1e30 N/m^1.5, so the contact takes no deflection): the force
    [N] at each, with the plastic set carried from one to the next (Eqs. R57–R59)."""
    table = law.table
    buf = np.zeros((K.B_CONTACTS, K.B_FIELDS))
    buf[0, K.B_SHARE] = 1.0
    up, out = 0.0, []
    for d in deflection:
        buf[0, K.B_GAP] = d - up  # the overlap against the rim at its current set
        _, force, step = K.rim_response(buf, 1, 1e30, law.stiffness, table, up)
        up += step
        out.append(force)
    return np.array(out)


def test_rim_element_reproduces_the_push_it_was_derived_from(law):
    # the static check: force at first yield and at the hinge within 5 % of the FE
    # push. First yield: where the push leaves its elastic line; the hinge: the whole root
    # section plastic (Eq. F36). The element interpolates the push's own increments, so the
    # 5 % covers the interpolation and the series solve, not a model difference.
    d = law.push_displacement
    f = law.push_force
    first = law.first_yield_force / law.stiffness  # its deflection on the elastic line
    path = np.sort(np.concatenate([d[d > 0], [first, law.hinge_displacement]]))
    forces = element_force(law, path)
    at = {x: forces[int(np.searchsorted(path, x))] for x in (first, law.hinge_displacement)}
    assert at[first] == pytest.approx(law.first_yield_force, rel=0.05)
    assert at[law.hinge_displacement] == pytest.approx(law.hinge_force, rel=0.05)
    # and along the whole push (increments of at most 0.44 mm): within 5 % everywhere
    on_push = element_force(law, d[d > 0])
    assert np.allclose(on_push, f[d > 0], rtol=0.05)


def test_rim_law_is_ordered(law):
    # physics of the push: first yield below the hinge below rupture; the backbone never falls
    assert 0 < law.first_yield_force < law.hinge_force
    assert 0 < law.hinge_set < law.rupture_set < np.inf
    assert np.all(np.diff(law.force) >= 0) and np.all(np.diff(law.plastic_set) > 0)


def test_below_the_rims_yielding_and_rigid_rims_are_the_same_run(law):
    # the yielding branch only changes the rim contacts: a pulse that does not reach a rim
    # gives the same run to the last bit
    b = DFPBearing(pressure=60e6)
    a = _pulse(0.1)
    rigid_run = rigid.simulate(b, a, 0.005)
    yielding = rigid.simulate(b, a, 0.005, rims="yielding", rim_law=law)
    assert not rigid_run.impacts
    assert np.array_equal(rigid_run.displacement, yielding.displacement)
    assert np.array_equal(rigid_run.slider_rotation, yielding.slider_rotation)
    assert yielding.rim_sets == (0.0,) * 4 and not yielding.failed


def test_yielding_run_closes_its_energy_balance_and_orders_its_limit_states(law):
    b = DFPBearing(pressure=60e6)
    r = rigid.simulate(b, _pulse(0.8), 0.005, rims="yielding", rim_law=law,
                       limit_state="containment")
    states = r.limit_states
    assert r.failed and r.failure_mode == "yielding"
    assert states["hinge"] <= states["rupture"] <= states["containment"] == r.failure_time
    assert max(r.rim_sets) >= law.rupture_set
    # the plastic work is dissipated, and the balance with it closes: measured 0.2 % of the
    # input (the kernel calls a run numerical beyond 5 %); 1 % leaves room for other steps
    assert r.energy.plastic[-1] > 0
    assert r.energy.relative_error < 0.01


def test_hinge_criterion_stops_at_the_hinge(law):
    b = DFPBearing(pressure=60e6)
    r = rigid.simulate(b, _pulse(0.8), 0.005, rims="yielding", rim_law=law)  # default hinge
    assert r.limit_state == "hinge" and r.failed
    assert r.failure_time == r.limit_states["hinge"]
    assert r.limit_states["containment"] is None
    assert r.max_rim_force == pytest.approx(law.hinge_force, rel=0.05)


def test_rim_model_arguments_are_checked():
    b = DFPBearing()
    a = _pulse(0.1)
    with pytest.raises(ValueError, match="rims must be one of"):
        rigid.simulate(b, a, 0.005, rims="soft")
    with pytest.raises(ValueError, match="cannot yield"):
        rigid.simulate(b, a, 0.005, limit_state="hinge")
    with pytest.raises(ValueError, match="limit_state must be one of"):
        rigid.simulate(b, a, 0.005, rims="yielding", rim_law=object(), limit_state="bent")
    with pytest.raises(TypeError, match=r"must be a rigid\.rims\.RimLaw"):
        rigid.simulate(b, a, 0.005, rims="yielding", rim_law=object())


def test_critical_sa_orders_the_limit_states(law):
    # a ladder under each limit state: hinge ≤ rupture ≤ containment (each later state
    # needs the earlier ones), and every rim model's answer is recorded with it
    b = DFPBearing(pressure=60e6)
    motion = rigid.GroundMotion(name="pulse", dt=0.005, acceleration=_pulse(1.0))
    found = {s: rigid.critical_sa(b, motion, 0.05 * G, stop=2.0 * G, rims="yielding",
                                  limit_state=s, rim_law=law, cache=False)
             for s in ("hinge", "rupture", "containment")}
    assert found["hinge"].sa <= found["rupture"].sa <= found["containment"].sa
    assert {c.rims for c in found.values()} == {"yielding"}
    assert found["rupture"].limit_state == "rupture"


def test_a_stiff_rim_is_pushed_until_it_hinges(monkeypatch, tmp_path):
    """A rim that has not hinged at the end of the 1.5 mm fine push (the 80 mm rim of the
    stronger-rim variant hinges at about 5 mm) gets fine pushes twice as long, with
    increments of the same size, until it has; one that never does before half its height
    is refused with the reach in the message. A stand-in push hinges at ``hinge`` [m] and
    records each request, so no FE runs here; the baseline's push is unchanged (the module's
    fixture runs it)."""
    import fem.rim_laws
    from fem.pushover import Pushover

    requests = []

    def push(bearing, *, displacement=None, steps=40, plasticity=True, **_):
        d = bearing.rim_height / 2 if displacement is None else displacement
        requests.append((d, steps, plasticity))
        x = np.linspace(0.0, d, steps + 1)
        f = 1e9 * np.minimum(x, 0.004) + 1e7 * np.maximum(x - 0.004, 0.0)
        hinged = plasticity and d >= hinge
        return Pushover(displacement=x, force=f, yielded_fraction=np.zeros_like(x),
                        hinge_displacement=hinge if hinged else None,
                        hinge_force=float(np.interp(hinge, x, f)) if hinged else None,
                        max_plastic_strain=np.zeros_like(x),
                        averaged_plastic_strain=np.linspace(0.0, 0.5, x.size),
                        kinematics="finite", dofs=0, plate=None, final_displacement=None,
                        final_plastic_strain=None)

    monkeypatch.setattr(fem.rim_laws, "rim_pushover", push)
    bearing = DFPBearing(pressure=60e6, rim_thickness=0.08)
    hinge = 0.005
    law = rim_law(bearing, cache=False)
    fine = [(d, n) for d, n, plastic in requests if plastic and d < bearing.rim_height / 2]
    assert fine == [(1.5e-3, 60), (3e-3, 120), (6e-3, 240)]  # 0.025 mm increments throughout
    assert law.hinge_displacement == hinge
    requests.clear()
    hinge = 1.0  # never within the push: a squat rim whose face the slider crushes
    law = rim_law(bearing, cache=False)
    assert [d for d, n, plastic in requests if plastic][-2:] == [12e-3, bearing.rim_height / 2]
    assert law.hinge_set == law.hinge_force == law.hinge_displacement == np.inf
    assert np.isfinite(law.rupture_set)  # the stand-in's gauge strain passes 0.19 on the way


def test_a_run_without_a_law_still_gets_fems_with_a_deprecation_warning(law, monkeypatch):
    """For one release a yielding run given no law asks fem.rim_law for it (warning that the
    caller should pass rim_law=), and the old alias rigid.rim_law forwards to it: the same run
    as with the law given. fem.rim_law is stood in for by the module's law (no FE here)."""
    import fem.rim_laws

    asked = []
    monkeypatch.setattr(fem.rim_laws, "rim_law",
                        lambda bearing, **kw: asked.append(bearing) or law)
    b = DFPBearing(pressure=60e6)
    a = _pulse(0.8)
    given = rigid.simulate(b, a, 0.005, rims="yielding", rim_law=law)
    with pytest.warns(DeprecationWarning, match=r"pass it as rim_law="):
        fallback = rigid.simulate(b, a, 0.005, rims="yielding")
    assert asked == [b]
    assert np.array_equal(fallback.displacement, given.displacement)
    assert fallback.limit_states == given.limit_states
    with pytest.warns(DeprecationWarning, match=r"moved to fem\.rim_law"):
        assert rigid.rim_law(b) is law


def test_one_ladder_to_containment_answers_every_limit_state(law):
    """critical_sa_by_limit_state runs each rung to containment and reads the hinge and the
    rupture off the way; a run to containment is the run stopped at the hinge up to the
    hinge, so its answers must equal three ladders run each to its own limit state, with the
    full search and with the fast one (exact equality: the same rungs of the same runs)."""
    from rigid.collapse.limit_state_ladder import critical_sa_by_limit_state, failure_mode

    b = DFPBearing(pressure=60e6)
    motion = rigid.GroundMotion(name="pulse", dt=0.005, acceleration=_pulse(1.0))
    ladder = {"step": 0.05 * G, "stop": 2.0 * G, "cache": False}
    for search in ("full", "fast"):
        by = critical_sa_by_limit_state(b, motion, law, search=search, coarse=4, **ladder)
        for state, found in by.items():
            alone = rigid.critical_sa(b, motion, rims="yielding", limit_state=state,
                                      rim_law=law, search=search, coarse=4, **ladder)
            assert found.sa == alone.sa is not None, (search, state)
            assert found.limit_state == state and failure_mode(found) == "rim"
        assert by["hinge"].sa < by["containment"].sa


def test_a_rim_too_strong_to_yield_fails_by_uplift_under_every_limit_state(law):
    """A rim a hundred times as strong, without hinge or rupture, never yields on the way: the
    slider leaves over it, so every limit state's critical SA is the same rung, by uplift, and
    it is the rigid-rim model's (within one 0.05 g rung: the rim's elastic give differs)."""
    import dataclasses

    from rigid.collapse.limit_state_ladder import critical_sa_by_limit_state, failure_mode

    strong = dataclasses.replace(law, force=100 * law.force, stiffness=100 * law.stiffness,
                                 hinge_set=np.inf, rupture_set=np.inf)
    b = DFPBearing(pressure=10e6)
    motion = rigid.GroundMotion(name="pulse", dt=0.005, acceleration=_pulse(1.0))
    by = critical_sa_by_limit_state(b, motion, strong, step=0.05 * G, stop=3.0 * G,
                                    cache=False)
    assert len({c.sa for c in by.values()}) == 1
    assert {failure_mode(c) for c in by.values()} == {"uplift"}
    rigid_rims = rigid.critical_sa(b, motion, 0.05 * G, stop=3.0 * G, cache=False)
    assert abs(by["containment"].sa - rigid_rims.sa) <= 0.05 * G * 1.001


def test_a_numerical_rung_keeps_the_limit_states_it_reached(monkeypatch):
    """A rung whose run goes unstable after the rim hinged (the 20 mm rim: the slider's
    penetration passes the rim's thickness once the rim is flattened) is neither a failure
    nor a survival, but the hinge it reached before is a fact: the rung keeps it, and the
    hinge's ladder counts it reached (the containment's does not)."""
    from types import SimpleNamespace

    import rigid.model
    from rigid.collapse.ladder import Rung, _run_rung
    from rigid.collapse.limit_state_ladder import reached

    def unstable(*args, **kwargs):
        partial = SimpleNamespace(limit_states={"hinge": 7.1, "rupture": None,
                                                "containment": None})
        raise rigid.NumericalInstabilityError("a contact penetration exceeded the rim "
                                              "thickness at t = 7.2 s", partial)

    monkeypatch.setattr(rigid.model, "simulate", unstable)
    out = _run_rung(DFPBearing(), np.zeros(10), 0.01, 1.0, {"free": 0.0})
    assert out["numerical_failure"] and not out["failed"] and out["limit_states"] == ["hinge"]
    rung = Rung(index=0, sa=1.0, scale=1.0, **{**out, "limit_states": ("hinge",)})
    assert reached(rung, "hinge").failed and not reached(rung, "containment").failed
