"""socrates target: structure of every file against the real SocRATES / fork files."""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest
import yaml
from defusedxml import ElementTree as DET

from socnavgen.bt.parse import parse_document
from socnavgen.errors import SocnavgenError
from socnavgen.export import export_run
from socnavgen.export.models import ExportedFile
from socnavgen.export.writer import write_export

from .export_helpers import GIVE_WAY_TREE, REGULAR_TREE, agent_shape, shape


def skeleton(n):  # noqa: ANN001, ANN201 - bt.model.Node -> nested tuples (names and ports)
    return (n.name, tuple(sorted(n.ports)), tuple(skeleton(c) for c in n.children))


@pytest.fixture
def exported(make_run, tmp_path: Path) -> Path:
    out = tmp_path / "out"
    export_run(make_run(), "socrates", out)
    return out


def test_agents_yaml_matches_fork_file(exported: Path, reference_dir: Path) -> None:
    ours = yaml.safe_load((exported / "hunav_agent_manager/config/custom_agents.yaml").read_text())
    ref = yaml.safe_load((reference_dir / "data/socrates-hunav/config/custom_agents.yaml").read_text())
    p, rp = ours["hunav_loader"]["ros__parameters"], ref["hunav_loader"]["ros__parameters"]
    assert set(p) - set(p["agents"]) == set(rp) - set(rp["agents"])  # map, publish_people, agents
    ref_agent = agent_shape(rp, rp["agents"][0])
    h1 = agent_shape(p, "human1")
    assert {k: v for k, v in h1.items() if not k.startswith("goal")} == \
        {k: v for k, v in ref_agent.items() if not k.startswith("goal")}
    assert h1["goal0"] == ref_agent["goal0"]
    a = p["human1"]
    assert (a["id"], a["behavior"], a["cyclic_goals"], a["radius"], a["max_vel"]) == (0, 7, False, 0.4, 1.5)
    assert p["human2"]["behavior"] == 8
    pose = a["init_pose"]
    assert set(pose) == {"x", "y", "z", "h"} and pose["z"] == 1.25
    assert math.dist((pose["x"], pose["y"]), (-0.475, 3.225)) <= 1.5  # spawned around node cc (test_spawn.py)
    assert [(a[g]["x"], a[g]["y"]) for g in a["goals"]] == [(-0.475, 2.475), (-1.475, 2.475)]


def test_trees_are_v3_and_selected_by_behavior(exported: Path, reference_dir: Path) -> None:
    trees = exported / "hunav_agent_manager/behavior_trees"
    docs = {i: parse_document((trees / f"LLMBT_{i}.xml").read_text(), f"LLMBT_{i}.xml") for i in (0, 1)}
    assert all(problems == [] and d is not None and d.format_version == 3 for d, problems in docs.values())
    assert docs[0][0].main_tree == "GiveWayTree" and docs[1][0].main_tree == "WalkTree"
    # human1 meets the robot at ee: its tree is wrapped in its timing (export.timing), its own tree inside intact
    timing = docs[0][0].trees["GiveWayTree"].root
    assert (timing.name, timing.label) == ("ReactiveFallback", "socnavgen_timing")
    own = parse_document(GIVE_WAY_TREE)[0].trees["GiveWayTree"].root
    inner = next(n for n in timing.walk() if n.name == "ForceSuccess").children[0]
    assert skeleton(inner) == skeleton(own)
    assert (trees / "LLMBT_1.xml").read_text().strip() == REGULAR_TREE.strip()  # human2 has no meeting place
    ours, _ = parse_document((trees / "BTRegularNav.xml").read_text())
    ref, problems = parse_document((reference_dir / "data/socrates-hunav/behavior_trees/BTRegularNav.xml").read_text())
    assert ours is not None and ref is not None and problems == []
    assert skeleton(ours.trees["RegularNavTree"].root) == skeleton(ref.trees["RegularNavTree"].root)


def test_robot_poses_and_trajectory_match_wrapper_files(exported: Path, reference_dir: Path) -> None:
    cfg = exported / "hunav_gazebo_wrapper/config"
    ref_cfg = reference_dir / "data/socrates-gazebo-wrapper/config"
    poses = yaml.safe_load((cfg / "robot_poses.yaml").read_text())
    assert shape(poses) == shape(yaml.safe_load((ref_cfg / "robot_poses.yaml").read_text()))
    assert poses["initial_pose"] == {"x": -2.475, "y": 2.475, "yaw": 0.0}
    assert [w["position"]["x"] for w in poses["waypoints"]] == [-1.475, -0.475, -0.475]
    assert poses["waypoints"][-1]["position"]["y"] == 3.225
    traj = json.loads((cfg / "trajectory.json").read_text())
    ref = json.loads((ref_cfg / "trajectory.json").read_text())
    assert list(traj) == list(ref)
    assert traj["trajectories"]["robot"] == ["aa", "ee", "bb", "cc"]
    # every human has an interaction point entry (the wrapper indexes it); "" = never paused: human2 has none,
    # human1's tree waits for the robot itself (the wrapper's pause would hold it a second time)
    assert traj["interaction_points"] == {"human1": "", "human2": ""}
    launch = yaml.safe_load((cfg / "launch_params.yaml").read_text())
    assert set(launch) == set(yaml.safe_load((ref_cfg / "launch_params.yaml").read_text()))


def test_groot_model_and_readme(exported: Path) -> None:
    model = DET.fromstring((exported / "hunav_agent_manager/behavior_trees/TreeNodesModel.xml").read_text())
    ids = {e.get("ID") for e in model.find("TreeNodesModel")}
    assert {"GiveWaytoRobot", "RobotSays", "RegularNav", "MakeGesture"} <= ids
    readme = (exported / "README.md").read_text()
    assert "hunav_agent_manager/behavior_trees" in readme and "ros2 launch" in readme


def test_invalid_tree_writes_nothing(make_run, tmp_path: Path) -> None:
    bad = GIVE_WAY_TREE.replace("GiveWaytoRobot", "GiveWayToRobot")
    out = tmp_path / "never"
    with pytest.raises(SocnavgenError, match="GiveWayToRobot"):
        export_run(make_run(trees={"human1": bad, "human2": REGULAR_TREE}), "socrates", out)
    assert not out.exists()


def test_refuses_to_write_outside_the_folder(tmp_path: Path) -> None:
    out = tmp_path / "out"
    with pytest.raises(SocnavgenError, match="leaves"):
        write_export(out, [ExportedFile(path="ok.txt", text="x"), ExportedFile(path="../escape.txt", text="x")])
    assert not (tmp_path / "escape.txt").exists()
    assert not (out / "ok.txt").exists()  # checked before anything is written
