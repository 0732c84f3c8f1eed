"""What a re-keying compares (rigid.tasks.rekey): a rerun's result against the stored one,
its timings aside, so that a rerun on another machine or load can be identical."""

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
