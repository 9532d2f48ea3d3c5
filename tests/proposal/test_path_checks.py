"""Each stage-2 rule, broken on purpose, gives a message that names the exact mistake."""

from __future__ import annotations

from pathlib import Path

import pytest
from gen_helpers import paths_reply

from socnavgen.location import load_location
from socnavgen.proposal.path_checks import check_paths, to_path_plan
from socnavgen.proposal.replies import PathsReply

HUMANS = ["human1", "human2"]
ROOT = Path(__file__).resolve().parents[2]

# (changes to a valid reply, the exact message expected among the mistakes)
MISTAKES = {
    "unknown node": ({"trajectories": {"robot": ["32", "ch", "11", "07"], "human1": ["07", "zz", "ch"],
                                       "human2": ["f7", "07", "11"]}},
                     "node 'zz' is not in the scene graph"),
    "no edge": ({"trajectories": {"robot": ["0e", "07", "11"], "human1": ["07", "11", "ch"],
                                  "human2": ["f7", "07", "11"]}},
                "there is no edge between 0e and 07"),
    "missing human": ({"trajectories": {"robot": ["32", "ch", "11", "07"], "human1": ["07", "11", "ch"]}},
                      "trajectories: human2 has no path"),
    "extra human": ({"trajectories": {"robot": ["32", "ch", "11", "07"], "human1": ["07", "11", "ch"],
                                      "human2": ["f7", "07", "11"], "human3": ["ch"]}},
                    "trajectories: 'human3' is not a human of the scenario"),
    "lone group": ({"group_ids": {"human1": 1, "human2": -1}},
                   "group 1 has only one member (human1)"),
    "bad group id": ({"group_ids": {"human1": -3, "human2": -1}}, "human1 has group id -3"),
    "missing group id": ({"group_ids": {"human1": -1}}, "group_ids: human2 has no group id"),
    "point off robot path": ({"interaction_points": {"human1": "11", "human2": "f7"}},
                             "the interaction point f7 of human2 is not on the robot's path"),
    "point off human path": ({"interaction_points": {"human1": "32", "human2": "11"}},
                             "the interaction point 32 of human1 is not on human1's path"),
    "short robot path": ({"trajectories": {"robot": ["11"], "human1": ["07", "11", "ch"],
                                           "human2": ["f7", "07", "11"]}},
                         "the robot path needs at least two nodes"),
    "empty human path": ({"trajectories": {"robot": ["32", "ch", "11", "07"], "human1": [],
                                           "human2": ["f7", "07", "11"]},
                          "interaction_points": {"human2": "11"}},
                         "human1's path is empty"),
    "no robot": ({"trajectories": {"human1": ["07", "11", "ch"], "human2": ["f7", "07", "11"]}},
                 "the robot has no path"),
    # where everybody starts (location/placement.py)
    "goal is start": ({"trajectories": {"robot": ["32", "32"], "human1": ["11", "ch"],
                                        "human2": ["07", "11", "ch"]},
                       "interaction_points": {"human1": "ch", "human2": "ch"}},
                      "the robot's goal is its start (32)"),
    "on the robot": ({"trajectories": {"robot": ["32", "ch", "11", "07"], "human1": ["32", "ch", "11"],
                                       "human2": ["f7", "07", "11"]}},
                     "human1 starts at 32, where the robot starts"),
    "on each other": ({"trajectories": {"robot": ["32", "ch", "11", "07"], "human1": ["f7", "07", "11"],
                                        "human2": ["f7", "07", "11"]}},
                      "human1 and human2 start 0.00 m apart (f7, f7)"),
    "on the goal": ({"trajectories": {"robot": ["32", "ch", "11", "07"], "human1": ["07", "11", "ch"],
                                      "human2": ["07"]},
                     "interaction_points": {"human1": "11", "human2": "07"}},
                    "human2 starts at 07, on the robot's goal 07, and does not walk away"),
}


@pytest.fixture
def location(mini_location):
    return load_location(mini_location)


@pytest.fixture
def graph(location):
    return location.graph


def test_a_valid_reply_has_no_mistake(graph, location):
    reply = PathsReply.model_validate(paths_reply())
    assert check_paths(reply, graph, HUMANS) == [] and check_paths(reply, graph, HUMANS, location=location) == []
    plan = to_path_plan(reply, HUMANS)
    assert plan.robot == ["32", "ch", "11", "07"]
    assert [(h.name, h.group_id, h.interaction_point) for h in plan.humans] == [("human1", -1, "11"),
                                                                                ("human2", -1, "11")]


@pytest.mark.parametrize("case", sorted(MISTAKES))
def test_each_mistake_is_named(graph, location, case):
    changes, expected = MISTAKES[case]
    mistakes = check_paths(PathsReply.model_validate(paths_reply(**changes)), graph, HUMANS, location=location)
    assert any(expected in m for m in mistakes), mistakes


def test_a_group_shares_its_node_and_someone_may_leave_the_robots_goal(graph, location):
    group = paths_reply(trajectories={"robot": ["32", "ch", "11", "07"], "human1": ["f7", "07", "11"],
                                      "human2": ["f7", "07", "11"]}, group_ids={"human1": 1, "human2": 1})
    assert check_paths(PathsReply.model_validate(group), graph, HUMANS, location=location) == []
    leaving = paths_reply()  # human1 starts on the robot's goal 07 and walks away to ch
    assert paths_reply()["trajectories"]["human1"][0] == paths_reply()["trajectories"]["robot"][-1]
    assert check_paths(PathsReply.model_validate(leaving), graph, HUMANS, location=location) == []


def test_every_mistake_is_listed_at_once(graph):
    reply = paths_reply(trajectories={"robot": ["0e", "07"], "human1": ["zz"], "human2": ["f7"]},
                        group_ids={"human1": 4, "human2": -1})
    mistakes = check_paths(PathsReply.model_validate(reply), graph, HUMANS)
    text = "\n".join(mistakes)
    for expected in ("there is no edge between 0e and 07", "node 'zz' is not in the scene graph",
                     "group 4 has only one member", "not on human2's path"):
        assert expected in text


def test_human_keys_are_normalised(graph):
    reply = paths_reply(trajectories={"ROBOT": ["32", "ch", "11"], "Human 1": ["07", "11"], "HUMAN_2": ["11"]},
                        group_ids={"Human 1": 3, "human 2": 3}, interaction_points={"Human1": "11"})
    parsed = PathsReply.model_validate(reply)
    assert check_paths(parsed, graph, HUMANS) == []
    plan = to_path_plan(parsed, HUMANS)
    assert [h.group_id for h in plan.humans] == [3, 3]
    assert plan.humans[1].interaction_point is None


def test_numeric_node_ids_are_read_as_text(graph):
    reply = paths_reply(trajectories={"robot": [32, "ch"], "human1": ["ch"], "human2": ["ch"]},
                        interaction_points={"human1": "ch", "human2": "ch"})
    assert check_paths(PathsReply.model_validate(reply), graph, HUMANS) == []


def test_a_robot_route_ending_in_a_doorway_between_two_spaces_is_refused():
    """hospital_04: the robot's route ended in the doorway x5 (the text: "stops just inside the room zx"); the resident
    who stopped just past the door then held it 1.2 m back in the corridor, and that counted as arrived. A doorway is a
    passage, not a place to stop: the route ends in the room beyond it or before it. An outer door (an ENTRANCE with
    one neighbour, the home's front door g9) is a place to go to."""
    hospital = load_location(ROOT / "examples/locations/hospital")

    def doorway(robot: list[str], where=hospital) -> list[str]:  # noqa: ANN001
        reply = PathsReply.model_validate({"reasoning": "r", "trajectories": {"robot": robot}, "group_ids": {},
                                           "interaction_points": {}})
        return [m for m in check_paths(reply, where.graph, []) if "doorway" in m]

    refused = doorway(["cs", "zs", "i1", "x5"])
    assert len(refused) == 1 and "ends in the doorway x5" in refused[0], refused
    assert "zx" in refused[0] and "i1" in refused[0], refused  # the nodes on either side, to end at instead
    assert doorway(["cs", "zs", "i1", "x5", "zx"]) == []  # through it into the room
    assert doorway(["cs", "zs", "i1"]) == []  # before it
    home = load_location(ROOT / "examples/locations/home")
    assert doorway(["41", "vh", "z2", "i6", "g9"], home) == []  # the front door: an outer door, one neighbour


def test_an_at_node_cue_must_name_a_node_of_the_robots_route(graph):
    """The robot waits at an `at_node` cue's node only if its route passes it: a node off the route, or none of the
    map, is named, with the way out to stage 1."""
    from socnavgen.run.spec import CueTrigger, RobotCue, RobotScript, ScenarioSpec

    def spec(node: str) -> ScenarioSpec:
        return ScenarioSpec(script=RobotScript(cues=[RobotCue(trigger=CueTrigger(when="at_node", node=node,
                                                                                   distance=0.5), wait=5.0)]))

    reply = PathsReply.model_validate(paths_reply())  # the robot 32 -> ch -> 11 -> 07
    assert not [m for m in check_paths(reply, graph, HUMANS, spec("ch")) if "at node" in m]
    off = [m for m in check_paths(reply, graph, HUMANS, spec("f7")) if "fires at node f7" in m]
    assert off and "is not on the robot's path: route the robot through f7" in off[0]
    assert any("which is not a node of the scene graph" in m for m in check_paths(reply, graph, HUMANS, spec("qq")))
