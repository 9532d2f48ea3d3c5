"""`simulate --bag`: the episode as a rosbag2 folder with MCAP storage, holding what Foxglove and RViz show
(robot odometry and tf, people as hunav_msgs, the map, scene graph, paths and agents as markers), every
message carrying its definition, the map placed by the location's own transform."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from rosbags.interfaces import QosDurability
from rosbags.rosbag2 import Reader

from socnavgen.bag import write_bag
from socnavgen.bag.types import typestore
from socnavgen.errors import InputFileError
from socnavgen.location import load_location
from socnavgen.sim.trace import Trace

from .export_helpers import HEIGHT, ORIGIN, RES, WIDTH, default_plan, expected_world


def small_trace(steps: int = 5) -> Trace:
    t = np.arange(steps) * 0.1
    robot = np.zeros((steps, 6))
    robot[:, 0], robot[:, 1], robot[:, 2], robot[:, 3] = -2.0 + 0.5 * t, 2.5, math.pi / 2, 0.5
    humans = np.zeros((steps, 2, 6))
    humans[:, 0, :2], humans[:, 1, :2] = (-1.0, 2.0), (0.0, 2.2)
    gesture = np.zeros(steps, np.int8)
    gesture[2:] = 4
    return Trace(dt=0.1, t=t, robot=robot, humans=humans, human_names=["human1", "human2"], group_ids=[-1, -1],
                 human_radii=np.full(2, 0.4), robot_radius=0.35, node_names=["RegularNav"],
                 action=np.zeros((steps, 2), np.int16), succeeded=np.ones((steps, 2), np.int64),
                 human_gesture=np.zeros((steps, 2), np.int8), robot_gesture=gesture,
                 behavior_state=np.zeros((steps, 2), np.int8), robot_goal=(0.0, 2.5),
                 robot_waypoints=[(-2.0, 2.5), (0.0, 2.5)], end_reason="robot_goal", meta={"robot_goal_radius": 0.2})


def _messages(bag: Path) -> dict[str, list]:
    store = typestore("socrates")
    out: dict[str, list] = {}
    with Reader(bag) as reader:
        for conn, _, raw in reader.messages():
            out.setdefault(conn.topic, []).append(store.deserialize_cdr(raw, conn.msgtype))
    return out


def test_the_bag_holds_every_topic_with_its_definition(tmp_path: Path, tiny_location: Path) -> None:
    location = load_location(tiny_location)
    mcap = write_bag(small_trace(), tmp_path / "episode", location=location, plan=default_plan())
    assert mcap == tmp_path / "episode" / "episode.mcap" and (tmp_path / "episode" / "metadata.yaml").is_file()
    with Reader(mcap) as reader:  # the bare .mcap opens too (Foxglove reads this file)
        kinds = {c.topic: c.msgtype for c in reader.connections}
        assert all(c.msgdef.data for c in reader.connections)  # schemas embedded: viewers decode hunav_msgs
        latched = {c.topic for c in reader.connections
                   if any(q.durability == QosDurability.TRANSIENT_LOCAL for q in c.ext.offered_qos_profiles)}
    assert kinds == {"/socnavgen/meta": "std_msgs/msg/String", "/goal_pose": "geometry_msgs/msg/PoseStamped",
                     "/map": "nav_msgs/msg/OccupancyGrid", "/scene_graph": "visualization_msgs/msg/MarkerArray",
                     "/planned_paths": "visualization_msgs/msg/MarkerArray", "/human_states": "hunav_msgs/msg/Agents",
                     "/robot_states": "hunav_msgs/msg/Agent", "/robot_gesture": "std_msgs/msg/UInt32",
                     "/odom": "nav_msgs/msg/Odometry", "/tf": "tf2_msgs/msg/TFMessage",
                     "/agent_markers": "visualization_msgs/msg/MarkerArray", "/socnavgen/bt": "std_msgs/msg/String"}
    assert {"/map", "/scene_graph", "/planned_paths", "/socnavgen/meta"} <= latched
    msgs = _messages(tmp_path / "episode")
    assert len(msgs["/human_states"]) == len(msgs["/odom"]) == len(msgs["/tf"]) == 5
    assert [m.data for m in msgs["/robot_gesture"]] == [0, 4]  # published when it changes
    humans = msgs["/human_states"][3]
    assert [(a.id, a.name, a.behavior, a.type) for a in humans.agents] == [(0, "human1", 7, 1), (1, "human2", 8, 1)]
    assert humans.header.stamp.sec == 0 and humans.header.stamp.nanosec == 300_000_000
    odom = msgs["/odom"][0]  # robot heading north at 0.5 m/s along +x: in its own frame that is sideways
    assert odom.child_frame_id == "base_link" and math.isclose(odom.twist.twist.linear.y, -0.5, abs_tol=1e-12)
    assert msgs["/tf"][0].transforms[0].transform.translation.x == -2.0
    nodes = [m for m in msgs["/scene_graph"][0].markers if m.ns == "scene_graph_labels"]
    assert sorted(m.text.split()[0] for m in nodes) == ["aa", "bb", "cc", "dd", "ee"]
    label = next(m for m in nodes if m.text.startswith("ee"))
    assert (label.pose.position.x, label.pose.position.y) == pytest.approx(expected_world("ee"))
    paths = {m.ns for m in msgs["/planned_paths"][0].markers}
    assert paths == {"robot_path", "human_paths", "interaction_points"}
    said = [m.text for m in msgs["/agent_markers"][4].markers if m.ns == "robot_label"]
    assert said == ["robot: EXCUSE ME"]


def test_the_map_is_placed_by_the_location_transform(tmp_path: Path, tiny_location: Path) -> None:
    location = load_location(tiny_location)
    write_bag(small_trace(), tmp_path / "episode", location=location)
    grid = _messages(tmp_path / "episode")["/map"][0]
    assert (grid.info.width, grid.info.height) == (WIDTH, HEIGHT)
    assert grid.info.resolution == pytest.approx(RES)
    assert (grid.info.origin.position.x, grid.info.origin.position.y) == pytest.approx(ORIGIN)  # map_server's
    cells = np.asarray(grid.data).reshape(HEIGHT, WIDTH)
    assert (cells[0] == 100).all() and (cells[-1] == 100).all() and (cells[1:-1, 1:-1] == 0).all()
    # row r of the grid is image row HEIGHT-1-r: the free interior starts one cell above the origin
    x, y = expected_world("ee")
    col = int((x - ORIGIN[0]) / RES)
    row = int((y - ORIGIN[1]) / RES)
    assert cells[row, col] == 0 and location.occupancy.occupied[HEIGHT - 1 - row, col] == np.False_


def test_an_existing_bag_is_never_overwritten_and_a_failed_write_leaves_nothing(tmp_path: Path,
                                                                               monkeypatch) -> None:  # noqa: ANN001
    (tmp_path / "episode").mkdir()
    (tmp_path / "episode" / "mine.txt").write_text("keep")
    with pytest.raises(InputFileError, match="already exists"):
        write_bag(small_trace(), tmp_path / "episode")
    assert (tmp_path / "episode" / "mine.txt").read_text() == "keep"
    import socnavgen.bag.writer as writer

    def broken(*args, **kwargs):  # noqa: ANN002, ANN003, ANN202
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(writer, "_step", broken)
    with pytest.raises(OSError):
        write_bag(small_trace(), tmp_path / "other")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["episode"]
