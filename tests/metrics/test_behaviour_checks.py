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
    """`person`: (T, 2) one person, or (T, H, 2) several."""
    t = np.arange(len(robot)) * DT
    humans = np.zeros((len(t), 0, 2)) if person is None else person if person.ndim == 3 else person[:, None, :]
    trace = build_trace(t, robot, humans, dt=DT, goal=tuple(robot[-1]))
    trace.robot_waypoints = waypoints or [tuple(robot[0]), tuple(robot[-1])]
    return trace


def _line(x0: float, x1: float, speed: float, y: float = 0.0) -> np.ndarray:
    x = np.arange(x0, x1 + 1e-9, speed * DT)
    return np.stack([x, np.full_like(x, y)], 1)


def _drive(*legs: tuple[float, float]) -> np.ndarray:
    """Positions along +x driving each (metres, m/s) leg in turn, one step every DT (no jump between legs)."""
    speeds = np.concatenate([np.full(max(1, round(length / (v * DT))), v) for length, v in legs])
    x = np.concatenate([[0.0], np.cumsum(speeds * DT)])
    return np.stack([x, np.zeros_like(x)], 1)


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


def test_slow_near_the_place_is_judged_on_the_approach_not_on_leaving() -> None:
    # home/blind-corner: the robot starts 1.6 m before the corner; slow up to it, at cruise once round it
    slow = _one("slow_near_place", _trace(_drive((1.8, 0.3), (4, 0.6))), 1.6 + 0j)
    assert slow["passed"] is True and slow["value"] == pytest.approx(0.3, abs=0.01)
    late = _drive((1.6, 0.6), (1.4, 0.3), (3, 0.6))  # slows only once past it
    assert _one("slow_near_place", _trace(late), 1.6 + 0j)["passed"] is False
    crawl = _one("slow_near_place", _trace(_drive((6, 0.3))), 3 + 0j)  # slow everywhere is slow there too
    assert crawl["passed"] is True
    brisk = _drive((2.8, 1.2), (2.7, 0.7), (3.5, 1.2))  # 0.7 of its 1.2 m/s by 2 m before the place
    assert _one("slow_near_place", _trace(brisk), 5 + 0j)["passed"] is True
    nearly = _drive((2.8, 1.2), (2.7, 1.0), (3.5, 1.2))  # 1.0 of 1.2 m/s: hardly slower
    assert _one("slow_near_place", _trace(nearly), 5 + 0j)["passed"] is False


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
    assert _one("keeps_distance", stopped)["passed"] is True  # the gap was 0.15 m, but she walked up to it
    pushing = _trace(_line(0, 6, 0.5), np.repeat([[6.5, 0.0]], len(_line(0, 6, 0.5)), axis=0))
    result = _one("stops_when_close", pushing)
    assert result["passed"] is False and result["value"] == pytest.approx(0.5, abs=0.01)
    far = _trace(_line(0, 4, 0.5), np.repeat([[4.0, 5.0]], len(_line(0, 4, 0.5)), axis=0))
    assert _one("stops_when_close", far)["passed"] is None  # nobody came that close: does not apply
    assert _one("keeps_distance", far)["passed"] is True


def test_keeps_distance_is_the_gap_the_robot_drives_at_not_one_a_person_walks_into() -> None:
    robot = _line(0, 8, 0.5)
    n = len(robot)
    standing = np.repeat([[4.0, 0.95]], n, axis=0)  # it drives past her 0.2 m from her shoulder
    brushed = _one("keeps_distance", _trace(robot, standing))
    assert brushed["passed"] is False and brushed["value"] == pytest.approx(0.2, abs=0.01)
    wide = np.repeat([[4.0, 1.5]], n, axis=0)  # 0.75 m
    assert _one("keeps_distance", _trace(robot, wide))["passed"] is True
    back = np.stack([np.linspace(0, -2, n), np.zeros(n)], 1)  # it backs away from someone walking at it
    pressing = np.stack([np.linspace(3, -1.1, n), np.zeros(n)], 1)
    assert _one("keeps_distance", _trace(back, pressing))["passed"] is True
    assert _one("keeps_distance", _trace(robot))["passed"] is None  # nobody there


def test_stops_when_close_counts_the_robots_own_speed_toward_the_person_not_theirs() -> None:
    robot = _line(0, 6, 0.5)  # drives on at 0.5 m/s
    n = len(robot)
    behind = np.stack([np.linspace(-3, 6.5, n), np.zeros(n)], 1)  # a person walks up behind it and into it
    walked_into = _one("stops_when_close", _trace(robot, behind))
    assert walked_into["passed"] is True and walked_into["value"] == 0.0  # it drove away from them
    aside = np.stack([np.linspace(-3, 9, n), np.full(n, 0.8)], 1)  # overtakes 0.05 m beside it
    assert _one("stops_when_close", _trace(robot, aside))["passed"] is True  # it neither turned nor drove at them
    ahead = np.stack([np.linspace(9, 2, n), np.zeros(n)], 1)  # walks at it head-on, and it keeps driving at them
    assert _one("stops_when_close", _trace(robot, ahead))["passed"] is False


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
    assert _one("keeps_line", _trace(swerve, person))["passed"] is False  # 0.6 m toward the overtaker
    aside = _line(0, 8, 1.0)
    aside[30:50, 1] = -0.6  # 0.6 m off its line, away from them: it makes room, as the card asks
    assert _one("keeps_line", _trace(aside, person))["passed"] is True


def test_keeps_line_judges_a_swerve_toward_someone_within_reach_not_making_room_for_an_overtaker() -> None:
    # parallel traffic: someone overtakes 0.2 m off its left shoulder while another walks 2.8 m ahead, 0.75 m right
    # of its route; it moves 0.6 m right to let the overtaker by: making room, though toward the side of the one ahead
    robot = _line(0, 8, 1.0)
    n = len(robot)
    robot[30:60, 1] = -0.6
    overtaker = np.stack([np.linspace(-2, 12, n), np.full(n, 0.95)], 1)  # left of +x travel is +y
    ahead = np.stack([robot[:, 0] + 3.55, np.full(n, -0.75)], 1)  # a 2.8 m gap ahead, 0.75 m right
    both = np.stack([overtaker, ahead], 1)
    assert _one("keeps_line", _trace(robot, both))["passed"] is True
    # a cut-in: it moves 0.6 m right into the lane of someone 1.2 m ahead (a 0.45 m gap) - rude
    close = np.stack([robot[:, 0] + 1.2, np.full(n, -0.75)], 1)
    cut = _one("keeps_line", _trace(robot, np.stack([overtaker, close], 1)))
    assert cut["passed"] is False and cut["value"] == pytest.approx(0.6, abs=0.01)


def test_who_reaches_the_place_first() -> None:
    robot = _line(0, 10, 1.0)  # at x = 5 after 5 s
    early = np.stack([np.full(len(robot), 5.0), np.linspace(-3, 7, len(robot))], 1)  # at y 0 after 3 s
    late = np.stack([np.full(len(robot), 5.0), np.linspace(-8, 2, len(robot))], 1)  # after 8 s
    assert _one("lets_person_pass_first", _trace(robot, early), 5 + 0j)["passed"] is True
    assert _one("lets_person_pass_first", _trace(robot, late), 5 + 0j)["passed"] is False
    assert _one("goes_first", _trace(robot, late), 5 + 0j)["passed"] is True
    # intersection-wait: it stops 0.8 m short of the crossing (inside the 1 m it is judged in) until she is over
    waits = np.concatenate([_line(0, 4.2, 1.0), np.repeat([[4.2, 0.0]], 50, axis=0), _line(4.3, 10, 1.0)])
    crossing = np.stack([np.full(len(waits), 5.0), np.arange(len(waits)) * DT - 7.0], 1)  # over it at 7 s
    assert _one("lets_person_pass_first", _trace(waits, crossing), 5 + 0j)["passed"] is True  # it passes at 9.9 s
    # (by first arrival within 1 m it came first, at 4 s: waiting inside the circle read as going first)
    assert _one("lets_person_pass_first", _trace(robot, crossing[:len(robot)]), 5 + 0j)["passed"] is False


def test_goes_first_without_hesitation_and_never_arriving_is_not_going_first() -> None:
    # intersection-proceed: the person stops 2 m short of the crossing and waves the robot on
    drive = _drive((10, 1.0))
    hesitant = np.concatenate([drive[:36], np.repeat(drive[35:36], 30, axis=0), drive[36:]])  # stands 3 s at x 3.5
    n = len(hesitant)
    waits = np.stack([np.full(n, 5.0), np.minimum(np.linspace(-6, 4, n), -2.0)], 1)
    assert _one("goes_first", _trace(drive, waits[:len(drive)]), 5 + 0j)["passed"] is True
    stood = _one("goes_first", _trace(hesitant, waits), 5 + 0j)
    assert stood["passed"] is False  # it did go first, after standing 3 s 1.5 m before the crossing
    timid = np.repeat([[3.0, 0.0]], 101, axis=0)  # never moves off 2 m before it; the person crosses at last
    crosses = np.stack([np.full(101, 5.0), np.linspace(-6, 4, 101)], 1)
    assert _one("goes_first", _trace(timid, crosses), 5 + 0j)["passed"] is False
    assert _one("lets_person_pass_first", _trace(timid, crosses), 5 + 0j)["passed"] is True
    nobody = np.stack([np.full(101, 5.0), np.full(101, -6.0)], 1)
    assert _one("goes_first", _trace(timid, nobody), 5 + 0j)["passed"] is None  # neither got there


def test_going_first_by_driving_into_the_person_who_waved_it_on_is_not_going_first() -> None:
    # home/intersection-proceed: she stops beside the crossing and waves it on; the rude robot goes first at
    # full speed brushing her (a 0.05 m gap), the polite one goes first as promptly with room
    drive = _drive((10, 1.0))
    n = len(drive)
    brushed = np.stack([np.full(n, 5.7), np.full(n, -0.8)], 1)  # 1.06 m from the crossing; a 0.05 m gap
    rude = _one("goes_first", _trace(drive, brushed), 5 + 0j, within=1.0)
    assert rude["passed"] is False  # though it did pass the place first, promptly
    room = np.stack([np.full(n, 5.7), np.full(n, -1.3)], 1)  # a 0.55 m gap
    assert _one("goes_first", _trace(drive, room), 5 + 0j, within=1.0)["passed"] is True


def test_follow_distance_fails_tailgating_and_losing_the_person() -> None:
    person = _line(2, 12, 1.0)
    robot = _line(0, 10, 1.0)
    assert _one("follow_distance", _trace(robot, person))["passed"] is True  # 2 m behind: gap 1.25
    stopping = person.copy()
    stopping[50:, 0] = stopping[50, 0]  # she stops at x 7; it drives on into her back
    tailgate = _one("follow_distance", _trace(robot, stopping))
    assert tailgate["passed"] is False and tailgate["value"] >= 0.8  # never lost her, but drove into her space
    walks_up = robot.copy()
    walks_up[30:, 0] = walks_up[30, 0]  # it stops at x 3; she walks back to 0.3 m of it: her doing
    back = np.concatenate([person[:30], np.stack([np.linspace(5, 4.05, len(robot) - 30), np.zeros(len(robot) - 30)], 1)])
    assert _one("follow_distance", _trace(walks_up, back))["passed"] is True


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
