"""The proof's robot that plays the robot's part (export.as_target, `--robot script`): the scenario's own
criteria on what the robot does (stands at the loading door, stays back until she has crossed, stops and says
EXCUSE ME) are the robot's script, which travels with every export as robot_script.yaml for its operator; a
waypoint robot that drives through them misses them whatever the people's timing does (docs/export.md)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from socnavgen.export.as_target import SPEEDS, scaled_script, target_twin, trace_as_target
from socnavgen.run import HumanPlan, PathPlan, RunFolder
from socnavgen.run.spec import CueTrigger, RobotCue, RobotScript, ScenarioSpec
from tests.synthetic import write_location

from .export_helpers import REGULAR_TREE, build_run

CRUISE, WAIT = 0.4, 4.0  # m/s the script drives at; s its cue stands at bb
RES = 0.05
NODES = {"aa": (20, 40), "bb": (80, 40), "cc": (140, 40), "dd": (200, 40), "ee": (200, 10)}  # pixels: a 12 x 4 m hall


def _hall_run(root: Path) -> tuple[Path, tuple[float, float]]:
    """A run in an empty 12 x 4 m hall: the robot drives aa -> bb -> cc -> dd (3 m legs), its script standing WAIT s
    at bb; one person stands far off at ee. Returns the run and bb in world coordinates."""
    free = np.ones((80, 240), dtype=bool)
    free[0, :] = free[-1, :] = free[:, 0] = free[:, -1] = False
    location = write_location(root / "hall", free, NODES, [("aa", "bb"), ("bb", "cc"), ("cc", "dd"), ("dd", "ee")],
                              resolution=RES, name="hall", default_type="CORNER", schema_nodes=["CORNER"])
    plan = PathPlan(robot=["aa", "bb", "cc", "dd"], humans=[HumanPlan(name="human1", path=["ee"])])
    run = build_run(root / "run", location, plan, {"human1": REGULAR_TREE})
    cue = RobotCue(trigger=CueTrigger(when="at_node", node="bb", distance=0.3), wait=WAIT)
    RunFolder(run).write_spec(ScenarioSpec(script=RobotScript(speed=CRUISE, cues=[cue])))
    px, py = NODES["bb"]
    return run, (RES * (px + 0.5), RES * (80 - py - 0.5))


def _longest_stand_near(trace, point: tuple[float, float], reach: float = 0.6) -> float:  # noqa: ANN001
    """Seconds of the longest stretch the robot stood (below 2 cm/s) within `reach` of `point`."""
    speed = np.hypot(trace.robot[:, 3], trace.robot[:, 4])
    near = np.hypot(trace.robot[:, 0] - point[0], trace.robot[:, 1] - point[1]) <= reach
    best = run = 0
    for still in (speed < 0.02) & near:
        run = run + 1 if still else 0
        best = max(best, run)
    return best * float(trace.dt)


def test_scaled_script_scales_speeds_only() -> None:
    cues = [RobotCue(trigger=CueTrigger(when="start"), wait=2.0, say="EXCUSE ME"),
            RobotCue(trigger=CueTrigger(when="at_node", node="ee"), speed=0.3, wait=WAIT)]
    script = scaled_script(RobotScript(speed=CRUISE, cues=cues), 1.5)
    assert script.speed == pytest.approx(1.5 * CRUISE)
    assert [c.speed for c in script.cues] == [None, pytest.approx(0.45)]
    assert [(c.wait, c.say) for c in script.cues] == [(c.wait, c.say) for c in cues]
    assert scaled_script(RobotScript(speed=1.8), 1.5).speed == 2.0  # a script's highest speed


def test_the_script_robot_plays_the_robots_part(tmp_path: Path) -> None:
    """At every speed the script robot stands its cue's wait at bb and cruises at the speed's share of the script's
    speed; the careful waypoint robot of the same proof drives through bb (the check can fail)."""
    run, at = _hall_run(tmp_path)
    twin = target_twin(run, "socrates", tmp_path / "twin")
    for speed in SPEEDS:
        trace = trace_as_target(twin, speed, "script")
        assert _longest_stand_near(trace, at) >= WAIT - 0.5, speed  # its braking and start are moves
        moving = np.abs(np.diff(trace.robot[:, 0] + 1j * trace.robot[:, 1])) / trace.dt
        cruise = float(np.median(moving[moving > 0.05]))  # m/s on most of its way
        assert cruise == pytest.approx(speed * CRUISE, rel=0.05), speed
    assert _longest_stand_near(trace_as_target(twin, 1.0, "careful"), at) < 1.0
