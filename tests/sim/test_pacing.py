"""Pacing brings a person to their interaction node when the robot gets there, whatever the robot does on its
way: it stands for its cues, it drives slowly, or the person waits out of sight beside a corner."""

from __future__ import annotations

import numpy as np
import pytest

from socnavgen.bodies import CLEAR_LEAD
from socnavgen.run.spec import CueTrigger, RobotCue, RobotScript
from socnavgen.sim import PacingPlan, RobotAction, ThrottleConfig
from socnavgen.sim.people.pacing import door_lead
from socnavgen.sim.robot.api import ScriptedPolicy
from socnavgen.sim.world.grid import empty_room
from tests.sim.simhelpers import INSTANT, REGULAR, human, make_sim, tree_xml

NODE = complex(10.0, 4.6)
ROBOT = [(1.0, 4.6), (5.0, 4.6), (10.0, 4.6), (18.0, 4.6)]
ROBOT_NODES = ["r0", "r1", "n", "r3"]


def _tracks(trace) -> tuple[np.ndarray, np.ndarray]:  # noqa: ANN001
    return trace.robot[:, 0] + 1j * trace.robot[:, 1], trace.humans[:, 0, 0] + 1j * trace.humans[:, 0, 1]


def _meeting(trace, node: complex, within: float = 2.0) -> tuple[float, float]:  # noqa: ANN001
    """(when robot and person first come within `within` m, how far their midpoint is from `node` then)."""
    robot, person = _tracks(trace)
    close = np.flatnonzero(np.abs(robot - person) <= within)
    assert close.size, f"robot and person never came within {within} m"
    k = int(close[0])
    return float(trace.t[k]), float(abs((robot[k] + person[k]) / 2 - node))


def _crossing(script: RobotScript | None, timeout: float = 90.0, paced: bool = True):  # noqa: ANN202
    """A person walking towards the robot along the corridor, meeting it at NODE, then on."""
    walker = human(start=(16.0, 5.4), goals=[(13.0, 5.4), (10.0, 5.4), (2.0, 5.4)])
    pacing = PacingPlan(ThrottleConfig(), ROBOT_NODES, [(0, ["h0", "h1", "n", "h3"], "n", -1)]) if paced else None
    return make_sim([walker], [tree_xml(REGULAR)], ROBOT, policy=ScriptedPolicy(), script=script, pacing=pacing,
                    timeout=timeout).run()


def test_a_robot_that_stands_on_its_way_is_still_met_at_the_node():
    """The robot stands 5 s at its start and 3 s more later on (its own cues): the person is not let go while
    it stands but waits for it, and they meet at the node, ~8 s later than without the waits."""
    waits = RobotScript(cues=[RobotCue(trigger=CueTrigger(when="start"), wait=5.0),
                              RobotCue(trigger=CueTrigger(when="after", seconds=9.0), wait=3.0)])
    trace = _crossing(waits)
    robot, _ = _tracks(trace)
    assert abs(robot[int(4.5 / trace.dt)] - complex(*ROBOT[0])) < 0.05  # it did stand
    when, off = _meeting(trace, NODE)
    assert off <= 1.0
    plain_when, plain_off = _meeting(_crossing(None), NODE)
    assert plain_off <= 1.0
    assert when - plain_when > 6.0  # the person waited for the robot's 8 s of standing
    # the paced person walked no farther towards the node than the robot's ETA asked: not past it, early
    _, person = _tracks(trace)
    assert person[: int(when / trace.dt)].real.min() > NODE.real - 1.0


def test_a_slow_robot_is_met_at_the_node():
    """The script drives at 0.3 m/s (a sweeper): the person's pace follows its ETA."""
    trace = _crossing(RobotScript(speed=0.3), timeout=120.0)
    when, off = _meeting(trace, NODE)
    assert off <= 1.0 and when > 25.0  # 9 m at 0.3 m/s


def test_a_person_waiting_out_of_sight_beside_a_corner_comes_out_as_the_robot_arrives():
    """A worker waits 3.5 m up a side aisle (walls hide them from the cross aisle the robot sweeps along at
    0.3 m/s) and meets the robot at the aisle mouth: they stand out of sight until walking out at their own
    speed gets them there with the robot, then come out walking (not crawling) and meet it at the node, before
    the slow robot has passed."""
    walls = [(0.0, 3.5, 9.0, 10.0), (11.0, 3.5, 20.0, 10.0)]  # the cross aisle y < 3.5, the side aisle 9 < x < 11
    world = empty_room(20.0, 10.0, walls=walls)
    node = complex(10.0, 1.75)
    route = [(1.0, 1.75), (5.0, 1.75), (10.0, 1.75), (19.0, 1.75)]
    worker = human(start=(10.0, 5.25), goals=[(10.0, 1.75), (2.0, 1.0)])
    pacing = PacingPlan(ThrottleConfig(), ROBOT_NODES, [(0, ["a", "n", "b"], "n", -1)])
    trace = make_sim([worker], [tree_xml(REGULAR)], route, policy=ScriptedPolicy(), world=world,
                     script=RobotScript(speed=0.3), pacing=pacing, timeout=60).run()
    robot, person = _tracks(trace)
    speed = np.abs(trace.humans[:, 0, 3] + 1j * trace.humans[:, 0, 4])
    seen = world.segments_clear(robot, person)
    assert seen.any() and node.real - robot[int(np.argmax(seen))].real <= 2.5  # hidden until the robot is close
    moves = int(np.argmax(speed > 0.1))
    assert 0.5 <= node.real - robot[moves].real <= 2.5  # set off with the robot ~(3.5 m / 1.5 m/s + 0.5 s) away
    mouth = int(np.argmax(person.imag < 3.5))
    assert speed[mouth] >= 1.0  # walks out at its own speed: a sudden appearance
    when, off = _meeting(trace, node)
    assert off <= 1.0
    assert robot[int(when / trace.dt)].real <= node.real  # met as the robot arrives, not after it passed


DOOR_WALLS = [(9.9, 0.0, 10.1, 4.55), (9.9, 5.45, 10.1, 10.0)]  # a wall at x = 10 with a 0.9 m door at y = 5


def test_a_door_on_the_robots_way_gets_a_lead_and_a_corridor_does_not():
    door = empty_room(20.0, 10.0, walls=DOOR_WALLS)
    route = [2 + 5j, 10 + 5j, 16 + 5j]
    assert door_lead(door, route, 1) == CLEAR_LEAD  # narrow at the node, room to pass 1.5 m before it
    assert door_lead(door, route, 2) == 0.0  # the room beyond is wide
    assert door_lead(door, [9.0 + 5j, 10 + 5j, 16 + 5j], 1) == 0.0  # the robot starts nearer the door than that
    corridor = empty_room(20.0, 10.0, walls=[(0.0, 0.0, 20.0, 4.4), (0.0, 5.6, 20.0, 10.0)])  # 1.2 m wide
    assert door_lead(corridor, route, 1) == 0.0  # narrow before it too: no place to let them through


def test_a_person_coming_out_through_a_door_clears_it_before_the_robot_gets_there():
    """The robot enters a room through a 0.9 m door while a person leaves the room through it: the person is
    paced to go through first, so they never stand face to face in the door, and the robot gets through."""
    world = empty_room(20.0, 10.0, walls=DOOR_WALLS)
    route = [(2.0, 5.0), (6.0, 5.0), (10.0, 5.0), (16.0, 5.0)]
    person = human(start=(15.0, 5.5), goals=[(10.0, 5.0), (4.0, 7.5)])
    pacing = PacingPlan(ThrottleConfig(), ROBOT_NODES, [(0, ["a", "n", "b"], "n", -1)])
    trace = make_sim([person], [tree_xml(REGULAR)], route, policy=ScriptedPolicy(), world=world, pacing=pacing,
                     timeout=60).run()
    robot, walker = _tracks(trace)
    door = 10 + 5j
    near = int(np.argmax(np.abs(robot - door) <= 1.0))
    assert np.abs(robot - door).min() <= 1.0 and walker[near].real < 9.5  # through before the robot gets there
    assert np.abs(robot - walker).min() >= 0.8  # never face to face in it
    _, off = _meeting(trace, door, within=3.0)
    assert off <= 1.5  # still met at the door
    assert trace.end_reason == "robot_goal"


def test_a_paced_person_next_to_someone_standing_on_their_node_waits_for_the_robot_there():
    """A patient starts 1 m from her meeting node, where another patient stands (issue 25, hospital_11 of the
    new-request suite): standing beside someone on a node counts as being at it (people.state.queued_at, a team at
    one bed), but not while pacing holds her: she did not walk there. She is held for the robot and meets it at
    the node, instead of counting it reached at once, walking on unpaced and standing 5 m down the corridor."""
    walker = human(start=(11.0, 5.4), goals=[(10.0, 5.4), (2.0, 5.4)])
    stander = human(name="human2", start=(10.0, 5.4), goals=[(10.0, 5.4)])
    pacing = PacingPlan(ThrottleConfig(), ROBOT_NODES, [(0, ["h0", "n", "h3"], "n", -1)])
    trace = make_sim([walker, stander], [tree_xml(REGULAR)] * 2, ROBOT, policy=ScriptedPolicy(), pacing=pacing,
                     timeout=40).run()
    robot, person = _tracks(trace)
    early = int(6.0 / trace.dt)  # the robot is still 5 m or more from the node
    assert abs(robot[early] - NODE) >= 4.5
    assert person[:early].real.min() > 10.3  # she stayed by the node, not walked on towards the robot
    when, off = _meeting(trace, NODE, within=3.0)  # she passes round the other patient, the robot round both
    assert off <= 1.0 and when >= 12.0  # they meet at the node, as the robot gets there


class Edging:
    """A robot that edges back and forth by its start for `until` s (0.3 m/s, 0.3 m each way: no progress along
    its route, yet never standing), or stands there (`stand`), then drives on east."""

    def __init__(self, until: float, stand: bool = False) -> None:
        self.until, self.stand = until, stand

    def act(self, obs):  # noqa: ANN001, ANN201
        if obs.t >= self.until:
            return RobotAction(0.6, 0.0)
        return RobotAction(0.0 if self.stand else (0.3 if int(obs.t) % 2 == 0 else -0.3), 0.0)


@pytest.mark.parametrize("stand", [False, True])
def test_a_robot_edging_about_without_progress_has_an_eta_one_that_stands_has_none(stand: bool):
    """hospital_11 of the new-request suite: after letting the nurse pass, the robot drove 0.9 m back east and
    turned, getting nowhere along its route; pacing read the run end's idle clock (no progress for 2 s counts as
    idle) as 'the robot stands for no known time' and let both patients, held in its way down the corridor, walk
    on towards their nodes while it drove at 0.4 m/s. A robot that moves has an ETA: the person stays held. One
    that stands (1 s or more, no timed wait) waits for someone: then the person walks on to the node."""
    walker = human(start=(16.0, 5.4), goals=[(13.0, 5.4), (10.0, 5.4), (2.0, 5.4)])  # in its way, 15 m ahead
    pacing = PacingPlan(ThrottleConfig(), ROBOT_NODES, [(0, ["h0", "h1", "n", "h3"], "n", -1)])
    sim = make_sim([walker], [tree_xml(REGULAR)], ROBOT, policy=Edging(10.0, stand), pacing=pacing, body=INSTANT)
    start = complex(sim.people.pos[0])
    while sim.t < 9.5:
        sim.step()
    walked = abs(complex(sim.people.pos[0]) - start)
    assert abs(complex(sim.robot.pos) - complex(*ROBOT[0])) < 0.5  # the robot got nowhere
    if stand:
        assert walked > 1.5, f"she walked {walked:.2f} m while the robot stood for no known time"
    else:
        assert walked < 0.2, f"she walked {walked:.2f} m towards the node while the robot was edging about"
