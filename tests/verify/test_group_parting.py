"""A group that parts to let the robot through is still a group (hospital_08 of the new-request suite: two nurses
stepped aside to opposite sides of the robot, 3.34 m apart for a moment, and closed up again): group_together
judges cohesion outside the steps the robot is between them or one gives way, and while they close up again
after it; a member who leaves, or a pair that splits with no robot between them, still fails."""

from __future__ import annotations

import numpy as np

from socnavgen.run.spec import Criterion, ScenarioSpec
from socnavgen.verify.criteria import compile_criterion
from socnavgen.verify.models import VerifySettings
from socnavgen.verify.signals import Signals
from socnavgen.verify.stl import monitor

from .verify_builders import build_trace

T = np.arange(0, 24.0 + 1e-9, 0.1)


def _together(robot_x: list[float], north: tuple[list[float], list[float]],
              south: tuple[list[float], list[float]]) -> bool:
    """The robot drives along y = 3 (x at times 0, 8, 12, 24: robot_x); human1 / human2 stand at x = 5 and
    move in y at the times and to the ys given (`north`, `south`: times, ys)."""
    robot = np.stack([np.interp(T, [0, 8, 12, 24], robot_x), np.full_like(T, 3.0)], 1)
    humans = np.stack([np.stack([np.full_like(T, 5.0), np.interp(T, *who)], 1) for who in (north, south)], 1)
    trace = build_trace(T, robot, humans, dt=0.1, groups=[0, 0])
    cc = compile_criterion(Criterion(id="c", kind="group_together", humans=["human1", "human2"], distance=3.0,
                                     text="t"), ScenarioSpec(), VerifySettings(), 0.2)
    return monitor(cc.formula, Signals(trace)).passed


PASSING = [0.0, 4.0, 6.0, 12.0]  # the robot reaches the pair at ~8 s and is past them at ~12 s
APART_N, APART_S = ([0, 7, 8, 12, 14], [3.6, 3.6, 4.7, 4.7, 3.6]), ([0, 7, 8, 12, 14], [2.4, 2.4, 1.3, 1.3, 2.4])


def test_a_pair_parting_for_the_robot_and_closing_again_is_a_group():
    assert _together(PASSING, APART_N, APART_S)  # 3.4 m apart while the robot drives between them


def test_a_member_who_leaves_after_the_robot_passed_or_a_split_without_the_robot_is_not():
    leaves = ([0, 7, 8, 12, 20], [3.6, 3.6, 4.7, 4.7, 9.0])  # north keeps walking away after the robot passed
    assert not _together(PASSING, leaves, APART_S)
    assert not _together([0.0, 0.0, 0.0, 0.0], APART_N, APART_S)  # parted with the robot far away
    stays = ([0, 7, 8], [3.6, 3.6, 4.7])  # they never close up again after it has passed
    assert not _together(PASSING, stays, ([0, 7, 8], [2.4, 2.4, 1.3]))


def _swinging(swing: tuple[float, float]) -> bool:
    """The robot stands at (2.5, 3) facing the pair until t = 10 s, then drives between them (x 8 by 14 s); the pair
    at x = 5 steps apart from 1.2 m to 3.8 m at t = 7-9 s, stands apart, and closes up again at t = 12.5-14.5 s. While
    `swing` (t from, to) the robot's heading swings 1 rad off them (the gap is then not ahead of it)."""
    robot = np.stack([np.interp(T, [0, 10, 14, 24], [2.5, 2.5, 8.0, 12.0]), np.full_like(T, 3.0)], 1)
    ys = [np.interp(T, [0, 7, 9, 12.5, 14.5, 24], [3.0 + d * k for k in (0.6, 0.6, 1.9, 1.9, 0.6, 0.6)]) for d in (1, -1)]
    humans = np.stack([np.stack([np.full_like(T, 5.0), y], 1) for y in ys], 1)
    trace = build_trace(T, robot, humans, dt=0.1, groups=[0, 0])
    start, end = swing
    t = trace.t
    trace.robot[:, 2] = np.where((t >= start) & (t < end), 1.0, 0.0)
    cc = compile_criterion(Criterion(id="c", kind="group_together", humans=["human1", "human2"], distance=2.5,
                                     text="t"), ScenarioSpec(), VerifySettings(), 0.2)
    return monitor(cc.formula, Signals(trace)).passed


def test_a_parting_goes_on_while_the_robots_heading_swings_off_for_a_moment():
    assert _swinging((8.2, 8.6))  # still stepping apart (2.8 m) with the gap 0.4 s off its heading


def test_a_pair_that_splits_while_the_robot_looks_away_is_no_parting():
    assert not _swinging((0.0, 10.0))  # the gap never ahead of it while they split: no parting for it


TB = np.arange(0, 24.0 + 1e-9, 0.1)


def _beside_next_leg(closes_at: float) -> bool:
    """warehouse_08's shape: the robot drives east along y = 3 to (5, 3) by t = 10 s, then north along x = 5 (its
    route turns there); human1 stands at (6.3, 2.2); human2 stands on the north leg at (5, 4) and steps aside to
    (6.5, 4.9) at t = 7-8 s, beside that leg, 2.7 m from human1, waits there until the robot has gone by her
    (y 4.9 at t = 12 s) and closes up to (6, 3.6) from t = closes_at for 1 s."""
    rx = np.where(TB < 10.0, 0.5 * TB, 5.0)
    ry = np.where(TB < 10.0, 3.0, np.interp(TB, [10, 14, 24], [3.0, 6.8, 10.0]))
    h2 = np.stack([np.interp(TB, [0, 7, 8, closes_at, closes_at + 1, 24], x) for x in
                   ([5.0, 5.0, 6.5, 6.5, 6.0, 6.0], [4.0, 4.0, 4.9, 4.9, 3.6, 3.6])], 1)
    humans = np.stack([np.tile([[6.3, 2.2]], (len(TB), 1)), h2], 1)
    trace = build_trace(TB, np.stack([rx, ry], 1), humans, dt=0.1, groups=[0, 0], goal=(5.0, 10.0))
    trace.robot[:, 2] = np.where(TB < 10.0, 0.0, np.pi / 2)
    trace.robot_waypoints = [(0.0, 3.0), (5.0, 3.0), (5.0, 10.0)]
    cc = compile_criterion(Criterion(id="c", kind="group_together", humans=["human1", "human2"], distance=2.5,
                                     text="t"), ScenarioSpec(), VerifySettings(), 0.2)
    return monitor(cc.formula, Signals(trace)).passed


def test_a_member_waiting_beside_the_robots_next_leg_until_it_has_gone_by_is_parting():
    assert _beside_next_leg(12.5)  # closes up 0.5 s after the robot went by her


def test_a_member_who_stays_apart_after_the_robot_went_by_is_not():
    assert not _beside_next_leg(16.0)  # still 2.7 m apart 4 s after it went by


def _edge_of_the_aisle(resumes_at: float) -> bool:
    """warehouse_05's shape (first answer): the robot sweeps east along y = 3 at 0.5 m/s; a pair on its way (x 5 and
    6.5) steps north to the aisle edge (y 4.3) at t = 2-3 s. human1, gone by first, walks on west at 0.8 m/s from
    t = 12 s; human2 stands until `resumes_at`, then walks west at 1.2 m/s after her. The simulator's giver-way
    stands until the robot has gone by (its spot + both radii + give_way.PASSED_MARGIN: x 7.55, t 15.1 s)."""
    def walk(x0: float, y_aside: float, start: float, speed: float) -> np.ndarray:
        x = np.where(start > TB, x0, x0 - speed * (TB - start))
        return np.stack([x, np.interp(TB, [0, 2, 3, 24], [3.0, 3.0, y_aside, y_aside])], 1)

    humans = np.stack([walk(5.0, 4.3, 12.0, 0.8), walk(6.5, 4.3, resumes_at, 1.2)], 1)
    trace = build_trace(TB, np.stack([0.5 * TB, np.full_like(TB, 3.0)], 1), humans, dt=0.1, groups=[0, 0],
                        goal=(12.0, 3.0))
    trace.robot_waypoints = [(0.0, 3.0), (12.0, 3.0)]
    cc = compile_criterion(Criterion(id="c", kind="group_together", humans=["human1", "human2"], distance=2.5,
                                     text="t"), ScenarioSpec(), VerifySettings(), 0.2)
    return monitor(cc.formula, Signals(trace)).passed


def test_a_member_standing_aside_until_the_robot_has_gone_by_her_is_parting():
    # level with her at 13 s, gone by (a body length on) at 15.1 s: she walks after the other at 15 s, 3.5 m apart
    assert _edge_of_the_aisle(15.0)


def test_a_member_standing_on_after_the_robot_has_gone_by_her_is_not():
    assert not _edge_of_the_aisle(18.0)  # still standing 3 s after it went by, the other 5 m off
