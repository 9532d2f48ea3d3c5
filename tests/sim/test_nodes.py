"""Each library node in a small staged situation (semantics: reference §3 + NodeSpec.sim_note)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from socnavgen.bodies import INTIMATE_SPACE, PERSON_ROBOT_GAP, TOUCH_DISTANCE
from socnavgen.run.models import RobotGestureRule
from socnavgen.sim import RobotBody, empty_room, load_policy
from socnavgen.sim.people.leaves import FOLLOW_STOP

from .simhelpers import REGULAR, Drive, Stay, human, make_sim, tree_xml, xy
from .test_people_spots import robot_gaps


def robot_xy(trace, step):  # noqa: ANN001, ANN201
    return complex(trace.robot[step, 0], trace.robot[step, 1])


def test_human_whose_tree_stops_when_the_robot_blocks_it_stops():
    """In a corridor too narrow to pass (1.4 m), a robot standing in it blocks the way: the tree stops the
    person in front of it. In an open room a walker steps around the same robot (people.avoid)."""
    stop_tree = tree_xml('<Fallback><Sequence><IsRobotBlocking agent_id="{id}" distance="2.0"/>'
                         f'<LookAtRobot agent_id="{{id}}"/></Sequence>{REGULAR}</Fallback>')
    robot = [(8.0, 5.0), (9.0, 5.0)]
    corridor = empty_room(20.0, 10.0, walls=[(0.0, 0.0, 20.0, 4.3), (0.0, 5.7, 20.0, 10.0)])
    trace = make_sim([human(start=(2.0, 5.0), goals=[(18.0, 5.0)])], [stop_tree], robot, Stay(), world=corridor,
                     timeout=15).run()
    final = abs(xy(trace, -1) - 8.0 - 5.0j)
    assert 0.9 < final <= 2.05  # stopped in front of the robot, not on it
    assert abs(trace.humans[-1, 0, 3]) < 1e-9 and abs(trace.humans[-1, 0, 4]) < 1e-9
    assert trace.executed(0, "LookAtRobot")[-50:].all()
    assert trace.humans[:, 0, 0].max() < 8.0 - 0.75
    # control: the plain walking tree goes round the same robot in an open room
    walker = make_sim([human(start=(2.0, 5.0), goals=[(18.0, 5.0)])], [tree_xml(REGULAR)], robot, Stay(),
                      timeout=15).run()
    assert walker.humans[-1, 0, 0] > 12.0


def test_human_gives_way_on_excuse_me_steps_aside_then_resumes_to_its_goal():
    tree = tree_xml('<Fallback><Sequence><RobotSays agent_id="{id}" message="4"/>'
                    f'<GiveWaytoRobot agent_id="{{id}}" time_step="{{dt}}"/></Sequence>{REGULAR}</Fallback>')
    rules = [RobotGestureRule(gesture=4, when="blocked", distance=2.0, duration=3.0)]
    sim = make_sim([human(start=(16.0, 5.0), goals=[(3.0, 5.0)])], [tree], [(2.0, 5.0), (18.0, 5.0)],
                   load_policy("waypoints"), rules=rules, timeout=60)
    trace = sim.run()
    gave_way = trace.executed(0, "GiveWaytoRobot")
    assert gave_way.any() and (trace.robot_gesture == 4).any()
    lateral = np.abs(trace.humans[:, 0, 1] - 5.0)
    assert lateral[gave_way].max() > 0.5
    # while the robot drove past the human, the human stood aside
    passing = np.abs(trace.robot[:, 0] - trace.humans[:, 0, 0]) < 0.3
    assert passing.any() and lateral[passing].min() > 0.5 + 1e-9
    assert trace.end_reason == "robot_goal"
    # after the robot passed, the human resumes: keep simulating the humans until they arrive
    for _ in range(int(20 / sim.dt)):
        sim.step()
    assert abs(sim.people[0].pos - (3.0 + 5.0j)) < 0.7


def test_is_robot_visible_needs_line_of_sight_and_distance():
    tree = tree_xml('<Fallback><Sequence><IsRobotVisible agent_id="{id}" distance="{d}"/>'
                    '<MakeGesture agent_id="{id}" message="1"/></Sequence>'
                    '<MakeGesture agent_id="{id}" message="2"/></Fallback>')
    walled = empty_room(20.0, 10.0, walls=[(9.5, 2.0, 10.5, 8.0)])
    open_room = empty_room(20.0, 10.0)
    robot = [(12.0, 5.0), (13.0, 5.0)]

    def gesture(world, distance):  # noqa: ANN001, ANN202
        sim = make_sim([human(start=(8.0, 5.0))], [tree.replace("{d}", str(distance))], robot, Stay(), world=world)
        sim.step()
        return sim.people[0].gesture

    assert gesture(walled, 10) == 2  # 4 m away but behind the wall
    assert gesture(open_room, 10) == 1
    assert gesture(open_room, 3.5) == 2  # in sight but too far
    # IsRobotNearby ignores the wall
    nearby = tree.replace("IsRobotVisible", "IsRobotNearby").replace("{d}", "10")
    sim = make_sim([human(start=(8.0, 5.0))], [nearby], robot, Stay(), world=walled)
    sim.step()
    assert sim.people[0].gesture == 1


def test_time_expired_once_and_periodic():
    once = tree_xml('<Fallback><Sequence><Inverter><TimeExpiredCondition seconds="2" ts="{dt}" only_once="true"/>'
                    '</Inverter><MakeGesture agent_id="{id}" message="1"/></Sequence>'
                    '<MakeGesture agent_id="{id}" message="2"/></Fallback>')
    trace = make_sim([human()], [once], [(10.0, 5.0), (11.0, 5.0)], timeout=5).run()
    switch = int(np.argmax(trace.human_gesture[:, 0] == 2))
    assert trace.human_gesture[1:switch, 0].tolist() == [1] * (switch - 1)
    assert trace.t[switch] == pytest.approx(2.0, abs=0.051)
    assert (trace.human_gesture[switch:, 0] == 2).all()  # only_once: never again
    periodic = tree_xml('<TimeExpiredCondition seconds="1" ts="{dt}" only_once="false"/>')
    trace = make_sim([human()], [periodic], [(10.0, 5.0), (11.0, 5.0)], timeout=5).run()
    fired = np.flatnonzero(trace.fired(0, "TimeExpiredCondition"))
    assert len(fired) in (4, 5) and set(np.diff(fired).tolist()) <= {19, 20, 21}
    assert trace.t[fired[0]] == pytest.approx(1.0, abs=0.051)


def test_follow_robot_keeps_about_one_and_a_half_metres():
    """The follower closes the 7 m gap at their own pace (not 0.18 m/s per metre: well within 10 s) and stands
    FOLLOW_STOP from the robot, never stepping into its intimate space."""
    tree = tree_xml('<FollowRobot agent_id="{id}" time_step="{dt}"/>')
    trace = make_sim([human(start=(3.0, 5.0))], [tree], [(10.0, 5.0), (11.0, 5.0)], Stay(), timeout=20).run()
    d = np.abs(trace.humans[:, 0, 0] + 1j * trace.humans[:, 0, 1] - (10 + 5j))
    assert FOLLOW_STOP - 0.15 <= d[-1] <= FOLLOW_STOP + 0.2
    assert d[trace.t <= 8.0].min() <= FOLLOW_STOP + 0.2
    assert d.min() - TOUCH_DISTANCE >= INTIMATE_SPACE
    to_robot = (10 + 5j) - xy(trace, -1)
    assert trace.humans[-1, 0, 2] == pytest.approx(math.atan2(to_robot.imag, to_robot.real), abs=1e-6)


def test_follow_human_stops_near_the_target():
    trees = [tree_xml('<MakeGesture agent_id="{id}" message="0"/>'),
             tree_xml('<FollowHuman agent_id="{id}" target_id="0" time_step="{dt}"/>')]
    sim = make_sim([human(start=(12.0, 5.0)), human("human2", start=(3.0, 5.0))], trees, [(10.0, 8.0), (11.0, 8.0)],
                   timeout=20)
    trace = sim.run()
    d = abs(xy(trace, -1, 1) - xy(trace, -1, 0))
    assert FOLLOW_STOP - 0.15 <= d <= FOLLOW_STOP + 0.2


def test_block_robot_ends_up_in_front_of_the_robot():
    tree = tree_xml('<BlockRobot agent_id="{id}" time_step="{dt}"/>')
    trace = make_sim([human(start=(7.0, 8.0))], [tree], [(10.0, 5.0), (12.0, 5.0)], Stay(), timeout=25).run()
    assert abs(xy(trace, -1) - (11.5 + 5.0j)) < 0.5
    assert trace.behavior_state[-1, 0] == 1


def test_a_blocker_at_her_block_point_stands():
    """A person blocking a robot that stands still stands at her block point (a 1 s standoff needs her slower than
    0.1 m/s): the robot's social force pushed her off the 0.05 m point and her walk pulled her back, so she hovered
    round it at 0.03-0.07 m/s for good (home_01's child, 0.04-0.11 m/s)."""
    tree = tree_xml('<BlockRobot agent_id="{id}" time_step="{dt}"/>')
    trace = make_sim([human(start=(7.0, 8.0))], [tree], [(10.0, 5.0), (12.0, 5.0)], Stay(), timeout=25).run()
    speed = np.hypot(trace.humans[:, 0, 3], trace.humans[:, 0, 4])
    arrived = int(np.argmax(np.abs(trace.humans[:, 0, 0] + 1j * trace.humans[:, 0, 1] - (11.5 + 5.0j)) < 0.05))
    assert 0 < arrived < len(speed) - int(5.0 / trace.dt), "she never got to her block point"
    settled = arrived + int(3.0 / trace.dt)  # arriving at her walking speed, she has stopped 3 s later (was 0.074)
    assert speed[settled:].max() < 0.01, speed[settled:].max()
    assert abs(xy(trace, -1) - (11.5 + 5.0j)) < 0.1


def test_a_blocker_going_round_the_robot_keeps_a_gap_that_does_not_read_as_touching():
    """A blocker coming from behind the robot's side goes round its body to her point in front of it at
    PERSON_ROBOT_GAP from it at the least: walking to the robot (following, blocking), a person's own step kept only
    0.1 m from it (home_01's child 0.107 m, hospital_08's nurse 0.100 m: touching to the eyes)."""
    tree = tree_xml('<BlockRobot agent_id="{id}" time_step="{dt}"/>')
    trace = make_sim([human(start=(8.6, 5.9))], [tree], [(10.0, 5.0), (12.0, 5.0)], Stay(), timeout=15).run()
    assert robot_gaps(trace).min() >= PERSON_ROBOT_GAP - 1e-3, robot_gaps(trace).min()
    assert abs(xy(trace, -1) - (11.5 + 5.0j)) < 0.3  # and she got round to it


def test_run_away_from_robot_moves_away_slowly():
    run_away = tree_xml('<RunAwayFromRobot agent_id="{id}" time_step="{dt}"/>')
    trace = make_sim([human(start=(8.0, 5.0), goals=[(8.0, 5.0)])], [run_away], [(7.0, 5.0), (6.0, 5.0)],
                     timeout=3).run()
    assert abs(xy(trace, -1) - (7 + 5j)) > 2.0
    speed = np.hypot(trace.humans[:, 0, 3], trace.humans[:, 0, 4])
    assert speed.max() <= 0.6 + 1e-9


def test_look_at_robot_turns_without_moving():
    tree = tree_xml('<LookAtRobot agent_id="{id}"/>')
    sim = make_sim([human(start=(2.0, 5.0), yaw=0.0)], [tree], [(2.0, 8.0), (3.0, 8.0)])
    sim.step()
    sim.step()
    assert sim.people[0].yaw == pytest.approx(math.pi / 2)
    assert sim.people[0].pos == 2.0 + 5.0j and sim.people[0].vel == 0


def test_gestures_both_ways():
    trees = [tree_xml('<MakeGesture agent_id="{id}" message="3"/>'),
             tree_xml('<Fallback><Sequence><HumanSays agent_id="{id}" target_id="0" message="3"/>'
                      '<MakeGesture agent_id="{id}" message="1"/></Sequence>'
                      '<MakeGesture agent_id="{id}" message="0"/></Fallback>'),
             tree_xml('<Fallback><Sequence><RobotSays agent_id="{id}" message="4"/>'
                      '<MakeGesture agent_id="{id}" message="2"/></Sequence>'
                      '<MakeGesture agent_id="{id}" message="0"/></Fallback>')]
    people = [human(), human("human2", start=(3.0, 3.0)), human("human3", start=(3.0, 7.0))]
    sim = make_sim(people, trees, [(10.0, 5.0), (11.0, 5.0)], Drive(0.0, 0.0, gesture=4))
    sim.step()
    assert list(sim.people.gesture[:2]) == [3, 1]  # human2 saw human1's gesture
    sim.step()
    assert sim.people[2].gesture == 2  # the robot's EXCUSE ME reached human3


@pytest.mark.parametrize(("policy", "expected"), [(Drive(-0.8, 0.0), 2), (Stay(), 0), (Drive(0.05, 0.05), 0)])
def test_robot_moved_uses_speed(policy, expected):
    tree = tree_xml('<Fallback><Sequence><RobotMoved agent_id="{id}"/><MakeGesture agent_id="{id}" message="2"/>'
                    '</Sequence><MakeGesture agent_id="{id}" message="0"/></Fallback>')
    instant = RobotBody(kinematics="holonomic", max_accel=100.0, max_decel=100.0)  # the node, not the body, on test
    sim = make_sim([human()], [tree], [(10.0, 5.0), (11.0, 5.0)], policy, body=instant)
    sim.step()
    sim.step()
    assert sim.people[0].gesture == expected


def test_goal_queue_rules():
    """UpdateGoal pops the front but keeps the last goal (fork rule); the walking step consumes a goal reached
    inside its radius, the last one too; a cyclic queue re-appends what it pops; IsGoalReached is radius +
    0.1 m."""
    from socnavgen.sim.people.state import goal_reached, new_people, pop_goal

    def queue(goals, cyclic=False):  # noqa: ANN001, ANN202
        people, rings, _ = new_people([human(goals=[(g.real, g.imag) for g in goals], cyclic=cyclic)])
        return people, rings

    def front_to_back(people, rings):  # noqa: ANN001, ANN202
        p = people[0]
        return [complex(rings[0, (p.queue_start + j) % rings.shape[1]]) for j in range(p.queue_count)]

    g = [1 + 0j, 2 + 0j, 3 + 0j]
    people, rings = queue(g)
    pop_goal(people, rings, 0, True)
    assert front_to_back(people, rings) == g[1:] and people[0].goal == g[1]
    pop_goal(people, rings, 0, True)
    pop_goal(people, rings, 0, True)
    assert front_to_back(people, rings) == [3 + 0j]  # the last goal is kept (fork rule)
    pop_goal(people, rings, 0, False)
    assert front_to_back(people, rings) == [] and not people[0].has_goal  # the walking step may consume it
    people, rings = queue([g[0]], cyclic=True)
    pop_goal(people, rings, 0, True)
    assert front_to_back(people, rings) == [g[0], g[0]]
    people, rings = queue(g, cyclic=True)
    pop_goal(people, rings, 0, True)
    assert front_to_back(people, rings) == [g[1], g[2], g[0]]
    pop_goal(people, rings, 0, False)
    assert front_to_back(people, rings) == [g[2], g[0], g[1]]
    people, rings = queue([3 + 0j])
    people[0].pos = 3.55 + 0j
    assert goal_reached(people, rings, 0)
    people[0].pos = 3.65 + 0j
    assert not goal_reached(people, rings, 0)


def test_walker_visits_its_goals_in_order_and_freezes_at_the_last():
    goals = [(6.0, 2.0), (6.0, 7.0), (12.0, 7.0)]
    sim = make_sim([human(start=(2.0, 2.0), goals=goals)], [tree_xml(REGULAR)], [(18.0, 2.0), (19.0, 2.0)],
                   timeout=25)
    trace = sim.run()
    path = trace.humans[:, 0, :2]
    first = [int(np.argmin(np.hypot(*(path - np.array(gl)).T))) for gl in goals]
    assert first == sorted(first)
    assert np.hypot(*(path[-1] - np.array(goals[-1]))) <= 0.6 + 1e-9
    assert np.abs(trace.humans[-5:, 0, :2] - trace.humans[-1, 0, :2]).max() < 1e-9  # frozen in the band
    # nothing will change any more (human done, robot idle for 10 s): the run ends early
    assert trace.end_reason == "all_done" and trace.t[-1] < 24


def test_give_way_steps_to_the_free_side_when_a_wall_is_on_its_side():
    # corridor y in [3, 7]; the human is slightly left of the robot's path (y 5.2) but a wall box fills y > 5.9
    world = empty_room(20.0, 10.0, walls=[(0.0, 0.0, 20.0, 3.0), (0.0, 5.9, 20.0, 10.0)])
    tree = tree_xml('<GiveWaytoRobot agent_id="{id}" time_step="{dt}"/>')
    sim = make_sim([human(start=(10.0, 5.2), goals=[(2.0, 5.2)])], [tree], [(6.0, 5.0), (18.0, 5.0)], Stay(),
                   world=world)
    for _ in range(60):
        sim.step()
    y = sim.people[0].pos.imag
    assert y < 5.0 - 0.5  # went to the right-hand side, where there is room
    assert sim.world.clearance_at(sim.people[0].pos)[0] >= 0.4 - 1e-6


@pytest.mark.parametrize(("robot_at", "walls", "expected"), [
    ((10.0, 5.0), [], 1),  # straight ahead, 2 m
    ((8.0, 7.0), [], 0),  # 2 m to the left: outside the 0.5 rad cone
    ((10.0, 5.0), [(8.8, 3.0, 9.2, 7.0)], 0),  # ahead but behind a wall
    ((13.0, 5.0), [], 0),  # ahead but beyond `distance`
])
def test_is_robot_blocking_cone_distance_and_sight(robot_at, walls, expected):
    tree = tree_xml('<Fallback><Sequence><IsRobotBlocking agent_id="{id}" distance="3"/>'
                    '<MakeGesture agent_id="{id}" message="1"/></Sequence></Fallback>')
    world = empty_room(20.0, 10.0, walls=walls)
    sim = make_sim([human(start=(8.0, 5.0), yaw=0.0)], [tree], [robot_at, (robot_at[0] + 1, robot_at[1])],
                   world=world)
    sim.step()
    assert sim.people[0].gesture == expected


def test_make_gesture_zero_holds_a_walking_person_still():
    """The tree tutorial's claim (bt_examples.yaml: MakeGesture 0 'keeps it standing still'): a person walking
    (RegularNav) whose tree then ticks only MakeGesture 0 stands at once (zero velocity, like LookAtRobot), so the
    verifier's stop evidence (slower than STOP_SPEED for STOP_HOLD after having walked MOVED_DISTANCE) shows."""
    from socnavgen.verify.thresholds import MOVED_DISTANCE, STOP_HOLD, STOP_SPEED

    walk_then_hold = tree_xml('<Fallback><Sequence><Inverter><TimeExpiredCondition seconds="2" ts="{dt}" '
                              f'only_once="true"/></Inverter>{REGULAR}</Sequence>'
                              '<MakeGesture agent_id="{id}" message="0"/></Fallback>')
    trace = make_sim([human(start=(2.0, 5.0), goals=[(18.0, 5.0)])], [walk_then_hold], [(10.0, 9.0), (11.0, 9.0)],
                     Stay(), timeout=5).run()
    speed = np.hypot(trace.humans[:, 0, 3], trace.humans[:, 0, 4])
    held = trace.t >= 2.1
    assert speed[(trace.t > 1.0) & (trace.t < 1.9)].min() > 0.5  # it walked
    assert abs(xy(trace, -1) - 2.0 - 5.0j) >= MOVED_DISTANCE and speed[held].max() < STOP_SPEED
    assert trace.t[-1] - 2.1 >= STOP_HOLD and trace.executed(0, "MakeGesture")[held].all()
