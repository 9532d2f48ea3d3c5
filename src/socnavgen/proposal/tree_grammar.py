"""Stage 3's grammar for in-process models when the human has encounter parts in the spec: the tree
can only be "react (the trigger's condition, inverted for a negated trigger, gating the reaction's action,
with the timer of a reaction that `lasts` and the latch of a latched one), otherwise walk (or stand, for a
person whose `otherwise` is stand)", with nodes taken from bt.library's encounter-needs table, so a small
model's tree passes the validator AND the spec check by construction (the generic library grammar admits
trees the spec check refuses).

Only the parts a grammar-bound stage 1 can produce are covered (one part per human, triggers and
reactions whose nodes need no phrase or other human); for anything else `spec_tree_grammar` returns
None and the generic grammar is used."""

from __future__ import annotations

from socnavgen.bt.library import LIBRARY, REGULAR_NAV_CALL, Target, nodes_for_reaction
from socnavgen.proposal.gbnf import Chars, Grammar, Lit, Ref, Symbol, text_rules
from socnavgen.proposal.target_facts import LATCH_NODE, detecting_nodes
from socnavgen.proposal.tree_needs import TIMER, until_need, until_xml
from socnavgen.run.spec import ScenarioSpec

REASONING_CHARS = 200
_WALK = "".join(REGULAR_NAV_CALL).replace('"', "'")


def _node(name: str) -> list[Symbol] | None:
    """`<Name agent_id='{id}' .../>` with a number for each distance-like port; None if a port needs
    a value the grammar cannot choose (a phrase, another human)."""
    spec = LIBRARY[name]
    out: list[Symbol] = [Lit(f"<{name}")]
    for port in spec.ports:
        if not port.required:
            continue
        if port.reads_root is not None:
            out.append(Lit(f" {port.name}='{{{port.reads_root}}}'"))
        elif port.type == "double":
            out += [Lit(f" {port.name}='"), Ref("number"), Lit("'")]
        else:
            return None
    out.append(Lit("/>"))
    return out


def spec_tree_grammar(name: str, spec: ScenarioSpec | None, target: Target = "socrates") -> str | None:
    """The GBNF of a reply whose tree realizes `name`'s single encounter part, or None."""
    grammar = build_spec_tree_grammar(name, spec, target)
    return grammar.to_gbnf() if grammar is not None else None


def build_spec_tree_grammar(name: str, spec: ScenarioSpec | None, target: Target = "socrates") -> Grammar | None:
    parts = spec.parts_of(name) if spec is not None else []
    if len(parts) != 1:
        return None
    _, part = parts[0]
    reactions = [r for r in nodes_for_reaction(part.reaction, target) if r != "RegularNav"]
    walk_past = part.reaction == "walk_past"
    triggers, negated = detecting_nodes(part.trigger, target)
    if not walk_past and not reactions or part.trigger != "always" and not triggers:
        return None
    g = Grammar()
    text_rules(g, "reasoning", REASONING_CHARS, non_empty=True)
    g.add("number", [Chars("0-9", 1, 1), Lit("."), Chars("0-9", 1, 1)])
    walk = [Lit("<Sequence name='Walk'>" + _WALK + "</Sequence>")]
    stand = spec is not None and spec.person(name).otherwise == "stand"
    otherwise = [Lit("<MakeGesture agent_id='{id}' message='0'/>")] if stand else walk
    head: list[Symbol] = [Lit('{"reasoning": "'), Ref("reasoning"),
            Lit("\", \"tree\": \"<root main_tree_to_execute='MainTree'><include path='BTRegularNav.xml'/>"
                "<BehaviorTree ID='MainTree'>")]
    tail = [Lit('</BehaviorTree></root>"}')]
    if walk_past and part.trigger == "always" and not stand:
        g.add("root", [*head, *walk, *tail])
        return g
    gates = [n for t in triggers if (n := _node(t))] if part.trigger != "always" else [[]]
    if negated:
        gates = [[Lit("<Inverter>"), *gate, Lit("</Inverter>")] for gate in gates]
    acts = [walk] if walk_past else [n for r in reactions if (n := _node(r))]
    if not gates or not acts:
        return None
    lasting = part.lasting()
    timer = [Lit(f"<Inverter><{TIMER} seconds='{lasting:g}' ts='{{dt}}' only_once='true'/></Inverter>")] \
        if lasting is not None else []
    if until_need(part, target) is not None:  # ends once the robot said `until`: a gate like the timer
        timer = [*timer, Lit(until_xml(part))]
    if part.latch and part.trigger != "always":  # latched with `lasts`: the timer inside the latch (tree_needs)
        acts = [[Lit(f"<{LATCH_NODE}>"), *([Lit("<Sequence name='Timed'>"), *timer] if timer else []), *act,
                 *([Lit("</Sequence>")] if timer else []), Lit(f"</{LATCH_NODE}>")] for act in acts]
        timer = []
    g.add("gate", *gates)
    g.add("act", *acts)
    g.add("root", [*head, Lit("<Fallback name='ReactOrOtherwise'><Sequence name='React'>"), Ref("gate"), *timer,
                   Ref("act"), Lit("</Sequence>"), *otherwise, Lit("</Fallback>"), *tail])
    return g
