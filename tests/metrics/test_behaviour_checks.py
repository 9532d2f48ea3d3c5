"""The cards' expected robot behaviour, measured (sim/behaviour_checks.py): every check passes on a trace
that shows the behaviour, fails on one that does not, and says when it does not apply."""

from __future__ import annotations

import numpy as np
import pytest

from socnavgen.cards.library import all_cards
from socnavgen.sim.behaviour_checks import CHECKS, ExpectedCheck, check_behaviour
from tests.verify.verify_builders import build_trace

DT = 0.1


def _trace(robot: np.ndarray, person: np.ndarray | None = None, waypoints: list[tuple[float, float]] | None = None):  # noqa: ANN202
    t = np.arange(len(robot)) * DT
    humans = np.zeros((len(t), 0, 2)) if person is None else person[:, None, :]
    trace = build_trace(t, robot, humans, dt=DT, goal=tuple(robot[-1]))
    trace.robot_waypoints = waypoints or [tuple(robot[0]), tuple(robot[-1])]
    return trace


def _line(x0: float, x1: float, speed: float, y: float = 0.0) -> np.ndarray:
    x = np.arange(x0, x1 + 1e-9, speed * DT)
    return np.stack([x, np.full_like(x, y)], 1)


def _one(name: str, trace, place: complex | None = None, **params) -> dict:  # noqa: ANN001
    score, details = check_behaviour(trace, [ExpectedCheck(check=name, **params)], place, None)
    assert len(details) == 1
    return {"score": score, **details[0]}


def test_every_card_check_is_registered_with_a_definition_and_the_blind_corner_states_three() -> None:
    for card in all_cards():
        for check in card.expected_checks:
            assert check.check in CHECKS and CHECKS[check.check][1]
    corner = next(c for c in all_cards() if c.name == "blind-corner")
    assert [c.check for c in corner.expected_checks] == ["slow_near_place", "keeps_right", "stops_when_close"]
    assert sum(bool(c.expected_checks) for c in all_cards()) == len(all_cards())


def test_slow_near_the_place() -> None:
    slow = np.concatenate([_line(0, 2.4, 0.6), _line(2.43, 7.6, 0.3), _line(7.66, 10, 0.6)])
    assert _one("slow_near_place", _trace(slow), 5 + 0j)["passed"] is True  # 0.3 m/s within 2 m of x = 5
    fast = _one("slow_near_place", _trace(_line(0, 10, 0.6)), 5 + 0j)
    assert fast["passed"] is False and fast["value"] == pytest.approx(0.6, abs=0.01)
    assert _one("slow_near_place", _trace(_line(0, 10, 0.6)), 5 + 30j)["passed"] is None  # never near it


def test_keeps_right_of_its_route() -> None:
    route = [(0.0, 0.0), (10.0, 0.0)]
    right = _one("keeps_right", _trace(_line(0, 10, 0.5, y=-0.3), waypoints=route), 5 + 0j)
    assert right["passed"] is True and right["value"] == pytest.approx(0.3)  # y -0.3 is right of +x travel
    left = _one("keeps_right", _trace(_line(0, 10, 0.5, y=0.3), waypoints=route), 5 + 0j)
    assert left["passed"] is False and left["value"] == pytest.approx(-0.3)


def test_stops_when_the_person_is_close_and_keeps_its_distance() -> None:
    robot = np.concatenate([_line(0, 4, 0.5), np.repeat([[4.0, 0.0]], 40, axis=0)])
    n = len(robot)
    person = np.stack([np.linspace(7, 4.9, n), np.zeros(n)], 1)  # ends 0.9 m away: gap 0.15
    stopped = _trace(robot, person)
    assert _one("stops_when_close", stopped)["passed"] is True
    assert _one("keeps_distance", stopped)["passed"] is False  # it stood still, but the gap was 0.15 m
    pushing = _trace(_line(0, 6, 0.5), np.repeat([[6.5, 0.0]], len(_line(0, 6, 0.5)), axis=0))
    assert _one("stops_when_close", pushing)["passed"] is False
    far = _trace(_line(0, 4, 0.5), np.repeat([[4.0, 5.0]], len(_line(0, 4, 0.5)), axis=0))
    assert _one("stops_when_close", far)["passed"] is None  # nobody came that close: does not apply
    assert _one("keeps_distance", far)["passed"] is True


def test_smooth_braking_and_keeping_its_line() -> None:
    gentle = np.concatenate([_line(0, 3, 1.0), [[3 + sum(1.0 - 0.1 * k for k in range(1, j + 1)) * DT, 0.0]
                                                for j in range(1, 11)]])
    assert _one("smooth_braking", _trace(gentle))["passed"] is True  # 1 m/s^2
    sudden = np.concatenate([_line(0, 3, 1.0), np.repeat([[3.0, 0.0]], 10, axis=0)])
    assert _one("smooth_braking", _trace(sudden))["passed"] is False  # 1 m/s to 0 in one step
    person = np.stack([np.linspace(-3, 8, 81), np.full(81, 1.0)], 1)  # overtakes 1 m to the side
    straight = _trace(_line(0, 8, 1.0), person)
    assert _one("keeps_line", straight)["passed"] is True
    swerve = _line(0, 8, 1.0)
    swerve[30:50, 1] = 0.6
    assert _one("keeps_line", _trace(swerve, person))["passed"] is False


def test_who_reaches_the_place_first() -> None:
    robot = _line(0, 10, 1.0)  # at x = 5 after 5 s
    early = np.stack([np.full(len(robot), 5.0), np.linspace(-3, 7, len(robot))], 1)  # at y 0 after 3 s
    late = np.stack([np.full(len(robot), 5.0), np.linspace(-8, 2, len(robot))], 1)  # after 8 s
    assert _one("lets_person_pass_first", _trace(robot, early), 5 + 0j)["passed"] is True
    assert _one("lets_person_pass_first", _trace(robot, late), 5 + 0j)["passed"] is False
    assert _one("goes_first", _trace(robot, late), 5 + 0j)["passed"] is True


def test_follow_distance_and_the_score_over_the_checks_that_applied() -> None:
    robot = _line(0, 10, 1.0)
    behind = _trace(robot, robot + [-2.0, 0.0])  # 2 m behind: gap 1.25
    assert _one("follow_distance", behind)["passed"] is True
    lost = _trace(robot, np.stack([np.linspace(-2, -5, len(robot)), np.zeros(len(robot))], 1))
    assert _one("follow_distance", lost)["passed"] is False
    checks = [ExpectedCheck(check="follow_distance"), ExpectedCheck(check="slow_near_place")]
    score, details = check_behaviour(behind, checks, None, None)
    assert score == 1.0 and details[1]["passed"] is None  # no place: the second does not count
    assert check_behaviour(behind, [ExpectedCheck(check="slow_near_place")], None, None)[0] is None
