"""The strict rules that need their own geometry: walkable distance through a door, a deadlock behind someone
standing at its own goal beside the route (the paths, never that human), a place the map cannot offer (the
spec), and two encounters that must each have their own meeting."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from socnavgen.run.models import HumanPlan, PathPlan
from socnavgen.run.spec import Criterion, Encounter, HumanPart, ScenarioSpec
from socnavgen.sim.world import empty_room
from socnavgen.sim.world.walkable import WalkableDistance
from socnavgen.verify import verify_trace
from tests.synthetic import walled_room, write_location

from .corpus import base_scene, base_spec, build, make_corner_location, write_case_run
from .verify_builders import REGULAR_XML, build_trace, write_run


def test_walkable_distance_goes_through_the_door() -> None:
    """A 10 m x 6 m room split by a wall at x = 5 with a 1 m door at y 4.5-5.5: from (4, 1) to (6, 1) is 2 m
    straight, about 2 x sqrt(1 + 4^2) = 8.2 m through the door; in sight it is the straight distance."""
    world = empty_room(10.0, 6.0, walls=[(4.95, 0.0, 5.05, 4.5), (4.95, 5.5, 5.05, 6.0)])
    ways = WalkableDistance(world)
    a = np.array([4 + 1j, 4 + 1j, 1 + 5j])
    b = np.array([6 + 1j, 3 + 2j, 9 + 5j])
    got = ways.between(a, b)
    assert got[1] == pytest.approx(abs(b[1] - a[1]))  # in sight: straight
    assert got[2] == pytest.approx(8.0)  # straight through the open door
    assert 8.2 <= got[0] <= 8.2 * 1.09  # around the wall: 8-connected, at most ~8 % long
    assert len(ways.grid._fields) == 1  # one field for the one hidden pair
    assert WalkableDistance.of(world) is WalkableDistance.of(world)


def _trace(robot_x: list[tuple[float, float]], human: list[tuple[float, float, float]], t_end: float = 20.0):  # noqa: ANN202
    t = np.arange(0, t_end + 1e-9, 0.5)
    rx = np.interp(t, [k[0] for k in robot_x], [k[1] for k in robot_x])
    hx = np.interp(t, [k[0] for k in human], [k[1] for k in human])
    hy = np.interp(t, [k[0] for k in human], [k[2] for k in human])
    return t, np.stack([rx, np.full_like(t, 3.0)], 1), np.stack([hx, hy], 1)[:, None]


@pytest.mark.parametrize(("goal_y", "blame"), [(3.8, ("paths", None)), (3.3, ("behaviors", "human1"))])
def test_a_deadlock_behind_someone_at_its_own_goal_beside_the_route_is_the_paths(
        tmp_path: Path, goal_y: float, blame: tuple[str, str | None]) -> None:
    """The robot stops at x = 4 and stays, human1 stands at its own goal g (5, goal_y): 0.8 m beside the route
    (the robot's body could pass, 0.75 m) it is not its tree's fault; 0.3 m beside it (on the route) it is."""
    free = walled_room(120, 200)
    loc = write_location(tmp_path / "room", free, {"a": (20, 59.5), "b": (180, 59.5), "g": (100, 119.5 - goal_y * 20),
                                                   "s": (100, 15)}, [("a", "b"), ("s", "g")])
    plan = PathPlan(robot=["a", "b"], humans=[HumanPlan(name="human1", path=["s", "g"])])
    run = write_run(tmp_path / "run", loc, plan, {"human1": REGULAR_XML})
    from socnavgen.run.folder import RunFolder

    RunFolder(run).write_spec(ScenarioSpec())
    t, robot, human = _trace([(0, 1.025), (5, 4.0), (20, 4.0)], [(0, 5.025, goal_y), (20, 5.025, goal_y)])
    trace = build_trace(t, robot, human, goal=(9.025, 3.0))
    trace.robot_waypoints = [(1.025, 3.0), (9.025, 3.0)]
    report = verify_trace(run, trace)
    dead = next(f for f in report.findings if f.kind == "no_deadlock")
    assert not dead.passed and (dead.blame, dead.blame_human) == blame, dead.blame_reason
    if blame[0] == "paths":
        assert "its own goal (g)" in dead.blame_reason


def test_a_place_this_map_does_not_have_is_the_specs(tmp_path: Path) -> None:
    loc = make_corner_location(tmp_path / "corner")
    spec = base_spec()
    far = [(0.0, 1.975, 1.525), (3.0, 3.775, 1.525), (8.5, 3.775, 1.525), (18.1, 10.975, 1.525), (20.0, 10.975, 1.525)]
    scene = base_scene()
    scene.robot = far  # never meets human1 at the corner
    for place, words in (("KITCHEN", "this map has no KITCHEN node"),):
        bad = spec.model_copy(update={"encounters": [spec.encounters[0].model_copy(update={"place": place}),
                                                     spec.encounters[1]]})
        report = verify_trace(write_case_run(tmp_path / place, loc, bad), build(scene))
        meet = next(f for f in report.findings if f.criterion == "c1")
        assert not meet.passed and meet.blame == "spec" and words in meet.blame_reason, meet.blame_reason
    report = verify_trace(write_case_run(tmp_path / "ok", loc, spec), build(scene))
    assert next(f for f in report.findings if f.criterion == "c1").blame == "paths"  # a real place: the paths


@pytest.mark.parametrize("comes_back", [True, False])
def test_two_encounters_never_share_one_meeting(tmp_path: Path, comes_back: bool) -> None:
    """human1 takes part in two encounters at b2; the robot drives a1 -> c3 -> a1 past it. Met on the way
    there and again on the way back: both pass; met only on the way there: the second fails (paths)."""
    from .verify_builders import make_location

    loc = make_location(tmp_path / "corridor")
    plan = PathPlan(robot=["a1", "b2", "c3", "b2", "a1"], humans=[HumanPlan(name="human1", path=["d4", "b2"],
                                                                             interaction_point="b2")])
    run = write_run(tmp_path / "run", loc, plan, {"human1": REGULAR_XML})
    spec = ScenarioSpec(encounters=[
        Encounter(id="e1", place="CORRIDOR", node="b2", order=1, humans=[HumanPart(human="human1", reaction="stop")]),
        Encounter(id="e2", place="CORRIDOR", node="b2", order=2, humans=[HumanPart(human="human1", reaction="stop")])],
        criteria=[Criterion(id="c1", kind="robot_reaches_goal")])
    from socnavgen.run.folder import RunFolder

    RunFolder(run).write_spec(spec)
    back = [(26, 6.0, 5.0), (30, 6.0, 3.9), (34, 6.0, 3.9), (38, 6.0, 5.0)] if comes_back else [(38, 6.0, 5.0)]
    t = np.arange(0, 40.01, 0.5)
    rx = np.interp(t, [0, 20, 40], [1.025, 11.025, 1.025])
    keys = [(0, 6.0, 5.0), (6, 6.0, 5.0), (10, 6.0, 3.9), (13, 6.0, 3.9), (16, 6.0, 5.0), *back]
    hx = np.interp(t, [k[0] for k in keys], [k[1] for k in keys])
    hy = np.interp(t, [k[0] for k in keys], [k[2] for k in keys])
    trace = build_trace(t, np.stack([rx, np.full_like(t, 2.975)], 1), np.stack([hx, hy], 1)[:, None],
                        goal=(1.025, 2.975))
    trace.robot_waypoints = [(1.025, 2.975), (11.025, 2.975), (1.025, 2.975)]
    report = verify_trace(run, trace)
    meets = {f.criterion: f for f in report.findings if f.kind == "meets"}
    assert meets["meet_human1_e1"].passed and meets["meet_human1_e1"].time < 20
    second = meets["meet_human1_e2"]
    if comes_back:
        assert second.passed and second.time > 20, second.evidence
    else:
        assert not second.passed and second.blame == "paths" and "only once" in second.blame_reason, second.evidence
