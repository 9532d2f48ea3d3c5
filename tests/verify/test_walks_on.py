"""A stop that lasts while the robot is near, on a path that goes on, must be released before the run ends
(derive.walks_on, blame rule W1). Round 34's warehouse_26: a picker told to stop while the robot is within 4 m and
then walk on to the queue stood to the end, the robot's goal 3.3-3.9 m from her, and every criterion passed.

Here (as in test_stop_stays): the robot stands at x = 5 on y = 0, human1 walks along y = 1 toward it and stands at
x = 3.6 (1.7 m from it) from t = 6 s; her stop lasts while the robot is within 2.5 m.
"""

from __future__ import annotations

import numpy as np

from socnavgen.run.models import HumanPlan, PathPlan
from socnavgen.run.spec import Encounter, HumanPart, ScenarioSpec
from socnavgen.verify.blame import blame_criterion
from socnavgen.verify.criteria import compile_criterion
from socnavgen.verify.derive import WALKS_ON, with_implied
from socnavgen.verify.models import VerifySettings
from socnavgen.verify.signals import Signals
from socnavgen.verify.stl import monitor

from .verify_builders import build_trace

DT = 0.05
T = np.round(np.arange(0, 20.0 + 1e-9, DT), 6)


def _spec(lasts: float | None = None, trigger: str = "robot_near") -> ScenarioSpec:
    part = HumanPart(human="human1", trigger=trigger, distance=2.5, reaction="stop", lasts=lasts)
    return ScenarioSpec(encounters=[Encounter(id="e1", place="CORRIDOR", node="b", humans=[part])])


def _plan(path: list[str]) -> PathPlan:
    return PathPlan(robot=["x", "b"], humans=[HumanPlan(name="human1", path=path, interaction_point="b")])


def _walks_on(spec: ScenarioSpec, plan: PathPlan) -> list:
    return [c for c, _ in with_implied(spec, VerifySettings(), 1, plan) if c.id.startswith(WALKS_ON)]


def _signals(walk_on: float | None, robot_leaves: float | None, robot_arrives: float | None = None) -> Signals:
    """human1 stands at x = 3.6 from t = 6 s and walks on (+x, past the robot's side) at 0.6 m/s from `walk_on`;
    the robot stands at x = 5 (driving in from x = 20 at 1 m/s to arrive there at `robot_arrives`) and, from
    `robot_leaves`, drives off +x at 1 m/s."""
    x = np.minimum(0.6 * T, 3.6)
    if walk_on is not None:
        x = np.where(walk_on <= T, 3.6 + 0.6 * (T - walk_on), x)
    robot_x = np.full(len(T), 5.0)
    if robot_arrives is not None:
        robot_x = np.maximum(5.0, 5.0 + (robot_arrives - T))
    if robot_leaves is not None:
        robot_x = np.where(robot_leaves <= T, 5.0 + (T - robot_leaves), robot_x)
    return Signals(build_trace(T, np.stack([robot_x, np.zeros(len(T))], 1),
                               np.stack([x, np.ones(len(T))], 1)[:, None, :], dt=DT))


def _robustness(s: Signals) -> float:
    spec = _spec()
    c = _walks_on(spec, _plan(["a", "b", "c"]))[0]
    return monitor(compile_criterion(c, spec, VerifySettings(), 0.5, DT).formula, s).robustness


def test_a_stop_on_a_path_that_goes_on_implies_walking_on() -> None:
    found = _walks_on(_spec(), _plan(["a", "b", "c"]))
    assert [(c.kind, c.human, c.encounter) for c in found] == [("stl", "human1", "e1")]
    assert "2.5 m" in found[0].text


def test_no_such_criterion_where_it_need_not_end() -> None:
    """Their path ends where they stop; a timed stop (it ends by itself); a stop on another trigger."""
    assert _walks_on(_spec(), _plan(["a", "b"])) == []
    assert _walks_on(_spec(lasts=3.0), _plan(["a", "b", "c"])) == []
    assert _walks_on(_spec(trigger="robot_visible"), _plan(["a", "b", "c"])) == []
    assert _walks_on(_spec(), None) == []


def test_still_standing_with_the_robot_near_at_the_end_fails() -> None:
    """The robot never leaves: she stands to the end, 1.7 m from it, inside her 2.5 m, for 14 s."""
    assert _robustness(_signals(None, None)) < 0


def test_a_stop_the_run_ends_in_passes() -> None:
    """The robot arrives at 15 s (within her 2.5 m from ~13.9 s) and the run ends at 20 s: she has stood ~6 s
    while it is near, as her stop says; nothing yet says she would not walk on."""
    assert _robustness(_signals(None, None, robot_arrives=15.0)) > 0


def test_released_and_walking_on_passes() -> None:
    """The robot drives off at 9 s (beyond 2.5 m by ~10 s); she walks on at 11 s."""
    assert _robustness(_signals(11.0, 9.0)) > 0


def test_robot_gone_at_the_end_passes_even_before_she_set_off() -> None:
    """The run ends as the robot has just left her distance: her stop is over, whether or not she moved yet."""
    assert _robustness(_signals(None, 17.5)) > 0


def test_blame_is_where_the_robot_ends() -> None:
    spec = _spec()
    c = _walks_on(spec, _plan(["a", "b", "c"]))[0]
    cc = compile_criterion(c, spec, VerifySettings(), 0.5, DT)
    stage, who, reason = blame_criterion(cc, _signals(None, None), spec, _plan(["a", "b", "c"]), 30.0)
    assert (stage, who) == ("paths", None)
    assert "1.7 m away" in reason and "2.5 m" in reason and "last 10 s" in reason and "lasts" in reason
