"""A person who stands all the run ("otherwise": "stand", and only reactions that keep them standing: stop, look,
say) is met where they stand: stage 2 must start them within their encounter's `within` of its node (issue 25,
home_08 of the new-request suite: the wife stood at the stove 2.1 m from the kitchen node where the robot
stopped, `within` 1.5 m; the verifier saw her never come to the place, and a person saw the robot reach her)."""

from __future__ import annotations

from pathlib import Path

import pytest

from socnavgen.location import load_location
from socnavgen.proposal.path_checks import check_paths
from socnavgen.proposal.replies import PathsReply, ScenarioReply
from socnavgen.proposal.scenario import to_spec

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "locations"
ROBOT = ["up", "ki", "sh", "qs"]  # sw and ki are 4.0 m from sh, up 9.0 m


@pytest.fixture(scope="module")
def warehouse():
    return load_location(EXAMPLES / "warehouse")


def _spec(otherwise: str, reaction: str = "look"):  # noqa: ANN202
    return to_spec(ScenarioReply.model_validate({
        "scenario_description": "The robot drives up to a worker who stands at the crossing and looks at it.",
        "number_of_humans": 1, "human_behaviors": {"human1": "A worker stands at the crossing and looks at the robot."},
        "expected_robot_behavior": "Drive up to the worker and on.",
        "spec": {"script": {"route": "from up to qs"}, "people": {"human1": {"otherwise": otherwise}},
                 "encounters": [{"id": "e1", "place": "INTERSECTION", "order": 1, "within": 1.5, "humans": [
                     {"human": "human1", "trigger": "robot_near", "reaction": reaction, "distance": 3.0}]}],
                 "criteria": [{"id": "c1", "kind": "meets", "human": "human1", "encounter": "e1", "distance": 2.5}]}}))


def _answer(human: list[str]) -> PathsReply:
    return PathsReply.model_validate({"trajectories": {"robot": ROBOT, "human1": human}, "group_ids": {"human1": -1},
                                      "interaction_points": {"human1": "sh"}, "encounter_nodes": {"e1": "sh"}})


def _refusals(spec, human: list[str], warehouse) -> list[str]:  # noqa: ANN001
    return [m for m in check_paths(_answer(human), warehouse.graph, ["human1"], spec, warehouse) if "stands" in m]


def test_a_person_who_stands_all_the_run_away_from_their_encounters_node_is_refused(warehouse):
    refused = _refusals(_spec("stand"), ["sw", "sh"], warehouse)
    assert len(refused) == 1 and "human1 stands all the run" in refused[0] and "4.00 m from node sh" in refused[0] \
        and "`within` (1.5 m)" in refused[0], refused
    assert _refusals(_spec("stand"), ["sh"], warehouse) == []  # standing at the node itself
    assert _refusals(_spec("walk"), ["sw", "sh"], warehouse) == []  # walks their path to it
    assert _refusals(_spec("stand", reaction="wait_then_go"), ["sw", "sh"], warehouse) == []  # then goes: walks
