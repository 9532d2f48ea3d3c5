"""The default (waypoints) robot and GiveWaytoRobot in the situations that used to deadlock: a wall corner on
the robot's line, a person who just stands in the way, and a person giving way next to a turn of the
robot's path."""

from __future__ import annotations

import numpy as np

from socnavgen.bodies import ROBOT_RADIUS
from socnavgen.sim import empty_room, load_policy
from tests.sim.simhelpers import Stay, human, make_sim, tree_xml

STAND = tree_xml('<LookAtRobot agent_id="{id}"/>')  # a person who never moves, only faces the robot
# the deadlock of the brief: the person stands still while the robot blocks it
STAND_WHILE_BLOCKED = tree_xml('<Fallback><Sequence><IsRobotBlocking agent_id="{id}" distance="3.0"/>'
                               '<LookAtRobot agent_id="{id}"/></Sequence>'
                               '<LookAtRobot agent_id="{id}"/></Fallback>')


def _gaps(trace) -> np.ndarray:  # noqa: ANN001
    """Robot-human gap between the discs, (steps, humans)."""
    centre = np.hypot(*(trace.humans[:, :, :2] - trace.robot[:, None, :2]).transpose(2, 0, 1))
    return centre - trace.robot_radius - np.asarray(trace.human_radii)[None, :]


def test_robot_slides_along_a_wall_corner_on_its_line():
    # a wall block whose top corner is 0.1 m below the robot's straight line (y = 5): the disc (0.35 m) hits it
    world = empty_room(14.0, 10.0, walls=[(6.0, 0.0, 7.0, 4.9)])
    sim = make_sim([], [], [(1.0, 5.0), (12.0, 5.0)], load_policy("waypoints"), world=world, timeout=60)
    trace = sim.run()
    assert trace.end_reason == "robot_goal"
    xy = trace.robot[:, 0] + 1j * trace.robot[:, 1]
    clearance = world.clearance_at(xy)
    assert clearance.min() >= 0.5 * ROBOT_RADIUS  # never into the wall
    passing = (trace.robot[:, 0] > 6.0) & (trace.robot[:, 0] < 7.0)
    assert trace.robot[passing, 1].min() > 5.0  # it went over the corner, along the wall


def test_slide_removes_only_the_part_of_the_velocity_into_the_wall():
    from socnavgen.sim.robot.policies import slide_along_walls

    world = empty_room(10.0, 10.0, walls=[(0.0, 0.0, 10.0, 4.0)])  # wall surface at y = 4
    sim = make_sim([], [], [(5.0, 4.3), (9.0, 4.3)], Stay(), world=world)
    v = slide_along_walls(sim.state, 0.4 - 0.3j)  # forward and down into the wall
    assert v.real > 0.3 and v.imag >= 0.0  # the forward part is kept (the wall normal is per map cell), none goes in
    away = slide_along_walls(sim.state, 0.4 + 0.2j)  # moving away from the wall: kept (plus a push out of it)
    assert abs(away.real - 0.4) < 0.05 and away.imag >= 0.2
    free = slide_along_walls(sim.state, 0.4 + 0.0j)  # along the wall, clear of it: unchanged
    sim.robot.pos = 5.0 + 6.0j
    assert slide_along_walls(sim.state, 0.4 - 0.3j) == 0.4 - 0.3j and abs(free.real - 0.4) < 0.05


def _standing_run(tree: str, start=(10.0, 5.1), path=((2.0, 5.0), (18.0, 5.0)), world=None):  # noqa: ANN001, ANN202
    sim = make_sim([human(start=start, goals=[start])], [tree], list(path), load_policy("waypoints"), world=world,
                   timeout=90)
    return sim.run()


def test_robot_edges_past_a_person_standing_in_its_way():
    for tree in (STAND, STAND_WHILE_BLOCKED):
        trace = _standing_run(tree)
        assert trace.end_reason == "robot_goal"
        assert _gaps(trace)[:, 0].min() > -0.05  # no collision (the verifier's overlap threshold)
        speed = np.hypot(trace.robot[:, 3], trace.robot[:, 4])
        assert speed[(trace.robot[:, 0] > 7.0) & (trace.robot[:, 0] < 10.0)].min() < 0.3  # it slowed down
        if tree == STAND:  # not blocking on purpose, they make room once the robot has waited (people.make_room)
            assert (trace.behavior_state[:, 0] == 2).any()
            continue
        beside = np.abs(trace.robot[:, 0] - 10.0) < 0.2
        assert np.abs(trace.robot[beside, 1] - 5.1).min() > 0.7  # went around, not through


def test_robot_waits_then_drives_around_when_it_cannot_edge_aside():
    # a wall 0.6 m below the robot's line leaves no room to edge away from the person (who stands 0.2 m above
    # the line); there is room above the person: after waiting, the robot drives around over the top
    world = empty_room(20.0, 10.0, walls=[(0.0, 0.0, 20.0, 3.5)])
    for tree in (STAND, STAND_WHILE_BLOCKED):
        trace = _standing_run(tree, start=(10.0, 4.3), path=((2.0, 4.1), (18.0, 4.1)), world=world)
        assert trace.end_reason == "robot_goal"
        assert _gaps(trace)[:, 0].min() > -0.05
        speed = np.hypot(trace.robot[:, 3], trace.robot[:, 4])
        stopped = (speed < 0.05) & (trace.robot[:, 0] < 10.0) & (trace.t > 1.0)
        assert stopped.sum() * trace.dt >= 1.5  # it waited behind the person first
        beside = np.abs(trace.robot[:, 0] - 10.0) < 0.2
        if tree == STAND:  # not blocking on purpose, they make room once the robot has waited (people.make_room)
            assert (trace.behavior_state[:, 0] == 2).any()
        else:
            assert trace.robot[beside, 1].min() > 4.3 + 0.7  # passed above the person
        xy = trace.robot[:, 0] + 1j * trace.robot[:, 1]
        assert world.clearance_at(xy).min() >= 0.5 * ROBOT_RADIUS


def test_robot_skips_a_waypoint_someone_stands_on():
    trace_path = [(2.0, 5.0), (10.0, 5.0), (18.0, 5.0)]
    sim = make_sim([human(start=(10.0, 5.0), goals=[(10.0, 5.0)])], [STAND], trace_path, load_policy("waypoints"),
                   timeout=90)
    trace = sim.run()
    assert trace.end_reason == "robot_goal"
    assert _gaps(trace).min() > -0.05


def test_give_way_steps_away_from_the_robots_next_segment_and_waits_until_it_passed():
    # the robot drives east along y = 5 and turns north at x = 10; the person stands just past the turn, a bit
    # north of the robot's current line: stepping to "its side" of the current heading (north) would put it
    # onto the next segment (x = 10, northward)
    path = [(2.0, 5.0), (10.0, 5.0), (10.0, 9.5)]
    corner = np.array([10.0, 5.0])
    tree = tree_xml('<Fallback><Sequence><IsRobotNearby agent_id="{id}" distance="4.0"/>'
                    '<GiveWaytoRobot agent_id="{id}" time_step="{dt}"/></Sequence>'
                    '<Sequence><SetBlackboard output_key="agentid" value="{id}"/>'
                    '<SetBlackboard output_key="timestep" value="{dt}"/>'
                    '<SubTree ID="RegularNavTree" id="agentid" dt="timestep"/></Sequence></Fallback>')
    world = empty_room(20.0, 12.0)
    sim = make_sim([human(start=(10.3, 5.4), goals=[(10.3, 5.4)])], [tree], path, load_policy("waypoints"), world=world,
                   timeout=60)
    trace = sim.run()
    assert trace.end_reason == "robot_goal"
    assert trace.executed(0, "GiveWaytoRobot").any()
    person = trace.humans[:, 0, :2]
    # distance from the person to the robot's next segment (the northward one)
    along = np.clip(person[:, 1] - corner[1], 0.0, 4.5)
    to_next = np.hypot(person[:, 0] - corner[0], person[:, 1] - (corner[1] + along))
    # once the robot is within 3 m of the corner and until it is past the person, the person keeps clear of it
    robot = trace.robot[:, :2]
    approaching = np.hypot(*(robot - corner).T) < 3.0
    passed = robot[:, 1] > person[:, 1] + 1.2
    judged = approaching & ~passed & (trace.t > 3.0)
    assert judged.any()
    settled = judged & (np.cumsum(judged) * trace.dt > 2.0)  # give it 2 s to walk out of the way
    assert to_next[settled].min() >= 0.4 + ROBOT_RADIUS  # never back on the robot's path while it comes
    assert _gaps(trace).min() > -0.05
    # it stepped east/south-east (away from both legs), not north onto the next one
    first_aside = int(np.argmax(trace.executed(0, "GiveWaytoRobot")))
    final = person[int(np.argmax(judged)) + int(2.0 / trace.dt)]
    assert final[0] > 10.3 or final[1] < 5.0, (person[first_aside], final)


def test_scripted_robot_makes_way_in_a_corridor_too_narrow_for_both():
    """A person walks toward the robot down a 1.2 m corridor (a robot and a person need 1.5 m side by side):
    the default robot backs out of the corridor the way it came, steps aside in the open room, lets the
    person through, then reaches its goal (neither waits for the other for ever)."""
    world = empty_room(20.0, 10.0, walls=[(3.0, 0.0, 20.0, 4.4), (3.0, 5.6, 20.0, 10.0)])
    walker = tree_xml('<Sequence><SetBlackboard output_key="agentid" value="{id}"/>'
                      '<SetBlackboard output_key="timestep" value="{dt}"/>'
                      '<SubTree ID="RegularNavTree" id="agentid" dt="timestep"/></Sequence>')
    person = human(start=(15.0, 5.0), goals=[(1.0, 8.0)])
    trace = make_sim([person], [walker], [(1.5, 5.0), (18.0, 5.0)], load_policy("scripted"), world=world,
                     timeout=120).run()
    x, through = trace.robot[:, 0], trace.humans[:, 0, 0] < 3.0
    assert through.any()  # the person came through the corridor
    out = int(np.argmax(through))
    assert x[:out].max() > 4.0 and x[out] < 3.0  # the robot was in the corridor and out of it when they came out
    assert trace.end_reason == "robot_goal"


# stops while the robot is in front of her within 2 m (she faces it), walks her route otherwise: a resident
# with a cane meeting the robot at a door, a neighbour meeting it in a hallway
STOP_WHILE_BLOCKED = tree_xml('<Fallback><Sequence><IsRobotBlocking agent_id="{id}" distance="2.0"/>'
                              '<LookAtRobot agent_id="{id}"/></Sequence>'
                              '<Sequence><SetBlackboard output_key="agentid" value="{id}"/>'
                              '<SetBlackboard output_key="timestep" value="{dt}"/>'
                              '<SubTree ID="RegularNavTree" id="agentid" dt="timestep"/></Sequence></Fallback>')


def _standoff(world, person, path):  # noqa: ANN001, ANN202
    trace = make_sim([person], [STOP_WHILE_BLOCKED], path, load_policy("scripted"), world=world, timeout=90).run()
    assert trace.end_reason == "robot_goal"  # no deadlock until the timeout
    assert _gaps(trace)[:, 0].min() > 0.0  # never touching
    return trace


def test_scripted_robot_backs_out_of_a_hallway_for_a_person_its_presence_stopped():
    """A 1.2 m hallway: she sets off late and stops (IsRobotBlocking) as the robot comes up; her current goal is the hallway's
    end short of the robot, her route goes on past it. The robot backs out, steps aside in the room, she
    walks out of the hallway, then the robot goes up it to its goal."""
    world = empty_room(20.0, 10.0, walls=[(4.0, 0.0, 20.0, 4.4), (4.0, 5.6, 20.0, 10.0)])
    person = human(start=(11.0, 5.0), goals=[(4.5, 5.0), (1.5, 8.5)], start_delay=8.0)
    trace = _standoff(world, person, [(1.5, 5.0), (17.0, 5.0)])
    x, out = trace.robot[:, 0], trace.humans[:, 0, 0] < 4.0
    assert out.any()  # she came out of the hallway
    first = int(np.argmax(out))
    assert x[:first].max() > 5.0 and x[first] < 4.0  # the robot was in the hallway, and out of it when she came out
    assert np.hypot(*(trace.humans[-1, 0, :2] - (1.5, 8.5))) < 1.0  # she went on to her goal


def test_scripted_robot_backs_away_from_a_door_for_a_person_its_presence_stopped():
    """A 0.9 m door in a wall across the room: she stands beyond it, stopped by the robot in front; her route
    leads through the door and past the robot. The robot backs off and aside until she walks, waits while she
    comes through, then drives through the door to its goal."""
    world = empty_room(20.0, 10.0, walls=[(10.0, 0.0, 10.2, 4.55), (10.0, 5.45, 10.2, 10.0)])
    person = human(start=(12.5, 5.0), goals=[(10.1, 5.0), (7.0, 5.0), (2.0, 8.5)])
    trace = _standoff(world, person, [(3.0, 5.0), (16.0, 5.0)])
    through = trace.humans[:, 0, 0] < 9.5
    assert through.any()  # she came through the door
    first = int(np.argmax(through))
    gap = _gaps(trace)[first, 0]
    assert gap > 0.45  # the robot stood aside, out of her intimate space, as she came through
    assert trace.robot[first, 0] < 10.0  # ... on its side of the door, waiting
    assert (trace.robot[first:, 0] > 10.2).any()  # then it went through
