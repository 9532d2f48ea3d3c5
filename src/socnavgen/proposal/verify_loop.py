"""`--verify`: simulate the generated run and, while the verifier still finds failures, re-ask ONLY the
stage its blame names (verify/blame.py), as REASK says:

  robot_script, spec, scenario -> stage 1 (the scenario and its spec: the robot's script, the encounters
                                  and their places, the criteria); a tree is never asked to fix what only
                                  the robot, the spec or the choice of place can cause
  paths                        -> stage 2, with the findings (the spec's own stl formula failing again
                                  after stage 2 was re-asked for it -> stage 1: its thresholds)
  behaviors + human            -> stage 3 for that human only, with that human's findings
                                  (paths and trees blamed in the same round are both re-asked, paths first)

A finding without blame, or with a blame no stage can fix (`simulator`: the robot failed on its own), is not sent
anywhere. A finding of an encounter stage 2 was re-asked for that fails again goes to stage 1 (`routed`). Each re-ask continues
the stage's conversation after the model's own accepted answer (its words and reasoning, from the
transcript), and says which stage it is and what that stage may change (SCOPE). When a stage 2 or stage 3 answer
was CHANGED for some findings and the very same findings (same numbers, `same_findings`) come back, the cause is not in that stage:
they go to stage 1 instead, saying so (`escalated`). When stage 1 changes who takes part or where, the paths and trees that depended on it are
regenerated (also when its prose names other nodes of the map: `_named_nodes`); when it changes only what a person does (a part's trigger, distance, `lasts`, latch; their
`otherwise`), that person's tree is asked again from its FRESH prompt (never the old tree to correct); when
only the robot's script changed, they are kept (the grounding is carried over). Up to the restart budget."""

from __future__ import annotations

import re
from collections.abc import Callable
from typing import TYPE_CHECKING

from socnavgen.proposal.conversation import ProgressEvent, bullet_list
from socnavgen.proposal.stages import Stages
from socnavgen.proposal.templates import render
from socnavgen.run import PathPlan, ScenarioProposal
from socnavgen.run.spec import ScenarioSpec
from socnavgen.verify.derive import with_implied
from socnavgen.verify.models import VerifySettings

if TYPE_CHECKING:
    from socnavgen.verify.models import Finding, VerifyReport

STAGE = "verify"
# The stage that can fix what each blame names (verify/blame.py), the loop's one routing rule.
REASK: dict[str, str] = {"robot_script": "scenario", "spec": "scenario", "scenario": "scenario",
                         "paths": "paths", "behaviors": "behaviors"}
Verifier = Callable[..., "VerifyReport"]  # verify_run(run_dir, location=Location) -> VerifyReport
Outcome = tuple[ScenarioProposal, ScenarioSpec | None, PathPlan, dict[str, str], "VerifyReport"]


# What each re-asked stage is and may change, at the head of its correction (a round-7 player answered a tree
# correction with a scenario JSON: the correction alone did not say which stage asked).
SCOPE: dict[str, str] = {
    "scenario": ("This correction is for STAGE 1, the scenario and its spec (your JSON object with "
                 "\"scenario_description\", \"human_behaviors\" and \"spec\"). Here you may change the robot's "
                 "script (route, speed, cues and their triggers and distances), the encounters (their place, order, "
                 "`within`, each person's trigger, distance, reaction, `lasts`, `until`, latch), the people and the "
                 "criteria; the paths and trees are planned again from it where it changed who meets where."),
    "paths": ("This correction is for STAGE 2, the paths (your JSON object with the trajectories, group ids, "
              "interaction points and encounter nodes). Here you may change only where the robot and each person "
              "start, walk and end, and on which node each encounter happens; what anyone does, the robot's cues "
              "and the criteria are stage 1's and stay as they are."),
    "behaviors": ("This correction is for STAGE 3, the behavior tree of $human (your JSON object with "
                  "\"reasoning\" and \"tree\"). Here you may change only what $human does and when (the nodes of "
                  "the tree); where people walk, what the robot does and the criteria belong to earlier stages and "
                  "stay as they are. Answer with the tree, not with a scenario or paths."),
}
STAGE_NAMES = {"paths": "the paths (stage 2)", "behaviors": "the behavior tree of {human} (stage 3)"}
UNCHANGED = ("Your last answer was the same as the one before it, so the simulation was the same: change what "
             "the findings point at.")
REPEATED = ("Your last change did not change what happened (the same findings with the same numbers came back): "
            "the cause is probably not in this stage; change something else than last time.")


def describe(finding: Finding) -> str:
    who = f" ({finding.human})" if finding.human else ""
    fix = f" - fix: {finding.blame_reason}" if finding.blame_reason else ""
    return f"{finding.name}{who}: {finding.evidence}{fix}"


def _correction(findings: list[Finding], stage: str, human: str | None = None, repeat: str = "") -> str:
    scope = SCOPE[stage].replace("$human", human or "this human")
    return render("verify_correction.md", scope=scope, findings=bullet_list([describe(f) for f in findings]),
                  repeat=repeat)


Sent = dict[tuple[str, str | None], tuple[list[str], object]]  # (stage, human) -> (findings sent, answer then)


def escalated(to_ask: dict[str, list[Finding]], sent: Sent, answers: dict[tuple[str, str | None], object]
              ) -> tuple[dict[str, list[Finding]], dict[tuple[str, str | None], str]]:
    """`to_ask` (routed) with the findings that came back unchanged after stage 2 or a tree was CHANGED for them
    moved to stage 1 (the cause is not where they were sent), and a note per (stage, human) still asked whose
    findings repeat (its answer unchanged: UNCHANGED; stage 1 again: REPEATED). `sent`: what each stage was last
    sent and its answer then; `answers`: each stage's answer now."""
    out = {stage: list(found) for stage, found in to_ask.items()}
    notes: dict[tuple[str, str | None], str] = {}
    for stage in ("paths", "behaviors"):
        for human in sorted({f.blame_human if stage == "behaviors" else None for f in to_ask.get(stage, [])},
                            key=str):
            found = [f for f in to_ask[stage] if stage == "paths" or f.blame_human == human]
            before = sent.get((stage, human))
            if before is None or not same_findings(before[0], [describe(f) for f in found]):
                continue
            if before[1] == answers.get((stage, human)):
                notes[(stage, human)] = UNCHANGED
                continue
            what = STAGE_NAMES[stage].format(human=human)
            out[stage] = [f for f in out[stage] if f not in found]
            out.setdefault("scenario", []).extend(f.model_copy(update={"blame_reason": (
                f"{f.blame_reason}; {what} was changed for this and it came back with the same numbers: the cause "
                "is probably not there but in the spec (the place, a trigger or cue distance, the timing, `lasts`, "
                "an encounter's `within`, a criterion's distance)")}) for f in found)
    if "scenario" in to_ask and same_findings(sent.get(("scenario", None), ([], None))[0],
                                              [describe(f) for f in to_ask["scenario"]]):
        notes[("scenario", None)] = REPEATED
    return {stage: found for stage, found in out.items() if found}, notes


_NUMBER = re.compile(r"-?\d+(?:\.\d+)?")
SAME_ABS, SAME_REL = 0.25, 0.03  # numbers this close (absolute, or relative to the larger) are the same outcome


def same_findings(before: list[str], now: list[str]) -> bool:
    """The same findings with the same numbers: the same words, each number within SAME_ABS or SAME_REL of the one
    before (a changed answer that moves a deadlock's start from t=55.0 to t=54.9 s changed nothing that matters)."""
    if len(before) != len(now) or not now:
        return False
    for a, b in zip(before, now, strict=True):
        if _NUMBER.split(a) != _NUMBER.split(b):
            return False
        for x, y in zip(map(float, _NUMBER.findall(a)), map(float, _NUMBER.findall(b)), strict=True):
            if abs(x - y) > max(SAME_ABS, SAME_REL * max(abs(x), abs(y))):
                return False
    return True


def _own_formula(finding: Finding, spec: ScenarioSpec | None) -> bool:
    """The finding is about an `stl` criterion the spec wrote itself (its formula and thresholds are stage 1's)."""
    return spec is not None and any(c.id == finding.criterion and c.kind == "stl" for c in spec.criteria)


def routed(report: VerifyReport, spec: ScenarioSpec | None = None,
           paths_tried: frozenset[str] = frozenset()) -> dict[str, list[Finding]]:
    """The failing findings per stage to re-ask (REASK); findings no stage can fix are left out. The spec's own
    formula that still fails after the paths were re-asked for it (`paths_tried`: criterion ids) goes to stage 1:
    a re-asked stage 2 can only move people, the formula's thresholds are the spec's. So does any finding of an
    encounter stage 2 was re-asked for before (a criterion of it in `paths_tried`) that fails again: within its own
    rules stage 2 could not make that encounter happen (a guide who must meet the robot at its start), stage 1 can."""
    out: dict[str, list[Finding]] = {}
    tried = _encounters(spec, paths_tried)
    for finding in report.failures:
        stage = REASK.get(finding.blame or "")
        encounter = _encounters(spec, {finding.criterion} if finding.criterion else set())
        if stage == "paths" and finding.criterion in paths_tried and _own_formula(finding, spec):
            stage, finding = "scenario", finding.model_copy(update={"blame_reason": (
                f"{finding.blame_reason}; the paths were changed for it already and it still fails: its formula "
                "and thresholds are the spec's, make them fit this map's distances (the nodes' positions) and what "
                "the scenario does, or change the encounter's place")})
        elif stage == "paths" and encounter & tried:
            stage, finding = "scenario", finding.model_copy(update={"blame_reason": (
                f"{finding.blame_reason}; the paths were changed for encounter {', '.join(sorted(encounter))} "
                "already and it still fails: what stage 2 may change (where people start, walk and end, within its "
                "own rules, e.g. nobody waiting at an encounter's node near the robot's start) does not make this "
                "encounter happen; change the encounter itself (its place, who comes to whom and from where, the "
                "robot's speed or cues, its criteria)")})
        if stage == "behaviors" and not finding.blame_human:
            continue  # a tree to fix, but whose: nobody to ask
        if stage is not None:
            out.setdefault(stage, []).append(finding)
    return out


def _encounters(spec: ScenarioSpec | None, criteria: set[str] | frozenset[str]) -> set[str]:
    """The encounters the given criteria (the spec's own and those it implies: verify/derive.py) are about."""
    if spec is None or not criteria:
        return set()
    return {c.encounter for c, _ in with_implied(spec, VerifySettings()) if c.id in criteria and c.encounter}


def _shape(spec: ScenarioSpec | None) -> object:
    """What paths and trees depend on: who meets the robot where, doing what."""
    if spec is None:
        return None
    return [(e.id, e.place, [(p.human, p.trigger, p.phrase, p.reaction, p.says, p.other) for p in e.humans])
            for e in sorted(spec.encounters, key=lambda e: e.id)]


_TOKEN = re.compile(r"[A-Za-z0-9_]+")


def _named_nodes(scenario: ScenarioProposal, spec: ScenarioSpec | None, nodes: set[str]) -> object:
    """The map's nodes each part of the prose names (where the scenario says people start, meet and go; stage 2
    plans the paths from it): a stage-1 answer that moves a person's start in its words re-plans the paths
    (warehouse_04, round 10: the old start was simulated again)."""
    def named(text: str) -> frozenset[str]:
        return frozenset(w for w in _TOKEN.findall(text) if w in nodes)

    said = {"description": named(scenario.scenario_description),
            **{h: named(text) for h, text in scenario.human_behaviors.items()}}
    if spec is not None:
        said |= {e.id: named(e.robot_does or "") for e in spec.encounters}
    return said


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
    sent: Sent = {}  # what each stage was last sent (escalated: the same findings after a changed answer)
    nodes = set(getattr(getattr(stages.location, "inventory", None), "nodes", None) or ())  # the map's node ids
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
        answers: dict[tuple[str, str | None], object] = {("paths", None): paths.model_dump(),
                                                          **{("behaviors", h): xml for h, xml in trees.items()}}
        stages_to_ask, notes = escalated(routed(report, spec, frozenset(paths_tried)), sent, answers)
        if not stages_to_ask.get("scenario"):  # stage 1 goes first and alone: stage 2 is asked only without it
            paths_tried |= {f.criterion for f in stages_to_ask.get("paths", []) if f.criterion}
        for stage, found in stages_to_ask.items():
            for human in ({f.blame_human for f in found} if stage == "behaviors" else {None}):
                mine = [f for f in found if stage != "behaviors" or f.blame_human == human]
                sent[(stage, human)] = ([describe(f) for f in mine], answers.get((stage, human)))
        if stages_to_ask.get("scenario"):
            old, old_nodes = spec, _named_nodes(scenario, spec, nodes)
            scenario, spec = stages.scenario(correction=_correction(
                stages_to_ask["scenario"], "scenario", repeat=notes.get(("scenario", None), "")))
            sent = {key: value for key, value in sent.items() if key[0] == "scenario"}  # later stages start afresh
            if (_shape(spec) != _shape(old) or list(scenario.human_behaviors) != [h.name for h in paths.humans]
                    or _named_nodes(scenario, spec, nodes) != old_nodes):
                run.paths_path.unlink(missing_ok=True)
                paths_tried.clear()  # paths planned afresh on the new spec: nothing tried on them yet
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
            paths, spec = stages.paths(scenario, _ungrounded(spec), correction=_correction(
                stages_to_ask["paths"], "paths", repeat=notes.get(("paths", None), "")))
        if trees_to_fix:  # the blamed trees in the same round (on the new paths, if they changed)
            corrections = {human: _correction(found, "behaviors", human, notes.get(("behaviors", human), ""))
                           for human, found in
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
