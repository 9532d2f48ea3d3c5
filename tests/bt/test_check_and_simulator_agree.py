"""The tree language is one language: every construct the simulator runs is accepted by `bt check`, every
construct `bt check` accepts runs in the simulator, and runs as docs/behavior-trees.md says (control
and decorator semantics are the library table's `flow`, `reactive` and `rule`; the expected outcome of
each case below is derived from them, never from what the simulator happens to do).

Each case is a whole tree file; human 0 runs it, and its outcome is read from the gestures it makes:
a probed construct sits in `Fallback(Sequence(construct, say 2), say 1)`, so SUCCESS shows 2, FAILURE 1
and RUNNING leaves the previous gesture (0 at first). `None` = bt check refuses the tree (and so must
the simulator). Where today's simulator disagrees, the case is a strict xfail naming the change the
simulator needs."""

from __future__ import annotations

from dataclasses import dataclass

import pytest

from socnavgen.bt.describe import example_value
from socnavgen.bt.library import LIBRARY, TARGETS, NodeSpec, leaf_nodes, regular_nav_sequence
from socnavgen.bt.validate import validate_bt_text

from .sim_probe import FAR, NEAR, gestures

T = f'<IsRobotNearby agent_id="{{id}}" distance="{NEAR}"/>'  # SUCCESS
F = f'<IsRobotNearby agent_id="{{id}}" distance="{FAR}"/>'  # FAILURE
RUN = f"<KeepRunningUntilFailure>{T}</KeepRunningUntilFailure>"  # RUNNING
# counted once per execution (ts 1 s): FAILURE, then SUCCESS from the 2nd execution on (and the inverse)
F_THEN_T = '<TimeExpiredCondition seconds="1.5" ts="1.0" only_once="true"/>'
T_THEN_F = f"<Inverter>{F_THEN_T}</Inverter>"
ANY = "runs"  # the tree is accepted and runs; its gestures are not the point
S, FL, R = 2, 1, 0  # the probe's gesture for SUCCESS, FAILURE, RUNNING (from the start)


def say(code: int) -> str:
    return f'<MakeGesture agent_id="{{id}}" message="{code}"/>'


def probe(construct: str) -> str:
    return f"<Fallback><Sequence>{construct}{say(2)}</Sequence>{say(1)}</Fallback>"


def tree(body: str, fmt: int = 3, trees: str = "", include: bool = False, main: str | None = "M") -> str:
    head = "<root" + (f' main_tree_to_execute="{main}"' if main else "") + (' BTCPP_format="4"' if fmt == 4 else "")
    inc = '<include path="BTRegularNav.xml"/>' if include else ""
    return f'{head}>{inc}<BehaviorTree ID="M">{body}</BehaviorTree>{trees}</root>'


@dataclass(frozen=True)
class Case:
    id: str
    xml: str
    expect: tuple[int, ...] | str | None  # gestures after steps 1..3, ANY, or None: refused
    simulator_change: str | None = None  # today's simulator disagrees: what it must change


def c(id_: str, xml: str, expect: tuple[int, ...] | str | None, simulator_change: str | None = None) -> Case:
    return Case(id_, xml, expect, simulator_change)


# ---- control nodes and decorators: expectations from the table's semantics ---------------------------
def control_cases(spec: NodeSpec) -> list[Case]:
    seq = spec.flow == "sequence"

    def outcome(kids: list[bool]) -> int:
        return S if (all(kids) if seq else any(kids)) else FL

    def node(kids: str) -> str:
        return f"<{spec.name}>{kids}</{spec.name}>"

    out = [c(f"{spec.name}[{a},{b}]", tree(probe(node((T if a else F) + (T if b else F)))), (outcome([a, b]),) * 3)
           for a in (True, False) for b in (True, False)]
    # an earlier child that changes while a later one is RUNNING: a reactive control re-ticks it (and
    # halts the running child when it decides), one with memory resumes at the running child
    changing = T_THEN_F if seq else F_THEN_T
    decided = FL if seq else S
    out.append(c(f"{spec.name}[changing,running]", tree(probe(node(changing + RUN))),
                 (R, decided, decided) if spec.reactive else (R, R, R)))
    out.append(c(f"explicit <Control ID='{spec.name}'>", tree(probe(f'<Control ID="{spec.name}">{T}{F}</Control>')),
                 (outcome([True, False]),) * 3))
    out.append(c(f"{spec.name} without children", tree(probe(f"<{spec.name}/>")), None))
    return out


def repeat_cases(name: str, port: str) -> list[Case]:
    # the child succeeds on its 1st and 2nd execution and fails from the 3rd: 2 cycles succeed in tick 1
    child = "<Inverter><TimeExpiredCondition seconds='2.5' ts='1.0' only_once='true'/></Inverter>"
    return [c(f"{name} 2", tree(probe(f'<{name} {port}="2">{child}</{name}>')), (S, FL, FL)),
            c(f"{name} 3", tree(probe(f'<{name} {port}="3">{child}</{name}>')), (FL, FL, FL))]


def retry_cases(name: str, port: str) -> list[Case]:
    # the child fails on its 1st and 2nd execution and succeeds from the 3rd
    child = "<TimeExpiredCondition seconds='2.5' ts='1.0' only_once='true'/>"
    return [c(f"{name} 3", tree(probe(f'<{name} {port}="3">{child}</{name}>')), (S, S, S)),
            c(f"{name} 2", tree(probe(f'<{name} {port}="2">{child}</{name}>')), (FL, S, S))]


def decorator_cases(spec: NodeSpec) -> list[Case]:
    name, port = spec.name, spec.count_port or ""

    def one(child: str) -> str:
        return tree(probe(f"<{name}{f' {port}={chr(34)}2{chr(34)}' if port else ''}>{child}</{name}>"))

    by_rule = {
        "invert": [c(f"{name}(T)", one(T), (FL,) * 3), c(f"{name}(F)", one(F), (S,) * 3)],
        "force_success": [c(f"{name}(F)", one(F), (S,) * 3), c(f"{name}(T)", one(T), (S,) * 3)],
        "force_failure": [c(f"{name}(T)", one(T), (FL,) * 3), c(f"{name}(F)", one(F), (FL,) * 3)],
        "repeat": repeat_cases(name, port),
        "retry": retry_cases(name, port),
        "keep_running": [c(f"{name}(T)", one(T), (R,) * 3), c(f"{name}(F)", one(F), (FL,) * 3)],
    }[spec.rule or ""]
    by_rule.append(c(f"{name} with two children", one(T + T), None))
    by_rule.append(c(f"explicit <Decorator ID='{name}'>", tree(probe(
        f'<Decorator ID="{name}"{f" {port}={chr(34)}2{chr(34)}" if port else ""}>{T}</Decorator>')), ANY))
    if port:
        by_rule += [c(f"{name} {port}={bad}", tree(probe(f'<{name} {port}="{bad}">{T}</{name}>')), None)
                    for bad in ("0", "1001", "{n}", "2.0")]
    return by_rule


def leaf_case(spec: NodeSpec) -> Case:
    attrs = "".join(f' {p.name}="{example_value(p)}"' for p in spec.ports)
    return c(f"leaf {spec.name}", tree(f"<Sequence><{spec.name}{attrs}/>{say(3)}</Sequence>"), ANY)


CONTROLS = [n for n in LIBRARY.values() if n.kind == "control"]
DECORATORS = [n for n in LIBRARY.values() if n.kind == "decorator"]
GENERATED = ([case for spec in CONTROLS for case in control_cases(spec)]
             + [case for spec in DECORATORS for case in decorator_cases(spec)]
             + [leaf_case(spec) for spec in leaf_nodes()])


# ---- literals ----------------------------------------------------------------------------------------
def once(value: str) -> str:
    """TimeExpiredCondition (2nd execution on: SUCCESS) with only_once=`value`: true keeps SUCCESS at the
    3rd, false restarts the count after a SUCCESS (FAILURE at the 3rd)."""
    return tree(probe(f'<TimeExpiredCondition seconds="1.5" ts="1.0" only_once="{value}"/>'))


LITERALS = [
    *[c(f"bool {v}", once(v), (FL, S, S)) for v in ("true", "True", "TRUE", "1")],
    *[c(f"bool {v}", once(v), (FL, S, FL)) for v in ("false", "False", "FALSE", "0")],
    *[c(f"bool {v}", once(v), None) for v in ("yes", "tRue", "2", "")],
    c("double written as int", tree(probe(T.replace(f'"{NEAR}"', '"5"'))), (S,) * 3),
    c("double with spaces and exponent", tree(probe(T.replace(f'"{NEAR}"', '" 5e0 "'))), (S,) * 3),
    *[c(f"double {v}", tree(probe(T.replace(f'"{NEAR}"', f'"{v}"'))), None) for v in ("abc", "-1", "inf", "nan", "")],
    c("gesture code in the table", tree(say(3)), (3, 3, 3)),
    *[c(f"gesture code {v}", tree(say(3).replace('"3"', f'"{v}"')), None) for v in ("9", "-1", "3.0", "x")],
    c("agent_id literal", tree(probe(T.replace("{id}", "0"))), None),
    c("time_step literal", tree('<RegularNav agent_id="{id}" time_step="0.25"/>'), None),
    c("malformed reference", tree(probe(T.replace("{id}", "{id"))), None),
]

# ---- the blackboard ----------------------------------------------------------------------------------
SET = '<SetBlackboard output_key="{key}" value="{value}"/>'


def with_entry(key: str, value: str, reader: str) -> str:
    return tree(f"<Sequence>{SET.format(key=key, value=value)}{probe(reader)}</Sequence>")


BLACKBOARD = [
    c("literal text read as a double", with_entry("d", "5", T.replace(f'"{NEAR}"', '"{d}"')), (S,) * 3),
    c("literal text read as an int code",
      tree(f"<Sequence>{SET.format(key='m', value='3')}{say(3).replace(chr(34) + '3', chr(34) + '{m}')}</Sequence>"),
      (3, 3, 3)),
    c("copy of {id} read by agent_id", with_entry("me", "{id}", T.replace('"{id}"', '"{me}"')), (S,) * 3),
    c("text that does not convert", with_entry("d", "far", T.replace(f'"{NEAR}"', '"{d}"')), None),
    c("{dt} read by agent_id", with_entry("me", "{dt}", T.replace('"{id}"', '"{me}"')), None),
    c("key never set", tree(probe(T.replace(f'"{NEAR}"', '"{d}"'))), None),
    c("output_key with braces", with_entry("{d}", "5", T), None),
    c("key read before it is set", tree(f"<Sequence>{probe(T.replace(f'{NEAR}', '{d}'))}"
                                        f"{SET.format(key='d', value='5')}</Sequence>"), None),
]

# ---- SubTree remapping per format --------------------------------------------------------------------
GATE = '<BehaviorTree ID="Gate"><Sequence><IsRobotNearby agent_id="{me}" distance="{d}"/>' \
       + say(2).replace("{id}", "{me}") + "</Sequence></BehaviorTree>"
COPIES = SET.format(key="agentid", value="{id}") + SET.format(key="dist", value="5")


def calls(call: str, fmt: int = 3, copies: str = COPIES) -> str:
    return tree(f"<Fallback><Sequence>{copies}{call}</Sequence>{say(1)}</Fallback>", fmt, trees=GATE)


SUBTREES = [
    c("v3 remap", calls('<SubTree ID="Gate" me="agentid" d="dist"/>'), (S,) * 3),
    c("v3 remap with braces", calls('<SubTree ID="Gate" me="{agentid}" d="{dist}"/>'), None),
    *[c(f"v3 __shared_blackboard={v}",
        calls(f'<SubTree ID="Gate" __shared_blackboard="{v}"/>',
              copies=SET.format(key="me", value="{id}") + SET.format(key="d", value="5")), (S,) * 3)
      for v in ("true", "1", "True", "TRUE")],
    c("v3 __shared_blackboard=false needs the remaps",
      calls('<SubTree ID="Gate" __shared_blackboard="false"/>',
            copies=SET.format(key="me", value="{id}") + SET.format(key="d", value="5")), None),
    c("v3 _autoremap is v4 syntax", calls('<SubTree ID="Gate" _autoremap="true" me="agentid" d="dist"/>'), None),
    c("v4 remap", calls('<SubTree ID="Gate" me="{agentid}" d="{dist}"/>', 4), (S,) * 3),
    c("v4 remap {=}", calls('<SubTree ID="Gate" me="{=}" d="{dist}"/>', 4,
                            copies=SET.format(key="me", value="{id}") + SET.format(key="dist", value="5")), (S,) * 3),
    c("v4 constant", calls('<SubTree ID="Gate" me="{agentid}" d="5"/>', 4), (S,) * 3),
    c("v4 constant that does not convert", calls('<SubTree ID="Gate" me="{agentid}" d="far"/>', 4), None),
    c("v4 plain key name is a constant", calls('<SubTree ID="Gate" me="agentid" d="dist"/>', 4), None),
    c("v4 _autoremap", calls('<SubTree ID="Gate" _autoremap="true"/>', 4,
                             copies=SET.format(key="me", value="{id}") + SET.format(key="d", value="5")), (S,) * 3),
    c("v4 __shared_blackboard is v3 syntax",
      calls('<SubTree ID="Gate" __shared_blackboard="true"/>', 4,
            copies=SET.format(key="me", value="{id}") + SET.format(key="d", value="5")), None),
    c("remap of a key the tree never reads", calls('<SubTree ID="Gate" me="agentid" d="dist" x="dist"/>'), None),
    c("SubTree naming no tree", calls('<SubTree ID="Nowhere"/>'), None),
    c("SubTree calling itself", tree('<SubTree ID="M"/>'), None),
    c("library tree with its include", tree(regular_nav_sequence(), include=True), ANY),
    c("library tree without its include", tree(regular_nav_sequence()), None),
    c("include from disk", tree(T).replace("<BehaviorTree", '<include path="../other.xml"/><BehaviorTree'), None),
]

# ---- the file's structure ----------------------------------------------------------------------------
STRUCTURE = [
    c("explicit <Action ID>", tree('<Action ID="MakeGesture" agent_id="{id}" message="3"/>'), (3, 3, 3)),
    c("explicit <Condition ID>", tree(probe(T.replace("<IsRobotNearby", '<Condition ID="IsRobotNearby"'))), (S,) * 3),
    c("explicit form of the wrong kind", tree('<Condition ID="MakeGesture" agent_id="{id}" message="3"/>'), None),
    c("name attribute on every node", tree(probe(T.replace("/>", ' name="free text"/>')).replace(
        "<Fallback>", '<Fallback name="x">')), (S,) * 3),
    c("TreeNodesModel is ignored", tree(say(3)).replace("</root>", "<TreeNodesModel><Action ID='X'/>"
                                                                   "</TreeNodesModel></root>"), (3, 3, 3)),
    c("v4 file with one tree and no main", tree(say(3), fmt=4, main=None), (3, 3, 3)),
    c("v3 file with one tree and no main", tree(say(3), main=None), (3, 3, 3)),
    c("no main and an included tree", tree(say(3), main=None, include=True), None),
    c("no main and two trees", tree(say(3), main=None, trees=GATE), None),
    c("main tree naming no tree", tree(say(3), main="Other"), None),
    c("BehaviorTree with two children", tree(say(3) + say(2)), None),
    c("unknown node", tree("<Dance agent_id='{id}'/>"), None),
    c("unknown port", tree(say(3).replace("/>", ' speed="2"/>')), None),
    c("missing required port", tree('<MakeGesture agent_id="{id}"/>'), None),
    c("leaf with a child", tree(f'<MakeGesture agent_id="{{id}}" message="3">{T}</MakeGesture>'), None),
    c("unsupported BTCPP_format", tree(say(3)).replace("<root", '<root BTCPP_format="5"'), None),
]

CASES = [*GENERATED, *LITERALS, *BLACKBOARD, *SUBTREES, *STRUCTURE]

def accepted(xml: str) -> bool:
    """`bt check` accepts the file for some export target."""
    return any(validate_bt_text(xml, "probe.xml", target=target) == [] for target in TARGETS)


def params() -> list:  # noqa: ANN202 - pytest params
    out = []
    for case in CASES:
        change = case.simulator_change
        marks = [pytest.mark.xfail(strict=True, reason=f"simulator: {change}")] if change else []
        out.append(pytest.param(case, id=case.id, marks=marks))
    return out


@pytest.mark.parametrize("case", params())
def test_check_and_simulator_agree(case: Case) -> None:
    assert accepted(case.xml) == (case.expect is not None), validate_bt_text(case.xml, "probe.xml")
    ran = gestures(case.xml)
    if case.expect is None:
        assert isinstance(ran, str), f"the simulator ran a tree bt check refuses: {ran}"
    elif case.expect == ANY:
        assert not isinstance(ran, str), f"the simulator refused a tree bt check accepts: {ran}"
    else:
        assert ran == case.expect


def test_every_semantic_of_the_table_has_cases() -> None:
    """A new control flow or decorator rule must come with its cases (decorator_cases raises KeyError)."""
    assert {n.flow for n in CONTROLS} == {"sequence", "fallback"} and {n.reactive for n in CONTROLS} == {True, False}
    for spec in DECORATORS:
        assert decorator_cases(spec)
    ids = [case.id for case in CASES]
    assert len(ids) == len(set(ids))
