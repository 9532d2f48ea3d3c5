"""The run's default time limit follows the robot's route (sim.engine.budget): a slow robot on a long round
trip gets the time it needs, a short run keeps the floor, a caller's limit wins, the trace says which."""

from __future__ import annotations

import pytest

from socnavgen.run.spec import RobotScript
from socnavgen.sim import SimConfig, load_policy
from socnavgen.sim.engine.budget import FLOOR, MARGIN, SLACK, time_limit
from tests.sim.simhelpers import make_sim


def _script(speed: float, cues: list[dict] | None = None) -> RobotScript:
    return RobotScript.model_validate({"speed": speed, "cues": cues or []})


def test_limit_is_slack_times_route_time_plus_waits_plus_margin():
    wait = {"trigger": {"when": "start"}, "wait": 6.0}
    limit = time_limit([(0.0, 0.0), (50.0, 0.0), (0.0, 0.0)], None, _script(0.4, [wait]))
    assert limit.seconds == pytest.approx(SLACK * (100.0 / 0.4 + 6.0) + MARGIN)
    assert "100.0 m of route at 0.4 m/s" in limit.why and "6 s of waits" in limit.why


def test_short_route_keeps_the_floor_and_a_speed_cue_slows_the_budget():
    assert time_limit([(0.0, 0.0), (5.0, 0.0)], 0.6).seconds == FLOOR
    slow = _script(0.6, [{"trigger": {"when": "start"}, "speed": 0.2}])
    assert time_limit([(0.0, 0.0), (60.0, 0.0)], None, slow).seconds == pytest.approx(SLACK * 300.0 + MARGIN)
    # a policy slower than the script's speed
    assert time_limit([(0.0, 0.0), (60.0, 0.0)], 0.3, _script(0.6)).seconds == pytest.approx(SLACK * 200.0 + MARGIN)


def test_wait_until_clear_counts_its_longest_wait():
    cue = {"trigger": {"when": "blocked", "distance": 2.0}, "say": "EXCUSE ME", "wait_until_clear": True}
    with_cue = time_limit([(0.0, 0.0), (80.0, 0.0)], None, _script(0.5, [cue])).seconds
    without = time_limit([(0.0, 0.0), (80.0, 0.0)], None, _script(0.5)).seconds
    assert with_cue > without


def test_simulation_uses_the_route_limit_unless_given_one():
    path = [(1.0, 5.0), (19.0, 5.0), (1.0, 5.0), (19.0, 5.0), (1.0, 5.0)]  # 72 m
    sim = make_sim([], [], path, load_policy("waypoints"))
    assert sim.timeout == pytest.approx(SLACK * 72.0 / 0.6 + MARGIN)
    fixed = make_sim([], [], path, load_policy("waypoints"), timeout=30.0)
    assert fixed.timeout == 30.0 and fixed.max_steps == 600
    trace = fixed.run()
    assert trace.end_reason == "timeout" and trace.meta["timeout"] == 30.0
    assert trace.meta["timeout_why"] == "set by the caller"
    assert SimConfig().timeout is None
