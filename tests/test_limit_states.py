"""One vocabulary for the limit state (docs/architecture.md): the names, the one check, and the
old keyword and attribute names accepted for one release with a DeprecationWarning."""

from __future__ import annotations

import inspect

import pytest

import rigid
from rigid.limit_states import (
    LIMIT_STATES,
    check_limit_state,
    check_limit_states,
    renamed_limit_state,
)


def test_the_names():
    assert LIMIT_STATES == ("hinge", "rupture", "containment")
    assert rigid.LIMIT_STATES is LIMIT_STATES


@pytest.mark.parametrize(("limit_state", "rims", "expected"), [
    (None, "rigid", "containment"), (None, "yielding", "hinge"),
    ("containment", "rigid", "containment"), ("rupture", "yielding", "rupture"),
    ("hinge", None, "hinge"),
])
def test_check_limit_state_gives_the_name_or_the_rim_models_default(limit_state, rims,
                                                                    expected):
    assert check_limit_state(limit_state, rims=rims) == expected


@pytest.mark.parametrize(("limit_state", "rims", "message"), [
    ("bent", "yielding", "limit_state must be one of hinge, rupture, containment, got 'bent'"),
    (None, None, "limit_state must be one of"),
    ("hinge", "rigid", "rims='rigid' cannot yield"),
    ("hinge", "soft", "rims must be one of rigid, yielding"),
])
def test_check_limit_state_refuses(limit_state, rims, message):
    with pytest.raises(ValueError, match=message.replace("(", r"\(")):
        check_limit_state(limit_state, rims=rims)


def test_several_limit_states_keep_their_order_without_duplicates():
    assert check_limit_states(["rupture", "hinge", "rupture"]) == ("rupture", "hinge")
    with pytest.raises(ValueError, match="got none"):
        check_limit_states([])
    with pytest.raises(ValueError, match="got 'bent'"):
        check_limit_states(["hinge", "bent"])


def test_the_decorator_maps_an_old_name_and_keeps_the_signature():
    @renamed_limit_state("criterion")
    def run(x, *, limit_state="hinge"):
        """Doc."""
        return x, limit_state

    assert run(1) == (1, "hinge") and run.__doc__ == "Doc."
    assert "limit_state" in inspect.signature(run).parameters
    with pytest.warns(DeprecationWarning, match="criterion= is deprecated, use limit_state="):
        assert run(1, criterion="rupture") == (1, "rupture")
    with pytest.raises(TypeError, match="got both"):
        run(1, criterion="rupture", limit_state="hinge")
    with pytest.raises(ValueError, match="not a former name"):
        renamed_limit_state("failure")


def test_sweep_settings_and_ladders_accept_the_old_name():
    with pytest.warns(DeprecationWarning, match="failure_criterion= is deprecated"):
        s = rigid.SweepSettings(failure_criterion="containment")
    assert s.limit_state == "containment" and s == rigid.SweepSettings()
    with pytest.warns(DeprecationWarning, match=r"SweepSettings\.failure_criterion"):
        assert s.failure_criterion == "containment"
    c = rigid.CriticalSA(sa=None, scale=None, name="r", record_sa=1.0, period=4.5, start=0.1,
                         step=0.1, stop=1.0, search="full", rungs=())
    with pytest.warns(DeprecationWarning, match=r"CriticalSA\.failure_criterion"):
        assert c.failure_criterion == c.limit_state == "containment"


def test_the_fe_model_and_the_fe_runners_name_it_limit_state():
    """The signatures themselves (the FE runs are not run here)."""
    import fem
    from validation.fem_runs import fem_run
    from validation.studies.pulse_fe_runs import fe_pulse_run

    for function in (rigid.simulate, rigid.critical_sa, rigid.predict_critical_sa,
                     fem.simulate, fem_run, fe_pulse_run):
        parameters = inspect.signature(function).parameters
        assert "limit_state" in parameters, function
        assert not {"failure_criterion", "criterion"} & set(parameters) or (
            function is rigid.predict_critical_sa), function  # its criterion: the pulse's
