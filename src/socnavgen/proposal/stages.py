"""The three generation stages on one run folder (scenario + spec, paths + grounding, trees), each
resuming from its file when present and validating that file again (a user may have edited it).
`generate` (pipeline.py), the naive baseline and the --verify loop all drive a `Stages`."""

from __future__ import annotations

import json
from collections.abc import Callable

from socnavgen.errors import InputFileError, SocnavgenError
from socnavgen.llm.base import LLM, ChatMessage
from socnavgen.location import Location
from socnavgen.proposal import behaviors as bt_stage
from socnavgen.proposal import paths as path_stage
from socnavgen.proposal import scenario as scenario_stage
from socnavgen.proposal.conversation import (
    Outcome,
    Policy,
    ProgressEvent,
    Recorder,
    UpstreamFailed,
    accepted_reply,
    bullet_list,
    converse,
)
from socnavgen.proposal.path_checks import check_paths, ground_spec, to_path_plan
from socnavgen.proposal.replies import PathsReply
from socnavgen.proposal.review import ReviewHook
from socnavgen.proposal.spec_checks import spec_mistakes
from socnavgen.proposal.templates import render
from socnavgen.run import PathPlan, RunFolder, ScenarioProposal, ScenarioRequest
from socnavgen.run.spec import ScenarioSpec
from socnavgen.safeio import atomic_write_json

MAX_REVIEW_ROUNDS = 10

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
              "and the criteria are stage 1's and stay as they are. If only stage 1 can fix a finding (a speed, a "
              "cue's trigger or distance, a reaction, a criterion's bound), answer with the same paths and say why "
              "in your reasoning: stage 1 is then asked, with your words."),
    "behaviors": ("This correction is for STAGE 3, the behavior tree of $human (your JSON object with "
                  "\"reasoning\" and \"tree\"). Here you may change only what $human does and when (the nodes of "
                  "the tree); where people walk, what the robot does and the criteria belong to earlier stages and "
                  "stay as they are. Answer with the tree, not with a scenario or paths. If no tree of $human can "
                  "fix a finding, answer with the same tree and say why in your reasoning: stage 1 is then asked, "
                  "with your words."),
}
UPSTREAM_NAMES = {"paths": "Stage 2 (the paths)"}
MAX_SAID = 1500  # characters of a stage's own reasoning quoted to the stage it sends a finding to


def upstream_correction(failed: UpstreamFailed) -> str:
    """Stage 1's correction when a later stage cannot satisfy what stage 1's answer causes: the causes (deduplicated:
    a group's members share one) and that stage's own words on why."""
    causes = list(dict.fromkeys(c.upstream for c in failed.causes))
    said = f'Its last answer said: "{failed.said.strip()[:MAX_SAID]}"' if failed.said.strip() else ""
    return render("upstream_correction.md", scope=SCOPE["scenario"],
                  stage=UPSTREAM_NAMES.get(failed.stage, f"Stage '{failed.stage}'"), causes=bullet_list(causes),
                  said=said)


class Stages:
    """Stage 1-3 of one request on one run folder."""

    def __init__(self, request: ScenarioRequest, llm: LLM, run: RunFolder, location: Location,
                 recorder: Recorder, review: ReviewHook | None) -> None:
        self.request, self.llm, self.run, self.location = request, llm, run, location
        self.recorder, self.review = recorder, review
        self.policy = Policy(request.max_requeries, request.max_restarts, request.temperature)

    def emit(self, stage: str, key: str | None, kind: str, message: str = "") -> None:
        self.recorder.progress(ProgressEvent(stage, key, kind, message=message))  # type: ignore[arg-type]

    def reviewed(self, stage: str, key: str | None, outcome: Outcome, first: Callable[[Policy], Outcome],
                 again: Callable[[list[ChatMessage]], Outcome], show: Callable[[Outcome], str]) -> Outcome:
        """Loop accept / retry (fresh conversation, warmer) / edit (the request sent after the answer)."""
        if self.review is None:
            return outcome
        for round_ in range(1, MAX_REVIEW_ROUNDS + 1):
            decision = self.review(stage, key, show(outcome))
            if decision.action == "accept":
                break
            if decision.action == "retry":
                warmer = Policy(self.policy.max_requeries, self.policy.max_restarts,
                                min(1.0, self.policy.temperature + 0.3 * round_))
                outcome = first(warmer)
            else:
                edit = ChatMessage(role="user", content=render("review_edit.md", request=decision.request))
                outcome = again([*outcome.history, edit])
        return outcome

    # -- stage 1 -----------------------------------------------------------------------------------
    def read_spec(self, scenario: ScenarioProposal, grounded: bool = False) -> ScenarioSpec | None:
        """spec.json of a resumed run, checked again (None for runs made before specs existed)."""
        spec = self.run.read_spec()
        if spec is None:
            return None
        mistakes = spec_mistakes(spec, list(scenario.human_behaviors), list(self.location.schema.node_types),
                                 self.request.target, self.location)
        if grounded:
            mistakes += [f"encounter {e.id} has no node: re-run stage 2 (--redo paths)"
                         for e in spec.encounters if not e.node]
        if mistakes:
            raise InputFileError("spec.json does not fit the scenario: " + "; ".join(mistakes[:5]),
                                 file=self.run.spec_path,
                                 hint="fix spec.json, or regenerate it with --from RUN --redo scenario")
        return spec

    def previous_scenario(self) -> str:
        """Stage 1's accepted answer as the model wrote it (its own words and reasoning), else rebuilt
        from scenario.json and spec.json."""
        keys = [None] if self.request.proposals <= 1 else [f"proposal{self.request.pick + 1}", None]
        for key in keys:
            raw = accepted_reply(self.run, "scenario", key)
            if raw is not None:
                return raw
        scenario = self.run.read_scenario()
        previous: dict = scenario.model_dump()
        spec = self.run.read_spec()
        if spec is not None:
            previous["spec"] = spec.model_dump(mode="json", exclude_defaults=True)
        return json.dumps(previous)

    def scenario(self, correction: str | None = None) -> tuple[ScenarioProposal, ScenarioSpec | None]:
        """Stage 1: the prose and its spec. `correction` (from --verify) re-asks with the previous answer."""
        if self.run.scenario_path.is_file() and correction is None:
            self.emit("scenario", None, "skipped", "scenario.json exists")
            scenario = self.run.read_scenario()
            return scenario, self.read_spec(scenario)
        self.recorder.set_status("scenario", None, "running")
        self.emit("scenario", None, "start")
        check = scenario_stage.scenario_checker(self.location, self.request.target)
        grammar = scenario_stage.stage_grammar(self.llm, self.location, self.request.target)

        def again(messages: list[ChatMessage], policy: Policy | None = None) -> Outcome:
            return converse(self.llm, messages, scenario_stage.ScenarioReply, check, stage="scenario", key=None,
                            recorder=self.recorder, policy=policy or self.policy, grammar=grammar,
                            max_tokens=scenario_stage.MAX_TOKENS)

        def first(policy: Policy) -> Outcome:
            return again(scenario_stage.fitted_scenario_messages(self.request, self.location, self.llm,
                                                                 note=self.recorder.note), policy)

        if correction is not None:
            chosen = again(scenario_stage.fitted_scenario_messages(
                self.request, self.location, self.llm, note=self.recorder.note,
                tail=[ChatMessage(role="assistant", content=self.previous_scenario()),
                      ChatMessage(role="user", content=correction)]))
        else:
            outcomes = scenario_stage.propose_scenarios(self.request, self.location, self.llm, self.recorder,
                                                        self.policy)
            proposals = [scenario_stage.to_proposal(o.value) for o in outcomes]
            pick = self.request.pick
            if not 0 <= pick < len(proposals):
                raise SocnavgenError(f"--pick {pick + 1} but only {len(proposals)} proposal(s) were made",
                                     hint="--pick counts from 1 and must be at most --proposals")
            atomic_write_json(self.run.proposals_path, [p.model_dump() for p in proposals])
            chosen = outcomes[pick]
        chosen = self.reviewed("scenario", None, chosen, first, again,
                               lambda o: json.dumps(o.value.model_dump(), indent=2, ensure_ascii=False))
        proposal = scenario_stage.to_proposal(chosen.value)
        spec = scenario_stage.to_spec(chosen.value)
        self.run.write_scenario(proposal)
        if spec is not None:
            self.run.write_spec(spec)
        self.recorder.set_status("scenario", None, "done")
        self.emit("scenario", None, "done", f"{proposal.number_of_humans} human(s)")
        return proposal, spec

    # -- stage 2 -----------------------------------------------------------------------------------
    def paths(self, scenario: ScenarioProposal, spec: ScenarioSpec | None = None,
              correction: str | None = None) -> tuple[PathPlan, ScenarioSpec | None]:
        """Stage 2: paths, and each encounter of the spec grounded on a node (spec.json rewritten)."""
        humans = list(scenario.human_behaviors)
        if self.run.paths_path.is_file() and correction is None:
            self.emit("paths", None, "skipped", "paths.json exists")
            plan = self.run.read_paths()
            grounded = self.read_spec(scenario, grounded=spec is not None)
            if grounded is not None:
                answer = PathsReply.model_validate(path_stage.plan_to_answer(plan, grounded))
                mistakes = check_paths(answer, self.location.graph, humans, grounded, self.location,
                                       scenario.human_behaviors)
                if mistakes:
                    raise InputFileError("paths.json and spec.json disagree: " + "; ".join(mistakes[:5]),
                                         file=self.run.paths_path,
                                         hint="fix the files, or regenerate with --from RUN --redo paths")
            return plan, grounded
        self.recorder.set_status("paths", None, "running")
        self.emit("paths", None, "start")
        base = path_stage.fitted_paths_messages(self.location, scenario, self.llm, self.request, spec,
                                                note=self.recorder.note)
        messages = list(base)
        if correction is not None:  # the verifier's findings, after the answer that produced them
            previous = accepted_reply(self.run, "paths", None) or json.dumps(
                path_stage.plan_to_answer(self.run.read_paths(), self.run.read_spec()))
            messages = path_stage.fitted_paths_messages(
                self.location, scenario, self.llm, self.request, spec, note=self.recorder.note,
                tail=[ChatMessage(role="assistant", content=previous), ChatMessage(role="user", content=correction)])

        def first(policy: Policy) -> Outcome:
            return path_stage.plan_paths(base, self.location, scenario, self.llm, self.recorder, policy, spec)

        def again(history: list[ChatMessage]) -> Outcome:
            return path_stage.plan_paths(history, self.location, scenario, self.llm, self.recorder, self.policy,
                                         spec)

        outcome = again(messages)
        outcome = self.reviewed("paths", None, outcome, first, again,
                                lambda o: to_path_plan(o.value, humans, spec).model_dump_json(indent=2))
        plan = to_path_plan(outcome.value, humans, spec)
        self.run.write_paths(plan)
        grounded = None
        if spec is not None:
            grounded = ground_spec(spec, outcome.value)
            self.run.write_spec(grounded)
        self.recorder.set_status("paths", None, "done")
        self.emit("paths", None, "done", f"robot {' '.join(plan.robot)}")
        return plan, grounded

    def plan(self, scenario: ScenarioProposal, spec: ScenarioSpec | None = None, correction: str | None = None
             ) -> tuple[ScenarioProposal, ScenarioSpec | None, PathPlan, ScenarioSpec | None]:
        """Stage 2 (`paths`), and stage 1 again whenever stage 2 cannot satisfy a rule whose cause is stage 1's
        (UpstreamFailed: hospital_10's meeting distance), up to the restart budget; stage 2 then starts afresh on
        the new spec. Returns the scenario and its spec (new when stage 1 was asked), the paths and the grounded
        spec."""
        for asked in range(self.policy.max_restarts + 1):
            try:
                plan, grounded = self.paths(scenario, spec, correction)
                return scenario, spec, plan, grounded
            except UpstreamFailed as failed:
                if asked == self.policy.max_restarts:
                    raise
                self.emit("paths", None, "failed", "what it cannot satisfy is caused by stage 1: asking stage 1")
                scenario, spec = self.scenario(correction=upstream_correction(failed))
                correction = None
                self.run.paths_path.unlink(missing_ok=True)  # planned for the old spec (a --verify re-ask's)
        raise AssertionError("unreachable: the last UpstreamFailed is raised")

    # -- stage 3 -----------------------------------------------------------------------------------
    def behaviors(self, scenario: ScenarioProposal, paths: PathPlan, spec: ScenarioSpec | None = None,
                  corrections: dict[str, str] | None = None) -> dict[str, str]:
        humans = list(scenario.human_behaviors)
        target = self.request.target
        existing = self.run.behaviors()
        todo = [h for h in humans if h not in existing or (corrections and h in corrections)]
        for extra in set(existing) - set(humans):  # left over from an earlier scenario
            self.run.behavior_path(extra).unlink(missing_ok=True)
        if not todo:
            self.emit("behaviors", None, "skipped", "every tree exists")
            return {h: existing[h] for h in humans}
        self.recorder.set_status("behaviors", None, "running")
        self.emit("behaviors", None, "start", f"{len(todo)} tree(s)")
        accepted: dict[str, Outcome] = {}

        def save(name: str, outcome: Outcome) -> None:
            if self.review is None:
                self.run.write_behavior(name, bt_stage.pretty_xml(outcome.value.tree))
                self.recorder.set_status("behaviors", name, "done")
                self.emit("behaviors", name, "done")
            accepted[name] = outcome

        def ask(messages: list[ChatMessage], name: str, policy: Policy | None = None) -> Outcome:
            return bt_stage.ask_behavior(messages, name, humans, self.llm, self.recorder, policy or self.policy,
                                         spec, target)

        if corrections:
            for name in [h for h in todo if h in corrections]:
                previous = accepted_reply(self.run, "behaviors", name) or json.dumps(
                    {"reasoning": "", "tree": existing.get(name, "")})
                messages = bt_stage.fitted_behavior_messages(
                    name, scenario, paths, self.llm, spec, target, note=self.recorder.note,
                    tail=[ChatMessage(role="assistant", content=previous),
                          ChatMessage(role="user", content=corrections[name])])
                save(name, ask(messages, name))
            todo = [h for h in todo if h not in corrections]
        if todo:
            bt_stage.design_behaviors(todo, scenario, paths, self.llm, self.recorder, self.policy, save, spec, target)
        if self.review is not None:
            for name in sorted(accepted, key=humans.index):
                def first(policy: Policy, name: str = name) -> Outcome:
                    return ask(bt_stage.fitted_behavior_messages(name, scenario, paths, self.llm, spec, target,
                                                                 note=self.recorder.note), name, policy)

                def again(history: list[ChatMessage], name: str = name) -> Outcome:
                    return ask(history, name)

                outcome = self.reviewed("behaviors", name, accepted[name], first, again,
                                        lambda o: bt_stage.pretty_xml(o.value.tree))
                self.run.write_behavior(name, bt_stage.pretty_xml(outcome.value.tree))
                self.recorder.set_status("behaviors", name, "done")
        self.recorder.set_status("behaviors", None, "done")
        self.emit("behaviors", None, "done")
        return self.run.behaviors()
