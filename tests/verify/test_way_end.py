"""A follower of the robot ends in the room the robot's goal is in, or in its doorway (verify/way_end.py, issue 25):
home_09 of round 14 passed "both children follow it into the bedroom" with one child still at the far end of the
hallway when the robot reached the bedroom. Small graphs and traces: hall h1 - h2, doorway d, room r."""

from __future__ import annotations

import networkx as nx
import numpy as np

from socnavgen.run.models import HumanPlan, PathPlan
from socnavgen.run.spec import Criterion, Encounter, HumanPart, ScenarioSpec
from socnavgen.sim.trace import Trace
from socnavgen.verify.way_end import follows_robot_to_the_end, judge_room_end, room_ends, room_of

POINTS = {"h1": (0.0, 0.0), "h2": (4.0, 0.0), "d": (6.0, 0.0), "r": (8.0, 0.0)}
TYPES = {"h1": "HALLWAY", "h2": "HALLWAY", "d": "DOORWAY", "r": "BEDROOM"}


def _graph(door: bool = True) -> nx.Graph:
    g = nx.Graph()
    for n in POINTS:
        g.add_node(n, type=TYPES[n] if door else "OPEN AREA")
    g.add_edges_from([("h1", "h2"), ("h2", "d"), ("d", "r")])
    return g


def _spec(latch: bool = True, criterion: bool = False) -> ScenarioSpec:
    return ScenarioSpec(encounters=[Encounter(id="e1", place="HALLWAY", node="h1", humans=[
        HumanPart(human="human1", trigger="robot_says", phrase="FOLLOW ME", reaction="follow", latch=latch),
        HumanPart(human="human2", trigger="robot_says", phrase="FOLLOW ME", reaction="follow_human", other="human1",
                  latch=latch),
        HumanPart(human="human3", trigger="robot_near", reaction="give_way")])],
        criteria=[Criterion(id="c1", kind="follows_robot", human="human1", encounter="e1")] if criterion else [])


PLAN = PathPlan(robot=["h1", "h2", "d", "r"], humans=[HumanPlan(name=f"human{k}", path=["h1"]) for k in (1, 2, 3)])


def _trace(ends: dict[str, tuple[float, float]]) -> Trace:
    t = np.round(np.arange(0, 10 + 1e-9, 0.1), 6)
    names = sorted(ends)
    humans = np.zeros((len(t), len(names), 6))
    for i, n in enumerate(names):
        humans[:, i, :2] = ends[n]
    robot = np.zeros((len(t), 6))
    robot[:, :2] = POINTS["r"]
    return Trace(dt=0.1, t=t, robot=robot, humans=humans, human_names=names, group_ids=[-1] * len(names),
                 human_radii=np.full(len(names), 0.4), robot_radius=0.35, node_names=["RegularNav"],
                 action=np.zeros((len(t), len(names)), np.int16), succeeded=np.zeros((len(t), len(names)), np.int64),
                 human_gesture=np.zeros((len(t), len(names)), np.int8), robot_gesture=np.zeros(len(t), np.int8),
                 behavior_state=np.zeros((len(t), len(names)), np.int8), end_reason="robot_goal")


def test_the_room_of_a_node_is_its_part_of_the_graph_the_doorways_close_off() -> None:
    def door(n: str) -> bool:
        return TYPES[n] == "DOORWAY"

    assert room_of(_graph(), "r", door) == (frozenset({"r"}), frozenset({"d"}))
    assert room_of(_graph(), "h1", door) == (frozenset({"h1", "h2"}), frozenset({"d"}))
    assert room_of(_graph(), "d", door) is None
    assert room_of(_graph(door=False), "r", lambda n: False) is None  # one open floor: no room


def test_followers_for_good_and_a_line_behind_them_end_with_the_robot() -> None:
    spec = _spec()
    assert follows_robot_to_the_end(spec, "human1") and follows_robot_to_the_end(spec, "human2")
    assert not follows_robot_to_the_end(spec, "human3")  # the give-way goes where its tree sends it
    assert not follows_robot_to_the_end(_spec(latch=False), "human1")  # a follow that may end
    assert follows_robot_to_the_end(_spec(latch=False, criterion=True), "human1")  # judged to the end by c1
    assert [e.human for e in room_ends(PLAN, spec, _graph(), lambda n: TYPES[n])] == ["human1", "human2"]
    assert room_ends(PLAN, spec, _graph(door=False), lambda n: "OPEN AREA") == []


def _verdicts(ends: dict[str, tuple[float, float]], reached: bool = True) -> dict[str, object]:
    found = room_ends(PLAN, _spec(), _graph(), lambda n: TYPES[n])
    trace = _trace({**ends, "human3": POINTS["h1"]})
    return {e.human: judge_room_end(e, trace, POINTS, reached) for e in found}


def test_a_follower_inside_or_in_the_doorway_passes_and_one_left_in_the_hall_fails() -> None:
    found = _verdicts({"human1": (7.5, 0.3), "human2": (6.2, 0.0)})
    assert all(f.passed for f in found.values()), found
    found = _verdicts({"human1": (7.0, 0.0), "human2": (3.6, 0.2)})
    assert found["human1"].passed and not found["human2"].passed
    f = found["human2"]
    assert "human2, who follows it, was at h2 (4.4 m from the robot), outside the room of r" in f.evidence, f.evidence
    assert f.blame == "robot_script" and "wait for its followers" in f.blame_reason
    assert f.name == "human2 ends with the robot in the room of r (or a doorway of it: d)"


def test_nothing_is_judged_when_the_robot_never_reached_its_goal() -> None:
    found = _verdicts({"human1": (0.0, 0.0), "human2": (0.0, 0.0)}, reached=False)
    assert all(f.passed and "did not reach its goal" in f.evidence for f in found.values())
