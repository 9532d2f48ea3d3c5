"""Arriving short of a goal someone stands at (proxemics.short_of_goal): the robot that stops at a social
distance from a person standing on its goal has arrived; one driving past, stopping in another room, or
stopping near a person who walks on has not."""

from __future__ import annotations

import numpy as np

from socnavgen.run.spec import Criterion, ScenarioSpec
from socnavgen.verify.criteria import compile_criterion
from socnavgen.verify.models import VerifySettings
from socnavgen.verify.signals import Signals
from socnavgen.verify.stl import monitor

from .verify_builders import build_trace

T = np.arange(0, 20.0 + 1e-9, 0.5)
GOAL = (11.0, 3.0)


def _reaches_goal(robot_stop_x: float, person_xy=(11.0, 3.0), person_walks: bool = False,  # noqa: ANN001
                  robot_moves: tuple[list[float], list[float], list[float]] | None = None, world=None) -> bool:
    """The robot drives +x from x = 1 and stands at robot_stop_x from t = 10 s (or moves through `robot_moves`:
    times, xs, ys), along its one leg (1, 3) -> GOAL; human1 stands at person_xy (or walks +y past it at
    0.5 m/s); `world`: the walls (None: none known)."""
    times, xs, ys = robot_moves or ([0, 10, 20], [1.0, robot_stop_x, robot_stop_x], [3.0, 3.0, 3.0])
    robot = np.stack([np.interp(T, times, xs), np.interp(T, times, ys)], 1)
    human = np.tile([person_xy], (len(T), 1)).astype(float)
    if person_walks:
        human[:, 1] += 0.5 * (T - 10.0)
    trace = build_trace(T, robot, human[:, None], goal=GOAL)
    trace.robot_waypoints = [(1.0, 3.0), GOAL]
    cc = compile_criterion(Criterion(id="c", kind="robot_reaches_goal", text="t"), ScenarioSpec(), VerifySettings(),
                           0.2)
    return monitor(cc.formula, Signals(trace, goal_radius=0.2, world=world)).passed


def test_stopping_at_a_social_distance_from_someone_on_the_goal_is_arriving():
    assert _reaches_goal(11.0 - 0.75 - 1.2)  # gap 1.2 m (centres 1.95 m), standing
    assert "short_of_goal" in compile_criterion(Criterion(id="c", kind="robot_reaches_goal", text="t"),
                                                ScenarioSpec(), VerifySettings(), 0.2).formula


def test_stopping_too_far_or_beside_a_walker_or_for_nobody_is_not_arriving():
    assert not _reaches_goal(11.0 - 0.75 - 1.6)  # gap 1.6 m: still short of the social distance
    assert not _reaches_goal(11.0 - 0.75 - 1.2, person_walks=True)  # they walk away: the goal is free
    assert not _reaches_goal(11.0 - 0.75 - 1.2, person_xy=(11.0, 13.0))  # nobody near the goal
    # the person stands 1.5 m beyond the goal (next to it); the robot 2.9 m short of it (gap 1.2 m to them,
    # but too far from its own goal: in the room before theirs)
    assert not _reaches_goal(12.5 - 0.75 - 1.2 - 1.0, person_xy=(12.5, 3.0))


def test_the_scripted_robot_stops_short_of_someone_standing_on_its_goal_and_has_arrived():
    from socnavgen.sim import load_policy
    from tests.sim.simhelpers import human, make_sim, tree_xml

    stand = tree_xml('<LookAtRobot agent_id="{id}"/>')
    person = human(start=(12.0, 5.0), goals=[(12.0, 5.0)])
    trace = make_sim([person], [stand], [(2.0, 5.0), (12.0, 5.0)], load_policy("scripted")).run()
    assert trace.end_reason == "robot_goal"
    gap = np.hypot(*(trace.humans[-1, 0, :2] - trace.robot[-1, :2])) - 0.75
    assert 1.05 <= gap <= 1.35  # outside personal space, about 2 m centre to centre
    assert Signals(trace, goal_radius=0.2).get("short_of_goal")[-1] == 1.0


def test_a_robot_nearer_its_goal_than_the_person_is_not_short_of_it():
    # the person stands 1.4 m before a goal the robot (0.5 m from it) has not moved to: not an arrival
    assert not _reaches_goal(10.5, person_xy=(9.6, 3.0))


def test_a_robot_parked_beside_a_doorway_goal_behind_the_wall_has_not_arrived():
    # home_04: the goal is a 0.9 m doorway (x = 11, y 2.55-3.45) in a wall, the child stands just inside the
    # room beyond it; the robot parked in the corridor corner beside the door (1.21 m from the goal, 1.23 m gap
    # to the child) sees only the wall: not arrived. The same spot without the wall, or a stop on its way in
    # front of the door seeing the child through it, is an arrival.
    from socnavgen.sim import empty_room

    wall = empty_room(20.0, 10.0, walls=[(10.9, 0.0, 11.1, 2.55), (10.9, 3.45, 11.1, 10.0)])
    child = (11.9, 3.3)
    corner = ([0, 8, 10, 20], [1.0, 9.0, 10.5, 10.5], [3.0, 3.0, 1.9, 1.9])
    assert not _reaches_goal(0.0, person_xy=child, robot_moves=corner, world=wall)
    assert _reaches_goal(0.0, person_xy=child, robot_moves=corner, world=empty_room(20.0, 10.0))
    assert _reaches_goal(9.95, person_xy=child, world=wall)


def test_a_robot_pausing_short_of_its_goal_for_a_moment_and_driving_off_has_not_arrived():
    # it stands 1 s at a social distance from the person on its goal, then drives away sideways: the
    # simulator ends a run only after GOAL_STOP_DWELL standing there, and so do the verifier and the metrics
    stop = 11.0 - 0.75 - 1.2
    assert not _reaches_goal(0.0, robot_moves=([0, 10, 11, 20], [1.0, stop, stop, stop], [3.0, 3.0, 3.0, 0.0]))
    assert _reaches_goal(0.0, robot_moves=([0, 10, 14, 20], [1.0, stop, stop, stop], [3.0, 3.0, 3.0, 0.0]))


def test_stopping_short_where_a_nearer_spot_keeps_as_far_from_everyone_is_not_arriving():
    # hospital_04: a robot parked 1.6 m off its goal, 1.14 m (gap) from a person standing 1 m beside the goal, while
    # the other side of the goal (1 m south of it) is free and as far from them: the people leave room nearer, so
    # it has not arrived (sim.arrival.no_nearer_spot). With a wall filling that side, stopping there is arriving.
    from socnavgen.sim import empty_room

    beside = ([0, 10, 20], [1.0, 9.4, 9.4], [3.0, 3.0, 3.0])
    assert not _reaches_goal(0.0, person_xy=(11.0, 4.0), robot_moves=beside)
    assert not _reaches_goal(0.0, person_xy=(11.0, 4.0), robot_moves=beside, world=empty_room(20.0, 10.0))
    walled = empty_room(20.0, 10.0, walls=[(9.9, 0.0, 20.0, 2.6)])  # everything south of y 2.6 east of the robot
    assert _reaches_goal(0.0, person_xy=(11.0, 4.0), robot_moves=beside, world=walled)
