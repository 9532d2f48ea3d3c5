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

from socnavgen.sim.bt_runtime import FAILURE, SUCCESS, BTRuntimeError

# Constants of the SocRATES fork (reference §1.3, §3)
BLOCKING_CONE = 0.5  # rad
ROBOT_MOVED_SPEED = 0.1  # m/s
FOLLOW_STOP = 1.5  # m
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
        sim.command_walk_goal(i)
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
    _follow(sim, i, sim.robot_pos, sim.robot_radius)
    return SUCCESS


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
        extra = RUN_AWAY_GAIN / max(r - crowd.radius[i], 0.05) * away / r
    sim.command_walk_goal(i, v0=RUN_AWAY_SPEED, extra=extra)
    return SUCCESS


def block_robot(sim: Any, leaf: Any, i: int) -> int:
    sim.crowd.behavior_state[i] = 1
    ahead = sim.robot_pos + BLOCK_AHEAD * complex(math.cos(sim.robot_yaw), math.sin(sim.robot_yaw))
    sim.command_walk(i, ahead, BLOCK_RADIUS, BLOCK_SPEED, real_goal=False)
    sim.face_robot_after_step[i] = BLOCK_FACE
    return SUCCESS


def give_way_to_robot(sim: Any, leaf: Any, i: int) -> int:
    """Step to the side of the robot's path (the side the human is on, unless a wall is there), wait there
    while the robot passes, then walk on toward the goal. A new episode starts whenever the previous
    action of this human was something else (as the fork recomputes its side step then)."""
    crowd = sim.crowd
    p = crowd.pos[i]
    state = sim.give_way[i]
    if crowd.behavior_state[i] != 2 or state is None:
        crowd.behavior_state[i] = 2
        state = sim.give_way[i] = _plan_side_step(sim, i)
    u = state["dir"]
    rel = p - sim.robot_pos
    along = (rel * u.conjugate()).real  # > 0: the human is still ahead of the robot
    clear = crowd.radius[i] + sim.robot_radius + 0.3
    if state["phase"] != "resume" and (along < -clear or abs(rel) > 6.0 and along < 0):
        state["phase"] = "resume"
    if state["phase"] == "aside" and abs(state["target"] - p) <= GIVE_WAY_ARRIVED:
        state["phase"] = "wait"
    if state["phase"] == "aside":
        sim.command_walk(i, state["target"], 0.05, float(crowd.max_vel[i]), real_goal=False)
    elif state["phase"] == "wait":
        d = sim.robot_pos - p
        sim.command_turn(i, math.atan2(d.imag, d.real))
    else:
        sim.command_walk_goal(i)
    return SUCCESS


def _plan_side_step(sim: Any, i: int) -> dict:
    crowd = sim.crowd
    p = crowd.pos[i]
    u = sim.robot_direction()
    rel = p - sim.robot_pos
    lateral = (rel * u.conjugate()).imag  # > 0: human on the robot's left
    want = crowd.radius[i] + sim.robot_radius + GIVE_WAY_MARGIN
    radius = float(crowd.radius[i])
    best = None
    sides = (1.0, -1.0) if lateral >= 0 else (-1.0, 1.0)
    for side in sides:
        normal = u * 1j * side
        need = max(0.0, want - side * lateral)  # distance to walk along this normal
        room = sim.world.free_along(p, normal, need, radius) if need > 0 else 0.0
        final = side * lateral + room  # resulting distance from the robot's path on this side
        if best is None or final > best[0] + 1e-6:
            best = (final, p + normal * room)
        if room >= need - 1e-6:
            break
    return {"dir": u, "target": best[1], "phase": "aside"}


IMPLEMENTATIONS: dict[str, Callable[[Any, Any, int], int]] = {
    "IsRobotVisible": is_robot_visible,
    "IsRobotNearby": is_robot_nearby,
    "IsRobotBlocking": is_robot_blocking,
    "IsGoalReached": is_goal_reached,
    "TimeExpiredCondition": time_expired,
    "RobotSays": robot_says,
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
