"""The library's leaves, one function each (semantics: reference §3 plus each NodeSpec.sim_note).

Adding a leaf is one row in the node library (bt/library.py) and one function here (or in people.give_way
for the leaves that may give way or keep someone aside: RegularNav, GiveWaytoRobot, FollowRobot,
RunAwayFromRobot), decorated with
`@leaf("Name")`: the interpreter dispatches to it by the row's position. A leaf gets the simulation state
`s`, its node's record (`node.memory` is its own number to keep), the person `i` it acts for (its agent_id
port) and its ports by name, `a[Port.distance]`; it returns SUCCESS, FAILURE or RUNNING, or
`bad_port(Port.x)` when a port's value cannot be used (the run then stops with the tree's file and line).

Conditions read the step's snapshot; actions do not move anyone themselves: they set the person's motion
command for this step (people.state: walk_to_goal, walk_to, turn, stand), and the walking step moves
everyone at once afterwards, so every tree sees the same snapshot.
"""

from __future__ import annotations

import math
from collections.abc import Callable

from socnavgen.bt.library import BLOCKING_CONE
from socnavgen.sim.jit import jit
from socnavgen.sim.people.avoid import sees
from socnavgen.sim.people.grace import follow_in
from socnavgen.sim.people.routing import head
from socnavgen.sim.people.spots import LOOK, REACH, pick
from socnavgen.sim.people.state import (
    ROUTE_ROBOT,
    STANDING,
    done,
    goal_reached,
    pop_goal,
    turn,
    walk_to,
)
from socnavgen.sim.people.trees import FAILURE, SUCCESS, Port
from socnavgen.sim.trace import ROBOT_BEHAVIOR

LEAVES: dict[str, Callable] = {}
BAD_PORT = -10  # a leaf's status BAD_PORT - column: the port in that column holds an unusable value

# Constants of the SocRATES fork (reference §1.3, §3)
ROBOT_MOVED_SPEED = 0.1  # m/s
# A follower walks at their own pace to close a gap and slows only over the last FOLLOW_SLOWING metres before
# FOLLOW_STOP (along the walkable way, centre to centre), where they stand: people keep 1-1.5 m behind whom they
# follow. (The SocRATES fork's follow speed 1.8 * r / 10 closes a gap at 0.18 m/s per metre: chains of followers
# spread over tens of metres and a follower trails a 0.6 m/s robot by 3.3 m.)
FOLLOW_STOP = 1.3  # m
FOLLOW_SLOWING = 0.7  # m
FOLLOW_MIN_SPEED = 0.1  # m/s: a follower who would walk slower than this stands (no creeping in front of the stop)
RUN_AWAY_SPEED = 0.6  # m/s
RUN_AWAY_GAIN = 20 * 0.2  # 20 * sigma_obs
RUN_AWAY_MIN_GAP = 0.05  # m: the run-away push is computed as if no closer than this to the robot
BLOCK_AHEAD, BLOCK_RADIUS, BLOCK_SPEED, BLOCK_FACE = 1.5, 0.05, 0.5, 0.6
# A blocker stands at her block point: she slows down as she arrives (no faster than sqrt(2 BLOCK_DECEL d) at d m
# from it) and stands once within BLOCK_RADIUS of it, or within BLOCK_HOLD of it and (nearly) still, until the point
# moves off farther (the robot turns or drives). Walking at BLOCK_SPEED all the way, she braked in the point's
# 0.05 m radius, drifted out of it and walked back, the robot's social force pushing her off it: she hovered at
# 0.04-0.14 m/s and never stood (home_01's child).
BLOCK_DECEL = 1.0  # m/s^2
BLOCK_HOLD = 0.25  # m
# LookAtRobot turns 0.01*pi per manager call; Gazebo calls it every 1 ms. We keep that rate per second of
# simulated time (10*pi rad/s, i.e. practically at once) instead of per tick, so dt does not change it.
LOOK_TURN_RATE = 0.01 * math.pi / 0.001


def leaf(name: str) -> Callable[[Callable], Callable]:
    """Register the function of library leaf `name`."""
    def register(fn: Callable) -> Callable:
        LEAVES[name] = compiled = jit(fn)
        return compiled
    return register


@jit
def bad_port(column):  # noqa: ANN001, ANN201
    return BAD_PORT - column


@jit
def wrap(a):  # noqa: ANN001, ANN201
    return (a + math.pi) % (2 * math.pi) - math.pi


@jit
def robot_bearing(s, i):  # noqa: ANN001, ANN201
    """Bearing of the robot seen from person i (reference §0), in (-pi, pi]."""
    d = s.robot[0].pos - s.people[i].pos
    return wrap(math.atan2(d.imag, d.real) - s.people[i].yaw)


@jit
def sees_robot(s, i):  # noqa: ANN001, ANN201
    """Line of sight from person i to the robot, computed at most once per step."""
    return sees(s, i)


@jit
def human(s, a, column, offset):  # noqa: ANN001, ANN201
    """The person a port names (`offset` 1 for HuNavSim 2.x's 1-based ids); -1 when it names nobody."""
    h = a[column] - offset
    return int(h) if h == math.floor(h) and 0 <= h < s.people.shape[0] else -1


# ---- conditions -------------------------------------------------------------------------------------
@leaf("IsRobotVisible")
def is_robot_visible(s, node, i, a):  # noqa: ANN001, ANN201, ARG001
    return SUCCESS if s.people[i].robot_distance <= a[Port.distance] and sees_robot(s, i) else FAILURE


@leaf("IsRobotNearby")
def is_robot_nearby(s, node, i, a):  # noqa: ANN001, ANN201, ARG001
    return SUCCESS if s.people[i].robot_distance <= a[Port.distance] else FAILURE


@leaf("IsRobotBlocking")
def is_robot_blocking(s, node, i, a):  # noqa: ANN001, ANN201, ARG001
    if s.people[i].robot_distance > a[Port.distance] or abs(robot_bearing(s, i)) > BLOCKING_CONE:
        return FAILURE
    return SUCCESS if sees_robot(s, i) else FAILURE


@leaf("IsGoalReached")
def is_goal_reached(s, node, i, a):  # noqa: ANN001, ANN201, ARG001
    return SUCCESS if goal_reached(s.people, s.goals, i) else FAILURE


@leaf("TimeExpiredCondition")
def time_expired(s, node, i, a):  # noqa: ANN001, ANN201, ARG001
    """Accumulates `ts` per tick of this node; SUCCESS once `seconds` are reached (§3.2)."""
    elapsed = node.memory + a[Port.ts]
    if elapsed < a[Port.seconds]:
        node.memory = elapsed
        return FAILURE
    node.memory = elapsed if a[Port.only_once] != 0 else 0.0
    return SUCCESS


@leaf("RobotSays")
def robot_says(s, node, i, a):  # noqa: ANN001, ANN201, ARG001
    return SUCCESS if s.robot[0].gesture == a[Port.message] else FAILURE


@leaf("RobotSaid")
def robot_said(s, node, i, a):  # noqa: ANN001, ANN201, ARG001
    """Latching RobotSays: the robot showed the gesture at some step so far."""
    m = a[Port.message]
    return SUCCESS if 0 <= m < 63 and m == math.floor(m) and (s.robot[0].said >> int(m)) & 1 == 1 else FAILURE


@leaf("HumanSays")
def human_says(s, node, i, a):  # noqa: ANN001, ANN201, ARG001
    h = human(s, a, Port.target_id, 0)
    if h < 0:
        return bad_port(Port.target_id)
    return SUCCESS if s.people[h].gesture == a[Port.message] else FAILURE


@leaf("RobotMoved")
def robot_moved(s, node, i, a):  # noqa: ANN001, ANN201, ARG001
    return SUCCESS if abs(s.robot[0].vel) > ROBOT_MOVED_SPEED else FAILURE


# ---- actions ------------------------------------------------------------------------------------------
@leaf("UpdateGoal")
def update_goal(s, node, i, a):  # noqa: ANN001, ANN201, ARG001
    pop_goal(s.people, s.goals, i, True)
    return SUCCESS


@leaf("MakeGesture")
def make_gesture(s, node, i, a):  # noqa: ANN001, ANN201, ARG001
    s.people[i].gesture = int(a[Port.message])
    return SUCCESS


@jit
def look_at_robot_step(s, i):  # noqa: ANN001, ANN201
    """Stand and turn toward the robot at LOOK_TURN_RATE."""
    s.people[i].behavior = ROBOT_BEHAVIOR
    beta = robot_bearing(s, i)
    limit = LOOK_TURN_RATE * s.clock[0].dt
    step = min(beta, limit) if beta > 0 else (max(beta, -limit) if beta < 0 else 0.0)
    turn(s.people, i, s.people[i].yaw + step)


@leaf("LookAtRobot")
def look_at_robot(s, node, i, a):  # noqa: ANN001, ANN201, ARG001
    look_at_robot_step(s, i)
    return SUCCESS


def follow_trail(leader_speed: float, own_speed: float) -> float:
    """How far (m, along the walkable way) a follower walking at up to `own_speed` keeps behind someone
    walking steadily at `leader_speed` (`follow`)."""
    return FOLLOW_STOP + FOLLOW_SLOWING * min(leader_speed / max(own_speed, 1e-9), 1.0)


@jit(inline=True)
def follow_speed(r, own_speed):  # noqa: ANN001, ANN201
    """A follower's walking speed at distance r (along the walkable way) from whom they follow."""
    return own_speed * min(max((r - FOLLOW_STOP) / FOLLOW_SLOWING, 0.0), 1.0)


@jit
def follow(s, i, target, target_radius, route):  # noqa: ANN001, ANN201
    """Walk toward the target, around walls (`route`: people.routing), at their own pace, slowing over the last
    FOLLOW_SLOWING metres before FOLLOW_STOP (along the walkable way); stand facing it once that is slower than
    FOLLOW_MIN_SPEED."""
    p = s.people[i]
    p.behavior = ROBOT_BEHAVIOR
    _, r = head(s, i, target, route)
    speed = follow_speed(r, p.max_speed)
    if speed < FOLLOW_MIN_SPEED:
        d = target - p.pos
        turn(s.people, i, math.atan2(d.imag, d.real))
    else:
        walk_to(s.people, i, target, target_radius, speed, route)


@jit
def beside(s, i, h):  # noqa: ANN001, ANN201
    """A follower's part once whom they follow stands for good (at the last goal of their walk) within LOOK m:
    they come up to the free spot round them nearest to them, off the robot's way (people.spots.pick), and stand
    there facing them, as two people who walked somewhere together stand side by side, not a trail's length behind
    in file (warehouse_14: a follower stood 30 s in the passage the robot had to take). True when person i does
    that this step; False (no such spot, the leader walks on): they follow as before."""
    p, q = s.people[i], s.people[h]
    if not done(s.people, s.goals, h) or abs(q.pos - p.pos) > LOOK:
        p.has_spot = False
        return False
    # the spot is kept while the leader stands there: a robot coming by does not send them off to another spot
    # (home_16: the seeker re-picked as the robot came near and stepped in front of it)
    if not (p.has_spot and abs(p.spot_for - q.pos) <= REACH):
        found, spot = pick(s, i, q.pos)
        if not found:
            p.has_spot = False
            return False
        p.has_spot, p.spot, p.spot_for = True, spot, q.pos
    p.behavior = ROBOT_BEHAVIOR
    if abs(p.spot - p.pos) <= REACH:
        d = q.pos - p.pos
        turn(s.people, i, math.atan2(d.imag, d.real))
    else:
        walk_to(s.people, i, p.spot, REACH, p.max_speed, h)
    return True


@leaf("FollowHuman")
def follow_human(s, node, i, a):  # noqa: ANN001, ANN201, ARG001
    h = human(s, a, Port.target_id, 0)
    if h < 0:
        return bad_port(Port.target_id)
    if h != i and not follow_in(s, i, h) and not beside(s, i, h):
        follow(s, i, s.people[h].pos, s.people[h].radius, h)
    return SUCCESS


@jit
def push_away(s, i, within):  # noqa: ANN001, ANN201
    """The scared walker's extra force away from the robot (the fork's 20 sigma / (r - R), kept repulsive
    inside R where the fork flips sign); none from `within` metres on."""
    away = s.people[i].pos - s.robot[0].pos
    r = abs(away)
    if 1e-9 < r < within:
        return RUN_AWAY_GAIN / max(r - s.people[i].radius, RUN_AWAY_MIN_GAP) * away / r
    return 0j


@jit
def block(s, i, ahead):  # noqa: ANN001, ANN201
    """Walk to the point `ahead` metres in front of the robot and stand there facing it (slowing down as she
    arrives; she faces it walking once within BLOCK_FACE). Standing, she kept the heading she walked up with: the
    physiotherapist who came from the side to take the towel stood at 50 degrees to the robot (home_18, round 22)."""
    p = s.people[i]
    p.behavior = ROBOT_BEHAVIOR
    point = s.robot[0].pos + ahead * complex(math.cos(s.robot[0].yaw), math.sin(s.robot[0].yaw))
    away = abs(point - p.pos)
    if away <= BLOCK_RADIUS or (away <= BLOCK_HOLD and abs(p.vel) < STANDING):
        d = s.robot[0].pos - p.pos  # stands facing it (people.make_room: standing in its way on purpose)
        turn(s.people, i, math.atan2(d.imag, d.real))
    else:
        walk_to(s.people, i, point, BLOCK_RADIUS, min(BLOCK_SPEED, math.sqrt(2.0 * BLOCK_DECEL * away)), ROUTE_ROBOT)
    p.face_robot_within = BLOCK_FACE


@leaf("BlockRobot")
def block_robot(s, node, i, a):  # noqa: ANN001, ANN201, ARG001
    block(s, i, BLOCK_AHEAD)
    return SUCCESS
