"""What a --verify correction tells the model (round-7 players): which stage it is for and what that stage may
change (one answered a tree correction with a scenario JSON), and, when a stage 2 or 3 answer was CHANGED and the
very same findings came back, that the cause is not in that stage: the findings go to stage 1 instead."""

from __future__ import annotations

from gen_helpers import (
    LOOK_TREE,
    moved_paths_reply,
    paths_reply,
    request_for,
    run_replay,
    scenario_reply,
    tree_reply,
    write_script,
)

from socnavgen.proposal import Run
from socnavgen.proposal.verify_loop import REPEATED, SCOPE, describe, escalated
from socnavgen.verify.models import Finding, VerifyReport


def _finding(blame: str, human: str | None = None, evidence: str = "closest 0.97 m at t=33.8 s") -> Finding:
    return Finding(name="c1 stops_near_robot", kind="stops_near_robot", passed=False, evidence=evidence, human=human,
                   blame=blame, blame_human=human if blame == "behaviors" else None, blame_reason="did not stop")


def _verifier(*reports):  # noqa: ANN002, ANN202
    queue = iter([VerifyReport(run="run", passed=not found, findings=found) for found in reports])
    return lambda run_dir, location=None: next(queue)


def test_the_same_findings_after_a_changed_tree_go_to_the_spec():
    found = [_finding("behaviors", "human1")]
    sent = {("behaviors", "human1"): ([describe(f) for f in found], "<old tree/>")}
    out, notes = escalated({"behaviors": found}, sent, {("behaviors", "human1"): "<new tree/>"})
    assert list(out) == ["scenario"] and out["scenario"][0].criterion == found[0].criterion
    reason = out["scenario"][0].blame_reason
    assert reason.startswith("did not stop; the behavior tree of human1 (stage 3) was changed for this")
    assert "probably not there but in the spec" in reason and not notes
    assert found[0].blame_reason == "did not stop"  # the report's finding is not rewritten


def test_findings_that_changed_stay_with_their_stage_and_an_unchanged_answer_goes_to_stage_1():
    found = [_finding("behaviors", "human1")]
    other = [_finding("behaviors", "human1", evidence="closest 0.60 m at t=30.1 s")]
    sent = {("behaviors", "human1"): ([describe(f) for f in found], "<old tree/>")}
    moved, _ = escalated({"behaviors": other}, sent, {("behaviors", "human1"): "<new tree/>"})
    assert list(moved) == ["behaviors"]  # different numbers: the change did something
    same, notes = escalated({"behaviors": found}, sent, {("behaviors", "human1"): "<old tree/>"})
    assert list(same) == ["scenario"] and not notes  # it kept its answer: asking it again changes nothing (round 13)
    assert "answered with the same tree" in same["scenario"][0].blame_reason
    paths = [_finding("paths")]
    out, _ = escalated({"paths": paths}, {("paths", None): ([describe(f) for f in paths], {"a": 1})},
                       {("paths", None): {"a": 2}})
    assert list(out) == ["scenario"] and "the paths (stage 2) was changed" in out["scenario"][0].blame_reason
    spec = [_finding("spec")]
    again, notes = escalated({"scenario": spec}, {("scenario", None): ([describe(f) for f in spec], None)}, {})
    assert list(again) == ["scenario"] and notes == {("scenario", None): REPEATED}


def _tree_then_spec_loop(tmp_path, mini_location):  # noqa: ANN001, ANN202
    """The loop of a tree of human1 corrected, its changed tree giving the same findings, then stage 1 asked: the
    replayed model's calls."""
    script = write_script(tmp_path / "s.yaml", {
        "scenario": [scenario_reply(), scenario_reply()], "paths": [paths_reply()],
        "behaviors": {"human1": [tree_reply(), tree_reply(LOOK_TREE)], "human2": [tree_reply()]}})
    same = [_finding("behaviors", "human1")]
    run, llm = run_replay(script, mini_location, tmp_path / "run", verify=True,
                          verifier=_verifier(same, same, []))
    assert isinstance(run, Run), run
    return llm


def test_a_tree_correction_says_its_stage_and_a_repeat_goes_to_stage_1(tmp_path, mini_location):
    """Live through the loop: the tree of human1 is corrected, its changed tree gives the same findings, and the
    next correction goes to the scenario stage (its answer re-plans nothing here: the same shape)."""
    llm = _tree_then_spec_loop(tmp_path, mini_location)
    asked = [(s, k) for s, k, _ in llm.calls]
    assert asked.count(("behaviors", "human1")) == 2 and asked.count(("scenario", None)) == 2
    tree_fix = [m for s, k, m in llm.calls if (s, k) == ("behaviors", "human1")][1][-1].content
    assert tree_fix.startswith(SCOPE["behaviors"].replace("$human", "human1")[:60])
    assert "STAGE 3, the behavior tree of human1" in tree_fix and "Answer with the tree" in tree_fix
    spec_fix = [m for s, k, m in llm.calls if s == "scenario"][1][-1].content
    assert "STAGE 1, the scenario and its spec" in spec_fix and "came back with the same numbers" in spec_fix
    assert "closest 0.97 m at t=33.8 s" in spec_fix


def test_a_changed_tree_that_moves_the_numbers_by_a_hair_changed_nothing():
    """hospital_06: the tree changed, the deadlock came back 48.0 s from t=54.9 s instead of t=55.0 s, and the same
    correction went to the same tree: numbers this close are the same outcome; others are not."""
    from socnavgen.proposal.verify_loop import same_findings

    text = "moved 19.2 m without progress 48.0 s from t=55.0 s with human1 in its way (1.02 m gap)"
    assert same_findings([text], [text.replace("t=55.0", "t=54.9")])
    assert not same_findings([text], [text.replace("19.2 m", "12.0 m")])  # it moved otherwise
    assert not same_findings([text], [text.replace("human1", "human2")])  # someone else
    assert not same_findings([text], [text, text]) and not same_findings([], [])
    found = [_finding("behaviors", "human1", evidence="closest 0.97 m at t=33.8 s")]
    hair = [_finding("behaviors", "human1", evidence="closest 0.98 m at t=33.9 s")]
    out, _ = escalated({"behaviors": hair}, {("behaviors", "human1"): ([describe(f) for f in found], "<old tree/>")},
                       {("behaviors", "human1"): "<new tree/>"})
    assert list(out) == ["scenario"]


def test_an_encounter_stage_2_could_not_make_happen_goes_to_stage_1():
    """warehouse_06: a guide the robot follows can only meet it at its start, which stage 2's own rules forbid; the
    paths were re-asked for that encounter's meeting and its other criteria failed next: stage 1's, not stage 2's
    again. An encounter the paths were not asked about, and the derived order of encounters, stay with stage 2."""
    from socnavgen.proposal.verify_loop import routed
    from socnavgen.run.spec import ScenarioSpec

    spec = ScenarioSpec.model_validate({
        "encounters": [{"id": "e1", "place": "X", "humans": [{"human": "human1", "reaction": "walk_past"}]},
                       {"id": "e2", "place": "Y", "humans": [{"human": "human2", "reaction": "walk_past"}]}],
        "criteria": [{"id": "c2", "kind": "stl", "encounter": "e1", "human": "human1", "text": "she leads",
                      "formula": "(robot_to_e1 > 2.0) until (human1_to_e1 < 1.0)"}]})

    def failing(criterion: str) -> Finding:
        return Finding(name=criterion, kind="stl", passed=False, evidence="x", criterion=criterion, blame="paths",
                       blame_reason="check where and when the paths meet")

    report = VerifyReport(run="r", passed=False, findings=[failing(c) for c in
                                                          ("c2", "meet_human2_e2", "order_e1_e2")])
    assert "scenario" not in routed(report, spec)
    again = routed(report, spec, frozenset({"meet_human1_e1"}))
    assert [f.criterion for f in again["scenario"]] == ["c2"]
    assert [f.criterion for f in again["paths"]] == ["meet_human2_e2", "order_e1_e2"]
    assert "the paths were changed for encounter e1 already" in again["scenario"][0].blame_reason


def test_what_only_the_simulator_did_is_sent_nowhere():
    from socnavgen.proposal.verify_loop import routed

    stuck = Finding(name="c5", kind="robot_reaches_goal", passed=False, evidence="stood still 97 s", blame="simulator",
                    blame_reason="the robot's own navigation failed")
    assert routed(VerifyReport(run="r", passed=False, findings=[stuck])) == {}


def test_an_encounter_counts_as_tried_by_stage_2_only_once_stage_2_was_asked(tmp_path, mini_location):
    """Live: round 1 blames the spec and the paths (stage 1 goes first, alone), round 2 the meeting of e1 again:
    stage 2 was never asked about it, so it is asked now (not sent to stage 1 as if stage 2 had failed); round 3
    the same meeting, worse: stage 2 had its try for e1, so stage 1 is asked."""
    script = write_script(tmp_path / "s.yaml", {
        "scenario": [scenario_reply(), scenario_reply(), scenario_reply()], "paths": [paths_reply(), moved_paths_reply()],
        "behaviors": {"human1": [tree_reply()], "human2": [tree_reply()]}})

    def meet(evidence: str) -> Finding:
        return Finding(name="c1", kind="meets", passed=False, evidence=evidence, criterion="c1", human="human1",
                       blame="paths", blame_reason="the robot and human1 were not at 11 at the same time")

    spec = Finding(name="c9", kind="stl", passed=False, evidence="x", criterion="c9", blame="spec",
                   blame_reason="a standoff set by the spec")
    request = request_for(mini_location).model_copy(update={"max_restarts": 3})
    run, llm = run_replay(script, mini_location, tmp_path / "run", verify=True, request=request,
                          verifier=_verifier([spec, meet("closest 6 m")], [meet("closest 5 m")], [meet("closest 4 m")],
                                             []))
    assert isinstance(run, Run), run
    asked = [(s, k) for s, k, _ in llm.calls if s != "behaviors"]
    assert asked == [("scenario", None), ("paths", None), ("scenario", None), ("paths", None), ("scenario", None)]
    last = [m for s, k, m in llm.calls if s == "scenario"][-1][-1].content
    assert "the paths were changed for encounter e1 already" in last


def test_each_correction_says_how_many_simulations_are_left(tmp_path, mini_location):
    """Round 30's players asked which round they were in: the first correction (after simulation 1 of 3) says more
    can follow, the second (after simulation 2) that the answer gets the last simulation."""
    llm = _tree_then_spec_loop(tmp_path, mini_location)
    tree_fix = [m for s, k, m in llm.calls if (s, k) == ("behaviors", "human1")][1][-1].content
    spec_fix = [m for s, k, m in llm.calls if s == "scenario"][1][-1].content
    assert "This was simulation 1 of at most 3. 2 more can follow" in tree_fix and "LAST" not in tree_fix
    assert "This was simulation 2 of at most 3. Your answer gets the LAST simulation" in spec_fix


def test_a_later_stage_is_told_it_may_keep_its_answer_for_stage_1():
    """The keep-and-say-why escape (verify_loop.kept) is offered where a stage-2 or stage-3 correction is made."""
    for stage in ("paths", "behaviors"):
        assert "say why in your reasoning: stage 1 is then asked" in SCOPE[stage]
