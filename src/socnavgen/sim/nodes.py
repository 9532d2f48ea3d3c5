"""One function per leaf of the node library (semantics: reference §3 plus each NodeSpec.sim_note).

A function receives the simulation and the bound leaf (ports via `leaf.get`) and returns SUCCESS or
FAILURE. Conditions read the step's snapshot; actions do not move anyone themselves: they set the
agent's motion command for this step (target, speed, extra force, or a turn on the spot), and the
engine integrates every walking agent in one vectorised social-force step afterwards. All agents
therefore see the same snapshot (a Jacobi update; the fork's order among agents is unspecified).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np

from socnavgen.sim.bt_runtime import FAILURE, SUCCESS, BTRuntimeError

# Constants of the SocRATES fork (reference §1.3, §3)
BLOCKING_CONE = 0.5  # rad
ROBOT_MOVED_SPEED = 0.1  # m/s
FOLLOW_STOP = 1.5  # m
FOLLOW_WAY_AHEAD = 2.0  # m: a follower this close ahead of the robot, on its path, steps aside first
FOLLOW_WAY_MARGIN = 0.2  # m of free space beside the robot's path that counts as out of its way
FOLLOW_GAIN = 1.8 / 10.0  # follow speed = 1.8 * r / max_dist_view(10)
RUN_AWAY_SPEED = 0.6
RUN_AWAY_GAIN = 20 * 0.2  # 20 * sigma_obs
BLOCK_AHEAD, BLOCK_RADIUS, BLOCK_SPEED, BLOCK_FACE = 1.5, 0.05, 0.5, 0.6
# LookAtRobot turns 0.01*pi per manager call; Gazebo calls it every 1 ms. We keep that rate per second of
# simulated time (10*pi rad/s, i.e. practically at once) instead of per tick, so dt does not change it.
LOOK_TURN_RATE = 0.01 * math.pi / 0.001
# GiveWaytoRobot (ours: the fork discards its side step, see NodeSpec.sim_note)
GIVE_WAY_MARGIN = 0.5  # m of free space between the human and the robot's side when stepped aside
GIVE_WAY_ARRIVED = 0.15  # m
SIDE_STEP_DIRECTIONS = 16  # directions tried for the side step
SIDE_STEP_MAX = 3.0  # m: the farthest a human walks to get out of the robot's way
SEGMENT_TIE = 1e-9  # m: segments this much farther than the nearest count as equally near
SIDE_STEP_SPACING = 0.1  # m: candidate spots every 0.1 m along each direction, from 0.1 m on
SIDE_STEP_TURN_COST = 0.3  # m of walk a radian away from straight sideways is worth
SIDE_STEP_FAR_COST = 0.05  # per m of walk, against clearance, when no spot is far enough
SIDE_STEP_TIE = 1e-9  # spots and directions this close in distance or cost are as good: the first is taken
# (mirrored directions and walks along the path are exactly as good; the last bit must not choose)
ASIDE_RADIUS = 0.05  # m: the side-step target is reached within this
PASSED_MARGIN = 0.3  # m beyond both radii: the robot has passed the human's spot on its path
RUN_AWAY_MIN_GAP = 0.05  # m: the run-away push is computed as if no closer than this to the robot


def wrap(a: float) -> float:
    return (a + math.pi) % (2 * math.pi) - math.pi


def _target_human(sim: Any, leaf: Any) -> int:
    t = leaf.get("target_id")
    if type(t) is not int or not 0 <= t < sim.crowd.n:
        raise BTRuntimeError(f"{leaf.name}: target_id {t!r} is not a human id (0..{sim.crowd.n - 1})",
                             file=leaf.source, line=leaf.line, hint="ids are 0-based: human1 is 0")
    return t


def robot_bearing(sim: Any, i: int) -> float:
    """Bearing of the robot seen from agent i (reference §0), in (-pi, pi]."""
    d = sim.robot_pos - sim.crowd.pos[i]
    return wrap(math.atan2(d.imag, d.real) - sim.crowd.yaw[i])


# ---- conditions -------------------------------------------------------------------------------
def is_robot_visible(sim: Any, leaf: Any, i: int) -> int:
    return SUCCESS if sim.robot_dist[i] <= leaf.get("distance") and sim.robot_in_sight(i) else FAILURE


def is_robot_nearby(sim: Any, leaf: Any, i: int) -> int:
    return SUCCESS if sim.robot_dist[i] <= leaf.get("distance") else FAILURE


def is_robot_blocking(sim: Any, leaf: Any, i: int) -> int:
    if sim.robot_dist[i] > leaf.get("distance") or abs(robot_bearing(sim, i)) > BLOCKING_CONE:
        return FAILURE
    return SUCCESS if sim.robot_in_sight(i) else FAILURE


def is_goal_reached(sim: Any, leaf: Any, i: int) -> int:
    return SUCCESS if sim.crowd.queues[i].reached(sim.crowd.pos[i]) else FAILURE


def time_expired(sim: Any, leaf: Any, i: int) -> int:
    """Accumulates `ts` per tick of this node instance; SUCCESS once `seconds` are reached (§3.2)."""
    acc = leaf.state.get("acc", 0.0) + leaf.get("ts")
    if acc < leaf.get("seconds"):
        leaf.state["acc"] = acc
        return FAILURE
    leaf.state["acc"] = acc if leaf.get("only_once") else 0.0
    return SUCCESS


def robot_says(sim: Any, leaf: Any, i: int) -> int:
    return SUCCESS if sim.robot_gesture == leaf.get("message") else FAILURE


def robot_said(sim: Any, leaf: Any, i: int) -> int:
    """Latching RobotSays: the robot showed the gesture at some step so far."""
    return SUCCESS if leaf.get("message") in sim.robot_said else FAILURE


def human_says(sim: Any, leaf: Any, i: int) -> int:
    return SUCCESS if sim.crowd.gesture[_target_human(sim, leaf)] == leaf.get("message") else FAILURE


def robot_moved(sim: Any, leaf: Any, i: int) -> int:
    return SUCCESS if abs(sim.robot_vel) > ROBOT_MOVED_SPEED else FAILURE


# ---- actions ----------------------------------------------------------------------------------
def update_goal(sim: Any, leaf: Any, i: int) -> int:
    sim.crowd.queues[i].update_goal()
    sim.crowd.refresh_goal(i)
    return SUCCESS


def make_gesture(sim: Any, leaf: Any, i: int) -> int:
    sim.crowd.gesture[i] = int(leaf.get("message"))
    return SUCCESS


def regular_nav(sim: Any, leaf: Any, i: int) -> int:
    crowd = sim.crowd
    crowd.behavior_state[i] = 0
    if crowd.paused[i]:
        sim.command_stand(i)
    else:
        sim.command_walk_goal(i, v0=crowd.pace[i])
    return SUCCESS


def look_at_robot(sim: Any, leaf: Any, i: int) -> int:
    sim.crowd.behavior_state[i] = 1
    beta = robot_bearing(sim, i)
    limit = LOOK_TURN_RATE * sim.dt
    turn = min(beta, limit) if beta > 0 else (max(beta, -limit) if beta < 0 else 0.0)
    sim.command_turn(i, sim.crowd.yaw[i] + turn)
    return SUCCESS


def _follow(sim: Any, i: int, target: complex, target_radius: float) -> None:
    crowd = sim.crowd
    crowd.behavior_state[i] = 1
    d = target - crowd.pos[i]
    r = abs(d)
    if r <= FOLLOW_STOP:
        sim.command_turn(i, math.atan2(d.imag, d.real))  # face the target, no translation
    else:
        sim.command_walk(i, target, target_radius, FOLLOW_GAIN * r, real_goal=False)


def follow_robot(sim: Any, leaf: Any, i: int) -> int:
    """Follow the robot; a follower standing in the robot's way (ahead of it, on its remaining path) first
    steps aside and lets it pass, as a person told FOLLOW ME by a robot coming up behind does, instead of
    walking up to it and standing 1.5 m in front of it for good."""
    state = sim.give_way[i]
    stepping_aside = state is not None and sim.crowd.behavior_state[i] == 2 and state["phase"] != "resume"
    if stepping_aside or _in_robot_way(sim, i):
        give_way_to_robot(sim, leaf, i)
        if sim.give_way[i]["phase"] != "resume":
            return SUCCESS
    _follow(sim, i, sim.robot_pos, sim.robot_radius)
    return SUCCESS


def _in_robot_way(sim: Any, i: int) -> bool:
    """The human stands on the robot's remaining path, ahead of it within FOLLOW_WAY_AHEAD metres."""
    p = sim.crowd.pos[i]
    if abs(p - sim.robot_pos) > FOLLOW_WAY_AHEAD or abs(sim.robot_pos - sim.robot_waypoints[-1]) <= \
            sim.config.goal_tolerance:
        return False
    _, seg = robot_progress(sim)
    upcoming = np.concatenate([[sim.robot_pos], sim.robot_waypoints[seg + 1:]])
    if len(upcoming) < 2:
        return False
    _, along, dist = _project(p, upcoming[:-1], upcoming[1:])
    k = nearest_segment(dist)
    ahead = float(np.sum(np.abs(upcoming[1:k + 1] - upcoming[:k]))) + float(along[k])
    return bool(dist[k] < float(sim.crowd.radius[i]) + sim.robot_radius + FOLLOW_WAY_MARGIN and ahead > 0.0)


def follow_human(sim: Any, leaf: Any, i: int) -> int:
    t = _target_human(sim, leaf)
    if t != i:
        _follow(sim, i, sim.crowd.pos[t], float(sim.crowd.radius[t]))
    return SUCCESS


def run_away_from_robot(sim: Any, leaf: Any, i: int) -> int:
    crowd = sim.crowd
    crowd.behavior_state[i] = 1
    away = crowd.pos[i] - sim.robot_pos
    r = abs(away)
    extra = 0j
    if r > 1e-9:
        # fork: 20*sigma/(r - R) * unit; we keep it repulsive inside R instead of flipping its sign
        extra = RUN_AWAY_GAIN / max(r - crowd.radius[i], RUN_AWAY_MIN_GAP) * away / r
    sim.command_walk_goal(i, v0=RUN_AWAY_SPEED, extra=extra)
    return SUCCESS


def block_robot(sim: Any, leaf: Any, i: int) -> int:
    sim.crowd.behavior_state[i] = 1
    ahead = sim.robot_pos + BLOCK_AHEAD * complex(math.cos(sim.robot_yaw), math.sin(sim.robot_yaw))
    sim.command_walk(i, ahead, BLOCK_RADIUS, BLOCK_SPEED, real_goal=False)
    sim.face_robot_after_step[i] = BLOCK_FACE
    return SUCCESS


def give_way_to_robot(sim: Any, leaf: Any, i: int) -> int:
    """Step off the robot's UPCOMING path (its remaining waypoints, not only its current heading: after a
    turn the robot drives somewhere else), wait there facing the robot until it has passed, then walk on
    toward the goal. A new episode starts whenever the previous action of this human was something else
    (as the fork recomputes its side step then)."""
    crowd = sim.crowd
    p = crowd.pos[i]
    state = sim.give_way[i]
    if crowd.behavior_state[i] != 2 or state is None:
        crowd.behavior_state[i] = 2
        state = sim.give_way[i] = _plan_side_step(sim, i)
    if state["phase"] != "resume" and _robot_has_passed(sim, i, state):
        state["phase"] = "resume"
    if state["phase"] == "aside" and abs(state["target"] - p) <= GIVE_WAY_ARRIVED:
        state["phase"] = "wait"
    if state["phase"] == "aside":
        sim.command_walk(i, state["target"], ASIDE_RADIUS, float(crowd.max_vel[i]), real_goal=False)
    elif state["phase"] == "wait":
        d = sim.robot_pos - p
        sim.command_turn(i, math.atan2(d.imag, d.real))
    else:
        sim.command_walk_goal(i)
    return SUCCESS


def _robot_has_passed(sim: Any, i: int, state: dict) -> bool:
    """The robot is beyond the point of its path the human stepped away from (or done, or far behind)."""
    if abs(sim.robot_pos - sim.robot_waypoints[-1]) <= sim.config.goal_tolerance:
        return True
    progress, _ = robot_progress(sim)
    clear = sim.crowd.radius[i] + sim.robot_radius + PASSED_MARGIN
    return progress > state["at"] + clear and abs(sim.robot_pos - sim.crowd.pos[i]) > clear


def robot_progress(sim: Any) -> tuple[float, int]:
    """(arc length along the robot's waypoint path, segment index) of the robot's projection on it. Searched
    from the last segment found onward (a path may come back past the same place); cached per step."""
    cache = sim.__dict__.setdefault("_robot_progress", {"t": None, "seg": 0, "value": (0.0, 0)})
    if cache["t"] == sim.t:
        return cache["value"]
    wps = sim.robot_waypoints
    if len(wps) < 2:
        value = (0.0, 0)
    else:
        a, b = wps[:-1], wps[1:]
        lengths = np.abs(b - a)
        offsets = np.concatenate([[0.0], np.cumsum(lengths)[:-1]])
        first = cache["seg"]
        _, along, dist = _project(sim.robot_pos, a[first:], b[first:])
        k = nearest_segment(dist)
        seg = first + k
        value = (float(offsets[seg] + along[k]), seg)
        cache["seg"] = seg
    cache["t"], cache["value"] = sim.t, value
    return value


def nearest_segment(dist: np.ndarray) -> int:
    """The first segment within SEGMENT_TIE of the nearest: a point at a corner of the path is as near to both
    segments that meet there, and which one is "nearer" must not depend on the last bit of the arithmetic
    (numpy's vectorised loops and scalar code round differently; the compiled twin must choose the same)."""
    return int(np.flatnonzero(dist <= dist.min() + SEGMENT_TIE)[0])


def _project(points: Any, a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Closest points of segments a->b to each point: (closest point, distance along the segment, distance)
    with shape (len(points), len(a)) (or (len(a),) for a single point)."""
    pts = np.asarray(points, dtype=complex)[..., None]
    ab = b - a
    length = np.abs(ab)
    unit = np.where(length > 1e-9, ab / np.where(length > 1e-9, length, 1.0), 0)
    along = np.clip(((pts - a) * unit.conjugate()).real, 0.0, length)
    closest = a + unit * along
    return closest, along, np.abs(pts - closest)


def _plan_side_step(sim: Any, i: int) -> dict:
    """Where to stand: the nearest reachable spot (walls respected) that leaves GIVE_WAY_MARGIN between the
    human and the robot all along the robot's remaining path; preferring the side the human is already on.
    When no spot is that far, the one farthest from the path."""
    crowd = sim.crowd
    p = crowd.pos[i]
    radius = float(crowd.radius[i])
    want = radius + sim.robot_radius + GIVE_WAY_MARGIN
    progress, seg = robot_progress(sim)
    wps = sim.robot_waypoints
    upcoming = np.concatenate([[sim.robot_pos], wps[seg + 1:]]) if len(wps) > 1 else np.array([sim.robot_pos])
    if len(upcoming) < 2:
        upcoming = np.array([sim.robot_pos, sim.robot_pos + sim.robot_direction() * 0.01])
    a, b = upcoming[:-1], upcoming[1:]
    _, along, dist = _project(p, a, b)
    k = nearest_segment(dist)
    at = progress + float(np.sum(np.abs(b[:k] - a[:k]))) + float(along[k])  # arc length of the human's spot
    state = {"target": p, "phase": "aside", "at": at}
    if dist[k] >= want:
        return state
    seg_dir = b[k] - a[k]
    seg_dir = seg_dir / abs(seg_dir) if abs(seg_dir) > 1e-9 else sim.robot_direction()
    lateral = ((p - a[k]) * seg_dir.conjugate()).imag
    prefer = seg_dir * 1j * (1.0 if lateral >= 0 else -1.0)  # away from the path on the human's side
    best_key, best = None, p
    for j in range(SIDE_STEP_DIRECTIONS):
        u = prefer * complex(math.cos(2 * math.pi * j / SIDE_STEP_DIRECTIONS),
                             math.sin(2 * math.pi * j / SIDE_STEP_DIRECTIONS))
        room = sim.world.free_along(p, u, SIDE_STEP_MAX, radius)
        if room <= 0.0:
            continue
        s = np.arange(SIDE_STEP_SPACING, room + 1e-9, SIDE_STEP_SPACING)
        if len(s) == 0:
            continue
        spots = p + u * s
        d = _project(spots, a, b)[2].min(axis=1)
        ok = np.flatnonzero(d >= want)
        deviation = abs(math.remainder(2 * math.pi * j / SIDE_STEP_DIRECTIONS, 2 * math.pi))
        if len(ok):
            key = (0, float(s[ok[0]]) + SIDE_STEP_TURN_COST * deviation)  # shortest walk, straight sideways preferred
            spot = spots[ok[0]]
        else:
            m = int(np.flatnonzero(d >= d.max() - SIDE_STEP_TIE)[0])  # the first of the farthest spots
            key = (1, -float(d[m]) + SIDE_STEP_FAR_COST * float(s[m]))
            spot = spots[m]
        if best_key is None or key[0] < best_key[0] or (key[0] == best_key[0] and key[1] < best_key[1] - SIDE_STEP_TIE):
            best_key, best = key, complex(spot)
    state["target"] = best
    return state


IMPLEMENTATIONS: dict[str, Callable[[Any, Any, int], int]] = {
    "IsRobotVisible": is_robot_visible,
    "IsRobotNearby": is_robot_nearby,
    "IsRobotBlocking": is_robot_blocking,
    "IsGoalReached": is_goal_reached,
    "TimeExpiredCondition": time_expired,
    "RobotSays": robot_says,
    "RobotSaid": robot_said,
    "HumanSays": human_says,
    "RobotMoved": robot_moved,
    "UpdateGoal": update_goal,
    "MakeGesture": make_gesture,
    "RegularNav": regular_nav,
    "LookAtRobot": look_at_robot,
    "FollowRobot": follow_robot,
    "FollowHuman": follow_human,
    "RunAwayFromRobot": run_away_from_robot,
    "GiveWaytoRobot": give_way_to_robot,
    "BlockRobot": block_robot,
}
