"""`bt check`: one function used by stage 3 (re-query on mistakes), by `socnavgen bt check` (people
editing trees by hand) and by the exporters (target support).

The tree language itself is checked by bt.model (parsing) and bt.expand (SubTrees, blackboard data flow),
the same code the simulator loads trees with; this module adds what an export target and a scenario say:
nodes the target cannot run (its loader knows only its own nodes) and `other_human` ports naming a
human of the scenario. Every problem names the exact mistake and its line; hostile input never raises.
"""

from __future__ import annotations

from collections.abc import Iterable
from pathlib import Path

from socnavgen.bt.expand import check_text
from socnavgen.bt.library import TARGETS, NodeSpec, hunav2_refusal, known_nodes
from socnavgen.bt.model import BTProblem, Document
from socnavgen.bt.tree import MAX_XML_BYTES
from socnavgen.errors import SocnavgenError

__all__ = ["MAX_PROBLEMS", "TARGETS", "BTProblem", "format_problems", "validate_bt_file", "validate_bt_text"]
MAX_PROBLEMS = 50  # more than this is noise for a model (and for a person)


def validate_bt_text(text: str, source: str = "<reply>", *, target: str = "socrates",
                     human_ids: set[int] | None = None, agent_id: int | None = None) -> list[BTProblem]:
    """Every problem of a BT XML text (empty list = valid). Never raises on bad input.

    `target` reports nodes the export target cannot run; `human_ids` (the ids of the scenario's
    humans) bounds HumanSays/FollowHuman `target_id`; `agent_id` (the tree's own human) forbids
    targeting oneself.
    """
    problems: list[BTProblem] = []
    if target not in TARGETS:
        problems.append(BTProblem(f"unknown target '{target}'; targets: {', '.join(TARGETS)}", None, source))
    try:
        doc, _, found = check_text(text, source, known_nodes(target if target in TARGETS else None))
        problems += found
        if doc is not None:
            problems += _context_problems(doc, target, human_ids, agent_id)
    except RecursionError:
        problems.append(BTProblem("tree is nested too deeply to check", None, source))
    except Exception as exc:  # noqa: BLE001 - the contract: hostile input is a problem, not a crash
        problems.append(BTProblem(f"could not check the tree ({type(exc).__name__}: {exc})", None, source))
    if len(problems) > MAX_PROBLEMS:
        extra = len(problems) - MAX_PROBLEMS
        problems = [*problems[:MAX_PROBLEMS],
                    BTProblem(f"... and {extra} more problems (fix the ones above first)", None, source)]
    return problems


def validate_bt_file(path: Path | str, *, target: str = "socrates", human_ids: set[int] | None = None,
                     agent_id: int | None = None) -> list[BTProblem]:
    """Validate a tree file. Includes are resolved against the library's own trees, never the disk."""
    from socnavgen.safeio import read_text_limited

    source = str(path)
    try:
        text = read_text_limited(Path(path), limit=MAX_XML_BYTES)
    except SocnavgenError as exc:
        return [BTProblem(exc.message + (f" ({exc.hint})" if exc.hint else ""), exc.line, source)]
    except OSError as exc:
        return [BTProblem(f"cannot read the file: {exc.strerror or exc}", None, source)]
    return validate_bt_text(text, source, target=target, human_ids=human_ids, agent_id=agent_id)


def format_problems(problems: Iterable[BTProblem]) -> str:
    """Problems one per line, as appended to a re-query and printed by `bt check`."""
    return "\n".join(str(p) for p in problems)


def _context_problems(doc: Document, target: str, human_ids: set[int] | None,
                      agent_id: int | None) -> list[BTProblem]:
    """Nodes `target` cannot run; literal ids of other humans that are no human of the scenario."""
    problems: list[BTProblem] = []
    for tree in doc.trees.values():
        for node in tree.root.walk() if tree.root is not None else ():
            spec = node.spec
            if spec is None or node.kind == "unknown":  # named by the parser (the target's loader lacks it)
                continue
            if target in TARGETS and target not in spec.targets:
                problems.append(BTProblem(_target_message(spec, target), node.line, doc.source))
            for port in spec.ports:
                value = node.ports.get(port.name)
                if not port.other_human or not isinstance(value, int):
                    continue
                where = f"{spec.name} {port.name}='{node.attrs.get(port.name)}'"
                if agent_id is not None and value == agent_id:
                    problems.append(BTProblem(f"{where}: {port.name} {value} is this human itself; name another "
                                              "human", node.line, doc.source))
                elif human_ids is not None and value not in human_ids:
                    ids = ", ".join(str(i) for i in sorted(human_ids)) or "none"
                    problems.append(BTProblem(f"{where}: there is no human with id {value}; human ids: {ids}",
                                              node.line, doc.source))
    return problems


def _target_message(spec: NodeSpec, target: str) -> str:
    if target == "hunav2" and hunav2_refusal(spec.name):
        return f"node '{spec.name}' is not supported by target hunav2: {hunav2_refusal(spec.name)}"
    equivalent = getattr(spec, target, None) if target != "socrates" else None
    hint = f" (its {target} counterpart is '{equivalent}')" if equivalent else ""
    return f"node '{spec.name}' is not supported by target {target}{hint}"
