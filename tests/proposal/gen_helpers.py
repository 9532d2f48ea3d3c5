"""Helpers of the generation-pipeline tests: a small synthetic location (so the tests do not depend on
the bundled example), canned replies, and `generate` run against a replay script."""

from __future__ import annotations

import json
from pathlib import Path

import yaml
from PIL import Image

from socnavgen.llm import make_llm
from socnavgen.proposal import generate
from socnavgen.run import RunFolder, ScenarioRequest

# 0e - 32 - ch - 11 - 07 - f7 - d9 - ch   (0e and 07 are NOT joined: the brief's example mistake)
NODES = {"0e": ("CORNER", (10, 10)), "32": ("PASSAGEWAY", (30, 10)), "ch": ("INTERSECTION", (50, 10)),
         "11": ("BLIND CORNER", (50, 30)), "07": ("CORNER", (50, 50)), "f7": ("OPEN AREA", (70, 50)),
         "d9": ("PASSAGEWAY", (70, 10))}
EDGES = [("0e", "32", "PASSAGEWAY"), ("32", "ch", "PASSAGEWAY"), ("ch", "11", "NARROW PASSAGEWAY"),
         ("11", "07", "NARROW PASSAGEWAY"), ("07", "f7", "PASSAGEWAY"), ("f7", "d9", "PASSAGEWAY"),
         ("d9", "ch", "DOORWAY")]



def make_mini_location(root: Path) -> Path:
    root.mkdir()
    Image.new("L", (80, 60), 255).save(root / "map.png")
    Image.new("RGB", (80, 60), (255, 255, 255)).save(root / "scene_graph.png")
    (root / "location.yaml").write_text(yaml.safe_dump({
        "name": "mini", "description": "A tiny test warehouse with a loop of passageways.",
        "map": "map.png", "pixel_to_world": [[0.1, 0, 0], [0, -0.1, 6], [0, 0, 1]],
        "schema": {"node_types": ["CORNER", "PASSAGEWAY", "INTERSECTION", "BLIND CORNER", "OPEN AREA"],
                   "edge_types": ["PASSAGEWAY", "NARROW PASSAGEWAY", "DOORWAY"]}}))
    graph = {"directed": False, "multigraph": False, "graph": {},
             "nodes": [{"type": t, "pos": list(p), "id": i} for i, (t, p) in NODES.items()],
             "links": [{"type": t, "source": a, "target": b} for a, b, t in EDGES]}
    (root / "scene_graph.json").write_text(json.dumps(graph, indent=4))
    return root




def scenario_reply(n: int = 2, **changes: object) -> dict:
    reply = {"scenario_description": "The robot carries a box along the loop and meets workers at the "
                                     "blind corner.",
             "number_of_humans": n,
             "human_behaviors": {f"human{i}": f"Worker {i} walks to the corner and stops when the robot blocks "
                                              f"the way." for i in range(1, n + 1)},
             "expected_robot_behavior": "Slow down at the corner and say EXCUSE ME.",
             "spec": spec_for(n)}
    reply.update(changes)
    return reply


def spec_for(n: int = 2) -> dict:
    """A spec in which every worker stops (looks at the robot) when it blocks the way at the blind corner."""
    return {"script": {"route": "along the loop through the blind corner", "cues": []},
            "encounters": [{"id": "e1", "place": "BLIND CORNER", "humans": [
                {"human": f"human{i}", "trigger": "robot_blocking", "reaction": "stop", "distance": 0.5}
                for i in range(1, n + 1)]}],
            "criteria": [*({"id": f"c{i}", "kind": "meets", "human": f"human{i}", "encounter": "e1"}
                           for i in range(1, n + 1)),
                         *({"id": f"c{n + i}", "kind": "stops_near_robot", "human": f"human{i}", "encounter": "e1",
                            "text": f"human{i} stops with the robot in its way"} for i in range(1, n + 1))]}


def paths_reply(**changes: object) -> dict:
    reply = {"reasoning": "they meet at 11",
             "interaction_points": {"human1": "11", "human2": "11"},
             "trajectories": {"robot": ["32", "ch", "11", "07"], "human1": ["07", "11", "ch"],
                              "human2": ["f7", "07", "11"]},
             "group_ids": {"human1": -1, "human2": -1},
             "encounter_nodes": {"e1": "11"}}
    reply.update(changes)
    return reply


STOP_TREE = ("<root main_tree_to_execute='Stop'><include path='BTRegularNav.xml'/><BehaviorTree ID='Stop'>"
             "<Fallback name='F'><Sequence name='S'><IsRobotBlocking agent_id='{id}' distance='0.5'/>"
             "<LookAtRobot agent_id='{id}'/></Sequence><Sequence name='RegNav'>"
             "<SetBlackboard output_key='agentid' value='{id}'/><SetBlackboard output_key='timestep' value='{dt}'/>"
             "<SubTree ID='RegularNavTree' id='agentid' dt='timestep'/></Sequence></Fallback></BehaviorTree></root>")


LOOK_TREE = STOP_TREE.replace("distance='0.5'", "distance='1.0'")  # a changed tree for the same spec


def moved_paths_reply(**changes: object) -> dict:
    """A changed answer to a paths re-ask (human2 starts farther back): an unchanged one goes to stage 1."""
    return paths_reply(trajectories={"robot": ["32", "ch", "11", "07"], "human1": ["07", "11", "ch"],
                                     "human2": ["d9", "f7", "07", "11"]}, **changes)


def tree_reply(tree: str = STOP_TREE) -> dict:
    return {"reasoning": "stop when blocked", "tree": tree}


def write_script(path: Path, stages: dict) -> Path:
    path.write_text(yaml.safe_dump({"stages": stages}, sort_keys=False, width=1000))
    return path


def request_for(location: Path, **changes: object) -> ScenarioRequest:
    values = {"location": str(location), "context": "Delivery robot in a small warehouse",
              "task": "Transport a box", "rough": "The robot meets a worker at a blind corner",
              "llm": "replay"}
    values.update(changes)
    return ScenarioRequest(**values)


def run_replay(script: Path, location: Path, out: Path, **kwargs: object):
    """generate() against a replay script; returns (run or exception, llm) so tests can read llm.calls."""
    llm = make_llm(f"replay:{script}", transcript=out / "transcript.jsonl", use_cache=False)
    request = kwargs.pop("request", None) or request_for(location)
    try:
        return generate(request, llm, out, **kwargs), llm
    except Exception as exc:  # noqa: BLE001 - the test inspects it
        return exc, llm


def manifest(out: Path) -> dict:
    return json.loads(RunFolder(out).manifest_path.read_text())


def user_texts(messages) -> list[str]:  # noqa: ANN001
    return [m.content for m in messages if m.role == "user"]
