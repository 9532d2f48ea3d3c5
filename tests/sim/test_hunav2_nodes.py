"""The HuNavSim 2.x nodes an exported tree uses, each in a staged situation (semantics in
people/leaves_hunav2.py's docstring)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from .simhelpers import Drive, Stay, human, make_sim, tree_xml, xy


def v4(body: str) -> str:
    return tree_xml(body, fmt=4)


def gesture_with(body: str, robot_at=(4.0, 5.0)) -> int:  # noqa: ANN001
    sim = make_sim([human(start=(2.0, 5.0))], [v4(body)], [robot_at, (19.0, 5.0)])
    sim.step()
    return int(sim.people[0].gesture)


def test_is_robot_close_is_strictly_closer_than_its_threshold():
    close = ('<Fallback><Sequence><IsRobotClose agent_id="{id}" threshold="{t}"/><SaySomething agent_id="{id}" '
             'message="WAIT"/></Sequence><SaySomething agent_id="{id}" message="PROCEED"/></Fallback>')
    assert gesture_with(close.replace("{t}", "2.5")) == 1  # robot 2 m away
    assert gesture_with(close.replace("{t}", "2.0")) == 2  # exactly at the threshold: not closer
    assert gesture_with(close.replace("{t}", "1.0")) == 2


@pytest.mark.parametrize(("word", "code"), [("WAIT", 1), ("EXCUSE ME", 3), ("hello", 0)])
def test_say_something_shows_the_gesture_of_its_word(word: str, code: int):
    assert gesture_with(f'<SaySomething agent_id="{{id}}" message="{word}"/>') == code


def test_surprised_nav_turns_toward_the_robot_without_moving():
    sim = make_sim([human(start=(2.0, 5.0), yaw=0.0)], [v4('<SurprisedNav agent_id="{id}"/>')], [(2.0, 8.0), (3.0, 8.0)])
    sim.step()
    sim.step()
    assert sim.people[0].yaw == pytest.approx(math.pi / 2) and sim.people[0].pos == 2 + 5j


def test_curious_nav_approaches_the_robot_and_stops_at_its_distance_facing_it():
    body = ('<CuriousNav agent_id="{id}" time_step="{dt}" beh_duration="1" only_once="false" agent_vel="1.0" '
            'stop_distance="1.5"/>')
    trace = make_sim([human(start=(3.0, 5.0))], [v4(body)], [(10.0, 5.0), (11.0, 5.0)], Stay(), timeout=20).run()
    d = np.abs(trace.humans[:, 0, 0] + 1j * trace.humans[:, 0, 1] - (10 + 5j))
    assert 1.3 <= d[-1] <= 1.5 + 1e-9 and d.min() >= 1.3
    assert np.hypot(trace.humans[:, 0, 3], trace.humans[:, 0, 4]).max() <= 1.0 + 1e-9  # agent_vel caps it
    to_robot = (10 + 5j) - xy(trace, -1)
    assert trace.humans[-1, 0, 2] == pytest.approx(math.atan2(to_robot.imag, to_robot.real), abs=1e-6)  # facing it


def test_threatening_nav_walks_to_its_distance_in_front_of_the_robot():
    body = '<ThreateningNav agent_id="{id}" time_step="{dt}" beh_duration="1" only_once="false" goal_dist="1.2"/>'
    trace = make_sim([human(start=(7.0, 8.0))], [v4(body)], [(10.0, 5.0), (12.0, 5.0)], Stay(), timeout=25).run()
    assert abs(xy(trace, -1) - (11.2 + 5.0j)) < 0.5 and trace.behavior_state[-1, 0] == 1


def test_follow_agent_uses_hunavsims_one_based_ids_and_runs_for_its_duration():
    leader = human("human1", start=(12.0, 5.0), goals=[(12.0, 5.0)])
    follower = human("human2", start=(3.0, 5.0))
    body = ('<Sequence><FollowAgent agent_id="{id}" target_agent_id="1" time_step="{dt}" closest_dist="1.0" '
            'max_vel="1.2" duration="2.0"/><SaySomething agent_id="{id}" message="PROCEED"/></Sequence>')
    trace = make_sim([leader, follower], [v4('<SaySomething agent_id="{id}" message="WAIT"/>'), v4(body)],
                     [(10.0, 8.0), (11.0, 8.0)], timeout=3.0).run()
    done = np.flatnonzero(trace.fired(1, "FollowAgent"))
    assert done.tolist() == [40]  # RUNNING for 2 s of simulated time, then SUCCESS once (it restarts)
    assert (trace.human_gesture[1:40, 1] == 0).all() and trace.human_gesture[40, 1] == 2
    assert trace.humans[40, 1, 0] > 3.0 + 1.5  # it walked toward human1 (index 0), 1-based id 1


def test_avoid_robot_walks_on_pushed_away_while_the_robot_is_within_its_safe_distance():
    body = ('<AvoidRobot agent_id="{id}" time_step="{dt}" safe_distance="2.0" runaway_vel="0.8" '
            'duration="0"/>')
    near = make_sim([human(start=(8.0, 5.0), goals=[(8.0, 9.0)])], [v4(body)], [(7.0, 5.0), (6.0, 5.0)],
                    Stay(), timeout=2.0).run()
    far = make_sim([human(start=(8.0, 5.0), goals=[(8.0, 9.0)])], [v4(body)], [(4.0, 5.0), (3.0, 5.0)],
                   Stay(), timeout=2.0).run()
    assert np.hypot(near.humans[:, 0, 3], near.humans[:, 0, 4]).max() <= 0.8 + 1e-9
    assert near.humans[-1, 0, 0] > far.humans[-1, 0, 0] + 0.2  # pushed away (east) from the robot at x = 7
    assert far.humans[-1, 0, 1] > 5.5 and abs(far.humans[-1, 0, 0] - 8.0) < 0.1  # beyond 2 m: straight to its goal
    assert not near.fired(0, "AvoidRobot").any()  # duration 0: RUNNING until halted


def test_block_and_run_away_for_a_moving_robot():
    """RunAwayFromRobot keeps more distance from a robot driving at the person than RegularNav does."""
    walk = tree_xml('<RegularNav agent_id="{id}" time_step="{dt}"/>')
    scared = tree_xml('<RunAwayFromRobot agent_id="{id}" time_step="{dt}"/>')
    gaps = []
    for tree in (walk, scared):
        trace = make_sim([human(start=(10.0, 5.3), goals=[(10.0, 9.0)])], [tree], [(4.0, 5.0), (19.0, 5.0)],
                         Drive(0.6), timeout=10.0).run()
        gaps.append(np.hypot(*(trace.humans[:, 0, :2] - trace.robot[:, :2]).T).min())
    assert gaps[1] > gaps[0]
