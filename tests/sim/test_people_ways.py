"""People find their way: around a robot that stands in it (people.avoid), through a 0.9 m door and around
walls toward their goal or the robot they follow (people.routing, world.routes)."""

from __future__ import annotations

import numpy as np
import pytest

from socnavgen.bodies import CONTACT_MARGIN, PERSON_PASS_GAP, PERSON_RADIUS, ROBOT_RADIUS
from socnavgen.sim import RobotAction, empty_room, load_policy
from socnavgen.sim.people import spots

from .simhelpers import INSTANT, REGULAR, Drive, Stay, human, make_sim, tree_xml

REACH = PERSON_RADIUS + ROBOT_RADIUS


def gaps(trace, agent: int = 0) -> np.ndarray:  # noqa: ANN001
    """Surface gap between the person and the robot at every step."""
    d = np.hypot(trace.humans[:, agent, 0] - trace.robot[:, 0], trace.humans[:, agent, 1] - trace.robot[:, 1])
    return d - REACH


def final(trace, agent: int = 0) -> complex:  # noqa: ANN001
    return complex(trace.humans[-1, agent, 0], trace.humans[-1, agent, 1])


@pytest.mark.parametrize("offset", [0.0, 0.2, -0.4])
def test_a_walker_steps_around_a_standing_robot_with_a_margin(offset: float):
    """Walking at a robot that stands on (or near) their line, a person goes round it leaving more than
    intimate-space slack (0.3 m), and arrives; before, they walked into it and stood on its surface."""
    trace = make_sim([human(start=(2.0, 5.0 + offset), goals=[(18.0, 5.0 + offset)])], [tree_xml(REGULAR)],
                     [(10.0, 5.0), (10.5, 5.0)], Stay(), timeout=25).run()
    assert gaps(trace).min() >= 0.3
    assert abs(final(trace) - complex(18.0, 5.0 + offset)) <= 0.6


def test_with_no_room_to_pass_a_walker_stops_short_of_the_robot():
    """In a corridor too narrow to pass, the person slows down and stands a little off the robot (never
    touching it: the contact step is not how they stop)."""
    corridor = empty_room(20.0, 10.0, walls=[(0.0, 0.0, 20.0, 4.3), (0.0, 5.7, 20.0, 10.0)])
    trace = make_sim([human(start=(2.0, 5.0), goals=[(18.0, 5.0)])], [tree_xml(REGULAR)],
                     [(10.0, 5.0), (10.5, 5.0)], Stay(), world=corridor, timeout=20).run()
    assert gaps(trace).min() > CONTACT_MARGIN + 0.1
    assert 0.1 < gaps(trace)[-1] < 1.0
    assert np.hypot(trace.humans[-1, 0, 3], trace.humans[-1, 0, 4]) < 0.05


def test_a_robot_closing_in_from_behind_is_not_steered_around():
    """A person does not see a robot behind them: a fast robot driving into their back touches them (the
    robot's fault, counted against it), they do not dodge it."""
    trace = make_sim([human(start=(6.0, 5.0), goals=[(18.0, 5.0)], max_vel=0.6)], [tree_xml(REGULAR)],
                     [(2.0, 5.0), (19.0, 5.0)], Drive(1.5), timeout=6, body=INSTANT).run()
    assert gaps(trace).min() <= CONTACT_MARGIN
    assert np.abs(trace.humans[:, 0, 1] - 5.0).max() < 0.2  # kept to their line


@pytest.mark.parametrize("door", [0.9, 1.0])
def test_a_walker_passes_a_narrow_door_whose_goal_is_not_in_line(door: float):
    """A wall across the room with one door 0.9 m wide (a bedroom door of the bundled home): a person whose
    goal is off the door's line walks through it (the desired force straight at the goal pressed them against
    the jamb for the whole run)."""
    y0 = 2.0
    walls = [(9.8, 0.0, 10.2, y0), (9.8, y0 + door, 10.2, 10.0)]
    trace = make_sim([human(start=(4.0, 7.5), goals=[(16.0, 8.0)])], [tree_xml(REGULAR)],
                     [(1.0, 1.0), (1.5, 1.0)], Stay(), world=empty_room(20.0, 10.0, walls=walls), timeout=40).run()
    assert abs(final(trace) - (16.0 + 8.0j)) <= 0.6


def test_a_follower_follows_the_robot_around_a_wall():
    """The robot drives through a door into the next room; its follower goes through the door after it
    (a straight line at the robot ran into the wall), keeping up at HuNavSim's follow speed (1.8 d / 10)."""
    walls = [(9.8, 0.0, 10.2, 6.0), (9.8, 7.2, 10.2, 10.0)]  # the door at y 6.0 - 7.2
    path = [(6.0, 3.0), (9.0, 6.6), (11.0, 6.6), (14.0, 3.0)]

    trace = make_sim([human(start=(3.0, 3.0))], [tree_xml('<FollowRobot agent_id="{id}" time_step="{dt}"/>')],
                     path, load_policy("waypoints"), world=empty_room(20.0, 10.0, walls=walls), timeout=60).run()
    assert trace.humans[-1, 0, 0] > 10.5  # through the door
    assert abs(final(trace) - complex(trace.robot[-1, 0], trace.robot[-1, 1])) < 4.0


def test_a_group_whose_members_react_differently_splits_instead_of_freezing():
    """Two members of one group: one follows the robot driving off one way, the other walks its path the other
    way. Each goes their own way at a walking pace (the group force held both in a knot at 0.1-0.2 m/s)."""
    trees = [tree_xml(REGULAR), tree_xml('<FollowRobot agent_id="{id}" time_step="{dt}"/>')]
    people = [human("human1", start=(10.0, 5.3), goals=[(18.0, 5.0)], group_id=0),
              human("human2", start=(10.0, 4.7), goals=[(18.0, 5.0)], group_id=0)]
    trace = make_sim(people, trees, [(8.0, 5.0), (1.0, 5.0)], Drive(-0.8), timeout=8).run()
    assert trace.humans[-1, 0, 0] > 15.0  # the walker is well on its way east
    assert trace.humans[-1, 1, 0] < 7.0  # the follower went west after the robot


def test_a_person_with_a_start_delay_stands_until_then_and_walks_after():
    """HumanSpec.start_delay (campaigns draw it per seed): the person stands at its spawn point, facing its
    first goal, until the delay is over; then its tree runs as usual."""
    trace = make_sim([human(start=(2.0, 5.0), goals=[(18.0, 5.0)], start_delay=2.0)], [tree_xml(REGULAR)],
                     [(10.0, 8.5), (10.5, 8.5)], Stay(), timeout=5).run()
    before = trace.t < 2.0 - 1e-9
    assert np.allclose(trace.humans[before, 0, 0], 2.0) and np.allclose(trace.humans[before, 0, 1], 5.0)
    assert trace.humans[-1, 0, 0] > 4.0


def test_a_larger_personal_space_preference_keeps_a_walker_farther_from_the_robot():
    """HumanSpec.pass_gap (campaigns set it from each person's drawn personal-space preference,
    people.avoid.pass_gap_for): walking past a standing robot in an open room, a person preferring 1.5 m
    leaves more room than one preferring 1 m, and one preferring 0.5 m less."""
    from socnavgen.sim.people.avoid import pass_gap_for

    closest = {}
    for space in (0.5, 1.0, 1.5):
        trace = make_sim([human(start=(2.0, 5.0), goals=[(18.0, 5.0)], pass_gap=pass_gap_for(space))],
                         [tree_xml(REGULAR)], [(10.0, 5.0), (10.5, 5.0)], Stay(), timeout=25).run()
        closest[space] = float(gaps(trace).min())
        assert abs(final(trace) - complex(18.0, 5.0)) <= 0.6  # and still arrives
    assert closest[0.5] + 0.1 < closest[1.0] < closest[1.5] - 0.1
    assert closest[1.5] >= 0.6  # about the 0.75 m gap it asks for


class StandThenDrive:
    """A robot that stands until `t` s, then drives at (vx, 0)."""

    def __init__(self, t: float, vx: float) -> None:
        self.t, self.vx = t, vx

    def act(self, obs):  # noqa: ANN001, ANN201
        return RobotAction(self.vx if obs.t >= self.t else 0.0, 0.0)


def test_a_walker_whose_goal_the_robot_stands_on_stands_at_a_spot_a_social_gap_off_it():
    """The robot stands on the person's goal for a while, then drives on: the person walks up and stands at a free
    spot beside it (people.spots: a goal the robot stands on is taken, as one a person stands on), the passing gap
    off its body, and stays there (they walked at it and slid along its body 0.10 m off: the goal next to the robot
    exempted them from steering round it; then, since s7, they waited 0.3 m off its body and squeezed on to the goal
    after GOAL_PATIENCE, standing against a robot that did not leave)."""
    trace = make_sim([human(start=(2.0, 5.0), goals=[(10.3, 5.0)])], [tree_xml(REGULAR)],
                     [(10.0, 5.0), (19.0, 5.0)], StandThenDrive(8.0, 1.0), timeout=20, body=INSTANT).run()
    assert gaps(trace).min() >= PERSON_PASS_GAP - 0.05
    waiting = (trace.t > 7.0) & (trace.t < 8.0)  # arrived (8 m at ~1.3 m/s), the robot still standing
    assert np.hypot(trace.humans[waiting, 0, 3], trace.humans[waiting, 0, 4]).max() < 0.1  # stands, waiting
    assert abs(final(trace) - complex(10.3, 5.0)) <= spots.RINGS * spots.RING_STEP  # beside the goal


def test_a_walker_heading_across_a_moving_robots_path_lets_it_pass():
    """A person whose goal lies on the path of a robot driving by stops and lets it pass, never within 0.2 m
    of it (they walked into its side down to 0.10 m), then goes on to the goal."""
    trace = make_sim([human(start=(10.0, 1.0), goals=[(10.0, 5.3), (10.0, 9.0)], start_delay=9.5)],
                     [tree_xml(REGULAR)], [(2.0, 5.0), (19.0, 5.0)], Drive(0.6), timeout=30, body=INSTANT).run()
    assert gaps(trace).min() >= 0.2
    assert trace.robot[-1, 0] > 12.0  # it drove by
    assert trace.humans[:, 0, 1].max() > 8.0  # and they went on after it
