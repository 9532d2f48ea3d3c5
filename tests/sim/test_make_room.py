"""People standing still in the way of a robot that waits for them make room (sim.people.make_room), as people
do; a person who blocks the robot on purpose does not.

The place: two rooms joined by a 0.9 m door; the robot drives from the left room through the door to the
right one; a person stands just behind the door on the robot's route, where the robot cannot get past them."""

from __future__ import annotations

import numpy as np
import pytest

from socnavgen.bodies import CONTACT_MARGIN
from socnavgen.export.as_target import KEEP_GAP
from socnavgen.run.spec import CueTrigger, RobotCue, RobotScript
from socnavgen.sim import BUILTIN, empty_room, load_policy
from socnavgen.sim.contact import trace_gaps
from socnavgen.sim.engine.step import STALL_REACH
from socnavgen.sim.people.side_step import GIVE_WAY_MARGIN
from socnavgen.sim.robot.api import ScriptedPolicy
from tests.sim.simhelpers import REGULAR, human, make_sim, tree_xml

DOOR = (7.0, 3.0)  # centre of the 0.9 m door in the wall x = 7
WALLS = [(6.9, 0.0, 7.1, 2.55), (6.9, 3.45, 7.1, 6.0)]
ROUTE = [(3.0, 3.0), DOOR, (12.0, 3.0)]
SPOT = (7.85, 3.0)  # just behind the door, on the route
BYSTANDER = (10.0, 5.2)  # in the right room, well off the route
BLOCKS = tree_xml(f'<Fallback><Sequence><IsRobotBlocking agent_id="{{id}}" distance="3.0"/>'
                  f'<LookAtRobot agent_id="{{id}}"/></Sequence>{REGULAR}</Fallback>')


def run(trees: list[str]):  # noqa: ANN201
    people = [human("human1", start=SPOT, goals=[SPOT], yaw=np.pi),  # faces the door: idle at their goal
              human("human2", start=BYSTANDER, goals=[BYSTANDER])]
    sim = make_sim(people, trees, ROUTE, policy=load_policy("scripted"), world=empty_room(14.0, 6.0, walls=WALLS),
                   timeout=45)
    return sim.run()


def off_route(xy: np.ndarray) -> np.ndarray:
    """Distance of each point from the robot's route after the door (the line y = 3, x >= 7)."""
    return np.hypot(np.maximum(DOOR[0] - xy[..., 0], 0.0), xy[..., 1] - DOOR[1])


def test_a_person_idle_behind_a_door_steps_aside_and_the_robot_gets_through():
    """Idle at their goal behind the door: once the robot has waited they step aside far enough for it to pass
    with room, wait there, and go back to their spot after it passed; the robot reaches its goal and nobody is
    touched; the bystander off the route never moves."""
    trace = run([tree_xml(REGULAR)] * 2)
    assert trace.end_reason == "robot_goal"
    assert trace_gaps(trace).min() > CONTACT_MARGIN
    person = trace.humans[:, 0, :2]
    radii = trace.human_radii[0] + 0.35
    assert off_route(person).max() >= radii + GIVE_WAY_MARGIN - 0.1  # made room (0.5 m beside the robot)
    assert (trace.behavior_state[:, 0] == 2).any()  # giving way while they did
    assert np.hypot(*(person[-1] - SPOT)) < 0.3 or trace.t[-1] < 45  # back at their spot, or on the way there
    first_moved = int(np.argmax(np.hypot(*(person - SPOT).T) > 0.05))
    assert trace.t[first_moved] > 2.0  # not before the robot had waited
    assert np.hypot(*(trace.humans[:, 1, :2] - BYSTANDER).T).max() < 0.05


def test_a_person_who_blocks_the_robot_on_purpose_stays():
    """The same person whose tree blocks the robot (IsRobotBlocking, then stand looking at it) stays on the
    route while the robot waits: the robot does not get through."""
    trace = run([BLOCKS, tree_xml(REGULAR)])
    person = trace.humans[:, 0, :2]
    assert trace.end_reason != "robot_goal"
    assert trace.fired(0, "IsRobotBlocking").any()
    robot, last = trace.robot[:, :2], np.searchsorted(trace.t, trace.t[-1] - 10.0)
    # the robot waited for them the last 10 s (edging about within STALL_REACH: idle, which ends the run once
    assert np.hypot(*(robot[last:] - robot[last]).T).max() < STALL_REACH  # everyone is done, engine.step.ending)
    assert np.hypot(*(robot[-1] - person[-1])) < 2.0
    assert off_route(person).max() < 0.3
    assert not (trace.behavior_state[:, 0] == 2).any()


@pytest.mark.parametrize("cue", [{"let_pass": "human1", "wait": 12.0}, {"wait": 12.0}])
def test_nobody_makes_room_for_a_robot_its_script_stands(cue: dict):
    """A robot whose script stands it (letting this very person go first, or a timed wait) is not waiting to get
    past them: the person standing on its way stays where they are while the script holds it, and makes room only
    once it has then waited ROBOT_WAITED s to get by (hospital_04: the nurse the robot let go first was made to step
    aside for it, walked off along the corridor, and the robot then waited for her to pass until its wait ran out)."""
    script = RobotScript(cues=[RobotCue(trigger=CueTrigger(when="human_within", human="human1", distance=1.9), **cue)])
    sim = make_sim([human("human1", start=SPOT, goals=[SPOT], yaw=np.pi)], [tree_xml(REGULAR)], ROUTE,
                   policy=ScriptedPolicy(), world=empty_room(14.0, 6.0, walls=WALLS), script=script, timeout=45,
                   idle_end=60.0)  # the robot standing by its wait is not the end of the run
    trace = sim.run()
    person = trace.humans[:, 0, :2]
    robot = trace.robot[:, :2]
    fired = int(np.argmax(np.hypot(*(robot - person).T) <= 1.9))
    held = trace.t < trace.t[fired] + cue["wait"] - 0.1
    assert np.hypot(*(person[held] - SPOT).T).max() < 0.05  # she stood while the script held the robot
    assert not (trace.behavior_state[held, 0] == 2).any()
    assert (trace.behavior_state[:, 0] == 2).any()  # and made room once it waited to get by
    assert trace.end_reason == "robot_goal"



def test_a_walker_the_robot_meets_in_the_door_steps_aside_and_walks_on():
    """A walker coming along a 2 m hallway to the 0.9 m door the robot drives out of, into the room behind it
    (issue 27: home exiting-room as HuNavSim runs it, with a waypoint robot that stops short of people): the two
    meet at the door and each waits for the other - without the rule neither moves until the run ends. The walker
    is held up by the robot: they step aside, let it out and by, then walk on through the door to their goal."""
    goal = (3.0, 1.5)  # in the left room, beyond the door
    hallway = [(9.1, 0.0, 9.3, 6.0)]  # east of the door: a 2 m hallway x 7.1-9.1
    robot = BUILTIN["waypoints"](max_speed=0.6, keep_gap=KEEP_GAP)  # the careful robot of the proof
    sim = make_sim([human("human1", start=(8.3, 5.4), goals=[DOOR, goal], start_delay=1.5)], [tree_xml(REGULAR)],
                   [(4.5, 3.0), DOOR, (8.1, 3.0), (8.1, 5.6)], policy=robot,
                   world=empty_room(14.0, 6.0, walls=WALLS + hallway), timeout=60)
    trace = sim.run()
    person = trace.humans[:, 0, :2]
    assert trace.end_reason == "robot_goal", trace.end_reason
    assert trace.t[-1] < 30.0
    assert trace_gaps(trace).min() > CONTACT_MARGIN
    assert (trace.behavior_state[:, 0] == 2).any()  # gave way
    aside = int(np.argmax(trace.behavior_state[:, 0] == 2))
    assert trace.t[aside] > 2.0  # not before the robot had waited
    # once it was by, they walk on to the door (the run ends as the robot arrives): no longer aside, at the door
    assert trace.behavior_state[-1, 0] != 2
    assert np.hypot(*(person[-1] - DOOR)) < 0.6 < np.hypot(*(person[aside:] - DOOR).T).max()
