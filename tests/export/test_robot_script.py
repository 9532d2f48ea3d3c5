"""The robot's part travels with the export: robot_script.yaml in every export, played back from poses by the
simulator's own script code (ScriptPlayer), and the fork's ROS node that publishes it - tested without ROS."""

from __future__ import annotations

import importlib.util
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
import yaml

from socnavgen.errors import InputFileError
from socnavgen.export import export_run
from socnavgen.export.robot_script import ScriptPlayer, load_script, script_file, script_yaml
from socnavgen.export.scene import build_scene
from socnavgen.run import HumanPlan, PathPlan, RunFolder
from socnavgen.run.models import RobotGestureRule
from socnavgen.run.spec import CueTrigger, Encounter, HumanPart, RobotCue, RobotScript, ScenarioSpec
from socnavgen.sim import simulate_run
from tests.synthetic import walled_room, write_location

from .export_helpers import REGULAR_TREE, build_run

NODES = {"w": (30, 100), "x": (150, 100), "e": (270, 100), "s": (150, 190), "n": (150, 10)}
EDGES = [("w", "x"), ("x", "e"), ("s", "x"), ("x", "n")]
SCRIPT = RobotScript(speed=0.6, cues=[
    RobotCue(trigger=CueTrigger(when="start"), say="WAIT", hold=1.0),
    RobotCue(trigger=CueTrigger(when="after", seconds=4.0), say="PROCEED", hold=2.0),
    RobotCue(trigger=CueTrigger(when="at_encounter", encounter="e1", distance=3.0), say="FOLLOW ME", hold=2.0),
    RobotCue(trigger=CueTrigger(when="human_within", human="human2", distance=2.5), say="ACKNOWLEDGED", hold=1.5),
    RobotCue(trigger=CueTrigger(when="blocked", distance=1.5), say="EXCUSE ME", hold=3.0, wait_until_clear=True)])
RULES = [RobotGestureRule(gesture=3, when="near_human", distance=4.0, duration=1.0)]


@pytest.fixture(scope="module")
def scripted_run(tmp_path_factory) -> Path:  # noqa: ANN001
    """Two people cross the robot's way; a script with every kind of cue, and a gesture rule."""
    root = tmp_path_factory.mktemp("script")
    hall = write_location(root / "hall", walled_room(200, 300, wall=2), NODES, EDGES, resolution=0.1, name="hall")
    plan = PathPlan(robot=["w", "x", "e"], robot_gestures=RULES, humans=[
        HumanPlan(name="human1", path=["s", "x", "n"], interaction_point="x"),
        HumanPlan(name="human2", path=["e", "x", "w"], interaction_point="x")])
    run = build_run(root / "run", hall, plan, {"human1": REGULAR_TREE, "human2": REGULAR_TREE})
    RunFolder(run).write_spec(ScenarioSpec(script=SCRIPT, encounters=[Encounter(
        id="e1", place="NODE", node="x", humans=[HumanPart(human="human1"), HumanPart(human="human2")])]))
    return run


def replay(player: ScriptPlayer, trace) -> np.ndarray:  # noqa: ANN001 - sim.trace.Trace
    """The gesture the player makes at each row of the trace (the engine adds dt each step, as here)."""
    got, t = [0], 0.0
    for k in range(len(trace.robot) - 1):
        x, y, yaw = trace.robot[k, :3]
        people = [(float(h[0]), float(h[1])) for h in trace.humans[k]]
        got.append(player.gesture(t, (x, y, yaw), people, [int(g) for g in trace.human_gesture[k + 1]]))
        t += 0.05
    return np.array(got)


# steps a change may be seen apart: the engine reads its gesture rules after the step's move, its cues before
# (one step); and a `blocked` cue looks ahead along the built-in robot's steering, the player (poses only)
# along its yaw. Since the robot waits to the right of its way in a timed wait (robot.wait_spot.wait_aside, 2026-11-26
# s7) it turns on the spot near x (yaw 0.16 -> -2.7 rad while standing, off its steering): human1, 1.2 m south of
# it, enters the player's cone 14 steps (0.7 s) before the engine's EXCUSE ME at t=21.9 s and leaves it 10 steps
# before the engine's cue ends. A cue fired elsewhere (the check below that must fail) is seconds apart.
APART = 15


def same_within_a_step(got: np.ndarray, want: np.ndarray) -> bool:
    """Equal, but for a change seen up to APART steps apart (see APART)."""
    for k in np.flatnonzero(got != want):
        near = slice(max(k - APART, 0), k + APART + 1)
        if want[k] not in got[near] or got[k] not in want[near]:
            return False
    return True


def test_the_script_travels_with_every_export(scripted_run: Path, tmp_path: Path) -> None:
    for fmt, where in (("socrates", "hunav_gazebo_wrapper/config/robot_script.yaml"),
                       ("hunav2", "robot/robot_script.yaml"), ("hunav1", "robot/robot_script.yaml")):
        out = tmp_path / fmt
        export_run(scripted_run, fmt, out)
        data = yaml.safe_load((out / where).read_text())
        assert [c["say"] for c in data["cues"]] == ["WAIT", "PROCEED", "FOLLOW ME", "ACKNOWLEDGED", "EXCUSE ME"]
        assert [c.get("gesture") for c in data["cues"]] == [1, 2, 5, 3, 4]  # /robot_gesture codes
        assert data["encounters"]["e1"] == {"node": "x", "x": 15.05, "y": 9.95}  # world coordinates
        assert data["rules"][0]["say"] == "ACKNOWLEDGED" and data["route"][0]["node"] == "w"
        assert "robot_script.yaml" in (out / "README.md").read_text()
    assert (tmp_path / "socrates/hunav_gazebo_wrapper/scripts/socnavgen_robot_gestures.py").is_file()


def test_the_file_reads_back_to_the_same_script(scripted_run: Path, tmp_path: Path) -> None:
    scene, _ = build_scene(scripted_run)
    path = tmp_path / "robot_script.yaml"
    path.write_text(script_yaml(scene))
    assert load_script(path) == script_file(scene)


@pytest.mark.parametrize("text, what", [
    ("- 1\n- 2\n", "must be a mapping"),
    ("cues: [{trigger: {when: teleport}}]\n", "cues.0.trigger.when"),
    ("speed: -1\n", "speed"),
    ("cues: [{trigger: {when: blocked}, shout: x}]\n", "cues.0.shout"),
])
def test_a_broken_script_file_is_one_message(tmp_path: Path, text: str, what: str) -> None:
    path = tmp_path / "robot_script.yaml"
    path.write_text(text)
    with pytest.raises(InputFileError) as err:
        load_script(path)
    assert what in str(err.value) and "robot_script.yaml" in str(err.value)


def test_the_player_says_what_the_simulated_robot_said(scripted_run: Path, tmp_path: Path) -> None:
    scene, _ = build_scene(scripted_run)
    path = tmp_path / "robot_script.yaml"
    path.write_text(script_yaml(scene))
    trace = simulate_run(scripted_run, save=False)  # the scripted robot plays the script
    want = np.asarray(trace.robot_gesture)
    assert {1, 2, 3, 5} <= set(want.tolist())  # the cues and the rule fired
    assert same_within_a_step(replay(ScriptPlayer(load_script(path)), trace), want)
    # the check can fail: the same script with another encounter distance says FOLLOW ME elsewhere
    other = load_script(path)
    other.cues[2].trigger.distance = 1.0
    assert not same_within_a_step(replay(ScriptPlayer(other), trace), want)


def _node_module(path: Path):  # noqa: ANN202 - the exported node file, imported without ROS
    spec = importlib.util.spec_from_file_location("socnavgen_robot_gestures_under_test", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _pose(x: float, y: float) -> SimpleNamespace:
    return SimpleNamespace(position=SimpleNamespace(x=x, y=y))


def test_the_fork_node_publishes_each_change_of_gesture(scripted_run: Path, tmp_path: Path) -> None:
    out = tmp_path / "export"
    export_run(scripted_run, "socrates", out)
    node = _node_module(out / "hunav_gazebo_wrapper/scripts/socnavgen_robot_gestures.py")
    state = node.GestureState(ScriptPlayer(load_script(out / "hunav_gazebo_wrapper/config/robot_script.yaml")))
    trace = simulate_run(scripted_run, save=False)
    published = []
    stamp = SimpleNamespace(sec=100, nanosec=0)  # the node counts time from its first message
    assert state.on_humans(SimpleNamespace(header=SimpleNamespace(stamp=stamp), agents=[])) is None  # no robot yet
    for k in range(len(trace.robot) - 1):
        x, y, yaw = trace.robot[k, :3]
        state.on_robot(SimpleNamespace(position=_pose(x, y), yaw=yaw))
        t = 100 + 0.05 * k
        agents = [SimpleNamespace(position=_pose(h[0], h[1]), gesture=int(g))
                  for h, g in zip(trace.humans[k], trace.human_gesture[k + 1], strict=True)]
        code = state.on_humans(SimpleNamespace(header=SimpleNamespace(stamp=SimpleNamespace(
            sec=int(t), nanosec=int(round((t - int(t)) * 1e9)))), agents=agents))
        if code is not None:
            published.append(code)
    changes = [int(g) for k, g in enumerate(trace.robot_gesture) if k and g != trace.robot_gesture[k - 1]]
    assert published == changes and len(published) >= 4
    with pytest.raises(SystemExit, match="usage"):
        node.main([])


def test_an_at_node_cue_travels_with_its_node_and_plays_where_it_fired(scripted_run: Path, tmp_path: Path) -> None:
    """A cue on a node of the robot's route (no encounter there): robot_script.yaml carries the node's world point,
    and the player says it where the simulated robot did."""
    import shutil

    shutil.copytree(scripted_run.parent, tmp_path / "copy")  # the run and its location beside it
    run = tmp_path / "copy" / scripted_run.name
    at_node = RobotCue(trigger=CueTrigger(when="at_node", node="e", distance=4.0), say="ACKNOWLEDGED", hold=1.0)
    RunFolder(run).write_spec(ScenarioSpec(script=RobotScript(speed=0.6, cues=[at_node]), encounters=[Encounter(
        id="e1", place="NODE", node="x", humans=[HumanPart(human="human1"), HumanPart(human="human2")])]))
    scene, _ = build_scene(run)
    path = tmp_path / "robot_script.yaml"
    path.write_text(script_yaml(scene))
    data = yaml.safe_load(path.read_text())
    assert data["cues"][0]["trigger"]["node"] == "e" and data["nodes"]["e"]["node"] == "e"
    trace = simulate_run(run, save=False)
    want = np.asarray(trace.robot_gesture)
    assert 3 in set(want.tolist())  # said on the way to e
    assert same_within_a_step(replay(ScriptPlayer(load_script(path)), trace), want)
