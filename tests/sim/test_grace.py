"""After the robot arrives its followers finish their part (sim.people.grace, issue 25): the run goes on while
someone following the robot still walks in to where their path ends by its goal, at most ARRIVAL_GRACE, and ends at
the arrival when nobody does. home_09: the robot led two children into a small bedroom, its goal 1.6 m inside, and
the run ended with the second child still in the hallway, whatever the model wrote."""

from __future__ import annotations

import numpy as np

from socnavgen.run.spec import CueTrigger, RobotCue, RobotScript
from socnavgen.sim import empty_room
from socnavgen.sim.people.grace import ARRIVAL_GRACE
from socnavgen.sim.robot.api import ScriptedPolicy
from socnavgen.sim.social_metrics import arrival_step, social_metrics

from .simhelpers import REGULAR, human, make_sim, tree_xml
from .test_followers import FOLLOWS

# a hallway (x < 7.8) and a small bedroom behind a 1.0 m doorway at x = 8 (y 4.5 - 5.5), its far wall at x = 11
BEDROOM = [(7.8, 0.0, 8.2, 4.5), (7.8, 5.5, 8.2, 10.0), (11.0, 0.0, 20.0, 10.0)]
ROBOT_PATH = [(3.0, 5.0), (6.5, 5.0), (9.8, 5.0)]  # its goal 1.6 m inside the room
DOOR_INSIDE = 8.2 + 0.4  # a person whose centre is beyond this is in the room, past the doorway
FOLLOW_ME = RobotScript(speed=0.5, cues=[RobotCue(trigger=CueTrigger(when="start"), say="FOLLOW ME", hold=2.0,
                                                  wait=1.0)])


def _run(people, trees, world=None, **kw):  # noqa: ANN001, ANN202
    return make_sim(people, trees, ROBOT_PATH, ScriptedPolicy(), world=world or empty_room(20.0, 10.0, walls=BEDROOM),
                    script=FOLLOW_ME, timeout=90, **kw).run()


def _arrived(trace) -> int:  # noqa: ANN001
    step = arrival_step(trace)
    assert step is not None, "the robot never arrived"
    return step


def test_two_followers_led_into_a_small_room_both_end_inside_it_and_the_robot_keeps_its_arrival_time():
    """Two children follow the robot from the hallway into the bedroom (one's path ends at its goal, the other's in
    the hallway: a follower for good goes where the robot goes): both end in the room (before: the run ended as the
    robot arrived, the second child still in the hallway); the robot stood at its goal meanwhile, the run ended once
    they stood, within the grace, and the metrics keep the arrival."""
    people = [human("human1", start=(1.6, 5.0), goals=[(6.5, 5.0), (9.8, 5.0)]),
              human("human2", start=(0.5, 5.0), goals=[(6.5, 5.0)])]
    trace = _run(people, [FOLLOWS] * 2)
    arrived = _arrived(trace)
    assert trace.end_reason == "robot_goal"
    assert trace.steps - 1 > arrived, "the run ended at the robot's arrival"
    assert (trace.humans[-1, :, 0] > DOOR_INSIDE).all(), trace.humans[-1, :, :2]
    assert trace.t[-1] - trace.t[arrived] <= ARRIVAL_GRACE + trace.dt
    assert np.hypot(*(trace.robot[arrived:, :2] - trace.robot[arrived, :2]).T).max() < 0.05  # it stood there
    assert np.hypot(trace.humans[-1, :, 3], trace.humans[-1, :, 4]).max() < 0.1  # they stood when it ended
    assert trace.meta["robot_arrived"] == round(float(trace.t[arrived]), 6)
    metrics = social_metrics(trace, success=True)
    assert metrics["time_to_goal"] == trace.t[arrived]


def test_a_run_nobody_follows_ends_at_the_robots_arrival():
    """A walker who does not follow the robot (walking down the hallway, still walking when it arrives) does not
    hold the run: it ends at the step the robot arrives, as before."""
    people = [human("human1", start=(1.0, 2.0), goals=[(7.0, 2.0), (1.0, 2.0)], cyclic=True)]
    trace = _run(people, [tree_xml(REGULAR)])
    assert trace.end_reason == "robot_goal" and _arrived(trace) == trace.steps - 1
    assert "robot_arrived" not in trace.meta


def test_the_grace_is_bounded_for_a_follower_who_cannot_come_in_in_time():
    """A follower walking at 0.15 m/s is far behind when the robot arrives: the run goes on for ARRIVAL_GRACE after
    the arrival and ends then, with her still walking in."""
    people = [human("human1", start=(1.0, 5.0), goals=[(1.0, 5.0)], max_vel=0.15)]
    trace = _run(people, [FOLLOWS], world=empty_room(20.0, 10.0))
    arrived = _arrived(trace)
    assert trace.end_reason == "robot_goal"
    assert abs(trace.t[-1] - trace.t[arrived] - ARRIVAL_GRACE) <= trace.dt + 1e-9, (trace.t[-1], trace.t[arrived])
    assert np.hypot(trace.humans[-1, 0, 3], trace.humans[-1, 0, 4]) > 0.05  # still walking in

