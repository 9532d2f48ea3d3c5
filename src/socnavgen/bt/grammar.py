"""A GBNF grammar (llama.cpp syntax) for the stage-3 reply, so an in-process model can only write
a tree the validator accepts: library nodes with exactly their ports, typed values, gesture codes
in range, controls with children, decorators with one child, and the RegularNavTree idiom only
after its include. Generated from the library table; nesting is bounded to keep it small.

The reply is the JSON object {"reasoning": "...", "tree": "..."}; the XML sits inside a JSON
string, so its attributes are single-quoted and its line breaks are the two characters \\n.
"""

from __future__ import annotations

from collections.abc import Iterable

from socnavgen.bt.library import (
    LIBRARY_TREES,
    REGULAR_NAV_CALL,
    NodeSpec,
    Port,
    PortType,
    Target,
    prompt_nodes,
)

DEFAULT_TREE_ID = "HumanBehavior"
DEFAULT_MAX_DEPTH = 5
# llama.cpp expands x{1,n} into n nested rules; n over ~1000 overflows its stack (segfault, measured).
MAX_REASONING_CHARS = 400
# Children a control node may have, by its depth (1 = the BehaviorTree's child; the last value
# repeats). A small model under a grammar tends to take every "one more child" it is offered, so
# the bounds keep the largest possible tree (4*3*2 = 24 leaves, ~600 tokens) inside max_tokens.
# Where the bound is 1 only decorators are offered (a one-child Sequence says nothing).
CHILDREN_BY_DEPTH = (4, 3, 2, 1)


def _lit(text: str) -> str:
    """A GBNF string literal."""
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"') + '"'


def _alt(options: Iterable[str]) -> str:
    return " | ".join(options)


def _port_value(port: Port, target_ids: list[int] | None) -> str:
    """The GBNF expression for one port value (without quotes)."""
    if port.reads_root is not None:
        return _lit("{" + port.reads_root + "}")
    if port.allowed:
        return "(" + _alt(_lit(str(code)) for code in port.allowed) + ")"
    if port.other_human and target_ids is not None:
        return "(" + _alt(_lit(str(i)) for i in target_ids) + ")"
    typed = {PortType.INT: "int", PortType.DOUBLE: "num", PortType.BOOL: "bool", PortType.STRING: "text"}[port.type]
    return f"({_lit(port.example)} | {typed})" if port.example is not None else typed


def _ports_rule(spec: NodeSpec, target_ids: list[int] | None) -> str:
    """The node's ports as attributes: required ones always, optional ones maybe."""
    parts = []
    for port in spec.ports:
        attr = f"{_lit(f' {port.name}=' + chr(39))} {_port_value(port, target_ids)} {_lit(chr(39))}"
        parts.append(attr if port.required else f"({attr})?")
    return " ".join(parts)


def _leaf_rule(spec: NodeSpec, target_ids: list[int] | None) -> str:
    return " ".join(filter(None, [_lit(f"<{spec.name}"), "nm", _ports_rule(spec, target_ids), _lit("/>")]))


def _rule_name(name: str) -> str:
    return "".join(c if c.isalnum() else "-" for c in name).lower()


def bt_reply_grammar(human_ids: Iterable[int] | None = None, *, agent_id: int | None = None,
                     target: Target = "socrates", max_depth: int = DEFAULT_MAX_DEPTH,
                     tree_id: str = DEFAULT_TREE_ID) -> str:
    """GBNF for {"reasoning": "...", "tree": "<root ...>"} whose tree always passes `validate_bt_text`.

    `human_ids` (ids of the scenario's humans) and `agent_id` (this human) restrict target_id of
    HumanSays/FollowHuman to the other humans; with no other human those nodes are left out.
    """
    if not tree_id.isidentifier():
        raise ValueError(f"tree id must be an identifier, got {tree_id!r}")
    max_depth = max(1, max_depth)
    target_ids: list[int] | None = None
    if human_ids is not None:
        target_ids = sorted({int(i) for i in human_ids} - ({agent_id} if agent_id is not None else set()))
    nodes = [n for n in prompt_nodes() if target in n.targets]
    leaves = [n for n in nodes if n.kind in ("action", "condition")
              and not (target_ids == [] and any(p.other_human for p in n.ports))]
    composites = [n for n in nodes if n.kind in ("control", "decorator")]

    rules: dict[str, str] = {}
    rules["root"] = (f'"{{" ws {_lit(chr(34) + "reasoning" + chr(34) + ":")} ws reasoning "," ws '
                     f'{_lit(chr(34) + "tree" + chr(34) + ":")} ws "\\"" xml "\\"" ws "}}"')
    rules["ws"] = '" "?'
    rules["reasoning"] = f'"\\"" rchar{{1,{MAX_REASONING_CHARS}}} "\\""'
    rules["rchar"] = '[^"\\\\\\x7F\\x00-\\x1F] | "\\\\" ["\\\\/nt]'
    rules["s"] = '"\\\\n"? " "{0,16}'  # optional line break (two characters in JSON) + indentation
    rules["nm"] = "(\" name='\" [A-Za-z0-9_] [A-Za-z0-9_ ]{0,23} \"'\")?"
    rules["num"] = '[0-9]{1,3} ("." [0-9]{1,2})?'
    rules["int"] = '[0-9]{1,2}'
    rules["bool"] = '"true" | "false"'
    rules["text"] = '[A-Za-z0-9_] [A-Za-z0-9_ ]{0,31}'
    rules["leaf"] = _alt(f"leaf-{_rule_name(n.name)}" for n in leaves)
    for spec in leaves:
        rules[f"leaf-{_rule_name(spec.name)}"] = _leaf_rule(spec, target_ids)

    include_file = next(iter(LIBRARY_TREES))
    rules["inc"] = _lit(f"<include path='{include_file}'/>")
    walk = [line.replace('"', "'") for line in REGULAR_NAV_CALL]
    rules["regnav"] = " s ".join([_lit("<Sequence") + " nm " + _lit(">"), *map(_lit, walk), _lit("</Sequence>")])
    for family, extra in (("p", []), ("r", ["regnav"])):
        for depth in range(1, max_depth + 1):
            options = ["leaf", *extra]
            if depth < max_depth:
                limit = CHILDREN_BY_DEPTH[min(depth, len(CHILDREN_BY_DEPTH)) - 1]
                for spec in composites:
                    if spec.kind == "control" and limit < 2:
                        continue
                    rule = f"{_rule_name(spec.name)}-{family}{depth}"
                    child = f"node-{family}{depth + 1}"
                    children = (f"s {child} (s {child}){{0,{limit - 1}}}" if spec.kind == "control"
                                else f"s {child}")
                    head = " ".join(filter(None, [_lit("<" + spec.name), "nm", _ports_rule(spec, target_ids)]))
                    rules[rule] = f'{head} ">" {children} s {_lit("</" + spec.name + ">")}'
                    options.append(rule)
            rules[f"node-{family}{depth}"] = _alt(options)
        rules[f"tree-{family}"] = (f"{_lit(f'<BehaviorTree ID={chr(39)}{tree_id}{chr(39)}>')} s node-{family}1 s "
                                   f"{_lit('</BehaviorTree>')}")
    rules["xml"] = (f"{_lit(f'<root main_tree_to_execute={chr(39)}{tree_id}{chr(39)}>')} s "
                    f"(tree-p | inc s tree-r) s {_lit('</root>')}")
    return "\n".join(f"{name} ::= {body}" for name, body in rules.items()) + "\n"
