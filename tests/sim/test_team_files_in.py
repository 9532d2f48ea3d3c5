"""A team standing talking by a door files into the room behind it, one after another, while the robot waits behind
them (people.make_room, issue 25). hospital_04: the first resident, standing in the waiting robot's way, stepped
aside into the mouth of the room's 1.2 m door; when her tree walked her in, the give-way she had begun kept her
there for good (it waited for the robot to pass, the robot waited for the team), and the two behind her circled in
the corridor for 45 s, unable to get through the door."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from socnavgen.bodies import PERSON_RADIUS
from socnavgen.location import load_location
from socnavgen.sim import HumanSpec, World, empty_room
from socnavgen.sim.people.spots import occupied

from .simhelpers import REGULAR, Stay, make_sim, tree_xml

HOSPITAL = Path(__file__).resolve().parents[2] / "examples" / "locations" / "hospital"


def talk_then_walk(seconds: float) -> str:
    """Stand gesturing (talking) until `seconds`, then walk the path for good: a ward round's member."""
    return tree_xml(f'<Fallback><Sequence><TimeExpiredCondition seconds="{seconds}" ts="{{dt}}" only_once="true"/>'
                    f'<KeepRunningUntilFailure>{REGULAR}</KeepRunningUntilFailure></Sequence>'
                    '<MakeGesture agent_id="{id}" message="0"/></Fallback>')


def test_a_team_of_four_filing_through_a_door_past_a_waiting_robot_all_get_into_the_room() -> None:
    """Four people stand round the corridor node in front of the hospital's 1.2 m door x5, the robot waiting 2.6 m
    behind them on its way to that node; they go into the room zx one by one, 2 s apart: all four end inside it
    (before: three of them never got through the door - the first stepped aside into its mouth for the waiting
    robot and stayed there)."""
    hospital = load_location(HOSPITAL)
    at = {n: complex(*hospital.node_world(n)) for n in ("i1", "x5", "zx", "zs")}
    along = (at["zs"] - at["i1"]) / abs(at["zs"] - at["i1"])  # along the corridor, toward the robot
    across = along * 1j
    starts = [at["i1"] + 0.65 * along, at["i1"] + 0.65 * across, at["i1"] - 0.65 * along, at["i1"] - 0.65 * across]
    order = np.argsort([abs(s - at["x5"]) for s in starts])  # the nearest the door goes in first
    people = [HumanSpec(name=f"human{k + 1}", start=(s.real, s.imag), goals=[(at["x5"].real, at["x5"].imag),
                        (at["zx"].real, at["zx"].imag)], group_id=0) for k, s in enumerate(starts)]
    trees = [talk_then_walk(12.0 + 2.0 * int(np.flatnonzero(order == k)[0])) for k in range(4)]
    robot = at["i1"] + 2.6 * along
    trace = make_sim(people, trees, [(robot.real, robot.imag), (at["i1"].real, at["i1"].imag)], Stay(),
                     world=World.from_location(hospital), timeout=50.0).run()
    door = at["x5"]
    into = (door - at["i1"]) / abs(door - at["i1"])  # across the door's line, from the corridor into the room
    depth = [((complex(*xy) - door) * into.conjugate()).real for xy in trace.humans[-1, :, :2]]
    assert min(depth) > PERSON_RADIUS, depth  # every body wholly past the door's line, in the room


def test_someone_whose_tree_stopped_walking_them_at_a_shared_goal_stands_on_it() -> None:
    """people.spots.occupied: the step a person's tree stops walking them at their last goal (their speed is zeroed
    only when physics moves everyone), that goal is taken for the next one walking there, who keeps their spot round
    it (before: they dropped it for that step and stopped where they were, queued behind him - in a door's mouth)."""
    goal = (10.0, 5.0)
    people = [HumanSpec(name="human1", start=(7.0, 5.0), goals=[goal], group_id=0),
              HumanSpec(name="human2", start=(9.6, 5.0), goals=[goal], group_id=0)]
    sim = make_sim(people, [tree_xml(REGULAR)] * 2, [(1.0, 1.0), (1.5, 1.0)], Stay(), world=empty_room(20.0, 10.0))
    first = sim.state.people[1]
    first.pos, first.vel, first.walks = complex(9.6, 5.0), complex(0.7, 0.0), True
    assert not occupied(sim.state, 0, complex(*goal))  # walking up to it, not there yet (nor standing)
    first.walks = False  # his tree stopped walking him there this step
    assert occupied(sim.state, 0, complex(*goal))
