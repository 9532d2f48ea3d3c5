"""The metrics as computed before they were vectorised per component (socnavgen 4425df4, sim/metrics.py and
sim/contact.py, copied as they were): the straightforward formulas (np.linalg.norm of each difference, one
social force call per direction, a per-pair loop for collision sides) the fast implementation is checked
against, value for value. One change since: contact is a gap of at most bodies.CONTACT_MARGIN for every count
(collisions and the evaluator's collision sides), as sim/contact.py defines it. Nothing here is imported by the
package."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from socnavgen.bodies import CONTACT_MARGIN
from socnavgen.bodies import INTIMATE_SPACE as INTIMATE
from socnavgen.bodies import PERSONAL_SPACE as PERSONAL
from socnavgen.bodies import ROBOT_GOAL_TOLERANCE as EVALUATOR_GOAL_RADIUS
from socnavgen.bodies import SOCIAL_SPACE as SOCIAL
from socnavgen.sim.metrics import (
    EVALUATOR_METRICS,
    GROUP_CENTER_OFFSET,
    NAVIGATION_METRICS,
    NO_AGENT_DISTANCE,
    OBSTACLE_RANGE,
    SUCCESS_GOAL_RADIUS,
    EvaluatorSFM,
    obstacle_lookup,
    robot_goals,
    sample_indices,
)
from socnavgen.sim.trace import OMEGA, VX, VY, YAW, Trace


# ---- sim/contact.py as it was ---------------------------------------------------------------------
def centre_distances(robot_xy: np.ndarray, humans_xy: np.ndarray) -> np.ndarray:
    robot_xy = np.asarray(robot_xy, dtype=float)
    humans_xy = np.asarray(humans_xy, dtype=float)
    return np.linalg.norm(humans_xy - robot_xy[:, None, :], axis=-1)


def gaps_from(robot_xy: np.ndarray, humans_xy: np.ndarray, robot_radius: float,
              human_radii: np.ndarray) -> np.ndarray:
    radii = float(robot_radius) + np.asarray(human_radii, dtype=float).reshape(1, -1)
    return centre_distances(robot_xy, humans_xy) - radii


def collision_steps(trace: Trace) -> int:
    """contact.summarize(trace).collision_steps as it was."""
    h = trace.humans.shape[1] if trace.humans.ndim == 3 else 0
    if trace.steps == 0 or h == 0:
        return 0
    gaps = gaps_from(trace.robot[:, :2], trace.humans[:, :, :2], trace.robot_radius, trace.human_radii)
    return int((gaps <= CONTACT_MARGIN).any(axis=1).sum())


# ---- sim/metrics.py as it was ---------------------------------------------------------------------
def nearest(lookup: Any, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """ObstacleLookup.nearest as it was."""
    self = lookup
    pts = np.asarray(points, dtype=float)
    flat = pts.reshape(-1, 2)
    if self.empty or flat.size == 0:
        return np.zeros_like(pts), np.zeros(pts.shape[:-1], dtype=bool)
    px = self.transform.worlds_to_pixel(flat)
    # Integer pixel coordinates name pixel centres (location.transform convention): round.
    cols = np.clip(np.rint(px[:, 0]).astype(int), 0, self.shape[1] - 1)
    rows = np.clip(np.rint(px[:, 1]).astype(int), 0, self.shape[0] - 1)
    ob_px = np.stack([self.cols[rows, cols], self.rows[rows, cols]], axis=-1).astype(float)
    ob_world = self.transform.pixels_to_world(ob_px)
    within = _norm(ob_world - flat) <= OBSTACLE_RANGE
    return ob_world.reshape(pts.shape), within.reshape(pts.shape[:-1])


def _norm(v: np.ndarray) -> np.ndarray:
    return np.linalg.norm(v, axis=-1)


def social_force(p_src: np.ndarray, v_src: np.ndarray, p_dst: np.ndarray, v_dst: np.ndarray,
                 sfm: EvaluatorSFM = EvaluatorSFM()) -> np.ndarray:
    """Force exerted BY the agent at p_src ON the agent at p_dst, evaluator variant; broadcasts over leading
    axes of (..., 2) arrays. Coincident agents give zero instead of NaN."""
    p_src, v_src, p_dst, v_dst = np.broadcast_arrays(*(np.asarray(a, dtype=float) for a in (p_src, v_src, p_dst,
                                                                                              v_dst)))
    diff = p_src - p_dst
    dist = _norm(diff)
    safe = np.where(dist > 0, dist, 1.0)
    d_hat = diff / safe[..., None]
    inter = sfm.lambda_ * (v_dst - v_src) + d_hat
    length = _norm(inter)
    ok = (dist > 0) & (length > 0)
    length_safe = np.where(length > 0, length, 1.0)
    t_hat = inter / length_safe[..., None]
    # Evaluator quirk: the second atan2 takes (x, y), then one +-2pi correction.
    theta = np.arctan2(d_hat[..., 1], d_hat[..., 0]) - np.arctan2(t_hat[..., 0], t_hat[..., 1])
    theta = np.where(theta > math.pi, theta - 2 * math.pi, np.where(theta < -math.pi, theta + 2 * math.pi, theta))
    b = sfm.gamma * length_safe
    f_vel = -np.exp(-dist / b - (sfm.n_prime * b * theta) ** 2)
    f_ang = -np.sign(theta) * np.exp(-dist / b - (sfm.n * b * theta) ** 2)
    normal = np.stack([-t_hat[..., 1], t_hat[..., 0]], axis=-1)
    force = sfm.k_social * (f_vel[..., None] * t_hat + f_ang[..., None] * normal)
    return np.where(ok[..., None], force, 0.0)


def obstacle_force(p: np.ndarray, radius: np.ndarray | float, obstacle: np.ndarray, has_obstacle: np.ndarray,
                   sfm: EvaluatorSFM = EvaluatorSFM()) -> np.ndarray:
    """Obstacle force of ONE closest obstacle point per agent (the wrapper sends at most one); zero where
    `has_obstacle` is false or the agent stands exactly on the point."""
    diff = np.asarray(p, dtype=float) - np.asarray(obstacle, dtype=float)
    dist = _norm(diff)
    ok = np.asarray(has_obstacle, dtype=bool) & (dist > 0)
    safe = np.where(dist > 0, dist, 1.0)
    mag = sfm.k_obstacle * np.exp(-(safe - radius) / sfm.sigma_obstacle)
    return np.where(ok[..., None], (mag / safe)[..., None] * diff, 0.0)


def wrap(angle: np.ndarray) -> np.ndarray:
    """Normalise to (-pi, pi]."""
    a = np.mod(np.asarray(angle, dtype=float) + math.pi, 2 * math.pi) - math.pi
    return np.where(a == -math.pi, math.pi, a)


def _zone_share(values: np.ndarray, low: float, high: float, n: int) -> float:
    return 100.0 * float(np.count_nonzero((values >= low) & (values < high))) / n


def _collision_counts(pr: np.ndarray, yaw_r: np.ndarray, v_r: np.ndarray, pa: np.ndarray, yaw_a: np.ndarray,
                      v_a: np.ndarray, gap: np.ndarray) -> tuple[int, int]:
    """Evaluator rule: alpha = bearing of the robot seen from the agent, alpha2 = atan2(x', y') of the agent
    in the robot frame (swapped arguments); smaller |alpha| -> robot hit person, larger -> person hit robot,
    equal with equal speeds -> both; speeds must differ otherwise. Counts (sample, agent) pairs."""
    robot_hits = person_hits = 0
    for i, a in zip(*np.nonzero(gap <= CONTACT_MARGIN), strict=True):
        dx, dy = pr[i] - pa[i, a]
        alpha = math.atan2(-dx * math.sin(yaw_a[i, a]) + dy * math.cos(yaw_a[i, a]),
                           dx * math.cos(yaw_a[i, a]) + dy * math.sin(yaw_a[i, a]))
        ex, ey = -dx, -dy
        xr = ex * math.cos(yaw_r[i]) + ey * math.sin(yaw_r[i])
        yr = -ex * math.sin(yaw_r[i]) + ey * math.cos(yaw_r[i])
        alpha2 = math.atan2(xr, yr)
        same_speed = v_r[i] == v_a[i, a]
        if abs(alpha) < abs(alpha2) and not same_speed:
            robot_hits += 1
        elif abs(alpha) > abs(alpha2) and not same_speed:
            person_hits += 1
        elif abs(alpha) == abs(alpha2) and same_speed:
            robot_hits += 1
            person_hits += 1
    return robot_hits, person_hits


def time_to_collision(rel_pos: np.ndarray, rel_vel: np.ndarray, radius: np.ndarray | float) -> np.ndarray:
    """Constant-velocity time until two discs touch (0 if they overlap now, inf if never); (..., 2) inputs."""
    p = np.asarray(rel_pos, dtype=float)
    v = np.asarray(rel_vel, dtype=float)
    c = np.sum(p * p, axis=-1) - np.asarray(radius, dtype=float) ** 2
    a = np.sum(v * v, axis=-1)
    b = np.sum(p * v, axis=-1)  # half of the linear coefficient
    disc = b * b - a * c
    with np.errstate(divide="ignore", invalid="ignore"):
        t_hit = (-b - np.sqrt(np.maximum(disc, 0.0))) / a
    ttc = np.where((a > 0) & (disc >= 0) & (b < 0) & (t_hit >= 0), t_hit, np.inf)
    return np.where(c <= 0, 0.0, ttc)


def _own_metrics(trace: Trace) -> dict[str, Any]:
    """success, collisions and min_time_to_collision on EVERY step (sampling would miss short contacts)."""
    pr = trace.robot[:, :2]
    pa = trace.humans[:, :, :2]
    radii = trace.robot_radius + np.asarray(trace.human_radii, dtype=float)
    if trace.humans.shape[1]:
        collisions = collision_steps(trace)  # the one definition (sim/contact.py)
        ttc = time_to_collision(pa - pr[:, None, :], trace.humans[:, :, VX:VY + 1] - trace.robot[:, None, VX:VY + 1],
                                radii[None, :])
        min_ttc = float(ttc.min()) if ttc.size else math.inf
    else:
        collisions, min_ttc = 0, math.inf
    goals = robot_goals(trace)
    radius = float(trace.meta.get("robot_goal_radius", SUCCESS_GOAL_RADIUS)) if isinstance(trace.meta, dict) \
        else SUCCESS_GOAL_RADIUS
    reached = bool(goals) and trace.steps > 0 and float(_norm(pr - np.asarray(goals[-1])).min()) <= radius
    return {"success": bool(reached and collisions == 0), "collisions": collisions, "min_time_to_collision": min_ttc}


def compute_metrics(trace: Trace, location: Any = None, *, sample_hz: float | None = None,
                    robot_obstacles: bool = True, sfm: EvaluatorSFM = EvaluatorSFM()) -> dict[str, Any]:
    """Every hunav_evaluator metric (names as in HuNavSim's result files) plus success, collisions and
    min_time_to_collision. `sample_hz`: None = every step (evaluator `frequency: 0`), 1.0 = metrics.yaml.
    `location` supplies obstacle points for the obstacle forces (0 without it)."""
    idx = sample_indices(trace.t, sample_hz)
    n = len(idx)
    if n == 0:
        return {**dict.fromkeys(EVALUATOR_METRICS), **_own_metrics(trace), "samples": 0}
    t = np.asarray(trace.t, dtype=float)[idx]
    rob = np.asarray(trace.robot, dtype=float)[idx]
    hum = np.asarray(trace.humans, dtype=float)[idx].reshape(n, -1, 6)
    h = hum.shape[1]
    r_r = float(trace.robot_radius)
    r_a = np.asarray(trace.human_radii, dtype=float).reshape(h)
    pr, vr_vec = rob[:, :2], rob[:, VX:VY + 1]
    pa, va_vec = hum[:, :, :2], hum[:, :, VX:VY + 1]
    v_r, w_r = _norm(vr_vec), rob[:, OMEGA]
    v_a = _norm(va_vec)
    centre = centre_distances(pr, pa)  # (n, h)
    gap = gaps_from(pr, pa, r_r, r_a)  # sim/contact.py: the gap every report uses
    m: dict[str, Any] = {}

    duration = float(t[-1] - t[0])
    m["time_to_reach_goal"] = duration
    m["path_length"] = float(_norm(np.diff(pr, axis=0)).sum())
    m["cumulative_heading_changes"] = float(np.abs(wrap(rob[:-1, YAW] - rob[1:, YAW])).sum())
    closest = np.maximum(0.0, gap.min(axis=1)) if h else np.full(n, NO_AGENT_DISTANCE)
    m["avg_distance_to_closest_person"] = float(closest.sum()) / n if h else 0.0
    m["minimum_distance_to_people"] = float(np.maximum(0.0, gap).min()) if h else None
    m["maximum_distance_to_people"] = float((centre - r_r).max()) if h else None
    m["intimate_space_intrusions"] = _zone_share(closest, -math.inf, INTIMATE, n)
    m["personal_space_intrusions"] = _zone_share(closest, INTIMATE, PERSONAL, n)
    m["social_space_intrusions"] = _zone_share(closest, PERSONAL, SOCIAL, n)

    groups = sorted({g for g in trace.group_ids if g != -1})
    if groups:
        front = pa + GROUP_CENTER_OFFSET * np.stack([np.cos(hum[:, :, YAW]), np.sin(hum[:, :, YAW])], axis=-1)
        ids = np.asarray(trace.group_ids)
        centres = np.stack([front[:, ids == g].mean(axis=1) for g in groups], axis=1)  # (n, G, 2)
        g_dist = (_norm(pr[:, None, :] - centres) - r_r).min(axis=1)
        m["group_intimate_space_intrusions"] = _zone_share(g_dist, -math.inf, INTIMATE, n)
        m["group_personal_space_intrusions"] = _zone_share(g_dist, INTIMATE, PERSONAL, n)
        m["group_social_space_intrusions"] = _zone_share(g_dist, PERSONAL, SOCIAL, n)
    else:
        for zone in ("intimate", "personal", "social"):
            m[f"group_{zone}_space_intrusions"] = 0.0

    goals = np.asarray(robot_goals(trace), dtype=float).reshape(-1, 2)
    if len(goals):
        to_goal = _norm(pr[:, None, :] - goals[None, :, :])  # (n, G)
        m["completed"] = bool((to_goal[-1] - EVALUATOR_GOAL_RADIUS < 0).any())
        m["minimum_distance_to_target"] = float(to_goal.min())
        m["final_distance_to_target"] = float(to_goal[-1].min())
    else:
        m["completed"] = False
        m["minimum_distance_to_target"] = NO_AGENT_DISTANCE
        m["final_distance_to_target"] = NO_AGENT_DISTANCE

    robot_hits, person_hits = _collision_counts(pr, rob[:, YAW], v_r, pa, hum[:, :, YAW], v_a, gap) if h else (0, 0)
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

    # Social-force metrics (evaluator SFM).
    on_agents = social_force(pr[:, None, :], vr_vec[:, None, :], pa, va_vec, sfm) if h else np.zeros((n, 0, 2))
    on_robot = social_force(pa, va_vec, pr[:, None, :], vr_vec[:, None, :], sfm) if h else np.zeros((n, 0, 2))
    m["social_force_on_agents"] = float(_norm(on_agents).sum())
    m["social_force_on_robot"] = float(_norm(on_robot).sum())
    lookup = obstacle_lookup(location) if location is not None else None
    if lookup is not None and robot_obstacles:
        ob_r, has_r = nearest(lookup, pr)
        f_obs_r = obstacle_force(pr, r_r, ob_r, has_r, sfm)
    else:
        f_obs_r = np.zeros((n, 2))
    m["social_work"] = float((_norm(on_robot.sum(axis=1)) + _norm(f_obs_r) + _norm(on_agents).sum(axis=1)).sum())
    if h and lookup is not None:
        ob_a, has_a = nearest(lookup, pa)
        m["obstacle_force_on_agents"] = float(_norm(obstacle_force(pa, r_a[None, :], ob_a, has_a, sfm)).mean(axis=1)
                                              .sum())
    else:
        m["obstacle_force_on_agents"] = 0.0 if h else None
    m["obstacle_force_on_robot"] = float(_norm(f_obs_r).sum())

    m.update(_own_metrics(trace))
    m["samples"] = n
    return m


def navigation_metrics(trace: Trace, world: Any) -> dict[str, Any]:
    """path_irregularity, path_efficiency, static_obstacle_collisions, min_obstacle_clearance (see
    NAVIGATION_METRICS). `world` is a sim.world.World (for the walls); None leaves the wall metrics None."""
    pr = np.asarray(trace.robot[:, :2], dtype=float)
    yaw = np.asarray(trace.robot[:, YAW], dtype=float)
    out: dict[str, Any] = dict.fromkeys(NAVIGATION_METRICS)
    if len(pr) == 0:
        return out
    length = float(_norm(np.diff(pr, axis=0)).sum())
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
    if goals and float(_norm(pr - np.asarray(goals[-1])).min()) <= radius and length > 1e-9:
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
