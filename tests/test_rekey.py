"""What a re-keying compares (rigid.tasks.rekey): a rerun's result against the stored one,
its timings aside and its floats to a relative tolerance, so that a rerun on another
machine or load can pass."""

from rigid.tasks.rekey import _differences, _physics


def test_timings_are_left_out_and_the_physics_kept():
    """Fields named as a timing, or ending in one (``yielding_cpu_s`` of a design case), are
    dropped at any depth; every other field stays, even one that holds a time of the model
    (``failure_time``)."""
    stored = {"sa": 0.25, "cpu_s": 3.0, "yielding_cpu_s": 0.17, "failure_time": 7.7,
              "runs": [{"wall_seconds": 1.0, "failed": True}]}
    rerun = {**stored, "cpu_s": 9.0, "yielding_cpu_s": 1.44, "runs": [{"wall_seconds": 2.0,
                                                                         "failed": True}]}
    assert _physics(stored) == {"sa": 0.25, "failure_time": 7.7, "runs": [{"failed": True}]}
    assert _differences(_physics(rerun), _physics(stored)) == []
    moved = {**rerun, "failure_time": 7.8}
    assert _differences(_physics(moved), _physics(stored)) == [
        "failure_time: 7.8 now, 7.7 stored"]


def test_floats_compare_to_the_tolerance_and_everything_else_exactly():
    """Another machine's rounding (1e-10 relative, the largest measured on an FE run) passes
    and is reported as the largest change; 1e-5 relative, an integer one step off, a flipped
    verdict and a field present on one side only do not."""
    from rigid.tasks.rekey import _largest_change

    stored = {"sa": 0.25, "steps": 3209, "failed": True, "peaks": [1.0, -2.0, 0.0]}
    rerun = {**stored, "sa": 0.25 * (1 + 1e-10), "peaks": [1.0, -2.0 * (1 - 1e-10), 0.0]}
    assert _differences(rerun, stored) == []
    assert abs(_largest_change(rerun, stored) - 1e-10) < 1e-14
    for field, value in (("sa", 0.25 * (1 + 1e-5)), ("steps", 3210), ("failed", False),
                         ("mode", "yielding")):
        assert [d.split(":")[0] for d in _differences({**stored, field: value}, stored)] == [
            field]


def test_a_value_not_reached_on_both_sides_is_the_same():
    """NaN stored and NaN now (a rung that never touched a rim has no impact velocity) is no
    difference, though NaN != NaN; NaN on one side only is one."""
    nan = float("nan")
    stored = {"rungs": [{"max_impact_velocity": nan, "failed": False}]}
    assert _differences({"rungs": [{"max_impact_velocity": nan, "failed": False}]},
                        stored) == []
    assert [d.split(":")[0] for d in _differences(
        {"rungs": [{"max_impact_velocity": 0.4, "failed": False}]}, stored)] == [
        "rungs[0].max_impact_velocity"]
