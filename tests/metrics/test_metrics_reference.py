"""The metrics, vectorised per component, against the formulas as first written (reference_metrics.py: the
previous implementation, np.linalg.norm on (T, H, 2) arrays, one call per social force direction, a loop per
colliding pair). Every value must be IDENTICAL, not close: the new code performs the same floating-point
operations in the same order (sums over agents keep the (T, H, 2) layout, whose summation order decides the
last bit once there are 8 or more people), so no tolerance is needed anywhere. Campaign tables compare equal
before and after."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from socnavgen.location import load_location
from socnavgen.sim import metrics
from socnavgen.sim.trace import Trace
from tests.metrics import reference_metrics as reference
from tests.verify.verify_builders import make_location


def random_trace(steps: int, humans: int, *, seed: int, collide: bool = False, groups: bool = False,
                 repeat_times: bool = False, ties: bool = False, dtype: type = np.float64) -> Trace:
    """People and a robot wandering in the 12 m x 6 m corridor of verify_builders (walls at its edges)."""
    rng = np.random.default_rng(seed)
    t = np.cumsum(rng.uniform(0.04, 0.06, steps)) - 0.05
    if repeat_times and steps > 3:
        t[2] = t[1]  # a zero time step (the evaluator's acceleration divides by it)
    robot = np.zeros((steps, 6))
    robot[:, 0] = np.linspace(1.0, 11.0, steps) + rng.normal(0, 0.05, steps)
    robot[:, 1] = 3.0 + rng.normal(0, 0.3, steps)
    robot[:, 2] = rng.uniform(-math.pi, math.pi, steps)
    robot[:, 3:5] = rng.normal(0, 0.6, (steps, 2))
    robot[:, 5] = rng.normal(0, 0.3, steps)
    people = np.zeros((steps, humans, 6))
    people[:, :, 0] = rng.uniform(0.5, 11.5, humans) + np.cumsum(rng.normal(0, 0.05, (steps, humans)), axis=0)
    people[:, :, 1] = rng.uniform(0.5, 5.5, humans) + np.cumsum(rng.normal(0, 0.05, (steps, humans)), axis=0)
    people[:, :, 2] = rng.uniform(-math.pi, math.pi, (steps, humans))
    people[:, :, 3:5] = rng.normal(0, 0.8, (steps, humans, 2))
    if collide and humans:  # human1 on top of the robot for a while, at exactly the robot's speed sometimes
        k = slice(steps // 3, steps // 3 + max(1, steps // 5))
        people[k, 0, :2] = robot[k, :2] + rng.normal(0, 0.2, 2)
        people[k.start, 0, 3:5] = robot[k.start, 3:5]
        people[k.start + 1 if steps > k.start + 1 else k.start, 0, :2] = robot[k.start, :2]  # coincident centres
    if ties and humans:  # same x and same x-velocity as the robot: signed zeros in every difference
        people[:, 0, 0], people[:, 0, 3] = robot[:, 0], robot[:, 3]
        robot[: steps // 2, 3:5] = 0.0
        people[: steps // 2, -1, 3:5] = 0.0
    group_ids = [-1] * humans
    if groups and humans >= 3:
        group_ids[:3] = [0, 0, 1]
        group_ids[-1] = 1
    return Trace(dt=0.05, t=t, robot=robot.astype(dtype), humans=people.astype(dtype),
                 human_names=[f"human{i + 1}" for i in range(humans)], group_ids=group_ids,
                 human_radii=rng.uniform(0.3, 0.45, humans), robot_radius=0.35, node_names=[],
                 action=np.full((steps, humans), -1, np.int16), succeeded=np.zeros((steps, humans), np.int64),
                 human_gesture=np.zeros((steps, humans), np.int8), robot_gesture=np.zeros(steps, np.int8),
                 behavior_state=np.zeros((steps, humans), np.int8),
                 robot_goal=(11.0, 3.0) if seed % 3 else None, robot_waypoints=[(1.0, 3.0), (10.5, 3.2)],
                 meta={"robot_goal_radius": 0.6} if seed % 2 else {})


@pytest.fixture(scope="module")
def corridor(tmp_path_factory: pytest.TempPathFactory):  # noqa: ANN201 - a Location
    return load_location(make_location(Path(tmp_path_factory.mktemp("maps")) / "corridor"))


def same(a: object, b: object) -> bool:
    """Equal values of equal types; NaN equals NaN."""
    if type(a) is not type(b):
        return False
    if isinstance(a, float) and math.isnan(a):
        return math.isnan(b)
    return a == b


CASES = {
    "5 people": dict(steps=400, humans=5, seed=1),
    "no people": dict(steps=300, humans=0, seed=2),
    "one person, one step": dict(steps=1, humans=1, seed=3),
    "two steps": dict(steps=2, humans=2, seed=4),
    "collisions": dict(steps=300, humans=4, seed=5, collide=True),
    "groups": dict(steps=250, humans=6, seed=6, groups=True),
    "zero time step": dict(steps=200, humans=3, seed=7, repeat_times=True),
    "signed zeros": dict(steps=200, humans=3, seed=8, ties=True, collide=True),
    "8 people": dict(steps=300, humans=8, seed=9, collide=True),
    "13 people": dict(steps=200, humans=13, seed=10, groups=True, collide=True),
    "float32 trace": dict(steps=150, humans=3, seed=11, collide=True, dtype=np.float32),
}


@pytest.mark.parametrize("case", CASES)
@pytest.mark.parametrize("options", [dict(), dict(sample_hz=1.0), dict(robot_obstacles=False)],
                         ids=["every step", "1 Hz", "no robot obstacles"])
def test_metrics_equal_the_reference_formulas(case: str, options: dict, corridor) -> None:  # noqa: ANN001
    trace = random_trace(**CASES[case])
    for location in (corridor, None):
        new = metrics.compute_metrics(trace, location, **options)
        old = reference.compute_metrics(trace, location, **options)
        assert list(new) == list(old)
        different = {k: (new[k], old[k]) for k in old if not same(new[k], old[k])}
        assert different == {}, case


def test_the_cases_exercise_what_they_claim(corridor) -> None:  # noqa: ANN001
    """Guard against vacuous comparisons: the traces do collide, have forces, obstacles and both goals."""
    hit = metrics.compute_metrics(random_trace(**CASES["collisions"]), corridor)
    assert hit["collisions"] > 0 and hit["robot_on_person_collision"] + hit["person_on_robot_collision"] > 0
    assert hit["min_time_to_collision"] == 0.0 and hit["social_force_on_agents"] > 0
    assert hit["obstacle_force_on_agents"] > 0 and hit["obstacle_force_on_robot"] > 0
    grouped = metrics.compute_metrics(random_trace(**CASES["groups"]), corridor)
    assert grouped["group_social_space_intrusions"] + grouped["group_personal_space_intrusions"] > 0
    empty = metrics.compute_metrics(random_trace(**CASES["no people"]), corridor)
    assert empty["minimum_distance_to_people"] is None and empty["collisions"] == 0


def test_vector_helpers_equal_the_reference_formulas() -> None:
    rng = np.random.default_rng(0)
    p, v, q, w = (rng.normal(0, 2, (50, 7, 2)) for _ in range(4))
    q[0, 0] = p[0, 0]  # coincident agents
    assert np.array_equal(metrics.social_force(p, v, q, w), reference.social_force(p, v, q, w))
    assert np.array_equal(metrics.social_force(p[:, :1], v[:, :1], q, w), reference.social_force(p[:, :1], v[:, :1], q, w))
    has = rng.uniform(size=(50, 7)) > 0.2
    assert np.array_equal(metrics.obstacle_force(p, 0.4, q, has), reference.obstacle_force(p, 0.4, q, has))
    assert np.array_equal(metrics.time_to_collision(p, v, 0.75), reference.time_to_collision(p, v, 0.75))


def test_obstacle_lookup_equals_the_reference(corridor) -> None:  # noqa: ANN001
    lookup = metrics.obstacle_lookup(corridor)
    points = np.random.default_rng(1).uniform(-25, 37, (300, 4, 2))  # some farther than 10 m from any wall
    for got, want in zip(lookup.nearest(points), reference.nearest(lookup, points), strict=True):
        assert np.array_equal(got, want)
    assert lookup.nearest(points)[1].any() and not lookup.nearest(points)[1].all()


@pytest.mark.parametrize("case", ["5 people", "no people", "one person, one step", "zero time step", "float32 trace"])
def test_navigation_metrics_equal_the_reference_formulas(case: str, corridor) -> None:  # noqa: ANN001
    from socnavgen.sim.world import World

    trace = random_trace(**CASES[case])
    for world in (World.from_location(corridor), None):
        new, old = metrics.navigation_metrics(trace, world), reference.navigation_metrics(trace, world)
        assert {k: v for k, v in new.items() if not same(v, old[k])} == {}
    assert new["path_irregularity"] is not None or case == "one person, one step"
