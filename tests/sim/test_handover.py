"""A person comes up to the robot and takes something (a handover): someone walking to the robot (FollowRobot,
BlockRobot) while it stands is not someone to make way for. They walk up and stand at their usual distance in front
of it, facing it; the robot neither steps aside nor backs away; a script's wait holding it short of its goal, with
them standing there, is not an arrival. Once it drives on toward them, a follower steps aside as before (round 22:
warehouse_17's colleague coming for the first-aid kit stood 2.3 m off to the side; home_18's physiotherapist was
cut off by the run's end while the robot still waited for her)."""

from __future__ import annotations

import math

import numpy as np

from socnavgen.run.spec import CueTrigger, RobotCue, RobotScript
from socnavgen.sim.people.leaves import FOLLOW_STOP
from socnavgen.sim.robot.api import ScriptedPolicy
from tests.sim.simhelpers import human, make_sim, tree_xml

FOLLOW = tree_xml('<FollowRobot agent_id="{id}" time_step="{dt}"/>')
BLOCK = tree_xml('<BlockRobot agent_id="{id}" time_step="{dt}"/>')
LOOK = tree_xml('<LookAtRobot agent_id="{id}"/>')


def _facing(trace, k: int, who: int = 0) -> float:  # noqa: ANN001
    """Angle (rad) between person `who`'s heading at step k and the direction to the robot."""
    d = complex(trace.robot[k, 0] - trace.humans[k, who, 0], trace.robot[k, 1] - trace.humans[k, who, 1])
    return abs(math.remainder(math.atan2(d.imag, d.real) - trace.humans[k, who, 2], 2 * math.pi))


def test_a_follower_ahead_of_a_waiting_robot_comes_up_and_stands_in_front_then_lets_it_by():
    """The robot waits 12 s at its start; a colleague 6 m ahead on its route follows it (comes to take the kit):
    they stand about FOLLOW_STOP in front of it, facing it, and it does not move off its line meanwhile; once it
    drives on they step aside and it reaches its goal."""
    script = RobotScript(speed=0.6, cues=[RobotCue(trigger=CueTrigger(when="start"), wait=12.0)])
    sim = make_sim([human(start=(8.0, 5.0), goals=[(8.0, 5.0)])], [FOLLOW], [(2.0, 5.0), (16.0, 5.0)],
                   ScriptedPolicy(), script=script, timeout=80)
    trace = sim.run()
    k = int(np.searchsorted(trace.t, 11.0))
    there = np.hypot(trace.humans[k, 0, 0] - trace.robot[k, 0], trace.humans[k, 0, 1] - trace.robot[k, 1])
    assert FOLLOW_STOP - 0.2 <= there <= FOLLOW_STOP + 0.3, there  # came up (not 2.3 m off to the side)
    assert trace.humans[k, 0, 0] - trace.robot[k, 0] > 1.0  # in front of it
    assert np.hypot(trace.humans[k, 0, 3], trace.humans[k, 0, 4]) < 0.1  # standing
    assert _facing(trace, k) < 0.3  # facing it
    held = trace.robot[: k + 1, :2]
    assert np.abs(held - held[0]).max() < 0.05  # the robot neither stepped aside nor backed away
    assert trace.end_reason == "robot_goal"  # it drove on: they let it by


def test_a_driving_robot_passes_someone_walking_up_to_it_and_they_step_aside():
    """Driving on (no cue holds it), with a colleague walking out to it from ahead: it moves aside to pass them and
    they step aside (give way) as before a handover was a thing. Kept on its line for people walking up, with them
    waiting for it to drive on toward them, card robot-crowding [home] stood its three curious people in front of
    the robot, which rocked in place 73 s until the time limit."""
    script = RobotScript(speed=0.6)
    sim = make_sim([human(start=(12.0, 5.3), goals=[(12.0, 5.3)])], [FOLLOW], [(2.0, 5.0), (18.0, 5.0)],
                   ScriptedPolicy(), script=script, timeout=80)
    trace = sim.run()
    assert np.abs(trace.robot[:, 1] - 5.0).max() > 0.45  # it moved aside to pass them (0.30 m kept on its line)
    aside = trace.behavior_state[:, 0] == 2
    gap = np.hypot(trace.humans[:, 0, 0] - trace.robot[:, 0], trace.humans[:, 0, 1] - trace.robot[:, 1])
    assert aside.any() and gap[int(np.argmax(aside))] > FOLLOW_STOP + 0.3  # stepping aside on the way, not once
    assert trace.end_reason == "robot_goal"  # standing in front of it (1.35 m)


def test_a_blocker_stands_in_front_of_a_robot_waiting_short_of_its_goal_and_the_run_goes_on():
    """The robot waits 10 s 1.5 m short of its goal; the physiotherapist walks out to block it (her block point lies
    on its goal): the run does not end as an arrival while the script still holds it, so she is seen standing in
    front of it, facing it."""
    script = RobotScript(speed=0.6, cues=[RobotCue(trigger=CueTrigger(when="start"), wait=10.0)])
    sim = make_sim([human(start=(15.0, 2.0), goals=[(15.0, 2.0)])], [BLOCK], [(12.0, 5.0), (13.5, 5.0)],
                   ScriptedPolicy(), script=script, timeout=60)
    trace = sim.run()
    assert trace.t[-1] > 10.0, trace.t[-1]  # not "arrived" while it waits
    k = int(np.searchsorted(trace.t, 9.5))
    there = np.hypot(trace.humans[k, 0, 0] - trace.robot[k, 0], trace.humans[k, 0, 1] - trace.robot[k, 1])
    assert there < 1.7 and np.hypot(trace.humans[k, 0, 3], trace.humans[k, 0, 4]) < 0.1
    assert _facing(trace, k) < 0.3


def test_someone_standing_at_its_goal_still_ends_the_run_once_the_wait_is_over():
    """The arrival short of someone at the goal is unchanged after the wait: the robot stops short of them and the
    run ends (it does not wait for ever)."""
    script = RobotScript(speed=0.6, cues=[RobotCue(trigger=CueTrigger(when="start"), wait=4.0)])
    sim = make_sim([human(start=(14.0, 5.0), goals=[(14.0, 5.0)])], [LOOK], [(10.0, 5.0), (14.0, 5.0)],
                   ScriptedPolicy(), script=script, timeout=60)
    trace = sim.run()
    assert trace.end_reason == "robot_goal" and trace.t[-1] > 4.0  # not the timeout (60 s)
