"""Navigation metrics of a simulation trace: every metric of HuNavSim's `hunav_evaluator` (fork = upstream
1.x), with the evaluator's own definitions and quirks so that numbers are comparable with HuNavSim runs,
plus three of our own: `success`, `collisions`, `min_time_to_collision`.

Definitions: ../shared/reference/hunav-node-library.md section 10 (and section 6.9 for the evaluator's social
force model). Quirks reproduced on purpose (each also listed in docs/verify.md):

* time_to_reach_goal is the duration of the recording; it does not check that the goal was reached.
* avg_distance_to_closest_person divides by all N samples (also those without agents).
* maximum_distance_to_people subtracts the robot radius only and is not clamped.
* time_not_moving compares the *signed* angular speed with 0.02 (turning clockwise counts as not moving).
* avg_acceleration / avg_overacceleration sum N-1 differences but divide by N.
* group intrusions use a point 1.5 m in front of each member, no agent radius and no clamp.
* collisions: (robot|person)_on_(person|robot) use the evaluator's bearing test with swapped atan2 arguments.

One deliberate change (one definition of contact for every report): the evaluator attributes (sample, person)
pairs whose gap is under 0.02 m; here the pairs are those in contact by sim/contact.py (gap <= 0.05 m), the
same pairs `collisions`, `success` and the verifier count. So `robot_on_person_collision` or
`person_on_robot_collision` above 0 implies `collisions` above 0, and `collisions` 0 implies both are 0.
* the social-force metrics use the evaluator's SFM (k_soc = 2.1, theta with swapped atan2 arguments and a
  single +-2 pi correction), not lightsfm.

Deliberate differences (data the evaluator gets from Gazebo that we derive from the map):
* obstacle forces use the nearest occupied map cell within 10 m of each agent (the Gazebo wrapper sends one
  such point per human); without a `location` they are 0.
* obstacle_force_on_robot is computed the same way for the robot; the Gazebo wrapper sends the robot no
  obstacle points, so HuNavSim reports 0 there (pass `robot_obstacles=False` to get that behaviour).
* undefined values (the evaluator would divide by zero or take the minimum of nothing, e.g. with no humans)
  are None; zero-length vectors give zero force instead of NaN.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from socnavgen.bodies import INTIMATE_SPACE, PERSONAL_SPACE, ROBOT_GOAL_TOLERANCE, SOCIAL_SPACE
from socnavgen.memo import kept
from socnavgen.safeio import atomic_write_text
from socnavgen.sim import contact
from socnavgen.sim.arrival import short_of_goal_steps
from socnavgen.sim.trace import OMEGA, VX, VY, YAW, Trace, X, Y

NO_AGENT_DISTANCE = 10000.0  # the evaluator's "infinity"
GROUP_CENTER_OFFSET = 1.5  # m in front of each group member
OBSTACLE_RANGE = 10.0  # m, the wrapper sends the nearest obstacle point within this range
SUCCESS_GOAL_RADIUS = 0.5  # m, default for `success`; Trace.meta["robot_goal_radius"] overrides

EVALUATOR_METRICS = (
    "time_to_reach_goal", "path_length", "cumulative_heading_changes", "avg_distance_to_closest_person",
    "minimum_distance_to_people", "maximum_distance_to_people", "intimate_space_intrusions",
    "personal_space_intrusions", "social_space_intrusions", "group_intimate_space_intrusions",
    "group_personal_space_intrusions", "group_social_space_intrusions", "completed",
    "minimum_distance_to_target", "final_distance_to_target", "robot_on_person_collision",
    "person_on_robot_collision", "time_not_moving", "avg_robot_linear_speed", "avg_robot_angular_speed",
    "avg_acceleration", "avg_overacceleration", "avg_pedestrian_velocity", "avg_closest_pedestrian_velocity",
    "social_force_on_agents", "social_force_on_robot", "social_work", "obstacle_force_on_agents",
    "obstacle_force_on_robot",
)
OWN_METRICS = ("success", "collisions", "min_time_to_collision")


@dataclass(frozen=True)
class EvaluatorSFM:
    """Parameters of the evaluator's Python social force model (reference section 6.9)."""

    k_social: float = 2.1
    k_obstacle: float = 10.0
    sigma_obstacle: float = 0.2
    lambda_: float = 2.0
    gamma: float = 0.35
    n: float = 2.0
    n_prime: float = 3.0


def _norm(v: np.ndarray) -> np.ndarray:
    return np.linalg.norm(v, axis=-1)


def hypot2(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """sqrt(x*x + y*y): bit for bit np.linalg.norm(stack([x, y], -1), axis=-1) (which squares, adds the two
    squares and takes the root), without building the (..., 2) array or reducing over a 2-long axis."""
    return np.sqrt(x * x + y * y)


def _directions(dx: np.ndarray, dy: np.ndarray, dvx: np.ndarray, dvy: np.ndarray, dist: np.ndarray,
                sfm: EvaluatorSFM) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The parts of social_force that only change sign when source and target swap: (hx, hy) the unit vector
    from target to source, (tx, ty) the interaction direction, ok (a force exists), b (its range). Negating
    dx, dy, dvx and dvy negates hx, hy, tx and ty exactly (IEEE arithmetic is symmetric in sign)."""
    safe = np.where(dist > 0, dist, 1.0)
    hx, hy = dx / safe, dy / safe
    ix, iy = sfm.lambda_ * dvx + hx, sfm.lambda_ * dvy + hy
    length = hypot2(ix, iy)
    ok = (dist > 0) & (length > 0)
    length_safe = np.where(length > 0, length, 1.0)
    return hx, hy, ix / length_safe, iy / length_safe, ok, sfm.gamma * length_safe


def _force_xy(hx: np.ndarray, hy: np.ndarray, tx: np.ndarray, ty: np.ndarray, ok: np.ndarray, b: np.ndarray,
              dist: np.ndarray, sfm: EvaluatorSFM) -> tuple[np.ndarray, np.ndarray]:
    # Evaluator quirk: the second atan2 takes (x, y), then one +-2pi correction.
    theta = np.arctan2(hy, hx) - np.arctan2(tx, ty)
    theta = np.where(theta > math.pi, theta - 2 * math.pi, np.where(theta < -math.pi, theta + 2 * math.pi, theta))
    f_vel = -np.exp(-dist / b - (sfm.n_prime * b * theta) ** 2)
    f_ang = -np.sign(theta) * np.exp(-dist / b - (sfm.n * b * theta) ** 2)
    fx = sfm.k_social * (f_vel * tx + f_ang * -ty)  # normal = (-t_y, t_x)
    fy = sfm.k_social * (f_vel * ty + f_ang * tx)
    return np.where(ok, fx, 0.0), np.where(ok, fy, 0.0)


def _social_force_xy(dx: np.ndarray, dy: np.ndarray, dvx: np.ndarray, dvy: np.ndarray, dist: np.ndarray,
                     sfm: EvaluatorSFM) -> tuple[np.ndarray, np.ndarray]:
    """social_force per component: (dx, dy) = p_src - p_dst, dist = its length, (dvx, dvy) = v_dst - v_src.
    The same operations in the same order as on (..., 2) arrays, hence the same values."""
    return _force_xy(*_directions(dx, dy, dvx, dvy, dist, sfm), dist, sfm)


def _social_forces_both_ways(dx: np.ndarray, dy: np.ndarray, dvx: np.ndarray, dvy: np.ndarray, dist: np.ndarray,
                             sfm: EvaluatorSFM) -> tuple[tuple[np.ndarray, np.ndarray], tuple[np.ndarray, np.ndarray]]:
    """(_social_force_xy of (dx, dy, dvx, dvy), of the swapped pair (-dx, -dy, -dvx, -dvy)): the same values,
    the sign-symmetric parts computed once."""
    hx, hy, tx, ty, ok, b = _directions(dx, dy, dvx, dvy, dist, sfm)
    return _force_xy(hx, hy, tx, ty, ok, b, dist, sfm), _force_xy(-hx, -hy, -tx, -ty, ok, b, dist, sfm)


def social_force(p_src: np.ndarray, v_src: np.ndarray, p_dst: np.ndarray, v_dst: np.ndarray,
                 sfm: EvaluatorSFM = EvaluatorSFM()) -> np.ndarray:
    """Force exerted BY the agent at p_src ON the agent at p_dst, evaluator variant; broadcasts over leading
    axes of (..., 2) arrays. Coincident agents give zero instead of NaN."""
    p_src, v_src, p_dst, v_dst = np.broadcast_arrays(*(np.asarray(a, dtype=float) for a in (p_src, v_src, p_dst,
                                                                                              v_dst)))
    diff, dv = p_src - p_dst, v_dst - v_src
    fx, fy = _social_force_xy(diff[..., 0], diff[..., 1], dv[..., 0], dv[..., 1], hypot2(diff[..., 0], diff[..., 1]),
                              sfm)
    return np.stack([fx, fy], axis=-1)


def _obstacle_force_xy(dx: np.ndarray, dy: np.ndarray, radius: np.ndarray | float, has_obstacle: np.ndarray,
                       sfm: EvaluatorSFM) -> tuple[np.ndarray, np.ndarray]:
    """obstacle_force per component, (dx, dy) = p - obstacle."""
    dist = hypot2(dx, dy)
    ok = np.asarray(has_obstacle, dtype=bool) & (dist > 0)
    safe = np.where(dist > 0, dist, 1.0)
    scale = sfm.k_obstacle * np.exp(-(safe - radius) / sfm.sigma_obstacle) / safe
    return np.where(ok, scale * dx, 0.0), np.where(ok, scale * dy, 0.0)


def obstacle_force(p: np.ndarray, radius: np.ndarray | float, obstacle: np.ndarray, has_obstacle: np.ndarray,
                   sfm: EvaluatorSFM = EvaluatorSFM()) -> np.ndarray:
    """Obstacle force of ONE closest obstacle point per agent (the wrapper sends at most one); zero where
    `has_obstacle` is false or the agent stands exactly on the point."""
    diff = np.asarray(p, dtype=float) - np.asarray(obstacle, dtype=float)
    return np.stack(_obstacle_force_xy(diff[..., 0], diff[..., 1], radius, has_obstacle, sfm), axis=-1)


class ObstacleLookup:
    """Nearest occupied map cell (world coordinates) for any world point, from one distance transform."""

    def __init__(self, location: Any) -> None:
        from scipy import ndimage

        blocked = np.asarray(location.occupancy.blocked, dtype=bool)
        self.transform = location.transform
        self.shape = blocked.shape
        self.empty = not blocked.any()
        if not self.empty:
            rows, cols = ndimage.distance_transform_edt(~blocked, return_distances=False, return_indices=True)
            self.rows, self.cols = rows, cols
            self._rows_flat, self._cols_flat = rows.ravel(), cols.ravel()  # one gather by flat index

    def nearest(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(..., 2) world points -> (nearest obstacle world points, mask: one exists within OBSTACLE_RANGE)."""
        pts = np.asarray(points, dtype=float)
        flat = pts.reshape(-1, 2)
        if self.empty or flat.size == 0:
            return np.zeros_like(pts), np.zeros(pts.shape[:-1], dtype=bool)
        px = self.transform.worlds_to_pixel(flat)
        # Integer pixel coordinates name pixel centres (location.transform convention): round.
        cols = np.clip(np.rint(px[:, 0]).astype(int), 0, self.shape[1] - 1)
        rows = np.clip(np.rint(px[:, 1]).astype(int), 0, self.shape[0] - 1)
        cell = rows * self.shape[1] + cols
        ob_px = np.empty((len(flat), 2))
        ob_px[:, 0], ob_px[:, 1] = self._cols_flat[cell], self._rows_flat[cell]
        ob_world = self.transform.pixels_to_world(ob_px)
        within = hypot2(ob_world[:, 0] - flat[:, 0], ob_world[:, 1] - flat[:, 1]) <= OBSTACLE_RANGE
        return ob_world.reshape(pts.shape), within.reshape(pts.shape[:-1])


def obstacle_lookup(location: Any) -> ObstacleLookup:
    """The location's ObstacleLookup, built once per Location object (campaign workers compute metrics for
    thousands of episodes on the same map; the distance transform is the costly part)."""
    return kept(location, "obstacle_lookup", lambda: ObstacleLookup(location))


def sample_indices(t: np.ndarray, sample_hz: float | None) -> np.ndarray:
    """Indices of the steps the evaluator would see: every step (None or <= 0, like `frequency: 0`), or the
    latest step at each tick of a `sample_hz` clock started at the first step (metrics.yaml uses 1 Hz)."""
    n = len(t)
    if n == 0 or not sample_hz or sample_hz <= 0:
        return np.arange(n)
    ticks = t[0] + np.arange(int(math.floor((t[-1] - t[0]) * sample_hz + 1e-9)) + 1) / sample_hz
    idx = np.searchsorted(t, ticks + 1e-9, side="right") - 1
    return np.unique(np.clip(idx, 0, n - 1))


def wrap(angle: np.ndarray) -> np.ndarray:
    """Normalise to (-pi, pi]."""
    a = np.mod(np.asarray(angle, dtype=float) + math.pi, 2 * math.pi) - math.pi
    return np.where(a == -math.pi, math.pi, a)


def robot_goals(trace: Trace) -> list[tuple[float, float]]:
    """The goal the evaluator would attach to robot samples: the final goal (else the last waypoint)."""
    if trace.robot_goal is not None:
        return [(trace.robot_goal[0], trace.robot_goal[1])]
    return [(trace.robot_waypoints[-1][0], trace.robot_waypoints[-1][1])] if trace.robot_waypoints else []


def _zone_share(values: np.ndarray, low: float, high: float, n: int) -> float:
    return 100.0 * float(np.count_nonzero((values >= low) & (values < high))) / n


def _collision_counts(pr: np.ndarray, yaw_r: np.ndarray, v_r: np.ndarray, pa: np.ndarray, yaw_a: np.ndarray,
                      v_a: np.ndarray, gap: np.ndarray) -> tuple[int, int]:
    """Evaluator rule: alpha = bearing of the robot seen from the agent, alpha2 = atan2(x', y') of the agent
    in the robot frame (swapped arguments); smaller |alpha| -> robot hit person, larger -> person hit robot,
    equal with equal speeds -> both; speeds must differ otherwise. Counts (sample, agent) pairs in contact
    (contact.in_contact: the evaluator's own threshold is a gap under 0.02 m; see the module docstring). Scalar
    math on the few pairs in contact (Python floats are the same IEEE doubles as numpy's, without its
    per-scalar cost)."""
    robot_hits = person_hits = 0
    steps, agents = np.nonzero(contact.in_contact(gap))
    if not len(steps):
        return 0, 0
    columns = (pr[steps, 0], pr[steps, 1], pa[steps, agents, 0], pa[steps, agents, 1], yaw_r[steps],
               yaw_a[steps, agents], v_r[steps], v_a[steps, agents])
    for rx, ry, ax, ay, yr_, ya, vr, va in zip(*(c.tolist() for c in columns), strict=True):
        dx, dy = rx - ax, ry - ay
        alpha = math.atan2(-dx * math.sin(ya) + dy * math.cos(ya), dx * math.cos(ya) + dy * math.sin(ya))
        ex, ey = -dx, -dy
        xr = ex * math.cos(yr_) + ey * math.sin(yr_)
        yr = -ex * math.sin(yr_) + ey * math.cos(yr_)
        alpha2 = math.atan2(xr, yr)
        same_speed = vr == va
        if abs(alpha) < abs(alpha2) and not same_speed:
            robot_hits += 1
        elif abs(alpha) > abs(alpha2) and not same_speed:
            person_hits += 1
        elif abs(alpha) == abs(alpha2) and same_speed:
            robot_hits += 1
            person_hits += 1
    return robot_hits, person_hits


def _time_to_collision_xy(px: np.ndarray, py: np.ndarray, vx: np.ndarray, vy: np.ndarray,
                          radius: np.ndarray | float) -> np.ndarray:
    """time_to_collision per component: relative position (px, py), relative velocity (vx, vy)."""
    c = (px * px + py * py) - np.asarray(radius, dtype=float) ** 2
    a = vx * vx + vy * vy
    b = px * vx + py * vy  # half of the linear coefficient
    disc = b * b - a * c
    with np.errstate(divide="ignore", invalid="ignore"):
        t_hit = (-b - np.sqrt(np.maximum(disc, 0.0))) / a
    ttc = np.where((a > 0) & (disc >= 0) & (b < 0) & (t_hit >= 0), t_hit, np.inf)
    return np.where(c <= 0, 0.0, ttc)


def time_to_collision(rel_pos: np.ndarray, rel_vel: np.ndarray, radius: np.ndarray | float) -> np.ndarray:
    """Constant-velocity time until two discs touch (0 if they overlap now, inf if never); (..., 2) inputs."""
    p = np.asarray(rel_pos, dtype=float)
    v = np.asarray(rel_vel, dtype=float)
    return _time_to_collision_xy(p[..., 0], p[..., 1], v[..., 0], v[..., 1], radius)


@dataclass(frozen=True)
class _Pairs:
    """Robot-human geometry of a trace's steps, every (T, H) array computed once and shared by the metrics:
    human minus robot position (dx, dy) and velocity (dvx, dvy), centre distance, surface gap."""

    dx: np.ndarray
    dy: np.ndarray
    dvx: np.ndarray
    dvy: np.ndarray
    centre: np.ndarray
    gap: np.ndarray


def _pairs(rob: np.ndarray, hum: np.ndarray, robot_radius: float, human_radii: np.ndarray) -> _Pairs:
    dx, dy = hum[:, :, X] - rob[:, None, X], hum[:, :, Y] - rob[:, None, Y]
    centre = hypot2(dx, dy)  # = contact.centre_distances
    return _Pairs(dx=dx, dy=dy, dvx=hum[:, :, VX] - rob[:, None, VX], dvy=hum[:, :, VY] - rob[:, None, VY],
                  centre=centre, gap=centre - (float(robot_radius) + human_radii.reshape(1, -1)))  # = contact.gaps_from


def _own_metrics(trace: Trace, pairs: _Pairs | None = None, to_goal: np.ndarray | None = None,
                 location: Any = None) -> dict[str, Any]:
    """success, collisions and min_time_to_collision on EVERY step (sampling would miss short contacts).
    `location`: its walls decide whether a robot short of its goal sees the person standing there.
    `pairs` and `to_goal` (distance of every step to the last goal): the same values compute_metrics already
    has when it saw every step of a float64 trace."""
    h = trace.humans.shape[1]
    if h:
        radii = trace.robot_radius + np.asarray(trace.human_radii, dtype=float)
        if pairs is None:
            collisions = contact.summarize(trace).collision_steps  # the one definition (sim/contact.py)
            rel_pos, rel_vel = trace.humans[:, :, :2] - trace.robot[:, None, :2], \
                trace.humans[:, :, VX:VY + 1] - trace.robot[:, None, VX:VY + 1]
            ttc = time_to_collision(rel_pos, rel_vel, radii[None, :])
        else:
            collisions = contact.collision_steps(pairs.gap)
            ttc = _time_to_collision_xy(pairs.dx, pairs.dy, pairs.dvx, pairs.dvy, radii[None, :])
        min_ttc = float(ttc.min()) if ttc.size else math.inf
    else:
        collisions, min_ttc = 0, math.inf
    goals = robot_goals(trace)
    radius = float(trace.meta.get("robot_goal_radius", SUCCESS_GOAL_RADIUS)) if isinstance(trace.meta, dict) \
        else SUCCESS_GOAL_RADIUS
    if goals and trace.steps > 0 and to_goal is None:
        pr = trace.robot[:, :2] - np.asarray(goals[-1])
        to_goal = hypot2(pr[:, 0], pr[:, 1])
    reached = bool(goals) and trace.steps > 0 and to_goal is not None and (
        float(to_goal.min()) <= radius or bool(short_of_goal_steps(trace, goals[-1], _world(location)).any()))
    return {"success": bool(reached and collisions == 0), "collisions": collisions, "min_time_to_collision": min_ttc}


def _world(location: Any) -> Any:
    """The location's sim World (its walls), built once per Location object; None without a location."""
    if location is None:
        return None
    from socnavgen.sim.world import World

    return kept(location, "world", lambda: World.from_location(location))


def compute_metrics(trace: Trace, location: Any = None, *, sample_hz: float | None = None,
                    robot_obstacles: bool = True, sfm: EvaluatorSFM = EvaluatorSFM()) -> dict[str, Any]:
    """Every hunav_evaluator metric (names as in HuNavSim's result files) plus success, collisions and
    min_time_to_collision. `sample_hz`: None = every step (evaluator `frequency: 0`), 1.0 = metrics.yaml.
    `location` supplies obstacle points for the obstacle forces (0 without it).

    Vectors are handled per component ((T, H) arrays of x and y, robot-human differences computed once):
    the same operations as on (T, H, 2) arrays and np.linalg.norm, so the same values, at a fraction of the
    numpy calls (tests/metrics/test_metrics_reference.py checks them against the formulas as written)."""
    idx = sample_indices(trace.t, sample_hz)
    n = len(idx)
    if n == 0:
        return {**dict.fromkeys(EVALUATOR_METRICS), **_own_metrics(trace, location=location), "samples": 0}
    every = n == trace.steps  # no sampling: the arrays are the trace's own
    t = np.asarray(trace.t, dtype=float)
    rob = np.asarray(trace.robot, dtype=float)
    hum = np.asarray(trace.humans, dtype=float).reshape(trace.steps, -1, 6)
    if not every:
        t, rob, hum = t[idx], rob[idx], hum[idx]
    h = hum.shape[1]
    r_r = float(trace.robot_radius)
    r_a = np.asarray(trace.human_radii, dtype=float).reshape(h)
    rx, ry, w_r = rob[:, X], rob[:, Y], rob[:, OMEGA]
    v_r = hypot2(rob[:, VX], rob[:, VY])
    v_a = hypot2(hum[:, :, VX], hum[:, :, VY])
    pairs = _pairs(rob, hum, r_r, r_a)
    centre, gap = pairs.centre, pairs.gap
    m: dict[str, Any] = {}

    duration = float(t[-1] - t[0])
    m["time_to_reach_goal"] = duration
    m["path_length"] = float(hypot2(np.diff(rx), np.diff(ry)).sum())
    m["cumulative_heading_changes"] = float(np.abs(wrap(rob[:-1, YAW] - rob[1:, YAW])).sum())
    closest = np.maximum(0.0, contact.row_min(gap)) if h else np.full(n, NO_AGENT_DISTANCE)
    m["avg_distance_to_closest_person"] = float(closest.sum()) / n if h else 0.0
    m["minimum_distance_to_people"] = float(np.maximum(0.0, gap).min()) if h else None
    m["maximum_distance_to_people"] = float((centre - r_r).max()) if h else None
    m["intimate_space_intrusions"] = _zone_share(closest, -math.inf, INTIMATE_SPACE, n)
    m["personal_space_intrusions"] = _zone_share(closest, INTIMATE_SPACE, PERSONAL_SPACE, n)
    m["social_space_intrusions"] = _zone_share(closest, PERSONAL_SPACE, SOCIAL_SPACE, n)

    groups = sorted({g for g in trace.group_ids if g != -1})
    if groups:
        pr, pa = rob[:, :2], hum[:, :, :2]
        front = pa + GROUP_CENTER_OFFSET * np.stack([np.cos(hum[:, :, YAW]), np.sin(hum[:, :, YAW])], axis=-1)
        ids = np.asarray(trace.group_ids)
        centres = np.stack([front[:, ids == g].mean(axis=1) for g in groups], axis=1)  # (n, G, 2)
        g_dist = (_norm(pr[:, None, :] - centres) - r_r).min(axis=1)
        m["group_intimate_space_intrusions"] = _zone_share(g_dist, -math.inf, INTIMATE_SPACE, n)
        m["group_personal_space_intrusions"] = _zone_share(g_dist, INTIMATE_SPACE, PERSONAL_SPACE, n)
        m["group_social_space_intrusions"] = _zone_share(g_dist, PERSONAL_SPACE, SOCIAL_SPACE, n)
    else:
        for zone in ("intimate", "personal", "social"):
            m[f"group_{zone}_space_intrusions"] = 0.0

    goals = np.asarray(robot_goals(trace), dtype=float).reshape(-1, 2)
    to_goal = None
    if len(goals):
        to_goal = hypot2(rx[:, None] - goals[None, :, 0], ry[:, None] - goals[None, :, 1])  # (n, G)
        m["completed"] = bool((to_goal[-1] - ROBOT_GOAL_TOLERANCE < 0).any())
        m["minimum_distance_to_target"] = float(to_goal.min())
        m["final_distance_to_target"] = float(to_goal[-1].min())
    else:
        m["completed"] = False
        m["minimum_distance_to_target"] = NO_AGENT_DISTANCE
        m["final_distance_to_target"] = NO_AGENT_DISTANCE

    robot_hits, person_hits = _collision_counts(rob[:, :2], rob[:, YAW], v_r, hum[:, :, :2], hum[:, :, YAW], v_a,
                                                gap) if h else (0, 0)
    m["robot_on_person_collision"] = robot_hits
    m["person_on_robot_collision"] = person_hits
    # Quirk kept: signed omega comparison.
    m["time_not_moving"] = duration / n * int(np.count_nonzero((v_r < 0.01) & (w_r < 0.02)))
    m["avg_robot_linear_speed"] = float(v_r.sum()) / n
    m["avg_robot_angular_speed"] = float(np.abs(w_r).sum()) / n
    dt = np.diff(t)
    dv = np.diff(v_r)
    moving = dt != 0
    safe_dt = np.where(moving, dt, 1.0)
    m["avg_acceleration"] = float(np.abs(np.where(moving, dv / safe_dt, 0.0)).sum()) / n
    m["avg_overacceleration"] = float(np.abs(np.where(moving, dv / safe_dt**2, 0.0)).sum()) / n
    m["avg_pedestrian_velocity"] = float(v_a.sum()) / (n * h) if h else None
    m["avg_closest_pedestrian_velocity"] = (
        float(v_a[np.arange(n), centre.argmin(axis=1)].sum()) / n if h else 0.0)

    # Social-force metrics (evaluator SFM): by the robot on each agent, by each agent on the robot.
    hx, hy, hvx, hvy = hum[:, :, X], hum[:, :, Y], hum[:, :, VX], hum[:, :, VY]
    rx_, ry_, rvx, rvy = rx[:, None], ry[:, None], rob[:, None, VX], rob[:, None, VY]
    (agents_x, agents_y), (robot_x, robot_y) = _social_forces_both_ways(rx_ - hx, ry_ - hy, hvx - rvx, hvy - rvy,
                                                                        centre, sfm)
    on_agents = hypot2(agents_x, agents_y)  # (n, h)
    m["social_force_on_agents"] = float(on_agents.sum())
    m["social_force_on_robot"] = float(hypot2(robot_x, robot_y).sum())
    lookup = obstacle_lookup(location) if location is not None else None
    if lookup is not None and robot_obstacles:
        ob_r, has_r = lookup.nearest(rob[:, :2])
        f_obs_r = hypot2(*_obstacle_force_xy(rx - ob_r[:, 0], ry - ob_r[:, 1], r_r, has_r, sfm))
    else:
        f_obs_r = np.zeros(n)
    # summed over agents as a (n, h, 2) array, as the formula is written: the order of that sum decides the last bit
    on_robot = np.stack([robot_x, robot_y], axis=-1).sum(axis=1)
    m["social_work"] = float((hypot2(on_robot[:, 0], on_robot[:, 1]) + f_obs_r + on_agents.sum(axis=1)).sum())
    if h and lookup is not None:
        ob_a, has_a = lookup.nearest(hum[:, :, :2])
        obstacle = _obstacle_force_xy(hx - ob_a[..., 0], hy - ob_a[..., 1], r_a[None, :], has_a, sfm)
        m["obstacle_force_on_agents"] = float(hypot2(*obstacle).mean(axis=1).sum())
    else:
        m["obstacle_force_on_agents"] = 0.0 if h else None
    m["obstacle_force_on_robot"] = float(f_obs_r.sum())

    full = every and trace.robot.dtype == np.float64 and trace.humans.dtype == np.float64
    m.update(_own_metrics(trace, pairs if full and h else None, to_goal[:, -1] if full and to_goal is not None
                          else None, location))
    m["samples"] = n
    return m


def _json_safe(value: Any) -> Any:
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, np.generic):
        return _json_safe(value.item())
    return value


def metrics_json(metrics: dict[str, Any]) -> str:
    """Strict JSON (non-finite numbers such as a never-reached time to collision become null), every metric
    followed by a `definitions` object: unit, meaning (and formula where ours) of each one."""
    from socnavgen.sim.metric_definitions import metric_definitions

    values = {k: _json_safe(v) for k, v in metrics.items() if k != "definitions"}
    return json.dumps({**values, "definitions": metric_definitions(list(values))}, indent=2) + "\n"


def write_metrics(metrics: dict[str, Any], path: Path) -> None:
    atomic_write_text(Path(path), metrics_json(metrics))


# -- Metrics HuNavSim's evaluator leaves as TODO ------------------------------------------------------------
# Formulas and units are in NAVIGATION_METRICS (written to metrics.json's "definitions" by campaigns and
# shown in the campaign report). They need the walls, hence a World (sim.world) rather than a Location.
NAVIGATION_METRICS = {
    "path_irregularity": {
        "unit": "rad/m",
        "formula": "(sum_t |wrap(yaw_{t+1} - yaw_t)| - |wrap(bearing(p_0 -> goal) - yaw_0)|)^+ / L, "
                   "L = robot path length",
        "meaning": "robot rotation beyond the one turn needed to face its goal, per metre driven "
                   "(0 = only the necessary turn; None when the robot did not move)"},
    "path_efficiency": {
        "unit": "1",
        "formula": "|goal - p_0| / L when the goal was reached, L = robot path length",
        "meaning": "1 = a straight line from start to goal; detours, hesitation and back-and-forth lower it. "
                   "Walls lower it for every policy alike, so compare policies on the same scenario "
                   "(None when the goal was not reached)"},
    "static_obstacle_collisions": {
        "unit": "count",
        "formula": "number of contact onsets: steps t with c(p_t) < r_robot and c(p_{t-1}) >= r_robot, "
                   "c = distance from the robot centre to the nearest occupied map cell",
        "meaning": "times the robot's body touched a wall or static obstacle (every step, no sampling)"},
    "min_obstacle_clearance": {
        "unit": "m",
        "formula": "min_t c(p_t) - r_robot",
        "meaning": "closest the robot's body came to a wall (negative = overlapping it)"},
}


def navigation_metrics(trace: Trace, world: Any) -> dict[str, Any]:
    """path_irregularity, path_efficiency, static_obstacle_collisions, min_obstacle_clearance (see
    NAVIGATION_METRICS). `world` is a sim.world.World (for the walls); None leaves the wall metrics None."""
    pr = np.asarray(trace.robot[:, :2], dtype=float)
    yaw = np.asarray(trace.robot[:, YAW], dtype=float)
    out: dict[str, Any] = dict.fromkeys(NAVIGATION_METRICS)
    if len(pr) == 0:
        return out
    length = float(contact.lengths(np.diff(pr, axis=0)).sum())
    goals = robot_goals(trace)
    if length > 1e-9:
        turning = float(np.abs(wrap(np.diff(yaw))).sum())
        needed = 0.0
        if goals:
            to_goal = np.asarray(goals[-1]) - pr[0]
            if float(np.hypot(*to_goal)) > 1e-9:
                needed = abs(float(wrap(np.arctan2(to_goal[1], to_goal[0]) - yaw[0])))
        out["path_irregularity"] = max(0.0, turning - needed) / length
    radius = float(trace.meta.get("robot_goal_radius", SUCCESS_GOAL_RADIUS)) if isinstance(trace.meta, dict) \
        else SUCCESS_GOAL_RADIUS
    if goals and float(contact.lengths(pr - np.asarray(goals[-1])).min()) <= radius and length > 1e-9:
        reference = float(np.hypot(*(np.asarray(goals[-1]) - pr[0])))
        out["path_efficiency"] = min(1.0, reference / length)
    if world is not None:
        clearance = np.asarray(world.clearance_at(pr[:, 0] + 1j * pr[:, 1]), dtype=float)
        touching = clearance < float(trace.robot_radius)
        onsets = int(touching[0]) + int(np.count_nonzero(touching[1:] & ~touching[:-1]))
        out["static_obstacle_collisions"] = onsets
        low = float(clearance.min()) - float(trace.robot_radius)
        out["min_obstacle_clearance"] = low if math.isfinite(low) else None
    return out
