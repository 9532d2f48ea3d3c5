"""Conformance with the real BehaviorTree.CPP 4 (behaviortreepy): every hunav2 tree exported from
every card on every bundled location, and from every tree of the replay fixtures, passes the v4
loader rules with 2.x's registered ports, loads in BT.CPP and survives ticks."""

from __future__ import annotations

import pytest

from socnavgen.bt.library import HUNAV2, HUNAV2_REGISTERED, hunav2_refusal, regular_walker_xml
from socnavgen.bt.loader_rules import hunav2_problems
from socnavgen.bt.validate import validate_bt_text
from socnavgen.errors import ValidationFailed
from socnavgen.export import build_files
from socnavgen.export.hunav2 import translate_person, translate_tree
from socnavgen.export.scene import build_scene
from socnavgen.export.timing import Hold

from .conformance_helpers import btcpp_factory, card_scenes, human_for, replay_trees, without_leaf_ports

TICKS = 40
REGULAR_XML = regular_walker_xml()


@pytest.fixture(scope="module")
def scenes(tmp_path_factory):  # noqa: ANN001, ANN201
    return card_scenes(str(tmp_path_factory.mktemp("cards")))


def load_and_tick(text: str, label: str) -> list[str]:
    ticks: list[str] = []
    factory, bt = btcpp_factory(ticks)
    board = bt.Blackboard.create()
    board.set_int("id", 1)
    board.set_double("dt", 0.05)
    tree = factory.create_tree_from_text(without_leaf_ports(text), board)
    for _ in range(TICKS):
        tree.tick_exactly_once()
    assert ticks, f"{label}: no leaf was ever ticked"
    return ticks


def test_every_card_exports_to_socrates_and_hunav2_or_is_refused_per_node(scenes) -> None:  # noqa: ANN001
    assert len(scenes) >= 40  # all bundled locations, most cards fit
    exported, refused = 0, []
    for label, scene in scenes:
        for f in build_files(scene, "socrates"):  # the fork's trees, timing included, pass the v3.8 loader rules
            if "/LLMBT_" in f.path:
                assert validate_bt_text(f.text, f"{label}:{f.path}", target="socrates") == []
        try:
            files = build_files(scene, "hunav2", base="conf")
        except ValidationFailed as err:
            assert "cannot be exported:" in str(err), (label, str(err))
            refused.append(label)
            continue
        exported += 1
        trees = [f for f in files if f.path.endswith("_bt.xml")]
        assert len(trees) == len(scene.humans)
        for f in trees:
            assert hunav2_problems(f.text, f"{label}:{f.path}") == []
            load_and_tick(f.text, f"{label}:{f.path}")
    assert exported > len(refused) and exported >= 40, (exported, refused)


def test_every_replay_tree_translates_or_is_refused_per_node_and_loads() -> None:
    trees = replay_trees()
    assert len(trees) >= 2
    for label, xml in trees:
        text, problems = translate_tree(human_for(xml, label), [1])
        if problems:  # refused: nodes the library table refuses, each with its reason, and phrase conditions,
            for p in problems:  # which become the robot script's condition (that needs the run, below)
                assert (hunav2_refusal(p.node) and hunav2_refusal(p.node) in str(p)) or \
                    (HUNAV2[p.node].by_script and "robot script's condition" in str(p)), p
            continue
        assert hunav2_problems(text, label) == []
        load_and_tick(text, label)


def test_every_replayed_run_exports_with_timing_and_phrase_conditions_and_loads(bundled_runs) -> None:  # noqa: ANN001
    exported = 0
    for kind, label, run in bundled_runs:
        if kind != "fixtures":
            continue
        try:
            files = build_files(build_scene(run)[0], "hunav2", base="fixture")
        except ValidationFailed as err:  # only what no 2.x condition can say (e.g. a phrase said when another
            assert "cannot be exported:" in str(err), (label, str(err))  # person is near), each with its reason
            continue
        exported += 1
        for f in (f for f in files if f.path.endswith("_bt.xml")):
            assert hunav2_problems(f.text, f"{label}:{f.path}") == []
            load_and_tick(f.text, f"{label}:{f.path}")
    assert exported >= 5, exported


# ---- the checks can fail ---------------------------------------------------------------------
GOOD = """<root BTCPP_format="4" main_tree_to_execute="T"><BehaviorTree ID="T">
<ReactiveSequence><IsRobotClose agent_id="{id}" threshold="2.0"/>{leaf}</ReactiveSequence>
</BehaviorTree></root>"""


@pytest.mark.parametrize("leaf,message", [
    ('<ApproachRobot agent_id="{id}" time_step="{dt}" closest_dist="1.5" duration="1"/>',
     "ApproachRobot is missing required port 'max_vel'"),
    ('<CuriousNav agent_id="{id}" time_step="{dt}" stop_distance="1.5" agent_vel="1" speed="2"/>',
     "unknown port 'speed' on CuriousNav"),
    ('<RobotSays agent_id="{id}" message="4"/>', "unknown node 'RobotSays'"),
    ('<SubTree ID="Missing"/>', "names no BehaviorTree"),
    ('<IsRobotClose agent_id="{agentid}"/>', "blackboard key 'agentid' is never set"),
    ('<RunOnce><SetGoal agent_id="{id}"/></RunOnce>', "SetGoal is missing required port 'goal_id'"),
    ('<TimeDelay delay="1"/>', "TimeDelay must have exactly one child"),
])
def test_loader_rules_reject(leaf: str, message: str) -> None:
    problems = hunav2_problems(GOOD.replace("{leaf}", leaf))
    assert any(message in p for p in problems), problems


def test_loader_rules_accept_a_correct_tree() -> None:
    ok = GOOD.replace("{leaf}", '<ApproachRobot agent_id="{id}" time_step="{dt}" closest_dist="1.5" max_vel="1.5"/>')
    assert hunav2_problems(ok) == []
    assert hunav2_problems(ok.replace(' BTCPP_format="4"', "")) == ['<tree>: BTCPP_format must be "4" for BT.CPP 4']
    assert "ApproachRobot" in load_and_tick(ok, "ok")


def test_real_btcpp_rejects_a_node_hunav2_does_not_register() -> None:
    with pytest.raises(RuntimeError, match="RobotSays"):
        load_and_tick(GOOD.replace("{leaf}", '<RobotSays agent_id="{id}" message="4"/>'), "bad")


def scripted_factory(answers: dict[str, list[bool]], ticks: list[str]):  # noqa: ANN201
    """BT.CPP 4 with every 2.x leaf registered; a condition named in `answers` answers from its list (then its
    last answer for good), every other condition fails; actions succeed. Ticks are logged by node name."""
    import behaviortreepy as bt

    factory = bt.BehaviorTreeFactory()
    seen: dict[str, int] = {}

    def condition(node):  # noqa: ANN001, ANN202
        name = node.name()
        ticks.append(name)
        said = answers.get(name, [False])
        k = seen[name] = seen.get(name, -1) + 1
        return bt.NodeStatus.SUCCESS if said[min(k, len(said) - 1)] else bt.NodeStatus.FAILURE

    def action(node):  # noqa: ANN001, ANN202
        ticks.append(node.name())
        return bt.NodeStatus.SUCCESS

    for node in HUNAV2_REGISTERED.values():
        if node.kind == "Condition":
            factory.register_simple_condition(node.id, condition)
        elif node.kind == "Action":
            factory.register_simple_action(node.id, action)
    return factory, bt


def timed_ticks(text: str, close: list[bool] | None = None) -> list[list[str]]:
    """The leaves each of 10 ticks reaches: the waiting goal is reached on tick 3 (the person stands at it from
    then on), the robot close on tick 6 (the release's distance is asked from tick 3: `close` answers from there)."""
    ticks: list[str] = []
    factory, bt = scripted_factory({"socnavgen_goal_reached": [False, True, False, True],
                                    "socnavgen_goal_count": [False, True],
                                    "socnavgen_at_spot": [False, False, False, True],
                                    "socnavgen_robot_close": close or [False] * 3 + [True, False]}, ticks)
    board = bt.Blackboard.create()
    board.set_int("id", 1)
    board.set_double("dt", 0.05)
    tree = factory.create_tree_from_text(without_leaf_ports(text), board)
    per_tick = []
    for _ in range(10):
        ticks.clear()
        tree.tick_exactly_once()
        per_tick.append(list(ticks))
    return per_tick


def test_the_timing_latches_in_real_btcpp() -> None:
    """The hold as BT.CPP 4 runs it: walk until the waiting goal is reached (counted), then wait (no leaf moves),
    released once the robot is close; from then on only the person's own tree, its conditions never again."""
    hold = Hold(human="human1", node="x", goals_first=2, wait_goal=None, wait_index=0, release_distance=2.5,
                timeout=60.0, wait_at=(0.0, 0.0), robot_at=(0.0, 0.0), early_by=0.0)
    text = translate_person(human_for(REGULAR_XML, "regular"), [1, 2], None, hold).text
    assert hunav2_problems(text, "timed") == []
    per_tick = timed_ticks(text)
    assert "RegularNav" in per_tick[1] and "RegularNav" in per_tick[2]  # walking to the waiting goal
    assert per_tick[3][-2:] == ["socnavgen_goal_reached", "socnavgen_goal_count"]  # 2nd goal reached: stops
    assert all("RegularNav" not in t for t in per_tick[4:6])  # waiting: nothing moves
    assert "socnavgen_robot_close" in per_tick[6] and "RegularNav" in per_tick[6]  # released, walks on its own
    assert all("socnavgen_robot_close" not in t for t in per_tick[:3])  # on its way to the spot: not asked
    near = timed_ticks(text, close=[True])  # the robot near all along: released once at the spot, not on its way
    assert "RegularNav" in near[2] and "socnavgen_robot_close" in near[3] and "RegularNav" in near[4]
    for t in per_tick[7:]:  # latched: the hold's conditions are never ticked again, the tree runs every tick
        assert not any(name.startswith("socnavgen_") for name in t) and "RegularNav" in t, t
    # the check can fail: with a reactive latch the release is asked again and the person waits again
    reactive = text.replace('<Sequence name="socnavgen_timing_then">', '<ReactiveSequence name="socnavgen_timing_then">')
    reactive = reactive.replace('</Sequence>\n        <ReactiveFallback name="socnavgen_approach">',
                                '</ReactiveSequence>\n        <ReactiveFallback name="socnavgen_approach">')
    assert reactive != text
    again = timed_ticks(reactive)
    assert "socnavgen_robot_close" in again[7] and "RegularNav" not in again[7]
