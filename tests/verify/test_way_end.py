"""A person whose way ends in a room ends inside it (verify/way_end.py, issue 25): a follower of the robot in the
room the robot's goal is in, a walker in the room (or elevator car) their path ends in; the doorway is not inside.
home_09 of round 14 passed "both children follow it into the bedroom" with one child still at the far end of the
hallway when the robot reached the bedroom, and round 31 with both in the doorway; hospital_01 and hospital_27 passed
visitors and porters sent into the elevator car who ended in its door or in the lobby. Small graphs and traces: hall
h1 - h2, doorway d, room r; and a lobby and a car behind a door edge, on a map."""

from __future__ import annotations

import networkx as nx
import numpy as np

from socnavgen.run.models import HumanPlan, PathPlan
from socnavgen.run.spec import Criterion, Encounter, HumanPart, Person, ScenarioSpec
from socnavgen.sim import empty_room
from socnavgen.sim.trace import Trace
from socnavgen.verify.way_end import (
    follows_robot_to_the_end,
    judge_room_end,
    room_ends,
    room_of,
    walks_to_the_end,
)

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


def test_a_follower_inside_passes_and_one_in_the_doorway_or_left_in_the_hall_fails_without_a_map() -> None:
    """Without a map nothing says the room is full: a follower at its doorway is not with the robot (home_09's
    children stood by the bedroom's doorway), nor one out in the hall."""
    found = _verdicts({"human1": (7.5, 0.3), "human2": (6.2, 0.0)})
    assert found["human1"].passed and not found["human2"].passed, found
    found = _verdicts({"human1": (8.4, -0.2), "human2": (3.6, 0.2)})
    assert found["human1"].passed and not found["human2"].passed
    f = found["human2"]
    assert "human2 was at (3.60, 0.20), nearest node h2, 4.4 m from the robot: not inside the room of r" in f.evidence, \
        f.evidence
    assert f.blame == "robot_script" and "wait for its followers" in f.blame_reason
    assert f.name == "human2 ends with the robot in the room of r (behind d)"


# A lobby (x < 14.9) and an elevator car 1.8 m x 2.2 m (x 15.3-17.1, y 4.4-6.6) behind a 1.2 m door through a 0.4 m
# wall: the bundled hospital's north elevator; its scene graph: lobby nodes a - l, the car c behind a door edge.
CAR_WALLS = [(14.9, 0.0, 20.0, 4.4), (14.9, 6.6, 20.0, 9.0), (14.9, 4.4, 15.3, 4.9), (14.9, 6.1, 15.3, 6.6),
             (17.1, 4.4, 20.0, 6.6)]
CAR_POINTS = {"a": (11.0, 5.5), "l": (13.8, 5.5), "c": (16.2, 5.5), "x": (2.0, 1.0), "y": (2.0, 8.0)}


def _car_graph() -> nx.Graph:
    g = nx.Graph()
    for n in CAR_POINTS:
        g.add_node(n, type="ELEVATOR" if n == "c" else "ELEVATOR LOBBY")
    g.add_edge("a", "l", type="OPEN SPACE")
    g.add_edge("l", "c", type="THROUGH DOOR")
    g.add_edge("x", "a", type="OPEN SPACE")
    g.add_edge("x", "y", type="OPEN SPACE")
    return g


def _car_ends(parts: list[HumanPart], people: dict[str, Person] | None = None) -> list:
    spec = ScenarioSpec(encounters=[Encounter(id="e1", place="ELEVATOR LOBBY", node="l", humans=parts)],
                        people=people or {})
    plan = PathPlan(robot=["c", "l", "a", "x", "y"],
                    humans=[HumanPlan(name=p.human, path=["a", "l", "c"]) for p in parts])
    g = _car_graph()
    return room_ends(plan, spec, g, lambda n: g.nodes[n]["type"], edge_type=lambda u, v: g.edges[u, v]["type"])


def _car_trace(ends: dict[str, tuple[float, float]], still_at: dict[str, tuple[float, float]] | None = None) -> Trace:
    trace = _trace(ends)
    trace.robot[:, :2] = CAR_POINTS["y"]
    for i, n in enumerate(trace.human_names):  # where they were 3 s before the end (default: where they end)
        trace.humans[: len(trace.t) - 30, i, :2] = (still_at or {}).get(n, ends[n])
    return trace


def test_a_room_behind_a_door_edge_is_a_room_and_its_doorway_the_node_across_the_door() -> None:
    g = _car_graph()
    assert room_of(g, "c", lambda n: False, lambda u, v: g.edges[u, v]["type"] == "THROUGH DOOR") == \
        (frozenset({"c"}), frozenset({"l"}))
    assert room_of(g, "c", lambda n: False) is None  # without its door edge the car is part of one open floor


def test_who_walks_into_the_room_to_the_end_is_judged_and_who_the_text_keeps_outside_is_not() -> None:
    give_way = HumanPart(human="human1", trigger="robot_says", phrase="EXCUSE ME", reaction="give_way", lasts=8.0)
    stands = HumanPart(human="human2", trigger="always", reaction="stop")  # the text keeps her at the door for good
    walks_on = HumanPart(human="human3", trigger="robot_says", phrase="PROCEED", reaction="walk_past", latch=True)
    waits = HumanPart(human="human4", trigger="robot_near", reaction="look")
    spec = ScenarioSpec(encounters=[Encounter(id="e1", place="X", humans=[give_way, stands, walks_on, waits])],
                        people={"human3": Person(otherwise="stand"), "human4": Person(otherwise="stand")})
    assert walks_to_the_end(spec, "human1") and not walks_to_the_end(spec, "human2")
    assert walks_to_the_end(spec, "human3")  # held at the start until PROCEED, then walks for good
    assert not walks_to_the_end(spec, "human4")  # stands by plan; nothing sets her going
    ends = _car_ends([give_way, stands, walks_on])
    assert [(e.human, e.goal, e.follows) for e in ends] == [("human1", "c", False), ("human3", "c", False)]


def test_a_walker_inside_the_car_passes_one_in_its_door_or_in_the_lobby_fails() -> None:
    parts = [HumanPart(human=f"human{k}", trigger="robot_says", phrase="EXCUSE ME", reaction="give_way", lasts=8.0)
             for k in (1, 2, 3)]
    ends = _car_ends(parts)
    world = empty_room(20.0, 9.0, walls=CAR_WALLS)
    trace = _car_trace({"human1": (16.6, 4.9), "human2": (15.1, 5.5), "human3": (13.9, 5.3)},
                       still_at={"human3": (11.0, 5.5)})
    found = {e.human: judge_room_end(e, trace, CAR_POINTS, True, world) for e in ends}
    assert found["human1"].passed, found["human1"]  # in a corner at the back of the car
    assert not found["human2"].passed and found["human2"].blame == "behaviors"  # in its door, standing
    assert found["human2"].blame_human == "human2" and "walk on to the end of their path" in \
        found["human2"].blame_reason
    assert found["human3"].passed and "never came" in found["human3"].evidence  # the run ended before they came
    assert found["human1"].name == "human1 ends inside the room of c, where their path ends (behind l)"


def test_nothing_is_judged_when_the_robot_never_reached_its_goal() -> None:
    found = _verdicts({"human1": (0.0, 0.0), "human2": (0.0, 0.0)}, reached=False)
    assert all(f.passed and "did not reach its goal" in f.evidence for f in found.values())


# A 1.2 m hallway (x 5.0-6.2) and a roomy bedroom (x 6.35-10, y 4.5-9.5) behind a 0.9 m door (y 6.55-7.45): the
# bundled home's second bedroom, drawn larger; hallway nodes a, h, its doorway node d, the bedroom's node b.
BEDROOM_WALLS = [(0.0, 0.0, 5.0, 10.0), (6.2, 0.0, 6.35, 6.55), (6.2, 7.45, 6.35, 10.0), (6.35, 0.0, 12.0, 4.5),
                 (6.35, 9.5, 12.0, 10.0), (10.0, 4.5, 12.0, 9.5)]
BEDROOM_POINTS = {"a": (5.6, 2.0), "h": (5.6, 7.0), "d": (6.3, 7.0), "b": (8.2, 7.0)}


def _followers_into(points: dict[str, tuple[float, float]], graph: nx.Graph, robot_at: tuple[float, float],
                    ends: dict[str, tuple[float, float]], world: object) -> dict[str, object]:
    """The verdicts on human1 and human2, following the robot to the end of its way to the last node of `points`."""
    nodes = list(points)
    plan = PathPlan(robot=nodes, humans=[HumanPlan(name=f"human{k}", path=[nodes[0]]) for k in (1, 2)])
    found = room_ends(plan, _spec(), graph, lambda n: graph.nodes[n]["type"],
                      edge_type=lambda u, v: graph.edges[u, v]["type"])
    trace = _trace({**ends, "human3": points[nodes[0]]})
    trace.robot[:, :2] = robot_at
    return {e.human: judge_room_end(e, trace, points, True, world) for e in found}


def test_a_follower_at_the_door_of_a_roomy_bedroom_fails_and_one_in_it_passes() -> None:
    """home_09: the robot stands in the bedroom, a child stands in its doorway (nearest the doorway node) with room
    for him inside: he did not follow it into the bedroom (before: a follower nearest a doorway node passed)."""
    g = nx.Graph()
    for n, kind in (("a", "HALLWAY"), ("h", "HALLWAY"), ("d", "DOORWAY"), ("b", "BEDROOM")):
        g.add_node(n, type=kind)
    g.add_edges_from([("a", "h"), ("h", "d"), ("d", "b")], type="OPEN SPACE")
    world = empty_room(12.0, 10.0, walls=BEDROOM_WALLS)
    found = _followers_into(BEDROOM_POINTS, g, BEDROOM_POINTS["b"], {"human1": (6.0, 6.9), "human2": (7.3, 8.2)},
                            world)
    assert not found["human1"].passed and "nearest node d" in found["human1"].evidence, found["human1"]
    assert found["human2"].passed and "inside" in found["human2"].evidence, found["human2"]


def test_a_follower_at_the_door_of_a_car_the_robot_fills_passes_of_an_empty_car_fails() -> None:
    """hospital_09: a guide robot fills the elevator car, the patient it led stands at its door - no spot is left
    for her inside (sim.people.spots.room_left); with the car empty she would have gone in."""
    world = empty_room(20.0, 9.0, walls=CAR_WALLS)
    g = _car_graph()
    points = {n: CAR_POINTS[n] for n in ("x", "a", "l", "c")}
    ends = {"human1": (14.3, 5.5), "human2": (16.4, 5.0)}
    found = _followers_into(points, g, CAR_POINTS["c"], ends, world)
    assert found["human1"].passed and "full room" in found["human1"].evidence, found["human1"]
    found = _followers_into(points, g, CAR_POINTS["y"], {"human1": (14.3, 5.5), "human2": (2.0, 7.0)}, world)
    assert not found["human1"].passed, found["human1"]  # the robot stands elsewhere: the car is empty

