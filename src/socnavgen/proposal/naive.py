"""The naive baseline (SocRATES Table III): one prompt, no tutorials and no examples, asking for the
scenario, the paths and the trees at once. It is checked by the SAME validators and given the same
attempt budget, and it stores the same run files, so the evaluation compares like with like."""

from __future__ import annotations

from socnavgen.bt.describe import library_text
from socnavgen.bt.library import Target
from socnavgen.llm.base import ChatMessage
from socnavgen.location import Location
from socnavgen.proposal.behaviors import pretty_xml, tree_checker
from socnavgen.proposal.conversation import converse
from socnavgen.proposal.path_checks import check_paths, to_path_plan
from socnavgen.proposal.paths import scene_graph_text
from socnavgen.proposal.replies import BehaviorReply, NaiveReply, PathsReply, ScenarioReply, human_name
from socnavgen.proposal.scenario import check_scenario, location_text, to_proposal
from socnavgen.proposal.stages import Stages
from socnavgen.proposal.templates import render
from socnavgen.run import PathPlan, ScenarioProposal, ScenarioRequest

STAGE = "naive"
MAX_TOKENS = 4096


def naive_messages(request: ScenarioRequest, location: Location) -> list[ChatMessage]:
    return [ChatMessage(role="user", content=render(
        "naive_user.md", context=request.context, task=request.task, location=location_text(location, inventory=False),
        rough=request.rough or "None", scene_graph=scene_graph_text(location), library=library_text(request.target or "socrates")))]


def naive_parts(reply: NaiveReply, location: Location, target: Target | None = None) -> dict[str, list[str]]:
    """Mistakes per part (scenario, paths, trees): the evaluation scores path and tree validity apart."""
    scenario = check_scenario(ScenarioReply.model_validate(reply.model_dump()))
    humans = sorted({h for k in reply.human_behaviors if (h := human_name(k))}, key=lambda s: int(s[5:]))
    paths = check_paths(PathsReply.model_validate(reply.model_dump()), location.graph, humans, location=location)
    trees: list[str] = []
    given = {human_name(k) or k: v for k, v in reply.trees.items()}
    for name in humans:
        if name not in given:
            trees.append(f"trees: {name} has no tree")
        else:
            trees += tree_checker(name, humans, None, target)(_tree_reply(given[name]))
    trees += [f"trees: '{k}' is not a human of the scenario" for k in given if k not in humans]
    return {"scenario": scenario, "paths": paths, "trees": trees}


def _tree_reply(tree: str) -> BehaviorReply:
    return BehaviorReply(tree=tree)


def generate_naive(pipeline: Stages) -> tuple[ScenarioProposal, PathPlan, dict[str, str]]:
    run = pipeline.run
    if run.scenario_path.is_file() and run.paths_path.is_file():
        scenario = run.read_scenario()
        if set(run.behaviors()) >= set(scenario.human_behaviors):
            return scenario, run.read_paths(), run.behaviors()
    location = pipeline.location
    pipeline.recorder.set_status(STAGE, None, "running")

    def check(reply: NaiveReply) -> list[str]:
        return [m for part in naive_parts(reply, location, pipeline.request.target).values() for m in part]

    outcome = converse(pipeline.llm, naive_messages(pipeline.request, location), NaiveReply, check, stage=STAGE,
                       key=None, recorder=pipeline.recorder, policy=pipeline.policy, max_tokens=MAX_TOKENS)
    reply = outcome.value
    scenario = to_proposal(ScenarioReply.model_validate(reply.model_dump()))
    humans = list(scenario.human_behaviors)
    paths = to_path_plan(PathsReply.model_validate(reply.model_dump()), humans)
    given = {human_name(k) or k: v for k, v in reply.trees.items()}
    run.write_scenario(scenario)
    run.write_paths(paths)
    for name in humans:
        run.write_behavior(name, pretty_xml(given[name]))
    pipeline.recorder.set_status(STAGE, None, "done")
    return scenario, paths, run.behaviors()
