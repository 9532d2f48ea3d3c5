"""A give-way that ran its time without effect is the place's fault (stage 1's), not the tree's (rule R7; round 29, home_21: a
father met where the robot turned off, in a 1.7 m passage; his tree ran GiveWaytoRobot 10 s and three re-asks of the
tree were told its gate "never ran its reaction"). A give-way the tree cut short is still the tree's."""

from __future__ import annotations

import numpy as np

from socnavgen.run.models import HumanPlan, PathPlan
from socnavgen.run.spec import Criterion, Encounter, HumanPart, ScenarioSpec
from socnavgen.verify.blame import blame_criterion
from socnavgen.verify.blame_tree import blame_tree_check, tree_activity
from socnavgen.verify.criteria import compile_criterion
from socnavgen.verify.models import VerifySettings
from socnavgen.verify.signals import Signals

from .verify_builders import build_trace

T = np.arange(0, 30.0 + 1e-9, 0.5)
NODES = {"a": (0.0, 3.0), "m": (4.0, 3.0), "g": (12.0, 3.0)}


def _trace(give_way: tuple[float, float], fired: list[str] | None = None) -> object:
    """The robot drives east from a toward g and stands 1.2 m short of someone who stands in its way at (6, 3)
    the whole run, running GiveWaytoRobot during `give_way` (t from, to) and RegularNav otherwise."""
    robot = np.stack([np.interp(T, [0.0, 8.0], [0.0, 4.8]), np.full_like(T, 3.0)], 1)
    actions = {(k, 0): "GiveWaytoRobot" if give_way[0] <= t < give_way[1] else "RegularNav" for k, t in enumerate(T)}
    trace = build_trace(T, robot, np.tile([(6.0, 3.0)], (len(T), 1))[:, None], goal=NODES["g"], actions=actions,
                        fired={(k, 0): fired for k in range(len(T))} if fired else None)
    trace.robot_waypoints = [NODES["a"], NODES["g"]]
    return trace


def _spec() -> ScenarioSpec:
    return ScenarioSpec(encounters=[Encounter(id="e1", place="CORRIDOR", node="m", within=3.0, humans=[
        HumanPart(human="human1", trigger="robot_near", distance=3.0, reaction="give_way")])])


def _blame(trace: object) -> tuple[str, str | None, str]:
    spec = _spec()
    s = Signals(trace, goal_radius=0.3, places={f"node_{n}": p for n, p in NODES.items()})
    criterion = Criterion(id="c", kind="gives_way", human="human1", encounter="e1", distance=3.0, text="t")
    cc = compile_criterion(criterion, spec, VerifySettings(), 0.3)
    plan = PathPlan(robot=["a", "m", "g"], humans=[HumanPlan(name="human1", path=["m", "g"])])
    return blame_criterion(cc, s, spec, plan, 10.0)


def test_a_give_way_that_ran_its_time_without_getting_aside_is_the_places() -> None:
    blame, who, reason = _blame(_trace((4.0, 30.0)))  # GiveWaytoRobot from 4 s on, still in the way (near: within 3.5 m)
    assert (blame, who) == ("spec", None), reason
    assert "ran GiveWaytoRobot 25.5 s at once from t=4.5 s" in reason and "no room to step aside" in reason
    blame, who, reason = blame_tree_check("GiveWaytoRobot", None, "human1", Signals(_trace((4.0, 30.0))), False,
                                          ran_at=4.0)
    assert (blame, who) == ("spec", None) and "no room to step aside" in reason


def test_a_give_way_cut_short_is_still_the_trees() -> None:
    blame, who, reason = _blame(_trace((4.0, 5.5)))  # 1.5 s of it, then walking on
    assert (blame, who) == ("behaviors", "human1"), reason
    blame, who, reason = blame_tree_check("GiveWaytoRobot", None, "human1", Signals(_trace((4.0, 5.5))), False,
                                          ran_at=4.0)
    assert (blame, who) == ("behaviors", "human1") and "do not cut it short" in reason


def test_the_vetoed_gate_hint_only_when_the_reaction_never_ran() -> None:
    s = Signals(_trace((4.0, 30.0), fired=["IsRobotNearby", "RobotSays"]))  # two gates that always held together
    near = s.get("dist_human1") <= 3.0
    assert "never ran its reaction" in tree_activity(s, "human1", near, 3.0)
    assert "never ran its reaction" not in tree_activity(s, "human1", near, 3.0, reaction="give_way")
