"""The typed tree: literals parsed once by the port's type, the Document the parser makes, SubTree
expansion (remapping, __shared_blackboard, _autoremap, v4 constants) and the blackboard data flow."""

from __future__ import annotations

import pytest

from socnavgen.bt.expand import ROOT_DT, ROOT_ID, TreeProblems, check_text, load_instance
from socnavgen.bt.library import LIBRARY, NODES, PortType
from socnavgen.bt.model import Entry, LiteralError, Node, Ref, parse_bool, parse_literal
from socnavgen.bt.parse import parse_document

INCLUDE = "<include path='BTRegularNav.xml'/>"


def doc(body: str, *, fmt: int = 3, extra: str = "") -> str:
    head = "<root main_tree_to_execute='T' BTCPP_format='4'>" if fmt == 4 else "<root main_tree_to_execute='T'>"
    return f"{head}\n{INCLUDE}\n<BehaviorTree ID='T'>\n{body}\n</BehaviorTree>\n{extra}</root>\n"


def messages(text: str) -> str:
    return "\n".join(p.message for p in check_text(text)[2])


# ---- literals ----------------------------------------------------------------------------------------
@pytest.mark.parametrize(("text", "expected"), [
    ("true", True), ("True", True), ("TRUE", True), ("1", True),
    ("false", False), ("False", False), ("FALSE", False), ("0", False)])
def test_bool_literals_are_exactly_btcpps(text: str, expected: bool) -> None:
    assert parse_bool(text) is expected
    assert parse_literal(text, PortType.BOOL) is expected


@pytest.mark.parametrize("text", ["yes", "on", " true", "tRue", "2", "", "false "])
def test_other_bool_spellings_are_refused(text: str) -> None:
    with pytest.raises(LiteralError, match="must be true or false"):
        parse_literal(text, PortType.BOOL)


@pytest.mark.parametrize(("text", "type_", "expected"), [
    ("3", PortType.INT, 3), (" -2 ", PortType.INT, -2), ("+7", PortType.INT, 7),
    ("2", PortType.DOUBLE, 2.0), ("2.5", PortType.DOUBLE, 2.5), (".5", PortType.DOUBLE, 0.5),
    ("1e3", PortType.DOUBLE, 1000.0), (" 1.5 ", PortType.DOUBLE, 1.5), ("a b", PortType.STRING, "a b")])
def test_number_literals(text: str, type_: PortType, expected: object) -> None:
    value = parse_literal(text, type_)
    assert value == expected and type(value) is type(expected)


@pytest.mark.parametrize(("text", "type_", "why"), [
    ("2.0", PortType.INT, "must be an integer"), ("two", PortType.INT, "must be an integer"),
    ("2147483648", PortType.INT, "out of range"), ("nan", PortType.DOUBLE, "must be a number"),
    ("inf", PortType.DOUBLE, "must be a number"), ("1e999", PortType.DOUBLE, "must be a number"),
    ("2,5", PortType.DOUBLE, "must be a number"), ("", PortType.DOUBLE, "must be a number")])
def test_bad_number_literals(text: str, type_: PortType, why: str) -> None:
    with pytest.raises(LiteralError, match=why):
        parse_literal(text, type_)


# ---- the document ------------------------------------------------------------------------------------
def test_ports_are_typed_once_and_nodes_carry_name_kind_line_source() -> None:
    text = doc("<Sequence name='go'>\n<Condition ID='IsRobotNearby' agent_id='{id}' distance='2'/>\n"
               "<TimeExpiredCondition seconds='3' ts='{dt}' only_once='TRUE'/>\n"
               "<MakeGesture agent_id='{id}' message='2'/>\n</Sequence>")
    document, problems = parse_document(text, "h.xml")
    assert problems == [] and document is not None
    root = document.trees["T"].root
    assert (root.name, root.kind, root.label, root.line, root.source) == ("Sequence", "control", "go", 4, "h.xml")
    near, timer, gesture = root.children
    assert (near.name, near.kind, near.line) == ("IsRobotNearby", "condition", 5)
    assert near.ports == {"agent_id": Ref("id"), "distance": 2.0} and type(near.ports["distance"]) is float
    assert timer.ports == {"seconds": 3.0, "ts": Ref("dt"), "only_once": True}
    assert gesture.ports["message"] == 2 and type(gesture.ports["message"]) is int
    assert near.value("distance") == 2.0
    lone = parse_document(doc("<TimeExpiredCondition/>"))[0].trees["T"].root
    assert lone.ports == {} and (lone.value("seconds"), lone.value("only_once")) == (1.0, False)  # table defaults


@pytest.mark.parametrize(("fmt", "attrs", "remap", "shared", "auto"), [
    (3, "id='agentid' dt='timestep'", {"id": Ref("agentid"), "dt": Ref("timestep")}, False, False),
    (3, "__shared_blackboard='1'", {}, True, False),
    (4, "id='{agentid}' dt='{=}'", {"id": Ref("agentid"), "dt": Ref("dt")}, False, False),
    (4, "id='{agentid}' dt='0.5' _autoremap='True'", {"id": Ref("agentid"), "dt": "0.5"}, False, True),
])
def test_subtree_calls_are_read_by_the_files_format(fmt: int, attrs: str, remap: dict, shared: bool,
                                                     auto: bool) -> None:
    document, _ = parse_document(doc(f"<SubTree ID='RegularNavTree' {attrs}/>", fmt=fmt))
    call = document.trees["T"].root.call
    assert (call.tree, dict(call.remap), call.shared, call.autoremap) == ("RegularNavTree", remap, shared, auto)
    assert document.tree("RegularNavTree").source == "BTRegularNav.xml"


# ---- expansion ---------------------------------------------------------------------------------------
REGNAV_V3 = ("<Sequence><SetBlackboard output_key='agentid' value='{id}'/>"
             "<SetBlackboard output_key='timestep' value='{dt}'/>"
             "<SubTree ID='RegularNavTree' id='agentid' dt='timestep'/></Sequence>")


def leaves(node: Node) -> dict[str, Node]:
    return {n.name: n for n in node.walk() if n.kind in ("action", "condition")}


def test_isolated_subtree_reads_the_callers_entries_and_its_nodes_keep_their_file() -> None:
    instance = load_instance(doc(REGNAV_V3), "h.xml")
    assert all(n.call is None and n.name != "SubTree" for n in instance.root.walk())
    nav = leaves(instance.root)["RegularNav"]
    assert nav.ports == {"agent_id": Entry(0, "agentid"), "time_step": Entry(0, "timestep")}
    assert (nav.source, nav.line) == ("BTRegularNav.xml", 8)
    copy = instance.root.children[0]
    assert copy.ports == {"output_key": Entry(0, "agentid"), "value": ROOT_ID}


@pytest.mark.parametrize("call", ["<SubTree ID='RegularNavTree' __shared_blackboard='true'/>",
                                  "<SubTree ID='RegularNavTree' __shared_blackboard='1'/>"])
def test_shared_blackboard_runs_on_the_callers_blackboard(call: str) -> None:
    nav = leaves(load_instance(doc(call)).root)["RegularNav"]
    assert nav.ports == {"agent_id": ROOT_ID, "time_step": ROOT_DT}


def test_shared_blackboard_false_is_isolated_and_then_lacks_the_keys() -> None:
    found = messages(doc("<SubTree ID='RegularNavTree' __shared_blackboard='false'/>"))
    assert "SubTree 'RegularNavTree' does not pass blackboard key 'id'" in found
    assert "does not pass blackboard key 'dt'" in found


def test_v4_autoremap_constants_and_private_keys() -> None:
    local = ("<BehaviorTree ID='Wave'><Sequence><SetBlackboard output_key='_mine' value='{code}'/>"
             "<MakeGesture agent_id='{id}' message='{_mine}'/></Sequence></BehaviorTree>\n")
    text = doc("<SubTree ID='Wave' code='2' _autoremap='true'/>", fmt=4, extra=local)
    instance = load_instance(text)
    gesture = leaves(instance.root)["MakeGesture"]
    assert gesture.ports["agent_id"] == ROOT_ID  # autoremapped to the caller's id
    scope = gesture.ports["message"].scope
    assert scope != 0 and gesture.ports["message"] == Entry(scope, "_mine")  # _private keys stay local
    assert instance.constants == {Entry(scope, "code"): "2"}
    bad = messages(text.replace("code='2'", "code='9'"))
    assert "code 9 is not allowed" in bad and "a plain value is a constant" in bad


@pytest.mark.parametrize(("body", "expected"), [
    # agent_id must hold the agent's own id: through copies it does, from dt or a literal it does not
    ("<Sequence><SetBlackboard output_key='a' value='{id}'/><SetBlackboard output_key='b' value='{a}'/>"
     "<LookAtRobot agent_id='{b}'/></Sequence>", None),
    ("<Sequence><SetBlackboard output_key='a' value='{dt}'/><LookAtRobot agent_id='{a}'/></Sequence>",
     "agent_id must be {id} (the human's own id from the blackboard); {a} holds {dt}"),
    ("<Sequence><SetBlackboard output_key='a' value='0'/><LookAtRobot agent_id='{a}'/></Sequence>",
     "{a} holds '0'"),
    # a text held in an entry converts to the reading port's type, within its bounds
    ("<Sequence><SetBlackboard output_key='d' value='2.5'/><IsRobotNearby agent_id='{id}' distance='{d}'/>"
     "</Sequence>", None),
    ("<Sequence><SetBlackboard output_key='d' value='far'/><IsRobotNearby agent_id='{id}' distance='{d}'/>"
     "</Sequence>", "{d} holds 'far', and distance must be a number"),
    ("<Sequence><SetBlackboard output_key='d' value='-1'/><IsRobotNearby agent_id='{id}' distance='{d}'/>"
     "</Sequence>", "distance cannot be negative"),
    # read before written (document order)
    ("<Sequence><IsRobotNearby agent_id='{id}' distance='{d}'/><SetBlackboard output_key='d' value='2'/>"
     "</Sequence>", "blackboard key 'd' is never set"),
    ("<Sequence><SetBlackboard output_key='x' value='{y}'/><SetBlackboard output_key='y' value='1'/></Sequence>",
     "blackboard key 'y' is never set"),
    ("<FollowHuman agent_id='{id}' target_id='{id}' time_step='{dt}'/>", "target_id {id} is the human itself"),
    # Repeat and RetryUntilSuccessful: literal counts within bounds
    ("<Repeat num_cycles='3'><UpdateGoal agent_id='{id}'/></Repeat>", None),
    ("<RetryUntilSuccessful num_attempts='2'><RobotMoved agent_id='{id}'/></RetryUntilSuccessful>", None),
    ("<Repeat num_cycles='-1'><UpdateGoal agent_id='{id}'/></Repeat>", "num_cycles must be at least 1"),
    ("<Repeat num_cycles='5000'><UpdateGoal agent_id='{id}'/></Repeat>", "num_cycles must be at most 1000"),
    ("<Repeat><UpdateGoal agent_id='{id}'/></Repeat>", "Repeat is missing required port 'num_cycles'"),
])
def test_data_flow(body: str, expected: str | None) -> None:
    found = messages(doc(body))
    if expected is None:
        assert found == ""
    else:
        assert expected in found


def test_problems_inside_a_library_tree_are_reported_at_the_call() -> None:
    text = doc("<Sequence><SetBlackboard output_key='agentid' value='{dt}'/>"
               "<SetBlackboard output_key='timestep' value='{dt}'/>\n"
               "<SubTree ID='RegularNavTree' id='agentid' dt='timestep'/></Sequence>")
    problems = check_text(text, "h.xml")[2]
    assert problems and {p.line for p in problems} == {5} and {p.source for p in problems} == {"h.xml"}
    assert "(in BTRegularNav.xml:6)" in problems[0].message


def test_load_instance_names_every_problem_and_is_cached() -> None:
    text = doc("<Sequence><Foo/><IsRobotNearby agent_id='{id}' distance='{nope}'/></Sequence>")
    with pytest.raises(TreeProblems) as err:
        load_instance(text, "h.xml")
    assert [p.line for p in err.value.problems] == [4, 4]
    assert "unknown node 'Foo'" in err.value.message and "'nope' is never set" in err.value.message
    good = doc(REGNAV_V3)
    assert load_instance(good, "h.xml") is load_instance(good, "h.xml")


def test_subtrees_that_multiply_are_capped() -> None:
    trees = "".join(f"<BehaviorTree ID='L{i}'><Sequence><SubTree ID='L{i + 1}' __shared_blackboard='true'/>"
                    f"<SubTree ID='L{i + 1}' __shared_blackboard='true'/></Sequence></BehaviorTree>"
                    for i in range(14))
    text = doc("<SubTree ID='L0' __shared_blackboard='true'/>",
               extra=trees + "<BehaviorTree ID='L14'><UpdateGoal agent_id='{id}'/></BehaviorTree>")
    assert "more than 5000 nodes once its SubTrees are expanded" in messages(text)


# ---- the table drives the rest -----------------------------------------------------------------------
def test_every_control_and_decorator_has_its_semantics_in_the_table() -> None:
    for spec in NODES:
        if spec.kind == "control":
            assert spec.flow in ("sequence", "fallback") and spec.min_children == 1 and spec.max_children is None
        elif spec.kind == "decorator":
            assert spec.rule is not None and (spec.min_children, spec.max_children) == (1, 1)
            if spec.rule in ("repeat", "retry"):
                count = spec.port(spec.count_port)
                assert count.type is PortType.INT and count.required and count.minimum == 1
        else:
            assert spec.flow is None and spec.rule is None
    assert {n.name for n in NODES if n.moves} >= {"RegularNav", "GiveWaytoRobot", "LookAtRobot"}
    assert not LIBRARY["MakeGesture"].moves and not LIBRARY["UpdateGoal"].moves
