"""`generate --verify` with the REAL simulator and verifier (no fake): a tree whose key condition never
fires in simulation is re-asked with the verifier's own finding, and the run records both rounds."""

from __future__ import annotations

import json
from pathlib import Path

import yaml

from socnavgen.llm import make_llm
from socnavgen.proposal import generate
from socnavgen.run import RunFolder, ScenarioRequest

SCENARIO = {"scenario_description": "A worker stands at a blind corner and gives way when asked.",
            "number_of_humans": 1, "human_behaviors": {"human1": "Gives way when the robot says EXCUSE ME."},
            "expected_robot_behavior": "Say EXCUSE ME and pass."}
PATHS = {"reasoning": "f7 is on both paths.", "trajectories": {"robot": ["6r", "f7", "54"], "human1": ["54", "f7", "6r"]},
         "group_ids": {"human1": -1}, "interaction_points": {"human1": "f7"}}
# The robot of this run never says EXCUSE ME (4): RobotSays can never succeed in simulation.
WAITS_FOR_EXCUSE_ME = """<root main_tree_to_execute='T'><include path='BTRegularNav.xml'/><BehaviorTree ID='T'>
<Fallback name='F'><Sequence name='Asked'><RobotSays agent_id='{id}' message='4'/>
<GiveWaytoRobot agent_id='{id}' time_step='{dt}'/></Sequence>
<Sequence name='Walk'><SetBlackboard output_key='agentid' value='{id}'/><SetBlackboard output_key='timestep' value='{dt}'/>
<SubTree ID='RegularNavTree' id='agentid' dt='timestep'/></Sequence></Fallback></BehaviorTree></root>"""
GIVES_WAY_WHEN_NEAR = WAITS_FOR_EXCUSE_ME.replace("<RobotSays agent_id='{id}' message='4'/>",
                                                  "<IsRobotNearby agent_id='{id}' distance='3.0'/>")


def test_verify_requeries_the_tree_with_the_real_finding(tmp_path: Path, warehouse_dir: Path) -> None:
    script = tmp_path / "script.yaml"
    script.write_text(yaml.safe_dump({"stages": {
        "scenario": [json.dumps(SCENARIO)], "paths": [json.dumps(PATHS)],
        "behaviors": {"human1": [json.dumps({"reasoning": "r", "tree": t})
                                 for t in (WAITS_FOR_EXCUSE_ME, GIVES_WAY_WHEN_NEAR)]}}}))
    out = tmp_path / "run"
    llm = make_llm(f"replay:{script}", transcript=out / "transcript.jsonl", use_cache=False)
    request = ScenarioRequest(location=str(warehouse_dir), context="Delivery robot in a warehouse",
                              task="Carry a box", llm=f"replay:{script}", max_restarts=1)
    run = generate(request, llm, out, verify=True)

    asks = [messages for stage, key, messages in llm.calls if stage == "behaviors"]
    assert len(asks) == 2, "the failing tree is asked again"
    correction = asks[1][-1].content
    assert "RobotSays" in correction and "never succeeded" in correction
    verify = json.loads((out / "manifest.json").read_text())["stages"]["verify"]
    assert verify["attempts"] == 2
    # The second tree is the one kept, and the verdict recorded is the real verifier's on it.
    assert "IsRobotNearby" in RunFolder(out).read_behavior("human1")
    report = json.loads((out / "sim" / "verify.json").read_text())
    assert report["passed"] == run.verify.passed
    assert verify["status"] == ("done" if report["passed"] else "failed")
