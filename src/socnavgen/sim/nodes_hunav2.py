"""HuNavSim 2.x nodes that socnavgen's hunav2 translations emit (bt.library.HUNAV2), with 2.x semantics,
so that an exported tree can be simulated and verified like its socrates original. Registered into the
simulator's dispatch (sim.nodes.IMPLEMENTATIONS) on import.

Semantics from robotics-upo/hunav_sim (2.x agent manager and node sources; reference §5):
- IsRobotClose: robot centre closer than `threshold` (strict <).
- SaySomething: publishes `message`; here the message is the gesture word, shown as that gesture.
- SurprisedNav: one call of the agent manager's look-at-robot turn (no translation).
- CuriousNav / approximateRobot: within `stop_distance` turn to face the robot; else walk toward it at
  agent_vel * d / (d + stop_distance).
- ThreateningNav / blockRobot: walk to the point `goal_dist` ahead of the robot, face it when close.
- FollowAgent / AvoidRobot: stateful (RUNNING; SUCCESS once `duration` > 0 seconds have passed; 0 = run
  until halted). 2.x measures wall time; the simulator measures simulated time.
  FollowAgent: like CuriousNav with the other agent (target_agent_id is HuNavSim's 1-based id).
  AvoidRobot: goal-directed walking at runaway_vel with a push away from the robot while it is closer
  than safe_distance.
"""

from __future__ import annotations

import math
from typing import Any

from socnavgen.bt.library import HUMAN_GESTURES, HUNAV2_FIRST_AGENT_ID
from socnavgen.sim import nodes
from socnavgen.sim.bt_runtime import FAILURE, RUNNING, SUCCESS, BTRuntimeError

GESTURE_OF_WORD = {word: code for code, word in HUMAN_GESTURES.items()}


def is_robot_close(sim: Any, leaf: Any, i: int) -> int:
    return SUCCESS if sim.robot_dist[i] < leaf.get("threshold") else FAILURE


def say_something(sim: Any, leaf: Any, i: int) -> int:
    sim.crowd.gesture[i] = GESTURE_OF_WORD.get(str(leaf.get("message")).strip(), 0)
    return SUCCESS


def always_success(sim: Any, leaf: Any, i: int) -> int:
    return SUCCESS


def _approach(sim: Any, i: int, target: complex, radius: float, stop: float, max_vel: float) -> None:
    sim.crowd.behavior_state[i] = 1
    d = target - sim.crowd.pos[i]
    r = abs(d)
    if r <= stop:
        sim.command_turn(i, math.atan2(d.imag, d.real))
    else:
        sim.command_walk(i, target, radius, max_vel * r / (r + stop), real_goal=False)


def curious_nav(sim: Any, leaf: Any, i: int) -> int:
    _approach(sim, i, sim.robot_pos, sim.robot_radius, leaf.get("stop_distance"), leaf.get("agent_vel"))
    return SUCCESS


def threatening_nav(sim: Any, leaf: Any, i: int) -> int:
    sim.crowd.behavior_state[i] = 1
    ahead = sim.robot_pos + leaf.get("goal_dist") * complex(math.cos(sim.robot_yaw), math.sin(sim.robot_yaw))
    sim.command_walk(i, ahead, nodes.BLOCK_RADIUS, nodes.BLOCK_SPEED, real_goal=False)
    sim.face_robot_after_step[i] = nodes.BLOCK_FACE
    return SUCCESS


def _timed(sim: Any, leaf: Any) -> int:
    """Stateful 2.x node: RUNNING until `duration` (> 0) seconds of being ticked, then SUCCESS."""
    duration = leaf.get("duration")
    elapsed = leaf.state.get("elapsed", 0.0) + sim.dt
    if duration > 0 and elapsed >= duration:
        leaf.state["elapsed"] = 0.0
        return SUCCESS
    leaf.state["elapsed"] = elapsed
    return RUNNING


def follow_agent(sim: Any, leaf: Any, i: int) -> int:
    t = leaf.get("target_agent_id") - HUNAV2_FIRST_AGENT_ID
    if type(t) is not int or not 0 <= t < sim.crowd.n:
        raise BTRuntimeError(f"FollowAgent: target_agent_id {t + HUNAV2_FIRST_AGENT_ID!r} is not an agent",
                             file=leaf.source, line=leaf.line, hint="HuNavSim ids start at 1")
    if t != i:
        _approach(sim, i, sim.crowd.pos[t], float(sim.crowd.radius[t]), leaf.get("closest_dist"),
                  leaf.get("max_vel"))
    return _timed(sim, leaf)


def avoid_robot(sim: Any, leaf: Any, i: int) -> int:
    crowd = sim.crowd
    crowd.behavior_state[i] = 1
    away = crowd.pos[i] - sim.robot_pos
    r = abs(away)
    extra = 0j
    if 1e-9 < r < leaf.get("safe_distance"):
        extra = nodes.RUN_AWAY_GAIN / max(r - crowd.radius[i], nodes.RUN_AWAY_MIN_GAP) * away / r
    sim.command_walk_goal(i, v0=leaf.get("runaway_vel"), extra=extra)
    return _timed(sim, leaf)


IMPLEMENTATIONS = {
    "IsRobotClose": is_robot_close,
    "SaySomething": say_something,
    "AlwaysSuccess": always_success,
    "SurprisedNav": nodes.look_at_robot,  # the same one-step turn toward the robot
    "CuriousNav": curious_nav,
    "ThreateningNav": threatening_nav,
    "FollowAgent": follow_agent,
    "AvoidRobot": avoid_robot,
}
nodes.IMPLEMENTATIONS.update(IMPLEMENTATIONS)
