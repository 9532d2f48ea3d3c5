"""`generate(request, llm, out)`: scenario -> paths -> behavior trees into a run folder.

Each stage writes its file atomically when it succeeds, and manifest.json after every attempt, so an
interrupted run resumes at the first missing file (re-running on the same folder) and a failed one
keeps everything it produced. `redo` deletes the files of the named stages (and of the stages that
depend on them) before resuming.
"""

from __future__ import annotations

import json
import shutil
from collections.abc import Callable
from dataclasses import dataclass, field
from datetime import UTC, datetime
from pathlib import Path

from socnavgen import __version__
from socnavgen.errors import LLMError, SocnavgenError, StageFailed
from socnavgen.llm.base import LLM, ChatMessage
from socnavgen.location import Location, load_location
from socnavgen.proposal import behaviors as bt_stage
from socnavgen.proposal import paths as path_stage
from socnavgen.proposal import scenario as scenario_stage
from socnavgen.proposal.conversation import (
    Outcome,
    Policy,
    ProgressEvent,
    ProgressFn,
    Recorder,
    converse,
    no_progress,
)
from socnavgen.proposal.path_checks import to_path_plan
from socnavgen.proposal.review import ReviewHook
from socnavgen.proposal.templates import render
from socnavgen.run import Manifest, PathPlan, RunFolder, ScenarioProposal, ScenarioRequest
from socnavgen.safeio import atomic_write_json

STAGES = ("scenario", "paths", "behaviors")
# Fields that define WHAT was asked: a folder holding another request is not resumed silently.
IDENTITY_FIELDS = ("location", "context", "task", "rough", "card", "naive")
MAX_REVIEW_ROUNDS = 10


@dataclass
class Run:
    folder: RunFolder
    scenario: ScenarioProposal
    paths: PathPlan
    behaviors: dict[str, str] = field(default_factory=dict)
    manifest: Manifest | None = None
    verify: object | None = None  # the verifier's report when --verify ran


def stages_to_redo(redo: set[str] | None) -> set[str]:
    """A stage's files depend on the stages before it: redoing one redoes all that follow."""
    if not redo:
        return set()
    unknown = set(redo) - set(STAGES)
    if unknown:
        raise SocnavgenError(f"cannot redo {', '.join(sorted(unknown))}", hint=f"stages are {', '.join(STAGES)}")
    first = min(STAGES.index(s) for s in redo)
    return set(STAGES[first:])


def copy_run(source: Path, out: Path) -> None:
    """`--from RUN --out OTHER`: start OTHER as a copy of RUN (its simulation results are left behind)."""
    source, out = Path(source), Path(out)
    if not (source / "request.json").is_file():
        raise SocnavgenError("not a run folder (no request.json)", file=source, hint="give the --out of an earlier run")
    if out.exists() and any(out.iterdir()):
        raise SocnavgenError("the --out folder already exists and is not empty", file=out,
                             hint="choose a new --out, or omit it to regenerate in place")
    shutil.copytree(source, out, ignore=shutil.ignore_patterns("sim", ".*.tmp"), dirs_exist_ok=True)


def _clear(run: RunFolder, stages: set[str], manifest: Manifest) -> None:
    if "scenario" in stages:
        run.scenario_path.unlink(missing_ok=True)
        run.proposals_path.unlink(missing_ok=True)
    if "paths" in stages:
        run.paths_path.unlink(missing_ok=True)
    if "behaviors" in stages and run.behaviors_dir.is_dir():
        for xml in run.behaviors_dir.glob("*.xml"):
            xml.unlink()
    for name in list(manifest.stages):
        if name.split(":")[0] in stages or name == "verify":
            del manifest.stages[name]


def _open_request(run: RunFolder, request: ScenarioRequest) -> None:
    if run.request_path.is_file():
        old = run.read_request()
        changed = [f for f in IDENTITY_FIELDS if getattr(old, f) != getattr(request, f)]
        if changed:
            raise SocnavgenError(f"this run folder holds a different request ({', '.join(changed)} differ)",
                                 file=run.request_path,
                                 hint="use a new --out, or --from RUN --redo STAGE to change a run")
    run.write_request(request)


def _open_manifest(run: RunFolder, request: ScenarioRequest, llm: LLM) -> Manifest:
    if run.manifest_path.is_file():
        manifest = run.read_manifest()
    else:
        manifest = Manifest(socnavgen_version=__version__, created=datetime.now(UTC).isoformat(timespec="seconds"),
                            llm=request.llm)
    manifest.llm, manifest.model, manifest.status, manifest.message = request.llm, getattr(llm, "model", None), \
        "running", None
    return manifest


class _Pipeline:
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
    def scenario(self) -> ScenarioProposal:
        if self.run.scenario_path.is_file():
            self.emit("scenario", None, "skipped", "scenario.json exists")
            return self.run.read_scenario()
        self.recorder.set_status("scenario", None, "running")
        self.emit("scenario", None, "start")
        outcomes = scenario_stage.propose_scenarios(self.request, self.location, self.llm, self.recorder, self.policy)
        proposals = [scenario_stage.to_proposal(o.value) for o in outcomes]
        pick = self.request.pick
        if not 0 <= pick < len(proposals):
            raise SocnavgenError(f"--pick {pick + 1} but only {len(proposals)} proposal(s) were made",
                                 hint="--pick counts from 1 and must be at most --proposals")
        atomic_write_json(self.run.proposals_path, [p.model_dump() for p in proposals])
        chosen = outcomes[pick]

        def first(policy: Policy) -> Outcome:
            return converse(
                self.llm, scenario_stage.scenario_messages(self.request, self.location), scenario_stage.ScenarioReply,
                scenario_stage.check_scenario, stage="scenario", key=None, recorder=self.recorder, policy=policy,
                grammar=self._grammar(scenario_stage.scenario_grammar), max_tokens=scenario_stage.MAX_TOKENS)

        def again(messages: list[ChatMessage]) -> Outcome:
            return converse(
                self.llm, messages, scenario_stage.ScenarioReply, scenario_stage.check_scenario, stage="scenario",
                key=None, recorder=self.recorder, policy=self.policy,
                grammar=self._grammar(scenario_stage.scenario_grammar), max_tokens=scenario_stage.MAX_TOKENS)

        chosen = self.reviewed("scenario", None, chosen, first, again,
                               lambda o: scenario_stage.to_proposal(o.value).model_dump_json(indent=2))
        proposal = scenario_stage.to_proposal(chosen.value)
        self.run.write_scenario(proposal)
        self.recorder.set_status("scenario", None, "done")
        self.emit("scenario", None, "done", f"{proposal.number_of_humans} human(s)")
        return proposal

    def _grammar(self, build: Callable[[], str]) -> str | None:
        return build() if getattr(self.llm, "supports_grammar", False) else None

    # -- stage 2 -----------------------------------------------------------------------------------
    def paths(self, scenario: ScenarioProposal, correction: str | None = None) -> PathPlan:
        if self.run.paths_path.is_file() and correction is None:
            self.emit("paths", None, "skipped", "paths.json exists")
            return self.run.read_paths()
        self.recorder.set_status("paths", None, "running")
        self.emit("paths", None, "start")
        images = self.request.use_image and getattr(self.llm, "supports_images", False)
        base = path_stage.paths_messages(self.location, scenario, seed=self.request.seed, images=images)
        messages = list(base)
        if correction is not None:  # the verifier's findings, after the answer that produced them
            previous = path_stage.plan_to_answer(self.run.read_paths())
            messages += [ChatMessage(role="assistant", content=json.dumps(previous)),
                         ChatMessage(role="user", content=correction)]
        humans = list(scenario.human_behaviors)

        def first(policy: Policy) -> Outcome:
            return path_stage.plan_paths(base, self.location, scenario, self.llm, self.recorder, policy)

        def again(history: list[ChatMessage]) -> Outcome:
            return path_stage.plan_paths(history, self.location, scenario, self.llm, self.recorder, self.policy)

        outcome = again(messages)
        outcome = self.reviewed("paths", None, outcome, first, again,
                                lambda o: to_path_plan(o.value, humans).model_dump_json(indent=2))
        plan = to_path_plan(outcome.value, humans)
        self.run.write_paths(plan)
        self.recorder.set_status("paths", None, "done")
        self.emit("paths", None, "done", f"robot {' '.join(plan.robot)}")
        return plan

    # -- stage 3 -----------------------------------------------------------------------------------
    def behaviors(self, scenario: ScenarioProposal, paths: PathPlan,
                  corrections: dict[str, str] | None = None) -> dict[str, str]:
        humans = list(scenario.human_behaviors)
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

        if corrections:
            for name in [h for h in todo if h in corrections]:
                messages = [*bt_stage.behavior_messages(name, scenario, paths),
                            ChatMessage(role="assistant", content=json.dumps(
                                {"reasoning": "", "tree": existing.get(name, "")})),
                            ChatMessage(role="user", content=corrections[name])]
                save(name, bt_stage.ask_behavior(messages, name, humans, self.llm, self.recorder, self.policy))
            todo = [h for h in todo if h not in corrections]
        if todo:
            bt_stage.design_behaviors(todo, scenario, paths, self.llm, self.recorder, self.policy, save)
        if self.review is not None:
            for name in sorted(accepted, key=humans.index):
                def first(policy: Policy, name: str = name) -> Outcome:
                    return bt_stage.ask_behavior(bt_stage.behavior_messages(name, scenario, paths), name, humans,
                                                 self.llm, self.recorder, policy)

                def again(history: list[ChatMessage], name: str = name) -> Outcome:
                    return bt_stage.ask_behavior(history, name, humans, self.llm, self.recorder, self.policy)

                outcome = self.reviewed("behaviors", name, accepted[name], first, again,
                                        lambda o: bt_stage.pretty_xml(o.value.tree))
                self.run.write_behavior(name, bt_stage.pretty_xml(outcome.value.tree))
                self.recorder.set_status("behaviors", name, "done")
        self.recorder.set_status("behaviors", None, "done")
        self.emit("behaviors", None, "done")
        return self.run.behaviors()


def generate(request: ScenarioRequest, llm: LLM, out: Path, *, redo: set[str] | None = None,
             review: ReviewHook | None = None, progress: ProgressFn = no_progress, verify: bool = False) -> Run:
    """Run (or resume) the pipeline into `out`. Raises StageFailed / LLMError with the run folder intact
    and manifest.json saying `failed`."""
    run = RunFolder(Path(out))
    run.root.mkdir(parents=True, exist_ok=True)
    location = load_location(request.location)
    _open_request(run, request)
    manifest = _open_manifest(run, request, llm)
    _clear(run, stages_to_redo(redo), manifest)
    recorder = Recorder(run, manifest, progress)
    recorder.save()
    pipeline = _Pipeline(request, llm, run, location, recorder, review)
    try:
        if request.naive:
            from socnavgen.proposal.naive import generate_naive
            scenario, paths, trees = generate_naive(pipeline)
        else:
            scenario = pipeline.scenario()
            paths = pipeline.paths(scenario)
            trees = pipeline.behaviors(scenario, paths)
        report = None
        if verify:
            from socnavgen.proposal.verify_loop import verify_and_repair
            scenario, paths, trees, report = verify_and_repair(pipeline, scenario, paths, trees)
    except (StageFailed, LLMError) as exc:
        _mark_failed(manifest, exc.message)
        recorder.save()
        raise
    except BaseException as exc:  # interrupted: the files written so far are complete; resume later
        _mark_failed(manifest, f"interrupted ({type(exc).__name__}: {exc})")
        recorder.save()
        raise
    manifest.status = "done"
    recorder.save()
    return Run(folder=run, scenario=scenario, paths=paths, behaviors=trees, manifest=manifest, verify=report)


def _mark_failed(manifest: Manifest, message: str) -> None:
    manifest.status, manifest.message = "failed", message
    for record in manifest.stages.values():
        if record.status == "running":
            record.status = "failed"


def verifier() -> Callable[[Path], object]:
    """The verifier `--verify` calls (a seam tests can replace)."""
    from socnavgen.verify import verify_run

    return verify_run
