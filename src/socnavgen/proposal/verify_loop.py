"""`--verify`: simulate the generated run and, while the verifier still finds failures, re-ask ONLY the
stage its blame names (verify/blame.py), as REASK says:

  robot_script, spec, scenario -> stage 1 (the scenario and its spec: the robot's script, the encounters
                                  and their places, the criteria); a tree is never asked to fix what only
                                  the robot, the spec or the choice of place can cause
  paths                        -> stage 2, with the findings (the spec's own stl formula failing again
                                  after stage 2 was re-asked for it -> stage 1: its thresholds)
  behaviors + human            -> stage 3 for that human only, with that human's findings
                                  (paths and trees blamed in the same round are both re-asked, paths first)

A finding without blame, or with a blame no stage can fix, is not sent anywhere. Each re-ask continues
the stage's conversation after the model's own accepted answer (its words and reasoning, from the
transcript). When stage 1 changes who takes part or where, the paths and trees that depended on it are
regenerated; when it changes only what a person does (a part's trigger, distance, `lasts`, latch; their
`otherwise`), that person's tree is asked again from its FRESH prompt (never the old tree to correct); when
only the robot's script changed, they are kept (the grounding is carried over). Up to the restart budget."""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING

from socnavgen.proposal.conversation import ProgressEvent, bullet_list
from socnavgen.proposal.stages import Stages
from socnavgen.proposal.templates import render
from socnavgen.run import PathPlan, ScenarioProposal
from socnavgen.run.spec import ScenarioSpec

if TYPE_CHECKING:
    from socnavgen.verify.models import Finding, VerifyReport

STAGE = "verify"
# The stage that can fix what each blame names (verify/blame.py), the loop's one routing rule.
REASK: dict[str, str] = {"robot_script": "scenario", "spec": "scenario", "scenario": "scenario",
                         "paths": "paths", "behaviors": "behaviors"}
Verifier = Callable[..., "VerifyReport"]  # verify_run(run_dir, location=Location) -> VerifyReport
Outcome = tuple[ScenarioProposal, ScenarioSpec | None, PathPlan, dict[str, str], "VerifyReport"]


def describe(finding: Finding) -> str:
    who = f" ({finding.human})" if finding.human else ""
    fix = f" - fix: {finding.blame_reason}" if finding.blame_reason else ""
    return f"{finding.name}{who}: {finding.evidence}{fix}"


def _correction(findings: list[Finding]) -> str:
    return render("verify_correction.md", findings=bullet_list([describe(f) for f in findings]))


def _own_formula(finding: Finding, spec: ScenarioSpec | None) -> bool:
    """The finding is about an `stl` criterion the spec wrote itself (its formula and thresholds are stage 1's)."""
    return spec is not None and any(c.id == finding.criterion and c.kind == "stl" for c in spec.criteria)


def routed(report: VerifyReport, spec: ScenarioSpec | None = None,
           paths_tried: frozenset[str] = frozenset()) -> dict[str, list[Finding]]:
    """The failing findings per stage to re-ask (REASK); findings no stage can fix are left out. The spec's own
    formula that still fails after the paths were re-asked for it (`paths_tried`: criterion ids) goes to stage 1:
    a re-asked stage 2 can only move people, the formula's thresholds are the spec's."""
    out: dict[str, list[Finding]] = {}
    for finding in report.failures:
        stage = REASK.get(finding.blame or "")
        if stage == "paths" and finding.criterion in paths_tried and _own_formula(finding, spec):
            stage, finding = "scenario", finding.model_copy(update={"blame_reason": (
                f"{finding.blame_reason}; the paths were changed for it already and it still fails: its formula "
                "and thresholds are the spec's, make them fit this map's distances (the nodes' positions) and what "
                "the scenario does, or change the encounter's place")})
        if stage == "behaviors" and not finding.blame_human:
            continue  # a tree to fix, but whose: nobody to ask
        if stage is not None:
            out.setdefault(stage, []).append(finding)
    return out


def _shape(spec: ScenarioSpec | None) -> object:
    """What paths and trees depend on: who meets the robot where, doing what."""
    if spec is None:
        return None
    return [(e.id, e.place, [(p.human, p.trigger, p.phrase, p.reaction, p.says, p.other) for p in e.humans])
            for e in sorted(spec.encounters, key=lambda e: e.id)]


def _tree_shape(spec: ScenarioSpec | None, human: str) -> object:
    """What `human`'s tree is built from (stage 3's prompt and tree_needs): their parts in order, whole, and
    what they do while no trigger holds."""
    if spec is None:
        return None
    return ([(e.order, p.model_dump()) for e, p in spec.parts_of(human)], spec.person(human).otherwise)


def _carry_grounding(old: ScenarioSpec | None, new: ScenarioSpec | None) -> ScenarioSpec | None:
    if old is None or new is None:
        return new
    nodes = {e.id: e.node for e in old.encounters}
    grounded = new.model_copy(deep=True)
    for encounter in grounded.encounters:
        encounter.node = nodes.get(encounter.id)
    return grounded


def verify_and_repair(stages: Stages, scenario: ScenarioProposal, spec: ScenarioSpec | None, paths: PathPlan,
                      trees: dict[str, str], verify_run: Verifier) -> Outcome:
    run, recorder = stages.run, stages.recorder
    report: VerifyReport | None = None
    paths_tried: set[str] = set()  # criteria the paths stage was re-asked for (routed: then the spec's formula)
    for round_ in range(stages.policy.max_restarts + 1):
        (run.sim_dir / "trace.npz").unlink(missing_ok=True)  # the trace of the previous answer is stale
        recorder.set_status(STAGE, None, "running")
        recorder.progress(ProgressEvent(STAGE, None, "attempt", round_ + 1))
        report = verify_run(run.root, location=stages.location)  # the loaded location: not re-read per round
        recorder.update(STAGE, None, lambda r: setattr(r, "attempts", r.attempts + 1))
        failing = report.failures  # warnings are not the model's to fix
        recorder.mistakes(STAGE, None, [describe(f) for f in failing])
        if report.passed:
            recorder.set_status(STAGE, None, "done")
            recorder.progress(ProgressEvent(STAGE, None, "done"))
            return scenario, spec, paths, trees, report
        if round_ == stages.policy.max_restarts:
            break
        recorder.progress(ProgressEvent(STAGE, None, "invalid", round_ + 1, message="; ".join(map(describe, failing))))
        stages_to_ask = routed(report, spec, frozenset(paths_tried))
        paths_tried |= {f.criterion for f in stages_to_ask.get("paths", []) if f.criterion}
        if stages_to_ask.get("scenario"):
            old = spec
            scenario, spec = stages.scenario(correction=_correction(stages_to_ask["scenario"]))
            if _shape(spec) != _shape(old) or list(scenario.human_behaviors) != [h.name for h in paths.humans]:
                run.paths_path.unlink(missing_ok=True)
                for xml in run.behaviors_dir.glob("*.xml"):
                    xml.unlink()
                paths, spec = stages.paths(scenario, spec)
                trees = stages.behaviors(scenario, paths, spec)
            else:
                spec = _carry_grounding(old, spec)
                if spec is not None:
                    run.write_spec(spec)
                stale = [h for h in scenario.human_behaviors if _tree_shape(old, h) != _tree_shape(spec, h)]
                for human in stale:  # asked again from the fresh prompt, on the new spec
                    run.behavior_path(human).unlink(missing_ok=True)
                if stale:
                    trees = stages.behaviors(scenario, paths, spec)
            continue
        trees_to_fix: dict[str, list[Finding]] = {}
        for finding in stages_to_ask.get("behaviors", []):
            if finding.blame_human in scenario.human_behaviors:
                trees_to_fix.setdefault(str(finding.blame_human), []).append(finding)
        if not stages_to_ask.get("paths") and not trees_to_fix:  # nothing a stage can fix: asking changes nothing
            break
        if stages_to_ask.get("paths"):
            paths, spec = stages.paths(scenario, _ungrounded(spec), correction=_correction(stages_to_ask["paths"]))
        if trees_to_fix:  # the blamed trees in the same round (on the new paths, if they changed)
            corrections = {human: _correction(found) for human, found in
                           sorted(trees_to_fix.items(), key=lambda kv: int(kv[0][5:]))}
            trees = stages.behaviors(scenario, paths, spec, corrections)
    recorder.set_status(STAGE, None, "failed")
    recorder.progress(ProgressEvent(STAGE, None, "failed", message="the verifier still finds problems"))
    assert report is not None
    return scenario, spec, paths, trees, report


def _ungrounded(spec: ScenarioSpec | None) -> ScenarioSpec | None:
    """The spec as stage 2 grounds it afresh."""
    if spec is None:
        return None
    fresh = spec.model_copy(deep=True)
    for encounter in fresh.encounters:
        encounter.node = None
    return fresh
