"""`generate --verify` with the REAL simulator and verifier (no fake): the stage re-asked after a failed
verification is exactly the one the verifier blames (robot_script / spec -> stage 1, paths -> stage 2,
behaviors -> that human's tree), with the verifier's own finding, and the run records both rounds."""

from __future__ import annotations

import json
from pathlib import Path

import yaml

from socnavgen.llm import make_llm
from socnavgen.proposal import generate
from socnavgen.run import RunFolder, ScenarioRequest

SPEC = {"script": {"route": "from 6r through the blind corner f7 to 54",
                   "cues": [{"trigger": {"when": "blocked", "distance": 2.5}, "say": "EXCUSE ME", "hold": 3.0}]},
        "encounters": [{"id": "e1", "place": "BLIND CORNER", "humans": [
            {"human": "human1", "trigger": "robot_says", "phrase": "EXCUSE ME", "reaction": "give_way"}]}],
        "criteria": [{"id": "c1", "kind": "reacts_after_phrase", "human": "human1", "encounter": "e1",
                      "phrase": "EXCUSE ME", "reaction": "give_way", "seconds": 5.0}]}
SCENARIO = {"scenario_description": "A worker comes round the blind corner f7 and gives way when asked.",
            "number_of_humans": 1,
            "human_behaviors": {"human1": "Walks to the entrance and gives way when the robot says EXCUSE ME."},
            "expected_robot_behavior": "Say EXCUSE ME at the corner and pass once the worker stepped aside.",
            "spec": SPEC}
PATHS = {"reasoning": "f7 is on both paths.", "trajectories": {"robot": ["6r", "f7", "54"], "human1": ["54", "f7", "6r"]},
         "group_ids": {"human1": -1}, "interaction_points": {"human1": "f7"}, "encounter_nodes": {"e1": "f7"}}
WAITS_FOR_EXCUSE_ME = """<root main_tree_to_execute='T'><include path='BTRegularNav.xml'/><BehaviorTree ID='T'>
<Fallback name='F'><Sequence name='Asked'><RobotSays agent_id='{id}' message='4'/>
<GiveWaytoRobot agent_id='{id}' time_step='{dt}'/></Sequence>
<Sequence name='Walk'><SetBlackboard output_key='agentid' value='{id}'/><SetBlackboard output_key='timestep' value='{dt}'/>
<SubTree ID='RegularNavTree' id='agentid' dt='timestep'/></Sequence></Fallback></BehaviorTree></root>"""
REASKED = {"robot_script": "scenario", "spec": "scenario", "paths": "paths", "behaviors": "behaviors"}


def test_verify_reasks_exactly_the_blamed_stage(tmp_path: Path, warehouse_dir: Path) -> None:
    tree = json.dumps({"reasoning": "r", "tree": WAITS_FOR_EXCUSE_ME})
    script = tmp_path / "script.yaml"
    script.write_text(yaml.safe_dump({"stages": {
        "scenario": [json.dumps(SCENARIO)] * 2, "paths": [json.dumps(PATHS)] * 2,
        "behaviors": {"human1": [tree] * 2}}}))
    out = tmp_path / "run"
    llm = make_llm(f"replay:{script}", transcript=out / "transcript.jsonl", use_cache=False)
    request = ScenarioRequest(location=str(warehouse_dir), context="Delivery robot in a warehouse",
                              task="Carry a box", llm=f"replay:{script}", max_restarts=1)
    first_reports = []

    from socnavgen.verify import verify_run

    def recording_verify(run_dir: Path, location=None):  # noqa: ANN001, ANN202
        report = verify_run(run_dir, location=location)
        first_reports.append(report)
        return report

    run = generate(request, llm, out, verify=True, verifier=recording_verify)
    record = json.loads((out / "manifest.json").read_text())
    first = first_reports[0]
    if first.passed:
        assert len(first_reports) == 1 and record["status"] == "done"
        return
    blamed = {REASKED[f.blame] for f in first.failures if f.blame}
    asked_again = {stage for stage, _key, _m in llm.calls[3:]}  # after scenario, paths, the tree
    first_stage = min(blamed, key=["scenario", "paths", "behaviors"].index)
    assert first_stage in asked_again
    if first_stage == "scenario":
        assert "behaviors" not in asked_again  # never a tree for what only the robot or the spec can fix
        assert any(f.evidence in llm.calls[3][2][-1].content for f in first.failures if f.blame in REASKED
                   and REASKED[f.blame] == "scenario")
    assert record["stages"]["verify"]["attempts"] == 2
    report = json.loads((out / "sim" / "verify.json").read_text())
    assert report["passed"] == run.verify.passed
    assert record["status"] == ("done" if report["passed"] else "failed")
    assert RunFolder(out).read_spec().encounters[0].node == "f7"
