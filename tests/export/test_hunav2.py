"""hunav2 target: v4 trees with 2.x node names and ports, yaml like upstream's scenario files."""

from __future__ import annotations

import math
from pathlib import Path

import pytest
import yaml
from defusedxml import ElementTree as DET

from socnavgen.bt.library import HUNAV2_REGISTERED
from socnavgen.bt.loader_rules import hunav2_vocabulary
from socnavgen.bt.parse import parse_document
from socnavgen.errors import SocnavgenError
from socnavgen.export import export_run

from .export_helpers import GIVE_WAY_TREE, REGULAR_TREE, TRANSLATABLE_TREE, shape

REF_YAML = "data/upstream-hunav-2x/hunav_gazebo_wrapper/scenarios/agents_warehouse.yaml"
REF_MODEL = "data/upstream-hunav-2x/hunav_sim/behavior_trees/TreeNodesModel.xml"
TREES = "hunav_gazebo_wrapper/behavior_trees"


@pytest.fixture
def exported(make_run, tmp_path: Path) -> Path:
    out = tmp_path / "out"
    export_run(make_run(trees={"human1": TRANSLATABLE_TREE, "human2": REGULAR_TREE}), "hunav2", out, base="demo")
    return out


def reference_ports(reference_dir: Path) -> dict[str, set[str]]:
    model = DET.parse(reference_dir / REF_MODEL).getroot().find("TreeNodesModel")
    return {e.get("ID"): {p.get("name") for p in e} for e in model}


def registered_ports() -> dict[str, set[str]]:
    return {n.id: {p.name for p in n.ports} for n in HUNAV2_REGISTERED.values()}


def test_registered_table_covers_the_reference_model(reference_dir: Path) -> None:
    """Every node and port of upstream's TreeNodesModel.xml is in our table of what 2.x registers
    (ours has more: ports the C++ declares that the model file forgot)."""
    ours = registered_ports()
    for node, ports in reference_ports(reference_dir).items():
        if node in ("GoTo", "ConversationFormation", "ApproachAgent", "BlockAgent", "SetGroupWalk", "LookAtAgent",
                    "LookAtPoint", "IsAnyoneSpeaking", "IsSpeaking", "IsAnyoneLookingAtMe", "IsLookingAtMe"):
            continue  # registered, but no translation uses them, so the table leaves them out
        assert node in ours, node
        if node == "RandomChanceCondition":  # the model file lists agent_id; the C++ does not declare it,
            ports = ports - {"agent_id"}        # so writing it would fail to load
        assert ports <= ours[node], (node, ports - ours[node])
    assert {"max_vel", "duration"} <= ours["ApproachRobot"]
    assert "duration" in ours["BlockRobot"] and "yaw_tolerance" in ours["LookAtRobot"]
    assert {"target_x", "target_y"} <= ours["SetGoal"]


def test_yaml_matches_upstream_structure(exported: Path, reference_dir: Path) -> None:
    ours = yaml.safe_load((exported / "hunav_gazebo_wrapper/scenarios/demo.yaml").read_text())
    ref = yaml.safe_load((reference_dir / REF_YAML).read_text())
    p, rp = ours["hunav_loader"]["ros__parameters"], ref["hunav_loader"]["ros__parameters"]
    assert set(p) - set(p["agents"]) == set(rp) - set(rp["agents"])
    assert shape(p["human1"]) == shape(rp[rp["agents"][0]])
    assert shape(p["global_goals"][1]) == shape(rp["global_goals"][1])
    assert p["yaml_base_name"] == "demo" and p["simulator"] == "Gazebo Classic"
    assert isinstance(p["human1"]["behavior"]["type"], str)
    # global goals: one per node, ids from 1; human1 walks cc -> bb -> ee, human2 stays at dd
    assert p["global_goals"] == {1: {"x": -0.475, "y": 2.475}, 2: {"x": -1.475, "y": 2.475},
                                 3: {"x": -2.475, "y": 3.225}}
    assert p["human1"]["goals"] == [1, 2] and p["human2"]["goals"] == [3]
    assert math.sin(p["human1"]["init_pose"]["h"]) < 0  # facing bb, below its spawn point cc
    # ids as upstream's scenario numbers them (from 1), goal ids are keys of global_goals
    assert [rp[a]["id"] for a in rp["agents"]] == [1, 2, 3] and [p[a]["id"] for a in p["agents"]] == [1, 2]
    assert all(type(g) is int and g in p["global_goals"] for a in p["agents"] for g in p[a]["goals"])
    assert all(type(g) is int and g in rp["global_goals"] for a in rp["agents"] for g in rp[a]["goals"])


def test_trees_are_v4_self_contained_and_use_2x_nodes(exported: Path) -> None:
    assert not (exported / TREES / "demo__agent_0_bt.xml").exists()  # HuNavSim ids start at 1
    text = (exported / TREES / "demo__agent_1_bt.xml").read_text()
    doc, problems = parse_document(text, "agent_1", hunav2_vocabulary())  # what 2.x's factory knows
    assert problems == [] and doc is not None
    assert doc.format_version == 4 and 'BTCPP_format="4"' in text
    assert doc.main_tree == "WaitTree"
    assert doc.includes == () and "RegularNavTree" in doc.trees  # inlined, not included
    known = registered_ports()
    builtins = {"ReactiveSequence", "ReactiveFallback", "Sequence", "Fallback", "Inverter", "RunOnce",
                "SetBlackboard", "SubTree", "KeepRunningUntilFailure", "ForceSuccess"}
    nodes = [n for t in doc.trees.values() if t.root is not None for n in t.root.walk()]
    for node in nodes:
        assert node.name in known or node.name in builtins, node.name
        if node.name in known:  # every port we write is a port 2.x declares
            assert set(node.attrs) - {"name"} <= known[node.name], (node.name, node.attrs)
    tags = {n.name: n.attrs for n in nodes}
    assert tags["SaySomething"]["message"] == "WAIT"
    assert tags["IsRobotClose"]["threshold"] == "2.0"
    assert tags["CuriousNav"]["stop_distance"] == "1.5" and tags["CuriousNav"]["agent_vel"] == "0.8"
    assert tags["SurprisedNav"]["agent_id"] == "{id}"
    assert "ApproachRobot" not in tags  # no RUNNING-forever node
    fallbacks = [n.label for n in nodes if n.name == "Fallback"]
    assert fallbacks == ["QueueGoalsThenBehave"]  # the tree's own controls became reactive
    assert tags["SubTree"]["id"] == "{agentid}"  # v4 remapping syntax
    main = doc.trees["WaitTree"].root
    assert main is not None
    set_goals = [n.ports["goal_id"] for n in main.walk() if n.name == "SetGoal"]
    assert set_goals == [1, 2]


def test_agent_ids_start_at_one_and_literal_target_ids_shift(make_run, tmp_path: Path) -> None:
    follow = REGULAR_TREE.replace(
        '<SetBlackboard output_key="agentid"', '<FollowHuman agent_id="{id}" target_id="0" time_step="{dt}"/>\n'
        '            <SetBlackboard output_key="agentid"')
    out = tmp_path / "out"
    export_run(make_run(trees={"human1": REGULAR_TREE, "human2": follow}), "hunav2", out, base="demo")
    params = yaml.safe_load((out / "hunav_gazebo_wrapper/scenarios/demo.yaml").read_text())
    p = params["hunav_loader"]["ros__parameters"]
    assert [p["human1"]["id"], p["human2"]["id"]] == [1, 2]
    doc, problems = parse_document((out / TREES / "demo__agent_2_bt.xml").read_text(), "a2", hunav2_vocabulary())
    assert doc is not None and problems == []
    follow_agent = next(n for t in doc.trees.values() if t.root for n in t.root.walk() if n.name == "FollowAgent")
    assert follow_agent.attrs["target_agent_id"] == "1"  # our human1 (0) is HuNavSim's agent 1
    assert follow_agent.attrs["duration"] == "0.0" and follow_agent.attrs["max_vel"] == "1.5"


def test_gesture_zero_says_nothing(make_run, tmp_path: Path) -> None:
    quiet = TRANSLATABLE_TREE.replace('message="1"', 'message="0"')
    out = tmp_path / "out"
    export_run(make_run(trees={"human1": quiet, "human2": REGULAR_TREE}), "hunav2", out, base="demo")
    text = (out / TREES / "demo__agent_1_bt.xml").read_text()
    assert "NO GESTURE" not in text and "<SaySomething" not in text.split("</TreeNodesModel>")[1]
    assert "<AlwaysSuccess/>" in text


def test_embedded_and_standalone_models_match_reference_structure(exported: Path) -> None:
    known = registered_ports()
    for path in [exported / TREES / "demo__agent_1_bt.xml", exported / TREES / "TreeNodesModel.xml"]:
        root = DET.parse(path).getroot()
        assert root.tag == "root" and root.get("BTCPP_format") == "4"
        model = root.find("TreeNodesModel")
        assert model is not None and len(model) > 0
        for node in model:
            assert node.tag in ("Action", "Condition", "Decorator")
            assert node.get("ID") in known, node.get("ID")
            for port in node:
                assert port.tag in ("input_port", "output_port")
                assert port.get("type") in ("int", "double", "bool", "std::string")
                assert port.get("name") in known[node.get("ID")]


def test_every_untranslatable_node_is_listed_and_nothing_written(make_run, tmp_path: Path) -> None:
    out = tmp_path / "out"
    moved = GIVE_WAY_TREE.replace('<RobotSays agent_id="{id}" message="4"/>', '<RobotMoved agent_id="{id}"/>')
    run = make_run(trees={"human1": moved, "human2": moved})
    with pytest.raises(SocnavgenError) as err:
        export_run(run, "hunav2", out)
    message = str(err.value)
    assert "2 node(s)" in message  # RobotMoved is refused; GiveWaytoRobot translates (AvoidRobot)
    for human in ("human1", "human2"):
        assert f"{human}.xml:6: RobotMoved cannot be exported: no 2.x condition reads the robot's velocity" in message
    assert "GiveWaytoRobot" not in message
    assert not out.exists()


def test_unknown_simulator_refused(make_run, tmp_path: Path) -> None:
    with pytest.raises(SocnavgenError, match="simulator"):
        export_run(make_run(trees={"human1": REGULAR_TREE, "human2": REGULAR_TREE}), "hunav2", tmp_path / "o",
                   simulator="Unreal")


def test_standalone_model_has_every_registered_port(exported: Path) -> None:
    model = DET.parse(exported / TREES / "TreeNodesModel.xml").getroot().find("TreeNodesModel")
    ports = {n.get("ID"): {p.get("name"): p.get("default") for p in n} for n in model}
    assert ports["ApproachRobot"] == {"agent_id": None, "time_step": None, "closest_dist": None, "max_vel": None,
                                      "duration": "0.0"}
    assert ports["BlockRobot"]["duration"] == "0.0" and ports["LookAtRobot"]["yaw_tolerance"] == "0.01"
    assert {"target_x", "target_y", "goal_id"} <= ports["SetGoal"].keys()
    assert ports["TimeExpiredCondition"] == {"seconds": "1.0", "ts": "0.01", "only_once": "false"}


SHARED = """<root main_tree_to_execute="M">
  <BehaviorTree ID="M">
    <Sequence>
      <SetBlackboard output_key="near" value="2"/>
      <SubTree ID="Look" __shared_blackboard="1"/>
    </Sequence>
  </BehaviorTree>
  <BehaviorTree ID="Look">
    <Sequence><IsRobotNearby agent_id="{id}" distance="{near}"/><LookAtRobot agent_id="{id}"/></Sequence>
  </BehaviorTree>
</root>"""


@pytest.mark.parametrize("xml, call", [
    (SHARED, {"ID": "Look", "_autoremap": "true"}),  # v3 shared blackboard -> v4 autoremap
    (SHARED.replace('<root main_tree_to_execute="M">', '<root main_tree_to_execute="M" BTCPP_format="4">')
     .replace(' __shared_blackboard="1"', ' id="{id}" near="2.5"').replace('output_key="near" value="2"',
                                                                         'output_key="x" value="1"'),
     {"ID": "Look", "id": "{id}", "near": "2.5"}),  # a v4 constant stays a constant
])
def test_subtree_semantics_survive_the_translation(xml: str, call: dict[str, str]) -> None:
    from socnavgen.bt.loader_rules import hunav2_problems
    from socnavgen.export.hunav2 import translate_tree

    from .conformance_helpers import human_for

    text, refused = translate_tree(human_for(xml, "t.xml"), [1])
    assert refused == [] and hunav2_problems(text) == []
    doc, _ = parse_document(text, "t", hunav2_vocabulary())
    assert doc is not None and doc.trees["M"].root is not None
    (subtree,) = [n for n in doc.trees["M"].root.walk() if n.name == "SubTree"]
    assert dict(subtree.attrs) == call


@pytest.mark.parametrize(("who", "heard"), [("human1", True), (None, True), ("human2", False)])
def test_a_phrase_said_when_someone_lags_behind_is_heard_farther_than_the_cue_distance(
        make_run, who: str | None, heard: bool) -> None:  # noqa: ANN001
    """human_farther (a guide calling a slow follower): the person hears it while the robot is farther than the
    cue's distance from it (Inverter(IsRobotClose)), if it is said to this person or to anyone; said to another
    person, never. Not refused."""
    from socnavgen.bt.library import ROBOT_GESTURES
    from socnavgen.export.hunav2 import translate_person
    from socnavgen.export.scene import build_scene
    from socnavgen.run import RunFolder
    from socnavgen.run.spec import CueTrigger, Encounter, HumanPart, RobotCue, RobotScript, ScenarioSpec

    run = make_run(trees={"human1": GIVE_WAY_TREE, "human2": REGULAR_TREE})  # human1: RobotSays message 4
    cue = RobotCue(trigger=CueTrigger(when="human_farther", human=who, distance=3.5), say=ROBOT_GESTURES[4], hold=2.0)
    meet = Encounter(id="e1", place="NODE", node="ee", humans=[HumanPart(human="human1"), HumanPart(human="human2")])
    RunFolder(run).write_spec(ScenarioSpec(script=RobotScript(cues=[cue]), encounters=[meet]))
    scene, _ = build_scene(run)
    done = translate_person(next(h for h in scene.humans if h.name == "human1"), None, scene)
    assert not done.problems
    root = DET.fromstring(done.text)
    far = [inv for inv in root.iter("Inverter") if any(c.tag == "IsRobotClose" and c.get("threshold") == "3.5"
                                                        for c in inv)]
    never = [inv for inv in root.iter("Inverter") if [c.tag for c in inv] == ["AlwaysSuccess"]]
    assert bool(far) is heard and bool(never) is not heard
    assert ("farther than 3.5 m" in done.spoken[0].text) is heard and not done.spoken[0].refused
