"""Whole runs: run folders, determinism, interaction throttling, the `simulate` command, the bundled warehouse."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from socnavgen.run import HumanPlan, PathPlan, RobotGestureRule, RunFolder, ScenarioRequest
from socnavgen.sim import SimConfig, ThrottleConfig, Trace, load_policy, load_simulation
from socnavgen.sim.robot.api import WaypointsPolicy
from tests.synthetic import walled_room, write_location

from .simhelpers import REGULAR, tree_xml

RES = 0.05


def make_location(root: Path) -> Path:
    """A 20 m x 10 m walled room with a few nodes; world = pixel centre * 0.05 (origin at the lower left)."""
    w, h = 400, 200

    def px(x: float, y: float) -> tuple[float, float]:
        return x / RES - 0.5, h - y / RES - 0.5

    nodes = {"r0": (1, 5), "r1": (7, 5), "ip": (10, 5), "r3": (18, 5), "h0": (10, 9), "h2": (10, 1)}
    edges = [("r0", "r1"), ("r1", "ip"), ("ip", "r3"), ("h0", "ip"), ("ip", "h2")]
    return write_location(root, walled_room(h, w), {k: px(*v) for k, v in nodes.items()}, edges, resolution=RES,
                          name="room", description="an empty room", default_type="ROOM",
                          default_edge="PASSAGEWAY", image="map.png")


def make_run(tmp_path: Path, tree: str = tree_xml(REGULAR), interaction: str | None = "ip",
             gestures: list[RobotGestureRule] | None = None, location: Path | None = None,
             robot: list[str] | None = None, human_path: list[str] | None = None) -> Path:
    loc = location or make_location(tmp_path / "room")
    run = RunFolder(tmp_path / "run")
    run.root.mkdir()
    run.write_request(ScenarioRequest(location=str(loc), context="test", task="cross the room"))
    run.write_paths(PathPlan(robot=robot or ["r0", "r1", "ip", "r3"],
                             humans=[HumanPlan(name="human1", path=human_path or ["h0", "ip", "h2"],
                                               interaction_point=interaction)],
                             robot_gestures=gestures or []))
    run.write_behavior("human1", tree)
    return run.root


def test_same_seed_same_trace_other_seed_other_spawn(tmp_path):
    run = make_run(tmp_path)
    a = load_simulation(run, WaypointsPolicy(), SimConfig(seed=3, timeout=20)).run()
    b = load_simulation(run, WaypointsPolicy(), SimConfig(seed=3, timeout=20)).run()
    for field in ("t", "robot", "humans", "action", "succeeded", "human_gesture", "robot_gesture", "behavior_state"):
        assert np.array_equal(getattr(a, field), getattr(b, field)), field
    c = load_simulation(run, WaypointsPolicy(), SimConfig(seed=4, timeout=20)).run()
    assert not np.array_equal(a.humans[0], c.humans[0])
    # spawn within 1.5 m of the first node (10, 9), facing the next one
    assert abs(complex(*a.humans[0, 0, :2]) - (10 + 9j)) <= 1.5


def test_interaction_throttle_paces_the_human_to_meet_at_the_node(tmp_path):
    run = make_run(tmp_path)
    held = load_simulation(run, WaypointsPolicy(), SimConfig(timeout=40)).run()
    free = load_simulation(run, WaypointsPolicy(), SimConfig(timeout=40), ThrottleConfig(enabled=False)).run()
    at4 = int(4.0 / held.dt)
    assert np.hypot(*(held.humans[at4, 0, :2] - held.humans[0, 0, :2])) < 1.0  # held back / slowed down
    assert np.hypot(*(free.humans[at4, 0, :2] - free.humans[0, 0, :2])) > 2.0

    def meeting_offset(trace) -> float:  # noqa: ANN001
        robot = trace.robot[:, 0] + 1j * trace.robot[:, 1]
        person = trace.humans[:, 0, 0] + 1j * trace.humans[:, 0, 1]
        close = np.abs(robot - person) <= 2.0
        return float(np.abs((robot + person)[close] / 2 - (10 + 5j)).min()) if close.any() else np.inf

    assert meeting_offset(held) <= 1.0  # they meet at the interaction node
    assert meeting_offset(free) > 1.0  # ... which they do not without pacing


def test_simulate_command_writes_the_trace(tmp_path):
    from socnavgen.cli import app

    rules = [RobotGestureRule(gesture=4, when="near_human", distance=3.0, duration=2.0)]
    run = make_run(tmp_path, gestures=rules)
    result = CliRunner().invoke(app, ["simulate", str(run), "--timeout", "40", "--seed", "1"])
    assert result.exit_code == 0, result.output
    trace = Trace.load(run / "sim" / "trace.npz")
    assert trace.end_reason == "robot_goal" and trace.steps > 100
    assert trace.human_names == ["human1"] and trace.meta["interaction_nodes"] == {"human1": "ip"}
    assert (trace.robot_gesture == 4).any()  # scripted speech when near the human
    assert "robot_goal" in result.output


def test_simulate_plots_unless_told_not_to(tmp_path):
    from socnavgen.cli import app

    run = make_run(tmp_path)
    result = CliRunner().invoke(app, ["simulate", str(run), "--timeout", "5", "--no-plot"])
    assert result.exit_code == 0, result.output
    written = {p.name for p in (run / "sim").iterdir()}
    assert {"trace.npz", "metrics.json"} <= written and "trajectories.png" not in written
    result = CliRunner().invoke(app, ["simulate", str(run), "--timeout", "5"])
    assert result.exit_code == 0, result.output
    assert (run / "sim" / "trajectories.png").stat().st_size > 0


def test_simulate_reports_a_broken_tree_with_its_line(tmp_path):
    from socnavgen.cli import app

    run = make_run(tmp_path, tree=tree_xml('<Sequence>\n<Dance agent_id="{id}"/>\n</Sequence>'))
    result = CliRunner().invoke(app, ["simulate", str(run)])
    assert result.exit_code != 0
    assert "behaviors/human1.xml:5: unknown node 'Dance'" in str(result.exception)


def test_custom_policy_from_a_file(tmp_path):
    policy_file = tmp_path / "mypolicy.py"
    policy_file.write_text("from socnavgen.sim import RobotAction\n"
                           "class Straight:\n"
                           "    def act(self, obs):\n"
                           "        d = obs.waypoints[-1] - obs.position\n"
                           "        return RobotAction(*(0.5 * d / max(1e-9, (d @ d) ** 0.5)), gesture=5)\n")
    policy = load_policy(f"{policy_file}:Straight")
    run = make_run(tmp_path)
    trace = load_simulation(run, policy, SimConfig(timeout=60)).run()
    assert trace.end_reason == "robot_goal"
    assert (trace.robot_gesture[1:] == 5).all()


def test_warehouse_blind_corner_run(tmp_path, warehouse_dir):
    if not (warehouse_dir / "location.yaml").is_file():
        pytest.fail("examples/locations/warehouse is not in this checkout")
    tree = tree_xml('<Fallback><Sequence><IsRobotVisible agent_id="{id}" distance="4"/>'
                    '<Inverter><TimeExpiredCondition seconds="3" ts="{dt}" only_once="true"/></Inverter>'
                    f'<LookAtRobot agent_id="{{id}}"/></Sequence>{REGULAR}</Fallback>')
    run = make_run(tmp_path, tree=tree, location=warehouse_dir, robot=["up", "co", "54", "f7", "6r"],
                   human_path=["6r", "f7", "54", "co"], interaction="f7")
    # the default robot: in this 2.3 m corridor a person cannot pass a robot that stays in its middle (a plain
    # waypoint robot drives on into them and both stand); the scripted robot pulls aside and the person walks past
    sim = load_simulation(run, load_policy("scripted"), SimConfig(timeout=120))
    trace = sim.run()
    assert trace.end_reason == "robot_goal"
    assert np.isfinite(trace.humans).all() and np.isfinite(trace.robot).all()
    looked = trace.executed(0, "LookAtRobot")
    assert 2.5 <= looked.sum() * trace.dt <= 3.1  # stopped to look for its 3 s, then walked on
    first_look = int(np.argmax(looked))
    f7 = np.array([5.025, 3.375])
    # the encounter happened at the blind corner: both near it when the person first sees the robot (the person,
    # let out at its own speed, walks ~2x faster than the robot, so it is ~2x farther from the corner then)
    assert np.hypot(*(trace.robot[first_look, :2] - f7)) < 2.0
    assert np.hypot(*(trace.humans[first_look, 0, :2] - f7)) < 3.5
    assert trace.meta["held_seconds"]["human1"] > 5.0  # thanks to the throttle
    clearance = sim.world.clearance_at(trace.humans[:, 0, 0] + 1j * trace.humans[:, 0, 1])
    assert clearance.min() > 0.1  # never inside a wall
    trace.save(tmp_path / "t.npz")
    assert np.array_equal(Trace.load(tmp_path / "t.npz").humans, trace.humans)


def test_socrates_release_rule_lets_the_human_go_when_the_robot_targets_the_node(tmp_path):
    run = make_run(tmp_path)
    trace = load_simulation(run, WaypointsPolicy(), SimConfig(timeout=40), ThrottleConfig(rule="socrates")).run()
    speed = np.hypot(trace.humans[:, 0, 3], trace.humans[:, 0, 4])
    start = int(np.argmax(speed > 0.1))
    # released once the robot came within 1.5 m of r1 (7, 5): its current waypoint is then the node
    assert np.hypot(trace.robot[start, 0] - 7.0, trace.robot[start, 1] - 5.0) <= 1.5 + 0.05
    assert trace.meta["held_seconds"]["human1"] > 5.0


def test_human_without_a_tree_file_walks_the_regular_tree(tmp_path):
    run = make_run(tmp_path)
    (run / "behaviors" / "human1.xml").unlink()
    trace = load_simulation(run, WaypointsPolicy(), SimConfig(timeout=30), ThrottleConfig(enabled=False)).run()
    assert trace.meta["default_trees"] == ["human1"]
    assert trace.executed(0, "RegularNav").any()


def test_robot_says_at_a_node(tmp_path):
    rules = [RobotGestureRule(gesture=2, when="at_node", node="ip", duration=0.5)]
    run = make_run(tmp_path, gestures=rules)
    trace = load_simulation(run, WaypointsPolicy(), SimConfig(timeout=40)).run()
    saying = trace.robot_gesture == 2
    assert saying.any()
    near = np.hypot(trace.robot[saying, 0] - 10.0, trace.robot[saying, 1] - 5.0)
    assert near.max() <= 1.0 + 0.5 * 0.6 + 0.05  # within 1 m of the node, plus the 0.5 s hold


def test_broken_paths_are_all_reported(tmp_path):
    from socnavgen.errors import ValidationFailed

    run = make_run(tmp_path, robot=["r0", "zz", "r3"], human_path=["h0", "qq"])
    with pytest.raises(ValidationFailed) as err:
        load_simulation(run, WaypointsPolicy())
    message = err.value.message
    assert "robot path: node 'zz' is not in the scene graph" in message
    assert "human1's path: node 'qq' is not in the scene graph" in message


def test_simulate_run_saves_and_returns_the_trace(tmp_path):
    from socnavgen.sim import simulate_run

    run = make_run(tmp_path)
    trace = simulate_run(run, robot="sfm", timeout=60, seed=2)
    assert trace.meta["robot_plugin"] == "sfm" and trace.end_reason == "robot_goal"
    assert np.array_equal(Trace.load(run / "sim" / "trace.npz").robot, trace.robot)
