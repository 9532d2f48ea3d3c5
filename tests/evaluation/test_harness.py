"""The evaluation harness end to end on scripted replies: valid and invalid runs are counted as such,
reports are written, and a second invocation resumes instead of asking again."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import yaml

from socnavgen.evaluation.harness import EvalSettings, plan_jobs, run_eval
from socnavgen.evaluation.report import table1, table3, write_reports
from socnavgen.evaluation.suite import EvalSuite, load_suite

TREE = """<root main_tree_to_execute='StopTree'>
  <include path='BTRegularNav.xml'/>
  <BehaviorTree ID='StopTree'>
    <Fallback name='StopOrWalk'>
      <Sequence name='Stop'>
        <IsRobotBlocking agent_id='{id}' distance='1.0'/>
        <LookAtRobot agent_id='{id}'/>
      </Sequence>
      <Sequence name='Walk'>
        <SetBlackboard output_key='agentid' value='{id}'/>
        <SetBlackboard output_key='timestep' value='{dt}'/>
        <SubTree ID='RegularNavTree' id='agentid' dt='timestep'/>
      </Sequence>
    </Fallback>
  </BehaviorTree>
</root>"""

SCENARIO = {"scenario_description": "A worker meets the robot at a blind corner and stops.",
            "number_of_humans": 1, "human_behaviors": {"Human 1": "Stops while the robot blocks the way."},
            "expected_robot_behavior": "Slow down at the corner and pass.",
            "spec": {"encounters": [{"id": "e1", "place": "BLIND CORNER", "humans": [
                {"human": "human1", "trigger": "robot_blocking", "reaction": "stop", "distance": 1.0}]}],
                     "criteria": [{"id": "c1", "kind": "meets", "human": "human1", "encounter": "e1"},
                                  {"id": "c2", "kind": "stops_near_robot", "human": "human1", "encounter": "e1"}]}}
PATHS = {"reasoning": "f7 is a blind corner on both paths.",
         "trajectories": {"robot": ["6r", "f7", "54"], "human1": ["54", "f7", "6r"]},
         "group_ids": {"human1": -1}, "interaction_points": {"human1": "f7"}, "encounter_nodes": {"e1": "f7"}}
BROKEN_TREE = TREE.replace("IsRobotBlocking", "IsRobotScary")


def _script(path: Path) -> Path:
    naive = {**SCENARIO, **PATHS, "trees": {"human1": BROKEN_TREE}}  # paths fine, tree never valid
    data = {"stages": {
        "scenario": [json.dumps(SCENARIO)],
        "paths": [json.dumps(PATHS)],
        "behaviors": {"human1": [json.dumps({"reasoning": "stop when blocked", "tree": TREE})]},
        "naive": [json.dumps(naive)] * 2,
    }}
    path.write_text(yaml.safe_dump(data))
    return path


def _suite(repo_root: Path) -> EvalSuite:
    suite = load_suite()
    suite.location = str(repo_root / "examples" / "locations" / "warehouse")
    suite.proposal_scenes = suite.proposal_scenes[:1]
    suite.path_scenes = suite.path_scenes[1:2]  # Scene B, the blind corner
    return suite


def test_bundled_suite_has_the_papers_scenes() -> None:
    suite = load_suite()
    assert [s.name for s in suite.proposal_scenes] == ["Scene 1", "Scene 2", "Scene 3"]
    assert [s.name for s in suite.path_scenes] == ["Scene A", "Scene B", "Scene C"]
    assert "blind corner" in suite.path_scenes[1].rough
    assert suite.paper_table3["ours"].path_validity == 0.86 and suite.paper_table3["naive"].bt_validity == 0.13


def test_eval_counts_valid_and_invalid_runs_and_resumes(tmp_path: Path, repo_root: Path) -> None:
    suite = _suite(repo_root)
    script = _script(tmp_path / "script.yaml")
    settings = EvalSettings(llm=f"replay:{script}", out=tmp_path / "eval", runs=2, proposals=2, verify=False,
                            max_requeries=1, max_restarts=0, temperature=0.0, use_cache=False)
    jobs = plan_jobs(suite, settings, suite.location)
    assert len(jobs) == 2 * 2 + 2 * 2  # Table I: 2 proposals x (with, without rough); III: 2 runs x 2 methods

    outcomes = run_eval(suite, settings, suite.location)
    rows = {r.method: r for r in table3(outcomes, suite)}
    assert rows["ours"].path_validity == 1.0 and rows["ours"].bt_validity == 1.0
    assert rows["ours"].path_first_attempt == 1.0 and rows["ours"].bt_first_attempt == 1.0
    assert rows["ours"].attempts_per_valid == 3.0
    # The naive replies always had valid paths and an unknown node in the tree: counted as invalid trees.
    assert rows["naive"].path_validity == 1.0 and rows["naive"].bt_validity == 0.0
    assert rows["naive"].tokens_per_valid is None and rows["naive"].paper_bt_validity == 0.13
    assert all(r.passed_checks == 1.0 for r in table1(outcomes))

    files = write_reports(settings.out, outcomes, suite, settings.model_dump(mode="json"), None)
    names = {f.name for f in files}
    assert names == {"results.csv", "results.md", "ratings.md"}
    md = (settings.out / "results.md").read_text()
    assert f"replay:{script}" in md and "| naive | 2 | 1.00 | 0.00 |" in md
    with open(settings.out / "results.csv") as fh:
        assert len(list(csv.DictReader(fh))) == len(jobs)
    assert "A worker meets the robot" in (settings.out / "ratings.md").read_text()

    # Resume: the script file is gone, so any new question would fail; finished runs are read back.
    script.unlink()
    again = run_eval(suite, settings, suite.location)
    assert [o.model_dump() for o in again] == [o.model_dump() for o in outcomes]


def test_eval_simulates_and_verifies_valid_runs(tmp_path: Path, repo_root: Path) -> None:
    suite = _suite(repo_root)
    settings = EvalSettings(llm=f"replay:{_script(tmp_path / 'script.yaml')}", out=tmp_path / "eval", runs=1,
                            tables=["III"], methods=["ours"], verify=True, max_requeries=1, max_restarts=0,
                            temperature=0.0, use_cache=False)
    outcomes = run_eval(suite, settings, suite.location)
    assert len(outcomes) == 1 and outcomes[0].valid
    report = json.loads((Path(outcomes[0].folder) / "sim" / "verify.json").read_text())
    assert outcomes[0].verified is report["passed"]
    assert (Path(outcomes[0].folder) / "sim" / "trace.npz").is_file()
    row = table3(outcomes, suite)[0]
    assert row.verified_share == (1.0 if report["passed"] else 0.0)
