"""Stage 3: one behavior tree per human (SocRATES Sec. III-D), asked in parallel.

The prompt holds the BT tutorial (syntax rules + Q&A, a template), the node library text and the
regular-navigation idiom (both generated from the library table by socnavgen.bt.describe), worked
examples, and the human's behavior with its path, group and meeting point. Every tree is checked by
the same validator as `socnavgen bt check`.
"""

from __future__ import annotations

import json
import re
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor

from defusedxml import minidom

from socnavgen.bt.describe import library_text, regular_nav_text
from socnavgen.bt.grammar import bt_reply_grammar
from socnavgen.bt.library import Target
from socnavgen.bt.validate import validate_bt_text
from socnavgen.errors import StageFailed
from socnavgen.llm.base import LLM, ChatMessage
from socnavgen.proposal.conversation import Outcome, Policy, Recorder, converse
from socnavgen.proposal.facts import physical_facts_text
from socnavgen.proposal.fit import NOTHING, Cut, Note, examples_kept, fit_prompt
from socnavgen.proposal.replies import BehaviorReply
from socnavgen.proposal.target_facts import export_text
from socnavgen.proposal.templates import render, template_data
from socnavgen.proposal.tree_grammar import spec_tree_grammar
from socnavgen.proposal.tree_needs import needs_text, tree_need_mistakes
from socnavgen.run import HumanPlan, PathPlan, ScenarioProposal
from socnavgen.run.spec import ScenarioSpec

STAGE = "behaviors"
MAX_TOKENS = 1536
# Nesting the grammar allows: Fallback > Sequence > leaf (the idiom of every example) fits; a small
# model under a grammar tends to take every level it is offered, and each level costs tokens.
GRAMMAR_DEPTH = 3


def examples_text(left_out: Cut = NOTHING) -> str:
    return "\n\n".join(render("bt_example.md", behavior=ex["behavior"].strip(),
                              answer=json.dumps({"reasoning": ex["reasoning"].strip(), "tree": ex["tree"].strip()}))
                       for ex in examples_kept(left_out, template_data("bt_examples.yaml")))


def path_line(plan: HumanPlan) -> str:
    """Where a human starts and its goal list as the simulator (and HuNavSim) walks it (HumanPlan.goals: the start
    is no goal), so RegularNav without UpdateGoal walks to the first node after it. Told "goals in order: ai, 41",
    home_18's model walked the physiotherapist "back to his current goal ai" after the handover, and he stood on
    the robot's goal 41 for good."""
    name, goals = plan.name, plan.goals
    if len(plan.path) < 2:
        return f"{name} starts at {', '.join(goals) or '?'}, its only goal."
    return (f"{name} starts at {plan.path[0]}; its goals in order: {', '.join(goals)} (the start is not one of "
            f"them: RegularNav walks to the current goal, {goals[0]} from the start on, and UpdateGoal moves on to "
            f"the next; to come back to a node, the path must end there again).")


def human_context(name: str, scenario: ScenarioProposal, paths: PathPlan | None) -> str:
    """Where this human walks, its group and its meeting point: what the tree has to fit."""
    lines = [f"Scenario: {scenario.scenario_description}"]
    if paths is not None:
        plan = paths.human(name)
        lines.append(path_line(plan))
        mates = [h.name for h in paths.humans if h.group_id >= 0 and h.group_id == plan.group_id and h.name != name]
        lines.append(f"{name} walks in a group with {', '.join(mates)}." if mates else f"{name} is not in a group.")
        if plan.interaction_point:
            lines.append(f"{name} meets the robot at node {plan.interaction_point}.")
    others = [f"{h} (agent id {i})" for i, h in enumerate(scenario.human_behaviors) if h != name]
    if others:
        lines.append(f"Other humans: {', '.join(others)}.")
    return "\n".join(lines)


def agent_id(name: str) -> int:
    return HumanPlan(name=name, path=[]).agent_id


def behavior_messages(name: str, scenario: ScenarioProposal, paths: PathPlan | None,
                      spec: ScenarioSpec | None = None, target: Target | None = None,
                      left_out: Cut = NOTHING) -> list[ChatMessage]:
    """The stage-3 prompt of one human; `left_out`: parts fit.py leaves out for a small context (the example
    trees, the tutorial's questions and answers)."""
    context = human_context(name, scenario, paths)
    needs = needs_text(name, spec, target or "socrates")
    if needs:
        context += "\n" + needs
    tutorial = render("bt_tutorial.md") + ("" if "tutorials" in left_out else "\n\n" + render("bt_tutorial_qa.md"))
    examples = "EXAMPLES\n" + examples_text(left_out) if "examples" not in left_out else ""
    user = render("bt_user.md", tutorial=tutorial, library=library_text(target or "socrates"),
                  export=export_text(target), regular_nav=regular_nav_text(), examples=examples, human=name,
                  agent_id=agent_id(name), behavior=scenario.human_behaviors[name], context=context,
                  facts=physical_facts_text())
    return [ChatMessage(role="system", content=render("bt_system.md")),
            ChatMessage(role="user", content=re.sub(r"\n{3,}", "\n\n", user))]


def fitted_behavior_messages(name: str, scenario: ScenarioProposal, paths: PathPlan | None, llm: LLM,
                             spec: ScenarioSpec | None = None, target: Target | None = None,
                             tail: list[ChatMessage] | None = None, note: Note | None = None) -> list[ChatMessage]:
    """The stage-3 prompt of one human (then `tail`) shortened to fit the model's context (fit.py)."""
    return fit_prompt(llm, lambda cut: [*behavior_messages(name, scenario, paths, spec, target, cut), *(tail or [])],
                      reply_tokens=MAX_TOKENS, stage=f"{STAGE} ({name})", note=note)


def tree_checker(name: str, humans: list[str], spec: ScenarioSpec | None = None,
                 target: Target | None = None) -> Callable[[BehaviorReply], list[str]]:
    """The validator's problems (nodes the target cannot run included); on a valid tree, what its
    encounter parts need and it lacks."""
    ids = {agent_id(h) for h in humans}

    def check(reply: BehaviorReply) -> list[str]:
        problems = [str(p) for p in validate_bt_text(reply.tree, f"behaviors/{name}.xml", target=target or "socrates",
                                                     human_ids=ids, agent_id=agent_id(name))]
        if problems:
            return problems
        return tree_need_mistakes(reply.tree, name, spec, target or "socrates")
    return check


def pretty_xml(text: str) -> str:
    """Indented XML with double-quoted attributes, as HuNavSim users read it (the reply used single quotes)."""
    dom = minidom.parseString(text.strip())
    root = dom.documentElement
    assert root is not None  # parseString refuses a document without a root element
    _strip_blank_text(root)
    body = root.toprettyxml(indent="    ")
    return "\n".join(line for line in body.splitlines() if line.strip()) + "\n"


def _strip_blank_text(node) -> None:  # noqa: ANN001 - a minidom node
    for child in list(node.childNodes):
        if child.nodeType == child.TEXT_NODE and not child.data.strip():
            node.removeChild(child)
        elif child.hasChildNodes():
            _strip_blank_text(child)


def ask_behavior(messages: list[ChatMessage], name: str, humans: list[str], llm: LLM, recorder: Recorder,
                 policy: Policy, spec: ScenarioSpec | None = None, target: Target | None = None
                 ) -> Outcome[BehaviorReply]:
    grammar = None
    if getattr(llm, "supports_grammar", False):
        grammar = spec_tree_grammar(name, spec, target or "socrates") or bt_reply_grammar(
            [agent_id(h) for h in humans], agent_id=agent_id(name), target=target or "socrates",
            max_depth=GRAMMAR_DEPTH)
    return converse(llm, messages, BehaviorReply, tree_checker(name, humans, spec, target), stage=STAGE, key=name,
                    recorder=recorder, policy=policy, grammar=grammar, max_tokens=MAX_TOKENS)


def design_behaviors(names: list[str], scenario: ScenarioProposal, paths: PathPlan | None, llm: LLM,
                     recorder: Recorder, policy: Policy,
                     on_done: Callable[[str, Outcome[BehaviorReply]], None], spec: ScenarioSpec | None = None,
                     target: Target | None = None) -> dict[str, Outcome[BehaviorReply]]:
    """Ask for every human in `names` in parallel (the LLM bounds concurrency); `on_done` runs as each
    tree arrives, so finished trees are saved even if another human's stage fails."""
    humans = list(scenario.human_behaviors)
    results: dict[str, Outcome[BehaviorReply]] = {}
    failures: list[StageFailed] = []

    def one(name: str) -> None:
        messages = fitted_behavior_messages(name, scenario, paths, llm, spec, target, note=recorder.note)
        outcome = ask_behavior(messages, name, humans, llm, recorder, policy, spec, target)
        on_done(name, outcome)
        results[name] = outcome

    with ThreadPoolExecutor(max_workers=max(1, len(names))) as pool:
        futures = {pool.submit(one, name): name for name in names}
        errors = []
        for future, _name in futures.items():
            exc = future.exception()
            if isinstance(exc, StageFailed):
                failures.append(exc)
            elif exc is not None:
                errors.append(exc)
    if errors:
        raise errors[0]
    if failures:
        if len(failures) == 1:
            raise failures[0]
        raise StageFailed("\n".join(f.message for f in failures), file=failures[0].file, hint=failures[0].hint)
    return results
