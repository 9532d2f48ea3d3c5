"""Adding a leaf is one table row (plus the simulator's function): the row alone drives the validator, the
prompt text, the reply grammar, the exporters, stage 3's tree needs and the verifier's expectations."""

from __future__ import annotations

from collections.abc import Iterator

import pytest

from socnavgen.bt import library
from socnavgen.bt.expand import load_instance
from socnavgen.bt.library import NodeSpec, Port, PortType

WAVE = NodeSpec(
    name="WaveAtRobot", kind="action", interaction=True, realizes=("look",),
    ports=[Port(name="agent_id", type=PortType.INT, description="the agent's own id; always write {id}",
                reads_root="id"),
           Port(name="hand", type=PortType.INT, description="which hand", allowed={1: "LEFT", 2: "RIGHT"})],
    description="The human waves at the robot with one hand.", capability="Wave at the robot")
TREE = ("<root main_tree_to_execute='M'><include path='BTRegularNav.xml'/><BehaviorTree ID='M'><Fallback>"
        "<Sequence><IsRobotVisible agent_id='{id}' distance='3.0'/><WaveAtRobot agent_id='{id}' hand='2'/>"
        "</Sequence>" + library.regular_nav_sequence().replace('"', "'") + "</Fallback></BehaviorTree></root>")


@pytest.fixture
def new_row() -> Iterator[NodeSpec]:
    library.NODES.append(WAVE)
    library.LIBRARY[WAVE.name] = WAVE
    yield WAVE
    library.NODES.remove(WAVE)
    del library.LIBRARY[WAVE.name]
    load_instance.cache_clear()  # instances read while the row existed


def test_without_the_row_the_node_is_unknown() -> None:
    from socnavgen.bt.validate import validate_bt_text

    assert "unknown node 'WaveAtRobot'" in str(validate_bt_text(TREE))


@pytest.mark.usefixtures("new_row")
def test_validator_prompt_and_grammar_follow_the_row() -> None:
    from socnavgen.bt.describe import capabilities_text, library_text
    from socnavgen.bt.grammar import bt_reply_grammar
    from socnavgen.bt.validate import validate_bt_text
    from socnavgen.cli.bt_cmd import library_markdown

    assert validate_bt_text(TREE) == []
    assert "code 3 is not allowed; codes: 1 LEFT, 2 RIGHT" in str(validate_bt_text(TREE.replace("hand='2'", "hand='3'")))
    assert "agent_id must be {id}" in str(validate_bt_text(TREE.replace("WaveAtRobot agent_id='{id}'",
                                                                        "WaveAtRobot agent_id='1'")))
    assert "node 'WaveAtRobot' is not supported by target hunav2" in str(validate_bt_text(TREE, target="hunav2"))
    text = library_text()
    assert "- WaveAtRobot: The human waves at the robot with one hand." in text
    assert "example: <WaveAtRobot agent_id='{id}' hand='1'/>" in text
    assert "Gesture codes for WaveAtRobot.hand: 1 = LEFT, 2 = RIGHT." in text
    assert "- Wave at the robot" in capabilities_text()
    grammar = bt_reply_grammar()
    assert "leaf-waveatrobot ::= \"<WaveAtRobot\" nm \" agent_id='\" \"{id}\" \"'\" \" hand='\" (\"1\" | \"2\")" in grammar
    assert "| `WaveAtRobot` | action | agent_id: int, hand: int {1 LEFT, 2 RIGHT} |" in library_markdown()


@pytest.mark.usefixtures("new_row")
def test_tree_needs_and_expectations_follow_the_row() -> None:
    from socnavgen.proposal.tree_needs import tree_need_mistakes
    from socnavgen.run.spec import ScenarioSpec
    from socnavgen.verify.expectations import tree_expectations

    spec = ScenarioSpec.model_validate({"encounters": [{"id": "e1", "place": "X", "humans": [
        {"human": "human1", "trigger": "robot_visible", "reaction": "look"}]}]})
    assert library.nodes_for_reaction("look") == ["LookAtRobot", "WaveAtRobot"]
    assert tree_need_mistakes(TREE, "human1", spec) == []
    ungated = TREE.replace("<IsRobotVisible agent_id='{id}' distance='3.0'/>", "")
    assert "never checks IsRobotVisible" in tree_need_mistakes(ungated, "human1", spec)[0]
    wave = next(e for e in tree_expectations("human1", TREE) if e.node == "WaveAtRobot")
    assert wave.kind == "executes" and wave.caused_by == [("IsRobotVisible", None)]


@pytest.mark.usefixtures("new_row")
def test_exporters_follow_the_row() -> None:
    from socnavgen.export.groot import model_block
    from socnavgen.export.hunav1 import builtin_behavior
    from socnavgen.export.hunav2 import translate_tree

    from ..export.conformance_helpers import human_for

    assert '<Action ID="WaveAtRobot">' in model_block("socrates")
    assert '<input_port name="hand" type="int">which hand: 1=LEFT, 2=RIGHT</input_port>' in model_block("socrates")
    _, refused = translate_tree(human_for(TREE, "t.xml"), [1])
    assert [str(p) for p in refused] == ["t.xml:1: WaveAtRobot cannot be exported: has no HuNavSim 2.x translation"]
    code, why = builtin_behavior(human_for(TREE, "t.xml"))
    assert code is None and "node WaveAtRobot does not exist in HuNavSim 1.x" in str(why[0])
