"""The behavior-tree validator: each rule yields its own message on the right line; valid trees
(ours and the reference ones the fork loads) pass; hostile input becomes a problem, fast."""

from __future__ import annotations

import time

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from socnavgen.bt.library import LIBRARY_TREE_XML
from socnavgen.bt.validate import BTProblem, format_problems, validate_bt_file, validate_bt_text

INCLUDE = "<include path='BTRegularNav.xml'/>"
REGNAV = ("<Sequence name='RegNav'>\n"
          "<SetBlackboard output_key='agentid' value='{id}'/>\n"
          "<SetBlackboard output_key='timestep' value='{dt}'/>\n"
          "<SubTree ID='RegularNavTree' id='agentid' dt='timestep'/>\n"
          "</Sequence>")


def tree(body: str, *, include: bool = False, main: str = "T") -> str:
    """A file whose line 3 is the first line of `body` (for line-number assertions)."""
    return (f"<root main_tree_to_execute='{main}'>\n"
            f"<BehaviorTree ID='T'>\n{body}\n</BehaviorTree>\n"
            + (INCLUDE + "\n" if include else "") + "</root>\n")


VALID_BODY = ("<Fallback name='F'>\n"
              "<Sequence>\n"
              "<IsRobotVisible agent_id='{id}' distance='4.0'/>\n"
              "<Inverter><TimeExpiredCondition seconds='30' ts='{dt}' only_once='True'/></Inverter>\n"
              "<RobotSays agent_id='{id}' message='4'/>\n"
              "<MakeGesture agent_id='{id}' message='3'/>\n"
              "<HumanSays agent_id='{id}' target_id='1' message='2'/>\n"
              "<GiveWaytoRobot agent_id='{id}' time_step='{dt}'/>\n"
              "</Sequence>\n"
              f"{REGNAV}\n"
              "</Fallback>")


def messages(problems: list[BTProblem]) -> str:
    return "\n".join(p.message for p in problems)


def test_valid_tree_has_no_problems() -> None:
    assert validate_bt_text(tree(VALID_BODY, include=True), human_ids={0, 1}, agent_id=0) == []


def test_problem_str_is_source_line_message() -> None:
    problems = validate_bt_text(tree("<Foo agent_id='{id}'/>"), "behaviors/human1.xml")
    assert len(problems) == 1
    assert str(problems[0]).startswith("behaviors/human1.xml:3: unknown node 'Foo'")
    assert format_problems(problems) == str(problems[0])


@pytest.mark.parametrize(("body", "expected", "line"), [
    ("<HasRobotMoved agent_id='{id}'/>", "unknown node 'HasRobotMoved' (did you mean 'RobotMoved'?); available: ", 3),
    ("<IsRobotVisible agent_id='{id}'/>", "IsRobotVisible is missing required port 'distance'", 3),
    ("<IsRobotVisible agent_id='{id}' distance='2' radius='3'/>", "unknown port 'radius' on IsRobotVisible", 3),
    ("<RegularNav agent_id='{id}' t='{dt}'/>", "unknown port 't' on RegularNav; its ports: agent_id, time_step", 3),
    ("<RobotSays agent_id='{id}' message='four'/>", "RobotSays message='four': message must be an integer", 3),
    ("<IsRobotNearby agent_id='{id}' distance='far'/>", "distance must be a number", 3),
    ("<IsRobotNearby agent_id='{id}' distance='-2'/>", "distance cannot be negative", 3),
    ("<IsRobotNearby agent_id='{id}' distance='nan'/>", "distance must be a number", 3),
    ("<TimeExpiredCondition only_once='yes'/>", "only_once must be true or false", 3),
    ("<MakeGesture agent_id='{id}' message='4'/>", "code 4 is not allowed; codes: 0 NO GESTURE, 1 WAIT, 2 PROCEED, "
                                                   "3 EXCUSE ME", 3),
    ("<RobotSays agent_id='{id}' message='6'/>", "code 6 is not allowed; codes: 0 NO GESTURE", 3),
    ("<IsGoalReached agent_id='0'/>", "agent_id must be {id}", 3),
    ("<RegularNav agent_id='{id}' time_step='0.1'/>", "time_step must be {dt}", 3),
    ("<IsRobotNearby agent_id='{id}' distance='{range}'/>", "blackboard key 'range' is never set", 3),
    ("<IsRobotNearby agent_id='{id}' distance='{id}'/>", "distance is double but {id} holds a int", 3),
    ("<IsRobotNearby agent_id='{id}' distance='{dt'/>", "malformed blackboard reference", 3),
    ("<Inverter>\n<RobotMoved agent_id='{id}'/>\n<RobotMoved agent_id='{id}'/>\n</Inverter>",
     "Inverter must have exactly one child, it has 2", 3),
    ("<Sequence>\n<Inverter/>\n</Sequence>", "Inverter must have exactly one child, it has 0", 4),
    ("<Fallback name='empty'/>", "Fallback must have at least 1 child, it has none", 3),
    ("<RegularNav agent_id='{id}' time_step='{dt}'>\n<RobotMoved agent_id='{id}'/>\n</RegularNav>",
     "RegularNav is an action and cannot have child nodes", 3),
    ("<Condition ID='RegularNav' agent_id='{id}' time_step='{dt}'/>", "'RegularNav' is an action, not a <Condition>",
     3),
    ("<Action agent_id='{id}'/>", "<Action> needs an ID attribute", 3),
    ("<BehaviorTree ID='X'/>", "<BehaviorTree> cannot appear inside a tree", 3),
    (REGNAV, "SubTree 'RegularNavTree' needs <include path='BTRegularNav.xml'/> directly under <root>", 6),
    ("<SubTree ID='Walk'/>", "SubTree ID 'Walk' names no BehaviorTree", 3),
    ("<SubTree/>", "SubTree is missing required port 'ID'", 3),
    ("<HumanSays agent_id='{id}' target_id='{id}' message='1'/>", "target_id {id} is the human itself", 3),
    ("<SetBlackboard output_key='{agentid}' value='{id}'/>", "output_key is a blackboard key name without braces", 3),
    ("<SetBlackboard output_key='x' value='{nothing}'/>", "blackboard key 'nothing' is never set", 3),
])
def test_each_mistake_is_named_with_its_line(body: str, expected: str, line: int) -> None:
    problems = validate_bt_text(tree(body))
    assert problems, body
    found = [p for p in problems if expected in p.message]
    assert found, f"{expected!r} not in {messages(problems)!r}"
    assert found[0].line == line


@pytest.mark.parametrize(("subtree", "expected"), [
    ("<SubTree ID='RegularNavTree' id='agentid'/>", "SubTree 'RegularNavTree' does not pass blackboard key 'dt'"),
    ("<SubTree ID='RegularNavTree' id='agentid' dt='step'/>", "blackboard key 'step' is not set before this SubTree"),
    ("<SubTree ID='RegularNavTree' id='{agentid}' dt='timestep'/>", "a remapping names a parent blackboard key "
                                                                    "without braces"),
    ("<SubTree ID='RegularNavTree' id='agentid' dt='timestep' speed='x'/>", "remaps 'speed', which that tree never "
                                                                          "reads"),
])
def test_subtree_remapping(subtree: str, expected: str) -> None:
    body = ("<Sequence>\n<SetBlackboard output_key='agentid' value='{id}'/>\n"
            f"<SetBlackboard output_key='timestep' value='{{dt}}'/>\n{subtree}\n</Sequence>")
    problems = validate_bt_text(tree(body, include=True))
    assert any(expected in p.message for p in problems), messages(problems)
    assert all(p.line == 6 for p in problems)


def test_remap_before_setblackboard_is_reported() -> None:
    body = ("<Sequence>\n<SubTree ID='RegularNavTree' id='agentid' dt='timestep'/>\n"
            "<SetBlackboard output_key='agentid' value='{id}'/>\n"
            "<SetBlackboard output_key='timestep' value='{dt}'/>\n</Sequence>")
    problems = validate_bt_text(tree(body, include=True))
    assert [p.line for p in problems] == [4, 4]
    assert "'agentid' is not set before this SubTree" in problems[0].message


def test_direct_remap_of_root_keys_is_valid_and_local_subtrees_resolve() -> None:
    xml = ("<root main_tree_to_execute='Main'>\n"
           "<BehaviorTree ID='Main'><Sequence>"
           "<SubTree ID='Look' id='id'/><SubTree ID='RegularNavTree' id='id' dt='dt'/></Sequence></BehaviorTree>\n"
           "<BehaviorTree ID='Look'><LookAtRobot agent_id='{id}'/></BehaviorTree>\n"
           f"{INCLUDE}\n</root>")
    assert validate_bt_text(xml) == []
    missing = xml.replace("<SubTree ID='Look' id='id'/>", "<SubTree ID='Look'/>")
    assert "SubTree 'Look' does not pass blackboard key 'id'" in messages(validate_bt_text(missing))


def test_subtree_loop_is_reported() -> None:
    xml = ("<root main_tree_to_execute='A'>\n"
           "<BehaviorTree ID='A'><SubTree ID='B' id='id'/></BehaviorTree>\n"
           "<BehaviorTree ID='B'><Sequence><LookAtRobot agent_id='{id}'/><SubTree ID='A' id='id'/></Sequence>"
           "</BehaviorTree>\n</root>")
    assert "SubTrees call each other in a loop: A -> B -> A" in messages(validate_bt_text(xml))


@pytest.mark.parametrize(("xml", "expected", "line"), [
    ("<root><BehaviorTree ID='T'><RobotMoved agent_id='{id}'/></BehaviorTree><BehaviorTree ID='U'>"
     "<RobotMoved agent_id='{id}'/></BehaviorTree></root>", "<root> has no main_tree_to_execute attribute", 1),
    # BT.CPP runs the only tree it knows; an included file's trees count
    ("<root><include path='BTRegularNav.xml'/><BehaviorTree ID='T'><RobotMoved agent_id='{id}'/></BehaviorTree>"
     "</root>", "<root> has no main_tree_to_execute attribute", 1),
    (tree("<RobotMoved agent_id='{id}'/>", main="Main"), "main_tree_to_execute='Main' names no <BehaviorTree>", 1),
    ("<root main_tree_to_execute='T'>\n<BehaviorTree ID='T'>\n<RobotMoved agent_id='{id}'/>\n"
     "<RobotMoved agent_id='{id}'/>\n</BehaviorTree>\n</root>", "must have exactly one child node, it has 2", 2),
    ("<root main_tree_to_execute='T'>\n<BehaviorTree ID='T'/>\n</root>", "must have exactly one child node, it has 0",
     2),
    ("<root main_tree_to_execute='T'>\n<BehaviorTree ID='T'><RobotMoved agent_id='{id}'/></BehaviorTree>\n"
     "<BehaviorTree ID='T'><RobotMoved agent_id='{id}'/></BehaviorTree>\n</root>", "'T' is defined twice", 3),
    ("<root main_tree_to_execute='T'>\n<BehaviorTree><RobotMoved agent_id='{id}'/></BehaviorTree>\n</root>",
     "<BehaviorTree> without an ID", 2),
    ("<root main_tree_to_execute='T'>\n<Sequence/>\n</root>", "unexpected <Sequence> directly under <root>", 2),
    ("<root main_tree_to_execute='T' foo='1'>\n<BehaviorTree ID='T'><RobotMoved agent_id='{id}'/></BehaviorTree>"
     "\n</root>", "unknown attribute 'foo' on <root>", 1),
    ("<tree><BehaviorTree ID='T'/></tree>", "the top element is <tree>, expected <root>", 1),
    ("<root main_tree_to_execute='T'>\n<BehaviorTree ID='T'>\n<RobotMoved agent_id='{id}'>\n</BehaviorTree>\n</root>",
     "XML does not parse", 4),
    ("", "the tree is empty", None),
])
def test_file_structure_mistakes(xml: str, expected: str, line: int | None) -> None:
    problems = validate_bt_text(xml)
    found = [p for p in problems if expected in p.message]
    assert found, messages(problems)
    assert found[0].line == line


@pytest.mark.parametrize(("path", "expected"), [
    ("../BTRegularNav.xml", "leaves the behavior-tree library"),
    ("/etc/passwd", "leaves the behavior-tree library"),
    ("sub/BTRegularNav.xml", "leaves the behavior-tree library"),
    ("C:BTRegularNav.xml", "leaves the behavior-tree library"),
    ("BTScaredNav.xml", "'BTScaredNav.xml' is not a library tree"),
    ("", "<include> without a path"),
])
def test_include_only_of_library_trees(path: str, expected: str) -> None:
    xml = (f"<root main_tree_to_execute='T'>\n<include path='{path}'/>\n"
           "<BehaviorTree ID='T'><RobotMoved agent_id='{id}'/></BehaviorTree>\n</root>")
    problems = validate_bt_text(xml)
    assert [p.line for p in problems] == [2]
    assert expected in problems[0].message
    assert "BTRegularNav.xml" in problems[0].message  # tells what may be included


def test_include_with_ros_pkg_is_rejected() -> None:
    xml = tree(REGNAV).replace("</root>", "<include ros_pkg='hunav' path='BTRegularNav.xml'/>\n</root>")
    assert "unknown attribute 'ros_pkg' on <include>" in messages(validate_bt_text(xml))


def test_tree_named_like_an_included_library_tree() -> None:
    xml = (f"<root main_tree_to_execute='RegularNavTree'>\n{INCLUDE}\n"
           "<BehaviorTree ID='RegularNavTree'><RobotMoved agent_id='{id}'/></BehaviorTree>\n</root>")
    assert "also defined by an included library tree" in messages(validate_bt_text(xml))


def test_target_ids() -> None:
    body = "<Sequence><HumanSays agent_id='{id}' target_id='{t}' message='1'/>" \
           "<FollowHuman agent_id='{id}' target_id='{t}' time_step='{dt}'/></Sequence>"
    assert validate_bt_text(tree(body.format(t=1, id="{id}", dt="{dt}")), human_ids={0, 1}, agent_id=0) == []
    missing = validate_bt_text(tree(body.format(t=5, id="{id}", dt="{dt}")), human_ids={0, 1}, agent_id=0)
    assert [p.message.split(": ", 1)[1] for p in missing] == ["there is no human with id 5; human ids: 0, 1"] * 2
    itself = validate_bt_text(tree(body.format(t=0, id="{id}", dt="{dt}")), human_ids={0, 1}, agent_id=0)
    assert len(itself) == 2 and all("is this human itself" in p.message for p in itself)
    # Without human ids any integer is accepted (hand-written trees checked alone).
    assert validate_bt_text(tree(body.format(t=5, id="{id}", dt="{dt}"))) == []


@pytest.mark.parametrize(("target", "unsupported"), [
    ("socrates", []),
    ("hunav2", ["HumanSays"]),  # RobotSays becomes the robot script's condition (export.speech)
    ("hunav1", ["RobotSays", "HumanSays", "GiveWaytoRobot", "MakeGesture"]),
])
def test_target_support(target: str, unsupported: list[str]) -> None:
    problems = validate_bt_text(tree(VALID_BODY, include=True), target=target)
    named = [p.message.split("'")[1] for p in problems]
    assert sorted(named) == sorted(unsupported)
    assert all(f"not supported by target {target}" in p.message for p in problems)


def test_target_message_names_the_counterpart() -> None:
    problems = validate_bt_text(tree("<FollowRobot agent_id='{id}' time_step='{dt}'/>"), target="hunav1")
    assert problems[0].message == ("node 'FollowRobot' is not supported by target hunav1 (its hunav1 counterpart "
                                   "is 'CuriousNav')")
    problems = validate_bt_text(tree("<IsRobotNearby agent_id='{id}' distance='2'/>"), target="hunav1")
    assert "not supported by target hunav1" in problems[0].message


def test_unknown_target() -> None:
    assert "unknown target 'ros'" in messages(validate_bt_text(tree("<RobotMoved agent_id='{id}'/>"), target="ros"))


def test_version_4_files() -> None:
    xml = ("<root BTCPP_format='4' main_tree_to_execute='T'>\n<BehaviorTree ID='T'><Sequence>"
           "<SetBlackboard output_key='agentid' value='{id}'/><SetBlackboard output_key='timestep' value='{dt}'/>"
           "<SubTree ID='RegularNavTree' id='{agentid}' dt='{timestep}'/></Sequence></BehaviorTree>\n"
           f"{INCLUDE}\n</root>")
    assert validate_bt_text(xml) == []
    plain = validate_bt_text(xml.replace("id='{agentid}'", "id='agentid'"))  # v4: a plain value is a constant
    assert len(plain) == 1 and plain[0].line == 2, messages(plain)
    assert ("SubTree 'RegularNavTree' id='agentid': in BTCPP_format 4 a plain value is a constant, not the "
            "caller's entry (agent_id must be {id}") in plain[0].message
    assert "write id='{agentid}' to pass the entry 'agentid'" in plain[0].message


def test_explicit_node_syntax_and_comments_and_declaration() -> None:
    body = ("<!-- a comment -->\n<Control ID='Sequence'><Condition ID='RobotMoved' agent_id='{id}'/>"
            "<Action ID='LookAtRobot' agent_id='{id}'/></Control>")
    assert validate_bt_text('<?xml version="1.0" encoding="UTF-8"?>\n' + tree(body)) == []


def test_many_problems_are_capped_with_a_count() -> None:
    body = "<Sequence>" + "<Foo/>" * 80 + "</Sequence>"
    problems = validate_bt_text(tree(body))
    assert len(problems) == 51
    assert problems[-1].message == "... and 30 more problems (fix the ones above first)"


# -- the reference trees of the SocRATES fork ----------------------------------------------------
LOADABLE = ["BTRegularNav.xml", "BTCuriousNav.xml", "LLMBT_0.xml", "LLMBT_1.xml", "LLMBT_2.xml"]


@pytest.mark.parametrize("name", LOADABLE)
def test_reference_trees_the_fork_loads_are_valid(reference_dir, name: str) -> None:
    path = reference_dir / "data" / "socrates-hunav" / "behavior_trees" / name
    assert validate_bt_file(path) == []


@pytest.mark.parametrize(("name", "expected"), [
    ("BTScaredNav.xml", [(30, "unknown node 'AvoidRobot'")]),
    ("BTSurprisedNav.xml", [(27, "unknown node 'SurprisedNav'")]),
    ("BTThreateningNav.xml", [(28, "unknown node 'ThreateningNav'")]),
    *[(f"LLMBT_{i}.xml", [(29, "unknown node 'HasRobotMoved' (did you mean 'RobotMoved'?)"),
                          (32, "unknown port 't' on RegularNav"),
                          (32, "RegularNav is missing required port 'time_step'"),
                          (34, "unknown port 't' on RegularNav"),
                          (34, "RegularNav is missing required port 'time_step'")]) for i in range(3, 10)],
])
def test_stale_reference_trees_fail_with_exact_findings(reference_dir, name: str, expected) -> None:
    path = reference_dir / "data" / "socrates-hunav" / "behavior_trees" / name
    problems = validate_bt_file(path)
    assert [(p.line, p.message[:len(m)]) for p, (_, m) in zip(problems, expected, strict=False)] == expected
    assert len(problems) == len(expected)
    assert all(p.source == str(path) for p in problems)


def test_library_trees_are_valid() -> None:
    for name, xml in LIBRARY_TREE_XML.items():
        assert validate_bt_text(xml, name) == []


# -- hostile input -------------------------------------------------------------------------------
BILLION_LAUGHS = ('<?xml version="1.0"?>\n<!DOCTYPE lolz [\n<!ENTITY lol "lol">\n'
                  + "".join(f'<!ENTITY lol{i} "{("&lol" + str(i - 1) + ";") * 10 if i > 1 else "&lol;" * 10}">\n'
                            for i in range(1, 10))
                  + "]>\n<root main_tree_to_execute='T'>&lol9;</root>")
EXTERNAL = ('<?xml version="1.0"?>\n<!DOCTYPE r [<!ENTITY x SYSTEM "file:///etc/passwd">]>\n'
            "<root main_tree_to_execute='T'><BehaviorTree ID='T'><Foo a='&x;'/></BehaviorTree></root>")


@pytest.mark.parametrize(("text", "expected"), [
    (BILLION_LAUGHS, "DTDs and entities are not allowed"),
    (EXTERNAL, "DTDs and entities are not allowed"),
    ("<root>" + "<Sequence>" * 10000 + "</Sequence>" * 10000 + "</root>", "nested more than 64 levels"),
    ("<root main_tree_to_execute='T'><BehaviorTree ID='T'><Sequence>" + "<RobotMoved agent_id='{id}'/>" * 10000
     + "</Sequence></BehaviorTree></root>", "larger than"),
    ("<root>" + "<a/>" * 6000 + "</root>", "more than 5000 elements"),
    ("x" * (10 * 1024 * 1024), "larger than"),
    ("<root>\x00</root>", "XML does not parse"),
    ("<root main_tree_to_execute='T'><BehaviorTree ID='T'><![CDATA[" + "]" * 5 + "</BehaviorTree></root>",
     "XML does not parse"),
    ("\ufeff\ud800", "does not parse"),
])
def test_hostile_input_is_a_problem_and_fast(text: str, expected: str) -> None:
    start = time.perf_counter()
    problems = validate_bt_text(text)
    elapsed = time.perf_counter() - start
    assert problems and expected in problems[0].message, messages(problems)
    assert elapsed < 2.0


def test_non_text_input_is_a_problem() -> None:
    assert "expected XML text, got bytes" in messages(validate_bt_text(b"<root/>"))  # type: ignore[arg-type]
    assert "expected XML text, got NoneType" in messages(validate_bt_text(None))  # type: ignore[arg-type]


@settings(max_examples=150, deadline=None)
@given(st.text(max_size=400))
def test_random_text_never_raises(text: str) -> None:
    assert isinstance(validate_bt_text(text), list)


@settings(max_examples=150, deadline=None)
@given(st.integers(0, 600), st.integers(0, 600), st.text(alphabet="<>/='\"{} &;!-?abcdefT", max_size=12))
def test_mutated_valid_tree_never_raises(cut: int, at: int, junk: str) -> None:
    xml = tree(VALID_BODY, include=True)
    mutated = xml[:at] + junk + xml[at + cut % 40:]
    result = validate_bt_text(mutated)
    assert isinstance(result, list)
    assert all(isinstance(p, BTProblem) for p in result)


# -- files ---------------------------------------------------------------------------------------
def test_file_problems(tmp_path) -> None:
    assert "file not found" in messages(validate_bt_file(tmp_path / "missing.xml"))
    big = tmp_path / "big.xml"
    big.write_bytes(b" " * (300 * 1024))
    assert "more than the" in messages(validate_bt_file(big))
    latin = tmp_path / "latin.xml"
    latin.write_bytes(b"<root>\xe9</root>")
    assert "not UTF-8" in messages(validate_bt_file(latin))
    assert "cannot read" in messages(validate_bt_file(tmp_path)) or "file not found" in messages(
        validate_bt_file(tmp_path))


def test_include_never_reads_the_disk(tmp_path) -> None:
    """A BTRegularNav.xml beside the file is ignored: includes resolve to the library's own copy."""
    (tmp_path / "BTRegularNav.xml").write_text("<root><BehaviorTree ID='Other'><Foo/></BehaviorTree></root>")
    path = tmp_path / "human1.xml"
    path.write_text(tree(REGNAV, include=True))
    assert validate_bt_file(path) == []


def test_shared_blackboard_and_autoremap() -> None:
    v3 = tree("<SubTree ID='RegularNavTree' __shared_blackboard='true'/>", include=True)
    assert validate_bt_text(v3) == []
    assert "must be true or false" in messages(validate_bt_text(v3.replace("'true'", "'maybe'")))
    v4 = ("<root BTCPP_format='4' main_tree_to_execute='T'><BehaviorTree ID='T'><Sequence>"
          "<SetBlackboard output_key='agentid' value='{id}'/>"
          "<SubTree ID='RegularNavTree' _autoremap='true'/></Sequence></BehaviorTree>"
          f"{INCLUDE}</root>")
    assert validate_bt_text(v4) == []
    # each format's own flag only: BT.CPP 4 ignores __shared_blackboard, 3.8 takes _autoremap for a remap
    assert "is not BTCPP_format 3 syntax; write __shared_blackboard='true'" in messages(
        validate_bt_text(v4.replace(" BTCPP_format='4'", "")))
    assert "is not BTCPP_format 4 syntax; write _autoremap='true'" in messages(validate_bt_text(
        v4.replace("_autoremap", "__shared_blackboard")))
    # BT.CPP (3.8 and 4) reads output_key as the key's NAME: '{agentid}' would name the key by agentid's value
    assert "output_key is a blackboard key name" in messages(validate_bt_text(v4.replace("'agentid'", "'{agentid}'")))
