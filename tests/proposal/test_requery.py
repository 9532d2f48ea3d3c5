"""The re-query / restart / failure policy, driven by replay scripts (no model)."""

from __future__ import annotations

import json

import pytest
from gen_helpers import (
    STOP_TREE,
    manifest,
    paths_reply,
    run_replay,
    scenario_reply,
    tree_reply,
    user_texts,
    write_script,
)
from test_path_checks import MISTAKES

from socnavgen.bt.validate import validate_bt_text
from socnavgen.errors import StageFailed
from socnavgen.llm.transcript import read_transcript
from socnavgen.proposal import Run
from socnavgen.run import RunFolder

GOOD_TREES = {"human1": [tree_reply()], "human2": [tree_reply()]}


def calls_of(llm, stage):  # noqa: ANN001
    return [messages for s, _key, messages in llm.calls if s == stage]


@pytest.mark.parametrize("case", sorted(MISTAKES))
def test_each_path_mistake_is_requeried_with_its_message(tmp_path, mini_location, case):
    changes, expected = MISTAKES[case]
    bad = paths_reply(**changes)
    script = write_script(tmp_path / "s.yaml", {"scenario": [scenario_reply()], "paths": [bad, paths_reply()],
                                                "behaviors": GOOD_TREES})
    run, llm = run_replay(script, mini_location, tmp_path / "run")
    assert isinstance(run, Run), run
    first, second = calls_of(llm, "paths")
    assert second[:len(first)] == first  # the same conversation, continued
    assistant, correction = second[len(first):]
    assert assistant.role == "assistant" and json.loads(assistant.content) == bad
    assert correction.role == "user" and expected in correction.content
    record = manifest(tmp_path / "run")["stages"]["paths"]
    assert (record["attempts"], record["restarts"], record["status"]) == (2, 0, "done")
    checks = [e for e in read_transcript(tmp_path / "run" / "transcript.jsonl")
              if e.get("kind") == "check" and e["stage"] == "paths"]
    assert [c["valid"] for c in checks] == [False, True] and any(expected in m for m in checks[0]["mistakes"])


def test_restart_after_three_failed_requeries(tmp_path, mini_location):
    bad = paths_reply(trajectories={"robot": ["0e", "07"], "human1": ["07"], "human2": ["07"]},
                      interaction_points={"human1": "07", "human2": "07"})
    script = write_script(tmp_path / "s.yaml", {"scenario": [scenario_reply()], "paths": [bad] * 4 + [paths_reply()],
                                                "behaviors": GOOD_TREES})
    run, llm = run_replay(script, mini_location, tmp_path / "run")
    assert isinstance(run, Run), run
    paths_calls = calls_of(llm, "paths")
    assert len(paths_calls) == 5
    assert [len(c) for c in paths_calls[:4]] == [2, 4, 6, 8]  # each re-query adds the answer + the correction
    restarted = paths_calls[4]
    assert restarted == paths_calls[0]  # a fresh conversation: the first prompt only
    assert not any("there is no edge between 0e and 07" in text for text in user_texts(restarted))
    assert "there is no edge between 0e and 07" in user_texts(paths_calls[3])[-1]
    record = manifest(tmp_path / "run")["stages"]["paths"]
    assert (record["attempts"], record["restarts"]) == (5, 1)


def test_clear_failure_after_the_restart_limit(tmp_path, mini_location):
    from gen_helpers import request_for
    bad = paths_reply(trajectories={"robot": ["0e", "zz"], "human1": ["07"], "human2": ["07"]},
                      interaction_points={})
    script = write_script(tmp_path / "s.yaml", {"scenario": [scenario_reply()], "paths": [bad] * 8})
    out = tmp_path / "run"
    error, llm = run_replay(script, mini_location, out, request=request_for(mini_location, max_restarts=1))
    assert isinstance(error, StageFailed)
    assert "stage 'paths'" in error.message and "8 attempts" in error.message
    assert "node 'zz' is not in the scene graph" in error.message
    assert "there is no edge between 0e" not in error.message  # only the real mistakes of the last answer
    data = manifest(out)
    assert data["status"] == "failed" and "stage 'paths'" in data["message"]
    assert data["stages"]["paths"]["status"] == "failed" and data["stages"]["paths"]["attempts"] == 8
    assert data["stages"]["paths"]["restarts"] == 1
    folder = RunFolder(out)
    assert folder.scenario_path.is_file() and folder.request_path.is_file() and folder.transcript_path.is_file()
    assert not folder.paths_path.exists()
    assert len(calls_of(llm, "paths")) == 8


SCENARIO_MISTAKES = {
    "count mismatch": (scenario_reply(n=2, number_of_humans=3),
                       "number_of_humans is 3 but human_behaviors describes 2 human(s)"),
    "empty behavior": (scenario_reply(n=2, human_behaviors={"human1": "walks", "human2": "  "}),
                       "the behavior of human2 is empty"),
    "too many humans": (scenario_reply(n=9), "number_of_humans is 9; a scenario has 1 to 8 humans"),
    "no humans": (scenario_reply(n=0), "number_of_humans is 0; a scenario has 1 to 8 humans"),
    "bad name": (scenario_reply(n=1, human_behaviors={"Bob": "walks"}), "'Bob' is not a human name"),
    "gap in names": (scenario_reply(n=2, human_behaviors={"human1": "walks", "human3": "runs"}),
                     "name the humans human1, human2"),
    "not json": ("Sure! Here is a scenario: the robot meets a worker.", None),
}


@pytest.mark.parametrize("case", sorted(SCENARIO_MISTAKES))
def test_scenario_checks_requery(tmp_path, mini_location, case):
    bad, expected = SCENARIO_MISTAKES[case]
    script = write_script(tmp_path / "s.yaml", {"scenario": [bad, scenario_reply()], "paths": [paths_reply()],
                                                "behaviors": GOOD_TREES})
    run, llm = run_replay(script, mini_location, tmp_path / "run")
    assert isinstance(run, Run), run
    first, second = calls_of(llm, "scenario")
    correction = user_texts(second)[-1]
    assert correction.startswith("Your answer has the following mistake(s):")
    if expected:
        assert expected in correction
    assert manifest(tmp_path / "run")["stages"]["scenario"]["attempts"] == 2
    assert run.scenario.number_of_humans == 2


def test_scenario_human_names_are_normalised(tmp_path, mini_location):
    reply = scenario_reply(n=2, human_behaviors={"Human 2": "Stands at the corner and watches the robot",
                                                 "Human 1": "Walks past the corner to the shelves"})
    script = write_script(tmp_path / "s.yaml", {"scenario": [reply], "paths": [paths_reply()],
                                                "behaviors": GOOD_TREES})
    run, _ = run_replay(script, mini_location, tmp_path / "run")
    assert list(run.scenario.human_behaviors) == ["human1", "human2"]
    assert run.scenario.human_behaviors["human2"] == "Stands at the corner and watches the robot"


def test_invalid_tree_is_requeried_with_the_validator_message(tmp_path, mini_location):
    bad_tree = STOP_TREE.replace("<LookAtRobot agent_id='{id}'/>", "<DanceWithRobot agent_id='{id}'/>")
    expected = [str(p) for p in validate_bt_text(bad_tree, "behaviors/human2.xml", human_ids={0, 1}, agent_id=1)]
    assert expected  # the validator does reject it
    script = write_script(tmp_path / "s.yaml", {
        "scenario": [scenario_reply()], "paths": [paths_reply()],
        "behaviors": {"human1": [tree_reply()], "human2": [tree_reply(bad_tree), tree_reply()]}})
    run, llm = run_replay(script, mini_location, tmp_path / "run")
    assert isinstance(run, Run), run
    human2 = [m for s, k, m in llm.calls if s == "behaviors" and k == "human2"]
    assert len(human2) == 2
    correction = user_texts(human2[1])[-1]
    for message in expected:
        assert message in correction
    data = manifest(tmp_path / "run")["stages"]
    assert data["behaviors:human2"]["attempts"] == 2 and data["behaviors:human1"]["attempts"] == 1
    text = RunFolder(tmp_path / "run").read_behavior("human2")
    assert '<LookAtRobot agent_id="{id}"/>' in text and '<include path="BTRegularNav.xml"/>' in text
    assert validate_bt_text(text, "human2.xml") == []


def test_tree_failure_names_the_human_and_keeps_the_other_tree(tmp_path, mini_location):
    from gen_helpers import request_for
    bad_tree = STOP_TREE.replace("distance='0.5'", "")
    script = write_script(tmp_path / "s.yaml", {
        "scenario": [scenario_reply()], "paths": [paths_reply()],
        "behaviors": {"human1": [tree_reply()], "human2": [tree_reply(bad_tree)] * 4}})
    error, _ = run_replay(script, mini_location, tmp_path / "run",
                          request=request_for(mini_location, max_restarts=0))
    assert isinstance(error, StageFailed)
    assert "stage 'behaviors' for human2" in error.message and "distance" in error.message
    folder = RunFolder(tmp_path / "run")
    assert set(folder.behaviors()) == {"human1"}
    data = manifest(tmp_path / "run")
    assert data["status"] == "failed"
    stages = data["stages"]
    assert (stages["behaviors"]["status"], stages["behaviors:human1"]["status"],
            stages["behaviors:human2"]["status"]) == ("failed", "done", "failed")
    assert stages["behaviors:human2"]["attempts"] == 4 and "distance" in stages["behaviors:human2"]["errors"][0]
