"""Conformance with the real BehaviorTree.CPP 4 (behaviortreepy): every hunav2 tree exported from
every card on every bundled location, and from every tree of the replay fixtures, passes the v4
loader rules with 2.x's registered ports, loads in BT.CPP and survives ticks."""

from __future__ import annotations

import pytest

from socnavgen.bt.library import hunav2_refusal
from socnavgen.bt.loader_rules import hunav2_problems
from socnavgen.errors import ValidationFailed
from socnavgen.export import build_files
from socnavgen.export.hunav2 import translate_tree

from .conformance_helpers import btcpp_factory, card_scenes, human_for, replay_trees, without_leaf_ports

TICKS = 40


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
        assert build_files(scene, "socrates")
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
        if problems:  # refused: only for nodes the library table refuses, each with its reason
            assert all(hunav2_refusal(p.node) and hunav2_refusal(p.node) in str(p) for p in problems), problems
            continue
        assert hunav2_problems(text, label) == []
        load_and_tick(text, label)


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
