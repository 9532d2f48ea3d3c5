"""hunav1 target: built-in behaviors only; custom trees are refused by human and node."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
import yaml

from socnavgen.bt.library import REGULAR_NAV_XML
from socnavgen.errors import SocnavgenError
from socnavgen.export import export_run

from .export_helpers import CURIOUS_TREE, GIVE_WAY_TREE, REGULAR_TREE, TRANSLATABLE_TREE, agent_shape


def test_builtin_patterns_map_to_behavior_codes(make_run, tmp_path: Path, reference_dir: Path) -> None:
    out = tmp_path / "out"
    export_run(make_run(trees={"human1": CURIOUS_TREE, "human2": REGULAR_TREE}), "hunav1", out)
    ours = yaml.safe_load((out / "hunav_agent_manager/config/agents.yaml").read_text())
    p = ours["hunav_loader"]["ros__parameters"]
    assert p["human1"]["behavior"] == 5 and p["human2"]["behavior"] == 1
    ref = yaml.safe_load((reference_dir / "data/upstream-hunav-1x/config/agents.yaml").read_text())
    rp = ref["hunav_loader"]["ros__parameters"]
    assert set(p) - set(p["agents"]) == set(rp) - set(rp["agents"])
    assert agent_shape(p, "human2").keys() <= agent_shape(rp, rp["agents"][0]).keys()
    assert p["human1"]["goals"] == ["g0", "g1"]  # 1.x names goals from g0
    assert not list(out.rglob("*.xml"))  # 1.x loads its own trees
    # ids numbered as upstream's own agents file numbers them (from 1; the SocRATES fork from 0)
    assert [rp[a]["id"] for a in rp["agents"]][:2] == [1, 2] == [p["human1"]["id"], p["human2"]["id"]]


def test_the_library_regular_tree_itself_is_behavior_1(make_run, tmp_path: Path) -> None:
    out = tmp_path / "out"
    export_run(make_run(trees={"human1": REGULAR_NAV_XML, "human2": REGULAR_TREE}), "hunav1", out)
    p = yaml.safe_load((out / "hunav_agent_manager/config/agents.yaml").read_text())["hunav_loader"]["ros__parameters"]
    assert p["human1"]["behavior"] == 1


def test_changed_parameter_is_not_a_builtin(make_run, tmp_path: Path) -> None:
    tree = CURIOUS_TREE.replace('distance="10"', 'distance="3"')
    with pytest.raises(SocnavgenError, match=r"human1 .*not one of the built-in"):
        export_run(make_run(trees={"human1": tree, "human2": REGULAR_TREE}), "hunav1", tmp_path / "o")


def test_refusal_names_human_and_node(make_run, tmp_path: Path) -> None:
    out = tmp_path / "out"
    with pytest.raises(SocnavgenError) as err:
        export_run(make_run(trees={"human1": REGULAR_TREE, "human2": GIVE_WAY_TREE}), "hunav1", out)
    message = str(err.value)
    assert "human2" in message and "RobotSays" in message and "GiveWaytoRobot" in message
    assert "human1" not in message.split("refused:")[1]
    assert not out.exists()


def test_tree_of_1x_nodes_in_a_custom_shape_is_refused(make_run, tmp_path: Path) -> None:
    # IsRobotNearby has no 1.x node; TRANSLATABLE_TREE also has a custom shape
    with pytest.raises(SocnavgenError, match="IsRobotNearby"):
        export_run(make_run(trees={"human1": TRANSLATABLE_TREE, "human2": REGULAR_TREE}), "hunav1", tmp_path / "o")


@pytest.mark.parametrize("variant", [
    lambda t: t.replace('distance="10"', 'distance="10.0"').replace('only_once="true"', 'only_once="TRUE"'),
    lambda t: t.replace('seconds="30"', 'seconds=" 30 "'),  # the port's double, however it is written
    lambda t: t.replace("<FollowRobot", '<Action ID="FollowRobot"'),  # the explicit form
    lambda t: t.replace('<Sequence name="RegNav">', "<Sequence><Sequence>").replace(
        "</Sequence>\n        </Fallback>", "</Sequence></Sequence>\n        </Fallback>"),  # nested controls
])
def test_same_meaning_is_the_same_builtin(variant) -> None:  # noqa: ANN001
    from socnavgen.export.hunav1 import builtin_behavior

    from .conformance_helpers import human_for

    tree = variant(CURIOUS_TREE)
    assert tree != CURIOUS_TREE
    assert builtin_behavior(human_for(tree, "t.xml")) == (5, [])
    # a port left out holds its default (only_once false): another behavior
    assert builtin_behavior(human_for(re.sub(' only_once="[^"]*"', "", tree), "t.xml"))[0] is None
