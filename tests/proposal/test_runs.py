"""Run folders: resume after a crash, --redo, --from, proposals, review, naive, verify."""

from __future__ import annotations

import json

import pytest
from gen_helpers import (
    LOOK_TREE,
    STOP_TREE,
    manifest,
    moved_paths_reply,
    paths_reply,
    request_for,
    run_replay,
    scenario_reply,
    tree_reply,
    user_texts,
    write_script,
)

from socnavgen.errors import LLMError, SocnavgenError
from socnavgen.proposal import Run
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
    new_paths = paths_reply(trajectories={"robot": ["d9", "ch", "11"], "human1": ["11", "ch"], "human2": ["ch", "11"]},
                            interaction_points={"human1": "11", "human2": "11"})
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


def _finding(blame, human=None, evidence="never closer than 6 m"):  # noqa: ANN001, ANN202
    from socnavgen.verify.models import Finding

    return Finding(name="c1 meets", kind="meets", passed=False, evidence=evidence, human=human, blame=blame,
                   blame_human=human if blame == "behaviors" else None, blame_reason=f"{blame} can fix it")


def _report(passed, findings):  # noqa: ANN001, ANN202
    from socnavgen.verify.models import VerifyReport

    return VerifyReport(run="run", passed=passed, findings=findings)


def _verifier(*reports):  # noqa: ANN002, ANN202
    queue = iter(reports)
    seen = []

    def verify(run_dir, location=None):  # noqa: ANN001, ANN202
        assert location is not None and location.name  # the pipeline's loaded Location, not a path to re-read
        seen.append(run_dir)
        return next(queue)
    return verify, seen


def test_verify_requeries_the_blamed_stage(tmp_path, mini_location):
    verify, seen = _verifier(_report(False, [_finding("paths")]), _report(True, []))
    script = full_script(tmp_path, paths=[paths_reply(), moved_paths_reply()])
    run, llm = run_replay(script, mini_location, tmp_path / "run", verify=True, verifier=verify)
    assert isinstance(run, Run), run
    asks = [m for s, _k, m in llm.calls if s == "paths"]
    assert len(asks) == 2 and "never closer than 6 m" in asks[1][-1].content
    assert run.verify.passed and len(seen) == 2
    assert manifest(tmp_path / "run")["stages"]["verify"]["status"] == "done"
    assert manifest(tmp_path / "run")["status"] == "done"


def test_robot_script_failure_goes_back_to_the_spec_never_to_the_trees(tmp_path, mini_location):
    """What only the robot can cause (it never said EXCUSE ME) re-asks stage 1 with the finding; the trees
    and paths are kept when the encounters did not change, and no behaviors stage is asked."""
    said = scenario_reply()
    said["spec"]["script"]["cues"] = [{"trigger": {"when": "blocked", "distance": 2.0}, "say": "EXCUSE ME"}]
    verify, _ = _verifier(_report(False, [_finding("robot_script", evidence="the robot never said EXCUSE ME")]),
                          _report(True, []))
    script = full_script(tmp_path, scenario=[scenario_reply(), said])
    out = tmp_path / "run"
    run, llm = run_replay(script, mini_location, out, verify=True, verifier=verify)
    assert isinstance(run, Run), run
    assert stages_called(llm).count(("scenario", None)) == 2
    assert [k for s, k in stages_called(llm) if s == "behaviors"] == ["human1", "human2"]  # only the first time
    assert "the robot never said EXCUSE ME" in [m for s, _k, m in llm.calls if s == "scenario"][1][-1].content
    spec = RunFolder(out).read_spec()
    assert spec.script.cues[0].say == "EXCUSE ME" and spec.encounters[0].node == "11"  # grounding carried over


def test_a_behaviors_failure_reasks_only_that_humans_tree(tmp_path, mini_location):
    verify, _ = _verifier(_report(False, [_finding("behaviors", human="human2")]), _report(True, []))
    script = full_script(tmp_path, behaviors={"human1": [tree_reply()], "human2": [tree_reply(), tree_reply(LOOK_TREE)]})
    run, llm = run_replay(script, mini_location, tmp_path / "run", verify=True, verifier=verify)
    assert isinstance(run, Run), run
    assert [k for s, k in stages_called(llm) if s == "behaviors"] == ["human1", "human2", "human2"] or \
        [k for s, k in stages_called(llm) if s == "behaviors"] == ["human2", "human1", "human2"]


def test_a_run_whose_verification_fails_does_not_say_done(tmp_path, mini_location):
    failing = _report(False, [_finding("paths")])
    verify, seen = _verifier(failing, failing, failing)
    # each round the paths answer the same, so stage 1 is asked each time too (and answers the same)
    script = full_script(tmp_path, paths=[paths_reply()] * 3, scenario=[scenario_reply()] * 3)
    out = tmp_path / "run"
    run, _ = run_replay(script, mini_location, out, verify=True, verifier=verify)
    assert isinstance(run, Run), run
    assert not run.verify.passed and len(seen) == 3
    record = manifest(out)
    assert record["stages"]["verify"]["status"] == "failed"
    assert record["status"] == "failed" and "never closer than 6 m" in record["message"]


def test_findings_without_blame_are_not_sent_to_any_stage(tmp_path, mini_location):
    verify, seen = _verifier(_report(False, [_finding(None)]), _report(True, []))
    run, llm = run_replay(full_script(tmp_path), mini_location, tmp_path / "run", verify=True, verifier=verify)
    assert isinstance(run, Run), run
    assert len(seen) == 1 and len(llm.calls) == 4  # scenario, paths, 2 trees: no re-ask
    assert manifest(tmp_path / "run")["status"] == "failed"


def test_paths_and_a_blamed_tree_are_reasked_in_the_same_round(tmp_path, mini_location):
    verify, seen = _verifier(_report(False, [_finding("paths"), _finding("behaviors", human="human1")]),
                             _report(True, []))
    script = full_script(tmp_path, paths=[paths_reply(), moved_paths_reply()],
                         behaviors={"human1": [tree_reply(), tree_reply(LOOK_TREE)], "human2": [tree_reply()]})
    run, llm = run_replay(script, mini_location, tmp_path / "run", verify=True, verifier=verify)
    assert isinstance(run, Run), run
    later = stages_called(llm)[4:]  # after scenario, paths, two trees
    assert later == [("paths", None), ("behaviors", "human1")] and len(seen) == 2
