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
transcript), and says which stage it is and what that stage may change (SCOPE). When a re-asked stage 2 or stage 3
answers with the SAME paths or tree (its model says no answer of its stage can fix it: home_12, warehouse_10 of round
13), its findings go to stage 1 in the same round, with its own words on why (`kept`), instead of simulating the same
answer again; when its answer was CHANGED and the very same findings (same numbers, `same_findings`) come back, the
cause is not in that stage either: they go to stage 1, saying so (`escalated`). A stage-2 answer that cannot satisfy a
rule only stage 1 can change asks stage 1 itself (Stages.plan). When stage 1 changes who takes part or where, the paths and trees that depended on it are
regenerated (also when its prose names other nodes of the map: `_named_nodes`); when it changes only what a person does (a part's trigger, distance, `lasts`, latch; their
`otherwise`), that person's tree is asked again from its FRESH prompt (never the old tree to correct); when
only the robot's script changed, they are kept (the grounding is carried over). Up to the restart budget."""

from __future__ import annotations

import json
import re
from collections.abc import Callable
from typing import TYPE_CHECKING

from socnavgen.proposal.conversation import ProgressEvent, accepted_reply, bullet_list
from socnavgen.proposal.stages import MAX_SAID, SCOPE, Stages
from socnavgen.proposal.templates import render
from socnavgen.run import PathPlan, ScenarioProposal
from socnavgen.run.spec import ScenarioSpec
from socnavgen.verify.blame_tree import without_tree_facts
from socnavgen.verify.derive import with_implied
from socnavgen.verify.models import VerifySettings

if TYPE_CHECKING:
    from socnavgen.verify.models import Finding, VerifyReport

STAGE = "verify"
NEAR_MISS = 0.25  # a spec's own formula failing by less than this (m, m/s or s) has a bound too tight, not a wrong place
# The stage that can fix what each blame names (verify/blame.py), the loop's one routing rule.
REASK: dict[str, str] = {"robot_script": "scenario", "spec": "scenario", "scenario": "scenario",
                         "paths": "paths", "behaviors": "behaviors"}
Verifier = Callable[..., "VerifyReport"]  # verify_run(run_dir, location=Location) -> VerifyReport
Outcome = tuple[ScenarioProposal, ScenarioSpec | None, PathPlan, dict[str, str], "VerifyReport"]


STAGE_NAMES = {"paths": "the paths (stage 2)", "behaviors": "the behavior tree of {human} (stage 3)"}
ANSWER_NAMES = {"paths": "paths", "behaviors": "tree"}
REPEATED = ("Your last change did not change what happened (the same findings with the same numbers came back): "
            "the cause is probably not in this stage; change something else than last time.")


def describe(finding: Finding) -> str:
    who = f" ({finding.human})" if finding.human else ""
    fix = f" - fix: {finding.blame_reason}" if finding.blame_reason else ""
    return f"{finding.name}{who}: {finding.evidence}{fix}"


ALSO = ("Also failing in that simulation (another stage is asked about these if they still fail after your "
        "answer; they are shown so that you can fix what your stage causes in one go and not work against them):")


def budget_text(simulated: int, total: int) -> str:
    """How many simulations the loop has left after this answer (round 30's players asked which round they were in:
    on the last one an answer should change what the findings name and nothing that passed)."""
    left = total - simulated
    if left <= 0:
        return ""
    head = f"This was simulation {simulated} of at most {total}. "
    if left == 1:
        return head + ("Your answer gets the LAST simulation: change what the findings above name, keep what passed "
                       "(a change elsewhere can break it), and prefer the change that certainly fixes them.")
    return head + f"{left} more can follow; each correction names what still fails."


def _correction(findings: list[Finding], stage: str, human: str | None = None, repeat: str = "",
                also: list[Finding] | None = None, budget: str = "") -> str:
    """The re-ask of `stage`: its own findings, and (`also`) what else failed in the same run for later stages, so
    the model sees every failure at once, not one a round (round 26's player spent its three rounds so); `budget`:
    how many simulations are left (budget_text)."""
    scope = SCOPE[stage].replace("$human", human or "this human")
    others = f"{ALSO}\n{bullet_list([describe(f) for f in also])}\n" if also else ""
    tail = "\n".join(part for part in (repeat, budget) if part)
    return render("verify_correction.md", scope=scope, findings=bullet_list([describe(f) for f in findings]),
                  repeat=others + tail)


def _later(to_ask: dict[str, list[Finding]], stage: str) -> list[Finding]:
    """The findings routed to the stages after `stage` (stage 1 and 2 are asked before the trees)."""
    order = ("scenario", "paths", "behaviors")
    return [f for later in order[order.index(stage) + 1:] for f in to_ask.get(later, [])]


Sent = dict[tuple[str, str | None], tuple[list[str], object]]  # (stage, human) -> (findings sent, answer then)


def escalated(to_ask: dict[str, list[Finding]], sent: Sent, answers: dict[tuple[str, str | None], object]
              ) -> tuple[dict[str, list[Finding]], dict[tuple[str, str | None], str]]:
    """`to_ask` (routed) with the findings that came back unchanged after stage 2 or a tree was asked for them moved
    to stage 1 (the cause is not where they were sent: its changed answer did nothing, or it kept its answer), and a
    note when stage 1's own findings repeat (REPEATED). `sent`: what each stage was last sent and its answer then;
    `answers`: each stage's answer now."""
    out = {stage: list(found) for stage, found in to_ask.items()}
    notes: dict[tuple[str, str | None], str] = {}
    for stage in ("paths", "behaviors"):
        for human in sorted({f.blame_human if stage == "behaviors" else None for f in to_ask.get(stage, [])},
                            key=str):
            found = [f for f in to_ask[stage] if stage == "paths" or f.blame_human == human]
            before = sent.get((stage, human))
            if before is None or not same_findings(before[0], [describe(f) for f in found]):
                continue
            what = STAGE_NAMES[stage].format(human=human)
            did = (f"was asked to fix this and answered with the same {ANSWER_NAMES[stage]}"
                   if before[1] == answers.get((stage, human)) else
                   "was changed for this and it came back with the same numbers")
            out[stage] = [f for f in out[stage] if f not in found]
            out.setdefault("scenario", []).extend(_to_stage1(found, f"{what} {did}"))
    if "scenario" in to_ask and same_findings(sent.get(("scenario", None), ([], None))[0],
                                              [describe(f) for f in to_ask["scenario"]]):
        notes[("scenario", None)] = REPEATED
    return {stage: found for stage, found in out.items() if found}, notes


def _to_stage1(found: list[Finding], why: str) -> list[Finding]:
    """Copies of findings sent to stage 1 because `why` (the report's own findings are not rewritten)."""
    return [f.model_copy(update={"blame_reason": (
        f"{f.blame_reason}; {why}: the cause is probably not there but in the spec (the place, a trigger or cue "
        "distance, the timing, `lasts`, an encounter's `within`, a criterion's kind or distance)")}) for f in found]


def kept(asked: dict[tuple[str, str | None], list[Finding]], before: dict[tuple[str, str | None], object],
         after: dict[tuple[str, str | None], object], said: Callable[[str, str | None], str]
         ) -> tuple[list[Finding], str]:
    """The findings of each re-asked (stage, human) that answered with the same paths or tree as before (simulating
    it again would show the same: they go to stage 1 now), and a note quoting each such stage's own words on why."""
    found: list[Finding] = []
    notes: list[str] = []
    for (stage, human), mine in asked.items():
        if before.get((stage, human)) != after.get((stage, human)):
            continue
        what = STAGE_NAMES[stage].format(human=human)
        found += _to_stage1(mine, f"{what} was asked to fix this and answered with the same {ANSWER_NAMES[stage]}")
        words = said(stage, human).strip()
        if words:
            notes.append(f'{what[0].upper()}{what[1:]} kept its answer, saying: "{words[:MAX_SAID]}"')
    return found, "\n".join(notes)


_NUMBER = re.compile(r"-?\d+(?:\.\d+)?")
SAME_ABS, SAME_REL = 0.25, 0.03  # numbers this close (absolute, or relative to the larger) are the same outcome


def same_findings(before: list[str], now: list[str]) -> bool:
    """The same findings with the same numbers: the same words, each number within SAME_ABS or SAME_REL of the one
    before (a changed answer that moves a deadlock's start from t=55.0 to t=54.9 s changed nothing that matters)."""
    if len(before) != len(now) or not now:
        return False
    for a, b in zip(map(without_tree_facts, before), map(without_tree_facts, now), strict=True):
        if _NUMBER.split(a) != _NUMBER.split(b):
            return False
        for x, y in zip(map(float, _NUMBER.findall(a)), map(float, _NUMBER.findall(b)), strict=True):
            if abs(x - y) > max(SAME_ABS, SAME_REL * max(abs(x), abs(y))):
                return False
    return True


def _near_miss(finding: Finding) -> bool:
    """The finding failed by less than NEAR_MISS (its robustness, in the unit of its deciding signal): the
    geometry is right and only the threshold is too tight - stage 2 can move people, not a bound."""
    return finding.robustness is not None and -NEAR_MISS < finding.robustness < 0.0


def _own_formula(finding: Finding, spec: ScenarioSpec | None) -> bool:
    """The finding is about an `stl` criterion the spec wrote itself (its formula and thresholds are stage 1's)."""
    return spec is not None and any(c.id == finding.criterion and c.kind == "stl" for c in spec.criteria)


def routed(report: VerifyReport, spec: ScenarioSpec | None = None,
           paths_tried: frozenset[str] = frozenset()) -> dict[str, list[Finding]]:
    """The failing findings per stage to re-ask (REASK); findings no stage can fix are left out. The spec's own
    formula that fails by a hair (_near_miss: players' corrections went to stage 2, which cannot change a bound,
    and came back unchanged) goes to stage 1 at once, and one that still fails after the paths were re-asked for it
    (`paths_tried`: criterion ids) goes to stage 1: a re-asked stage 2 can only move people, the formula's
    thresholds are the spec's. So does any finding of an
    encounter stage 2 was re-asked for before (a criterion of it in `paths_tried`) that fails again: within its own
    rules stage 2 could not make that encounter happen (a guide who must meet the robot at its start), stage 1 can."""
    out: dict[str, list[Finding]] = {}
    tried = _encounters(spec, paths_tried)
    for finding in report.failures:
        stage = REASK.get(finding.blame or "")
        encounter = _encounters(spec, {finding.criterion} if finding.criterion else set())
        if stage == "paths" and _own_formula(finding, spec) and _near_miss(finding):
            stage, finding = "scenario", finding.model_copy(update={"blame_reason": (
                f"{finding.blame_reason}; it missed by only {-(finding.robustness or 0.0):.2f} (in the unit of its "
                "deciding signal): the paths and the timing bring it about as planned and its bound is tighter than "
                "the simulation keeps it (people stand and walk up to a metre or more off their nodes - spawned round "
                "them, in a group round its node - and the robot cuts its route's corners): loosen the formula's "
                "threshold, do not move the paths")})
        elif stage == "paths" and finding.criterion in paths_tried and _own_formula(finding, spec):
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
    (warehouse_04, round 10: the old start was simulated again), and so does one that moves the robot's route
    (warehouse_13, round 15: the robot's start moved from sk to up, the same places named elsewhere)."""
    def named(text: str) -> frozenset[str]:
        return frozenset(w for w in _TOKEN.findall(text) if w in nodes)

    said = {"description": named(scenario.scenario_description),
            **{h: named(text) for h, text in scenario.human_behaviors.items()}}
    if spec is not None:
        said |= {e.id: named(e.robot_does or "") for e in spec.encounters}
        said["robot route"] = named(spec.script.route)
    return said


def _tree_shape(spec: ScenarioSpec | None, human: str) -> object:
    """What `human`'s tree is built from (stage 3's prompt and tree_needs): their parts in order, whole, and
    what they do while no trigger holds."""
    if spec is None:
        return None
    return ([(e.order, p.model_dump()) for e, p in spec.parts_of(human)], spec.person(human).otherwise)


def twins(trees: dict[str, str], spec: ScenarioSpec | None, blamed: set[str]) -> dict[str, str]:
    """{human: the blamed human whose tree they share}: people not blamed whose tree is the same as a blamed one's
    (whitespace aside) for the same part in the spec (names aside). A fault of one is theirs too: they take its fix
    (_Repair.share_fixes; round 29, warehouse_22: the fix reached two workers of a group one round after the other,
    and the supervisor with the very same tree never, before the rounds ran out)."""
    def part(h: str) -> object:
        shape = _tree_shape(spec, h)
        return None if shape is None else repr(shape).replace(repr(h), "'self'")

    def xml(h: str) -> str:
        return re.sub(r">\s+<", "><", " ".join(trees[h].split()))

    out: dict[str, str] = {}
    for h in sorted(set(trees) - blamed, key=str):
        same = [b for b in sorted(blamed, key=str) if b in trees and xml(b) == xml(h) and part(b) == part(h)]
        if same:
            out[h] = same[0]
    return out


def _carry_grounding(old: ScenarioSpec | None, new: ScenarioSpec | None) -> ScenarioSpec | None:
    if old is None or new is None:
        return new
    nodes = {e.id: e.node for e in old.encounters}
    grounded = new.model_copy(deep=True)
    for encounter in grounded.encounters:
        encounter.node = nodes.get(encounter.id)
    return grounded


class _Repair:
    """The state of one --verify loop: the current answers, what each stage was last sent (`sent`), the criteria the
    paths were re-asked for (`paths_tried`)."""

    def __init__(self, stages: Stages, scenario: ScenarioProposal, spec: ScenarioSpec | None, paths: PathPlan,
                 trees: dict[str, str]) -> None:
        self.stages, self.run = stages, stages.run
        self.scenario, self.spec, self.paths, self.trees = scenario, spec, paths, trees
        self.paths_tried: set[str] = set()  # criteria the paths stage was re-asked for (routed: then the spec's)
        self.sent: Sent = {}  # what each stage was last sent (escalated: the same findings came back)
        self.nodes = set(getattr(getattr(stages.location, "inventory", None), "nodes", None) or ())  # the map's
        self.budget = ""  # budget_text of the round being repaired

    def answers(self) -> dict[tuple[str, str | None], object]:
        """Each later stage's answer as the simulation sees it (the paths' reasoning and the XML's layout aside)."""
        grounding = [(e.id, e.node) for e in self.spec.encounters] if self.spec is not None else None
        return {("paths", None): (self.paths.model_dump(exclude={"reasoning"}), grounding),
                **{("behaviors", h): " ".join(xml.split()) for h, xml in self.trees.items()}}

    def said(self, stage: str, human: str | None) -> str:
        """The reasoning of a stage's last accepted answer (its own words), from the transcript."""
        raw = accepted_reply(self.run, stage, human)
        try:
            value = json.loads(raw) if raw else None
        except ValueError:
            return ""
        return str(value.get("reasoning") or "") if isinstance(value, dict) else ""

    def round(self, report: VerifyReport) -> bool:
        """Re-ask the stages that can fix the report's findings; False when there is nobody to ask."""
        answers = self.answers()
        to_ask, notes = escalated(routed(report, self.spec, frozenset(self.paths_tried)), self.sent, answers)
        if not to_ask.get("scenario"):  # stage 1 goes first and alone: stage 2 is asked only without it
            self.paths_tried |= {f.criterion for f in to_ask.get("paths", []) if f.criterion}
        asked: dict[tuple[str, str | None], list[Finding]] = {}
        for stage, found in to_ask.items():
            for human in (sorted({f.blame_human for f in found}, key=str) if stage == "behaviors" else [None]):
                asked[(stage, human)] = [f for f in found if stage != "behaviors" or f.blame_human == human]
                self.sent[(stage, human)] = ([describe(f) for f in asked[(stage, human)]], answers.get((stage, human)))
        if to_ask.get("scenario"):
            self.stage1(to_ask["scenario"], notes.get(("scenario", None), ""), _later(to_ask, "scenario"))
            return True
        trees_to_fix = {h: found for (stage, h), found in asked.items()
                        if stage == "behaviors" and h in self.scenario.human_behaviors}
        if not to_ask.get("paths") and not trees_to_fix:  # nothing a stage can fix: asking changes nothing
            return False
        if to_ask.get("paths"):
            scenario = self.scenario
            self.scenario, _, self.paths, self.spec = self.stages.plan(
                self.scenario, _ungrounded(self.spec),
                correction=_correction(to_ask["paths"], "paths", repeat=notes.get(("paths", None), ""),
                                       also=_later(to_ask, "paths"), budget=self.budget))
            if self.scenario is not scenario:  # stage 2 could not, stage 1 was asked: everything after it is new
                self.sent, self.paths_tried = {k: v for k, v in self.sent.items() if k[0] == "scenario"}, set()
                self.remake_trees()
                return True
        if trees_to_fix:  # the blamed trees in the same round (on the new paths, if they changed)
            corrections = {human: _correction(found, "behaviors", human, notes.get(("behaviors", human), ""),
                                              budget=self.budget)
                           for human, found in sorted(trees_to_fix.items(), key=lambda kv: int(str(kv[0])[5:]))}
            sharing = twins(self.trees, self.spec, set(trees_to_fix))
            before = dict(self.trees)
            self.trees = self.stages.behaviors(self.scenario, self.paths, self.spec, corrections)
            self.share_fixes(sharing, before)
        reasked = {key: found for key, found in asked.items() if key[0] == "paths" or key[1] in trees_to_fix}
        same, words = kept(reasked, answers, self.answers(), self.said)
        if same:  # the same answer simulates the same: its findings go to stage 1 now, not after another run
            self.sent[("scenario", None)] = ([describe(f) for f in same], None)
            self.stage1(same, words)
        return True

    def stage1(self, found: list[Finding], note: str, also: list[Finding] | None = None) -> None:
        """Ask stage 1 with `found` (and `also`: what failed for the later stages); re-plan what depended on what
        it changed."""
        stages, run = self.stages, self.run
        old, old_nodes, paths = self.spec, _named_nodes(self.scenario, self.spec, self.nodes), self.paths
        self.scenario, self.spec = stages.scenario(correction=_correction(found, "scenario", repeat=note, also=also,
                                                                             budget=self.budget))
        self.sent = {key: value for key, value in self.sent.items() if key[0] == "scenario"}  # later stages afresh
        if (_shape(self.spec) != _shape(old) or list(self.scenario.human_behaviors) != [h.name for h in paths.humans]
                or _named_nodes(self.scenario, self.spec, self.nodes) != old_nodes):
            run.paths_path.unlink(missing_ok=True)
            self.paths_tried.clear()  # paths planned afresh on the new spec: nothing tried on them yet
            self.scenario, _, self.paths, self.spec = stages.plan(self.scenario, self.spec)
            self.remake_trees()
            return
        self.spec = _carry_grounding(old, self.spec)
        if self.spec is not None:
            run.write_spec(self.spec)
        stale = [h for h in self.scenario.human_behaviors if _tree_shape(old, h) != _tree_shape(self.spec, h)]
        for human in stale:  # asked again from the fresh prompt, on the new spec
            run.behavior_path(human).unlink(missing_ok=True)
        if stale:
            self.trees = stages.behaviors(self.scenario, self.paths, self.spec)

    def share_fixes(self, same: dict[str, str], before: dict[str, str]) -> None:
        """Each twin (verify_loop.twins) takes the corrected tree of the person whose fault it shared: the same tree
        for the same part gets the same fix (the trees name no one: the agent is the {id} of the blackboard)."""
        for human, blamed in same.items():
            fixed = self.trees.get(blamed)
            if fixed is None or fixed == before.get(blamed) or human not in self.trees:
                continue
            self.run.write_behavior(human, fixed)
            self.trees[human] = fixed
            self.stages.emit("behaviors", human, "done", f"takes {blamed}'s corrected tree (the same tree, same part)")

    def remake_trees(self) -> None:
        """Every tree asked again from its fresh prompt (the scenario they were made for changed)."""
        for xml in self.run.behaviors_dir.glob("*.xml"):
            xml.unlink()
        self.trees = self.stages.behaviors(self.scenario, self.paths, self.spec)


def verify_and_repair(stages: Stages, scenario: ScenarioProposal, spec: ScenarioSpec | None, paths: PathPlan,
                      trees: dict[str, str], verify_run: Verifier) -> Outcome:
    run, recorder = stages.run, stages.recorder
    report: VerifyReport | None = None
    loop = _Repair(stages, scenario, spec, paths, trees)
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
            return loop.scenario, loop.spec, loop.paths, loop.trees, report
        if round_ == stages.policy.max_restarts:
            break
        recorder.progress(ProgressEvent(STAGE, None, "invalid", round_ + 1, message="; ".join(map(describe, failing))))
        loop.budget = budget_text(round_ + 1, stages.policy.max_restarts + 1)
        if not loop.round(report):
            break
    recorder.set_status(STAGE, None, "failed")
    recorder.progress(ProgressEvent(STAGE, None, "failed", message="the verifier still finds problems"))
    assert report is not None
    return loop.scenario, loop.spec, loop.paths, loop.trees, report


def _ungrounded(spec: ScenarioSpec | None) -> ScenarioSpec | None:
    """The spec as stage 2 grounds it afresh."""
    if spec is None:
        return None
    fresh = spec.model_copy(deep=True)
    for encounter in fresh.encounters:
        encounter.node = None
    return fresh
