"""What each export target can run of the node library (bt/library.py's `targets`): the triggers a target detects,
how a reaction is latched there, and what the prompts say a target lacks. Split from facts.py (the facts of the
simulated world); generated from the library table, never typed twice."""

from __future__ import annotations

from typing import get_args

from socnavgen.bt.library import LIBRARY, TARGETS, Target, nodes_for_reaction, nodes_for_trigger, prompt_nodes
from socnavgen.run.spec import NEGATED_TRIGGERS, HumanTrigger, Reaction

# Conditions of the library whose SUCCESS stays once reached (bt/library.py's "latching conditions"), by the
# trigger they latch; any other trigger latches with LATCH_NODE (where the target keeps a RUNNING child).
LATCHING_CONDITIONS: dict[str, str] = {"robot_says": "RobotSaid"}
LATCH_NODE = "KeepRunningUntilFailure"


def latches_by_running(target: Target) -> bool:
    """Whether `target` keeps a Sequence at its RUNNING child (BT.CPP's Sequence; a reactive one re-checks the
    conditions before it every tick), so that LATCH_NODE after a condition keeps the reaction for good."""
    keep, sequence = LIBRARY.get(LATCH_NODE), LIBRARY["Sequence"]
    name = sequence.name if target == "socrates" else getattr(sequence, target, None)
    row = LIBRARY.get(name or "")
    return keep is not None and target in keep.targets and row is not None and not row.reactive


def can_latch(trigger: str, target: Target = "socrates") -> bool:
    return latching_node(trigger, target) is not None or latches_by_running(target)


def latch_text(target: Target = "socrates") -> str:
    if not any(can_latch(t, target) for t in get_args(HumanTrigger)):
        return (f"- \"latch\" cannot be used: {target} re-checks every condition at each tick, so a reaction lasts "
                f"while its trigger holds, or `lasts` seconds.")
    return ("- \"latch\": true keeps a reaction going for good once its trigger fired (seen the robot once, it "
            "said FOLLOW ME once): the trigger is not checked again. Without a latch a reaction lasts while its "
            "trigger holds, or `lasts` seconds if set. With both, `lasts` wins: the reaction runs its `lasts` s once triggered, "
            "whatever the trigger does, then they walk on for good.")


def export_text(target: Target | None = None, spec_words: bool = False) -> str:
    """Which nodes each export target lacks (bt.library), or with `spec_words` which triggers and reactions
    cannot run there, so that a model knows what will not export (with a `target` the prompts offer only
    what it runs and say so themselves: nothing to add)."""
    if target is not None:
        return ""
    lines = []
    for t in TARGETS:
        if spec_words:
            lacks = [w for w in get_args(HumanTrigger) if w != "always" and not detected(w, t)] + \
                [r for r in get_args(Reaction) if not nodes_for_reaction(r, t)]
        else:
            lacks = missing_nodes(t)
        if t != "socrates" and lacks:
            lines.append(f"{t} lacks {', '.join(lacks)}")
    if not lines:
        return ""
    return ("- Export: everything runs in the simulator and the SocRATES fork (--format socrates); "
            + "; ".join(lines) + " (a scenario using them cannot be exported there).")


def detecting_nodes(trigger: str, target: Target = "socrates") -> tuple[list[str], bool]:
    """The library nodes that detect a spec trigger on `target`, and whether a tree inverts them (a negated
    trigger of run/spec.py: robot_far is robot_near's condition inverted)."""
    base = NEGATED_TRIGGERS.get(trigger)
    return nodes_for_trigger(base or trigger, target), base is not None


def detected(trigger: str, target: Target) -> bool:
    return bool(detecting_nodes(trigger, target)[0])


def missing_nodes(target: Target) -> list[str]:
    """Nodes the prompts offer for the simulator that `target` cannot run."""
    return [n.name for n in prompt_nodes() if target not in n.targets]


def latching_node(trigger: str, target: Target = "socrates") -> str | None:
    node = LATCHING_CONDITIONS.get(trigger)
    return node if node is not None and node in nodes_for_trigger(trigger, target) else None
