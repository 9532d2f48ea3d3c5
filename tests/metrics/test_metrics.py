"""hunav_evaluator metrics on small traces whose values are computed by hand in the comments."""

from __future__ import annotations

import json
import math
from types import SimpleNamespace

import numpy as np
import pytest

from socnavgen.location.transform import Transform
from socnavgen.sim.metrics import (
    EVALUATOR_METRICS,
    OWN_METRICS,
    ObstacleLookup,
    compute_metrics,
    metrics_json,
    obstacle_force,
    sample_indices,
    social_force,
    time_to_collision,
)
from socnavgen.sim.trace import Trace


def make_trace(t, robot, humans, *, radii=None, robot_radius=0.5, groups=None, goal=None, meta=None) -> Trace:
    t = np.asarray(t, dtype=float)
    robot = np.asarray(robot, dtype=float)
    humans = np.asarray(humans, dtype=float).reshape(len(t), -1, 6)
    h = humans.shape[1]
    return Trace(
        dt=float(t[1] - t[0]) if len(t) > 1 else 0.1, t=t, robot=robot, humans=humans,
        human_names=[f"human{i + 1}" for i in range(h)], group_ids=groups or [-1] * h,
        human_radii=np.asarray(radii if radii is not None else [0.5] * h, dtype=float), robot_radius=robot_radius,
        node_names=[], action=np.full((len(t), h), -1, dtype=np.int16), succeeded=np.zeros((len(t), h), np.int64),
        human_gesture=np.zeros((len(t), h), np.int8), robot_gesture=np.zeros(len(t), np.int8),
        behavior_state=np.zeros((len(t), h), np.int8), robot_goal=goal, meta=meta or {})


@pytest.fixture
def approach() -> Trace:
    """Robot (r 0.5) drives +x at 2 m/s for two steps and stops; one human (r 0.5) walks -x at 1 m/s.

    t      robot (x, yaw, |v|, omega)   human x   centre dist   gap = dist - 1
    0.0    0, 0,    2, 0                6.0       6.0           5.0
    0.5    1, 0,    2, 0                5.5       4.5           3.5
    1.0    2, pi/2, 0, 0                5.0       3.0           2.0
    1.5    2, pi/2, 0, -0.5             4.5       2.5           1.5
    """
    t = [0.0, 0.5, 1.0, 1.5]
    robot = [[0, 0, 0, 2, 0, 0], [1, 0, 0, 2, 0, 0], [2, 0, math.pi / 2, 0, 0, 0], [2, 0, math.pi / 2, 0, 0, -0.5]]
    humans = [[[x, 0, math.pi, -1, 0, 0]] for x in (6.0, 5.5, 5.0, 4.5)]
    return make_trace(t, robot, humans, goal=(3.0, 0.0))


def test_distances_and_zones_by_hand(approach: Trace) -> None:
    m = compute_metrics(approach)
    assert m["samples"] == 4
    assert m["time_to_reach_goal"] == pytest.approx(1.5)  # t_N - t_1
    assert m["path_length"] == pytest.approx(2.0)  # 1 + 1 + 0
    assert m["cumulative_heading_changes"] == pytest.approx(math.pi / 2)  # one quarter turn
    assert m["avg_distance_to_closest_person"] == pytest.approx((5 + 3.5 + 2 + 1.5) / 4)  # 3.0
    assert m["minimum_distance_to_people"] == pytest.approx(1.5)
    assert m["maximum_distance_to_people"] == pytest.approx(6.0 - 0.5)  # robot radius only
    assert m["intimate_space_intrusions"] == 0.0
    assert m["personal_space_intrusions"] == 0.0
    assert m["social_space_intrusions"] == pytest.approx(75.0)  # 3.5, 2, 1.5 are in [1.2, 3.6)
    assert m["group_social_space_intrusions"] == 0.0  # no groups


def test_goal_and_motion_by_hand(approach: Trace) -> None:
    m = compute_metrics(approach)
    # goal (3, 0): distances 3, 2, 1, 1; completed needs 1 - 0.2 < 0
    assert m["completed"] is False
    assert m["minimum_distance_to_target"] == pytest.approx(1.0)
    assert m["final_distance_to_target"] == pytest.approx(1.0)
    # duration/N * #{v < 0.01 and omega < 0.02}: steps 2 and 3 (omega -0.5 counts: signed quirk)
    assert m["time_not_moving"] == pytest.approx(1.5 / 4 * 2)
    assert m["avg_robot_linear_speed"] == pytest.approx((2 + 2 + 0 + 0) / 4)
    assert m["avg_robot_angular_speed"] == pytest.approx(0.5 / 4)
    # dv = 0, -2, 0 over dt 0.5: |a| sum = 4, divided by N = 4; jerk |-2/0.25| = 8 -> 2
    assert m["avg_acceleration"] == pytest.approx(1.0)
    assert m["avg_overacceleration"] == pytest.approx(2.0)
    assert m["avg_pedestrian_velocity"] == pytest.approx(1.0)
    assert m["avg_closest_pedestrian_velocity"] == pytest.approx(1.0)
    assert m["robot_on_person_collision"] == 0 and m["person_on_robot_collision"] == 0


def test_own_metrics_by_hand(approach: Trace) -> None:
    m = compute_metrics(approach)
    # TTC: gap / closing speed: 5/3, 3.5/3, 2/1, 1.5/1 -> min 3.5/3
    assert m["min_time_to_collision"] == pytest.approx(3.5 / 3)
    assert m["collisions"] == 0
    assert m["success"] is False  # closest to the goal is 1.0 m > 0.5 m default radius
    approach.meta["robot_goal_radius"] = 1.0
    assert compute_metrics(approach)["success"] is True


def test_every_metric_present_and_json_is_strict(approach: Trace) -> None:
    m = compute_metrics(approach)
    assert set(EVALUATOR_METRICS) | set(OWN_METRICS) <= set(m)
    # A trace that never closes in has an infinite TTC, written as null.
    still = make_trace([0, 1], [[0, 0, 0, 0, 0, 0]] * 2, [[[5, 0, 0, 0, 0, 0]]] * 2)
    ms = compute_metrics(still)
    assert ms["min_time_to_collision"] == math.inf
    assert json.loads(metrics_json(ms))["min_time_to_collision"] is None


def test_group_intrusions_by_hand() -> None:
    """Group 1: members at (-1, 3) yaw 0 and (1, 3) yaw pi -> points 1.5 m ahead (0.5, 3), (-0.5, 3): centre (0, 3).
    Robot (r 0.5) at y = 0, 1.5, 2.8: g = 3 - 0.5 = 2.5 (social), 1.5 - 0.5 = 1.0 (personal), 0.2 - 0.5 = -0.3
    (intimate; no clamp)."""
    humans = [[[-1, 3, 0, 0, 0, 0], [1, 3, math.pi, 0, 0, 0]]] * 3
    robot = [[0, y, 0, 0, 0, 0] for y in (0.0, 1.5, 2.8)]
    m = compute_metrics(make_trace([0, 1, 2], robot, humans, groups=[1, 1]))
    for zone in ("intimate", "personal", "social"):
        assert m[f"group_{zone}_space_intrusions"] == pytest.approx(100 / 3)


def test_evaluator_collision_sides() -> None:
    """Sample 0: robot (0,0) yaw 0 at 1 m/s, human (0.9, 0) yaw pi still: gap 0.9-0.9 = 0, in contact.
    alpha (robot seen from human) = 0, alpha2 = atan2(x'=0.9, y'=0) = pi/2 -> |alpha| < |alpha2|: robot on person.
    Sample 1: human beside the robot at (0, 0.9) yaw 0 moving 1 m/s, robot still: alpha = -pi/2,
    alpha2 = atan2(0, 0.9) = 0 -> person on robot. Sample 2: same as 1 but equal speeds -> neither."""
    robot = [[0, 0, 0, 1, 0, 0], [0, 0, 0, 0, 0, 0], [0, 0, 0, 1, 0, 0]]
    humans = [[[0.9, 0, math.pi, 0, 0, 0]], [[0, 0.9, 0, 1, 0, 0]], [[0, 0.9, 0, 1, 0, 0]]]
    m = compute_metrics(make_trace([0, 1, 2], robot, humans, radii=[0.4]))
    assert m["robot_on_person_collision"] == 1
    assert m["person_on_robot_collision"] == 1
    assert m["collisions"] == 3 and not m["success"]  # touching (gap 0 <= 5 cm) is contact on every step
    m2 = compute_metrics(make_trace([0, 1, 2], robot, humans, radii=[0.45]))
    assert m2["collisions"] == 3 and m2["min_time_to_collision"] == 0.0


@pytest.mark.parametrize(("gap", "contact"), [(0.03, True), (0.045, True), (0.06, False)])
def test_one_contact_threshold_for_every_count(gap: float, contact: bool) -> None:
    """A gap of 3 cm is contact for `collisions` AND for HuNavSim's collision sides (its own threshold is
    2 cm: here both count the pairs sim/contact.py counts); 6 cm is contact for neither."""
    robot = [[0, 0, 0, 1, 0, 0]] * 2
    humans = [[[0.9 + gap, 0, math.pi, 0, 0, 0]]] * 2
    m = compute_metrics(make_trace([0, 1], robot, humans, radii=[0.4]))
    assert (m["collisions"] > 0) is contact
    assert (m["robot_on_person_collision"] > 0) is contact
    assert m["collisions"] == (2 if contact else 0) and m["robot_on_person_collision"] == (2 if contact else 0)


def test_social_force_evaluator_variant() -> None:
    # Static pair along the 45 degree diagonal: the evaluator's swapped atan2 gives theta = 0, so
    # |F| = 2.1 * exp(-sqrt(2) / (0.35 * 1)) = 2.1 * exp(-4.0406) = 0.036932, pointing away from the robot.
    f = social_force(np.array([1.0, 1.0]), np.zeros(2), np.zeros(2), np.zeros(2))
    assert np.linalg.norm(f) == pytest.approx(0.036932, rel=1e-4)
    assert f[0] < 0 and f[1] < 0
    # Head-on along x (robot at origin, human at (2, 0)): theta = pi - atan2(-1, 0) = 3pi/2 -> -pi/2 after the
    # single correction; f_v = -exp(-2/0.35 - (3*0.35*pi/2)^2) = -2.1722e-4,
    # f_theta = +exp(-2/0.35 - (2*0.35*pi/2)^2) = 9.8456e-4; |F| = 2.1 * hypot = 2.1173e-3.
    f = social_force(np.zeros(2), np.zeros(2), np.array([2.0, 0.0]), np.zeros(2))
    assert np.linalg.norm(f) == pytest.approx(2.1173e-3, rel=1e-3)
    assert np.all(social_force(np.zeros(2), np.zeros(2), np.zeros(2), np.zeros(2)) == 0)  # coincident: no NaN


def test_social_force_metrics_sum_over_samples() -> None:
    # Two identical samples of the diagonal pair: on_agents = on_robot = 2 * 0.036932 (symmetric, static).
    # social_work = sum_i (|F(a->r)| + |F_obs(r)| (0, no map) + |F(r->a)|) = 4 * 0.036932.
    trace = make_trace([0, 1], [[1, 1, 0, 0, 0, 0]] * 2, [[[0, 0, 0, 0, 0, 0]]] * 2)
    m = compute_metrics(trace)
    assert m["social_force_on_agents"] == pytest.approx(2 * 0.036932, rel=1e-4)
    assert m["social_force_on_robot"] == pytest.approx(2 * 0.036932, rel=1e-4)
    assert m["social_work"] == pytest.approx(4 * 0.036932, rel=1e-4)
    assert m["obstacle_force_on_agents"] == 0.0 and m["obstacle_force_on_robot"] == 0.0


def test_obstacle_force_and_lookup() -> None:
    # Agent r 0.4 one metre from the point: 10 * exp(-(1 - 0.4) / 0.2) = 10 e^-3 = 0.49787, pointing away.
    f = obstacle_force(np.array([1.0, 0.0]), 0.4, np.zeros(2), np.array(True))
    assert f == pytest.approx([0.49787, 0.0], rel=1e-4)
    # A 10x10 map at 1 m/pixel with one occupied pixel at column 7, row 5 (its centre is world (7, 5) with
    # pixel_to_world x = px, y = 10 - py): nearest obstacle of (2, 5) is that centre, 5 m away.
    blocked = np.zeros((10, 10), dtype=bool)
    blocked[5, 7] = True
    loc = SimpleNamespace(occupancy=SimpleNamespace(blocked=blocked),
                          transform=Transform([[1, 0, 0], [0, -1, 10], [0, 0, 1]]))
    points, ok = ObstacleLookup(loc).nearest(np.array([[2.0, 5.0]]))
    assert ok[0] and points[0] == pytest.approx([7.0, 5.0])
    trace = make_trace([0, 1], [[2, 5, 0, 0, 0, 0]] * 2, [[[2, 7, 0, 0, 0, 0]]] * 2, radii=[0.4])
    m = compute_metrics(trace, loc)
    # robot r 0.5 at 5 m: 10 e^{-(5 - 0.5)/0.2} per sample; human at (2, 7) -> nearest (7, 5), dist sqrt(29)
    assert m["obstacle_force_on_robot"] == pytest.approx(2 * 10 * math.exp(-4.5 / 0.2))
    assert m["obstacle_force_on_agents"] == pytest.approx(2 * 10 * math.exp(-(math.sqrt(29) - 0.4) / 0.2))
    assert compute_metrics(trace, loc, robot_obstacles=False)["obstacle_force_on_robot"] == 0.0


def test_sampling_like_metrics_yaml() -> None:
    t = np.arange(9) * 0.25  # 0 .. 2 s
    assert list(sample_indices(t, 1.0)) == [0, 4, 8]
    assert list(sample_indices(t, None)) == list(range(9))
    robot = [[x, 0, 0, 1, 0, 0] for x in t]  # 1 m/s along x
    m = compute_metrics(make_trace(t, robot, np.zeros((9, 0, 6))), sample_hz=1.0)
    assert m["samples"] == 3 and m["path_length"] == pytest.approx(2.0)
    # no humans: the evaluator's undefined values are None, zones empty
    assert m["minimum_distance_to_people"] is None and m["social_space_intrusions"] == 0.0


def test_time_to_collision_cases() -> None:
    # receding, overlapping, crossing at an offset of 0.5 with radius 1: hit when |x| = sqrt(1 - 0.25)
    assert time_to_collision(np.array([3.0, 0]), np.array([1.0, 0]), 1.0) == math.inf
    assert time_to_collision(np.array([0.5, 0]), np.array([1.0, 0]), 1.0) == 0.0
    ttc = time_to_collision(np.array([4.0, 0.5]), np.array([-1.0, 0]), 1.0)
    assert ttc == pytest.approx(4.0 - math.sqrt(0.75))
    assert time_to_collision(np.array([4.0, 1.5]), np.array([-1.0, 0]), 1.0) == math.inf  # passes by
