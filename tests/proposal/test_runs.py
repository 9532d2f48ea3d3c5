"""Run folders: resume after a crash, --redo, --from, proposals, review, naive, verify."""

from __future__ import annotations

import json

import pytest
from gen_helpers import (
    STOP_TREE,
    manifest,
    paths_reply,
    request_for,
    run_replay,
    scenario_reply,
    tree_reply,
    user_texts,
    write_script,
)

from socnavgen.errors import LLMError, SocnavgenError
from socnavgen.proposal import Run, pipeline
from socnavgen.proposal.pipeline import copy_run
from socnavgen.proposal.review import ReviewDecision
from socnavgen.run import RunFolder

GOOD_TREES = {"human1": [tree_reply()], "human2": [tree_reply()]}


def full_script(tmp_path, name="s.yaml", **stages):  # noqa: ANN001, ANN201
    base = {"scenario": [scenario_reply()], "paths": [paths_reply()], "behaviors": GOOD_TREES}
    base.update(stages)
    return write_script(tmp_path / name, base)


def stages_called(llm) -> list[tuple[str, str | None]]:  # noqa: ANN001
    return [(s, k) for s, k, _ in llm.calls]


def test_resume_after_a_crash_mid_behaviors(tmp_path, mini_location):
    out = tmp_path / "run"
    crashing = full_script(tmp_path, "crash.yaml", behaviors={"human1": [tree_reply()]})  # human2 unscripted
    error, _ = run_replay(crashing, mini_location, out)
    assert isinstance(error, LLMError)
    folder = RunFolder(out)
    assert manifest(out)["status"] == "failed"
    assert set(folder.behaviors()) == {"human1"}  # the finished tree is kept
    scenario_before = folder.scenario_path.read_text()
    leftovers = [p.name for p in out.rglob("*.tmp")]
    assert leftovers == []  # no half-written file
    rest = write_script(tmp_path / "rest.yaml", {"behaviors": {"human2": [tree_reply()]}})
    run, llm = run_replay(rest, mini_location, out)
    assert isinstance(run, Run), run
    assert stages_called(llm) == [("behaviors", "human2")]  # nothing earlier is asked again
    assert folder.scenario_path.read_text() == scenario_before
    assert set(run.behaviors) == {"human1", "human2"}
    assert manifest(out)["status"] == "done"


def test_redo_paths_keeps_the_scenario_and_redoes_the_trees(tmp_path, mini_location):
    out = tmp_path / "run"
    run, _ = run_replay(full_script(tmp_path), mini_location, out)
    assert isinstance(run, Run)
    folder = RunFolder(out)
    scenario_before = folder.scenario_path.read_text()
    new_paths = paths_reply(trajectories={"robot": ["d9", "ch", "11"], "human1": ["11", "ch"], "human2": ["ch"]},
                            interaction_points={"human1": "ch", "human2": "ch"})
    script = write_script(tmp_path / "redo.yaml", {"paths": [new_paths], "behaviors": GOOD_TREES})
    run, llm = run_replay(script, mini_location, out, redo={"paths"})
    assert isinstance(run, Run), run
    assert sorted(stages_called(llm)) == [("behaviors", "human1"), ("behaviors", "human2"), ("paths", None)]
    assert folder.scenario_path.read_text() == scenario_before
    assert folder.read_paths().robot == ["d9", "ch", "11"]
    assert manifest(out)["stages"]["paths"]["attempts"] == 1  # the redone stage's record starts afresh


def test_redo_behaviors_only(tmp_path, mini_location):
    out = tmp_path / "run"
    run_replay(full_script(tmp_path), mini_location, out)
    paths_before = RunFolder(out).paths_path.read_text()
    script = write_script(tmp_path / "redo.yaml", {"behaviors": GOOD_TREES})
    run, llm = run_replay(script, mini_location, out, redo={"behaviors"})
    assert isinstance(run, Run), run
    assert {s for s, _ in stages_called(llm)} == {"behaviors"}
    assert RunFolder(out).paths_path.read_text() == paths_before


def test_from_run_into_another_folder(tmp_path, mini_location):
    first = tmp_path / "first"
    run_replay(full_script(tmp_path), mini_location, first)
    second = tmp_path / "second"
    copy_run(first, second)
    script = write_script(tmp_path / "redo.yaml", {"behaviors": GOOD_TREES})
    run, llm = run_replay(script, mini_location, second, redo={"behaviors"},
                          request=RunFolder(first).read_request())
    assert isinstance(run, Run), run
    assert RunFolder(second).scenario_path.read_text() == RunFolder(first).scenario_path.read_text()
    with pytest.raises(SocnavgenError, match="not empty"):
        copy_run(first, second)


def test_a_folder_with_another_request_is_not_resumed(tmp_path, mini_location):
    out = tmp_path / "run"
    run_replay(full_script(tmp_path), mini_location, out)
    error, _ = run_replay(full_script(tmp_path), mini_location, out,
                          request=request_for(mini_location, task="Clean the floor"))
    assert isinstance(error, SocnavgenError) and "different request (task differ)" in error.message


def test_unknown_redo_stage(tmp_path, mini_location):
    error, _ = run_replay(full_script(tmp_path), mini_location, tmp_path / "run", redo={"tree"})
    assert isinstance(error, SocnavgenError) and "cannot redo tree" in error.message


def test_proposals_differ_and_pick(tmp_path, mini_location):
    second = scenario_reply(scenario_description="Two workers stand at the open area and block the robot.")
    script = full_script(tmp_path, scenario=[scenario_reply(), second])
    out = tmp_path / "run"
    run, llm = run_replay(script, mini_location, out, request=request_for(mini_location, proposals=2, pick=1))
    assert isinstance(run, Run), run
    asks = [m for s, _k, m in llm.calls if s == "scenario"]
    assert len(asks) == 2
    assert "clearly DIFFERENT" not in user_texts(asks[0])[-1]
    assert scenario_reply()["scenario_description"] in user_texts(asks[1])[-1]
    stored = json.loads(RunFolder(out).proposals_path.read_text())
    assert [p["scenario_description"] for p in stored] == [scenario_reply()["scenario_description"],
                                                           second["scenario_description"]]
    assert run.scenario.scenario_description == second["scenario_description"]
    assert manifest(out)["stages"]["scenario:proposal2"]["attempts"] == 1


def test_review_edit_request_goes_back_to_the_model(tmp_path, mini_location):
    edited = scenario_reply(n=2, scenario_description="The robot meets the workers in the open area instead.")
    script = full_script(tmp_path, scenario=[scenario_reply(), edited])
    decisions = iter([ReviewDecision(action="edit", request="Move the encounter to the open area."),
                      ReviewDecision(action="accept"), ReviewDecision(action="accept"),
                      ReviewDecision(action="accept"), ReviewDecision(action="accept")])
    shown: list[tuple[str, str | None]] = []

    def review(stage, key, result):  # noqa: ANN001, ANN202
        shown.append((stage, key))
        return next(decisions)

    run, llm = run_replay(script, mini_location, tmp_path / "run", review=review)
    assert isinstance(run, Run), run
    second = [m for s, _k, m in llm.calls if s == "scenario"][1]
    assert second[-2].role == "assistant"
    assert "Move the encounter to the open area." in second[-1].content
    assert run.scenario.scenario_description.endswith("instead.")
    assert shown == [("scenario", None), ("scenario", None), ("paths", None), ("behaviors", "human1"),
                     ("behaviors", "human2")]


def test_naive_baseline_uses_the_same_checks_and_files(tmp_path, mini_location):
    good = {**scenario_reply(), **paths_reply(), "trees": {"human1": STOP_TREE, "human2": STOP_TREE}}
    bad = {**good, "trajectories": {**good["trajectories"], "robot": ["0e", "07"]}}
    script = write_script(tmp_path / "naive.yaml", {"naive": [bad, good]})
    out = tmp_path / "run"
    run, llm = run_replay(script, mini_location, out, request=request_for(mini_location, naive=True))
    assert isinstance(run, Run), run
    asks = [m for s, _k, m in llm.calls if s == "naive"]
    assert len(asks) == 2 and "there is no edge between 0e and 07" in user_texts(asks[1])[-1]
    assert "TUTORIAL" not in asks[0][0].content and "EXAMPLES" not in asks[0][0].content
    folder = RunFolder(out)
    assert folder.scenario_path.is_file() and folder.paths_path.is_file()
    assert set(folder.behaviors()) == {"human1", "human2"}
    assert manifest(out)["stages"]["naive"]["attempts"] == 2


class _Finding:
    def __init__(self, stage, human=None):  # noqa: ANN001
        self.name, self.evidence, self.stage, self.human, self.passed = "meets_human", "never closer than 6 m", \
            stage, human, False


class _Report:
    def __init__(self, passed, findings):  # noqa: ANN001
        self.passed, self.findings = passed, findings


def test_verify_requeries_the_blamed_stage(tmp_path, mini_location, monkeypatch):
    reports = iter([_Report(False, [_Finding("paths")]), _Report(True, [])])
    seen = []

    def fake_verify(run_dir):  # noqa: ANN001, ANN202
        seen.append(run_dir)
        return next(reports)

    monkeypatch.setattr(pipeline, "verifier", lambda: fake_verify)
    script = full_script(tmp_path, paths=[paths_reply(), paths_reply()])
    run, llm = run_replay(script, mini_location, tmp_path / "run", verify=True)
    assert isinstance(run, Run), run
    asks = [m for s, _k, m in llm.calls if s == "paths"]
    assert len(asks) == 2 and "never closer than 6 m" in asks[1][-1].content
    assert run.verify.passed and len(seen) == 2
    assert manifest(tmp_path / "run")["stages"]["verify"]["status"] == "done"
