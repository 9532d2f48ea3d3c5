"""The library's leaves, compiled: the twins of sim.nodes and sim.nodes_hunav2 (the reference; each
function here names its twin, and the constants are theirs). A leaf sets motion commands for this step and
returns SUCCESS, FAILURE, RUNNING or ERROR (the reference would raise: the compiled run gives up)."""

from __future__ import annotations

import math

import numpy as np

from socnavgen.bt.library import HUMAN_GESTURES, HUNAV2_FIRST_AGENT_ID, leaf_nodes
from socnavgen.sim.compiled.geometry import np_div
from socnavgen.sim.compiled.layout import (
    ERROR,
    FAILURE,
    GW_RESUME,
    HF_FACE_WITHIN,
    HF_PACE,
    HI_BSTATE,
    HI_FACE,
    HI_GESTURE,
    HI_GW,
    HI_GW_PHASE,
    HI_PAUSED,
    PORT_LITERAL,
    RC_POS,
    RC_VEL,
    RF_RADIUS,
    RF_YAW,
    RI_GESTURE,
    RI_SAID,
    RUNNING,
    SUCCESS,
    T_INT,
    T_UNSET,
)
from socnavgen.sim.compiled.motion import (
    bearing,
    goal_reached,
    in_sight,
    pop_goal,
    refresh_goal,
    stand,
    turn,
    walk,
    walk_goal,
)
from socnavgen.sim.compiled.path import give_way, in_robot_way
from socnavgen.sim.kernels import no_alloc
from socnavgen.sim.nodes import (
    BLOCK_AHEAD,
    BLOCK_FACE,
    BLOCK_RADIUS,
    BLOCK_SPEED,
    BLOCKING_CONE,
    FOLLOW_GAIN,
    FOLLOW_STOP,
    LOOK_TURN_RATE,
    ROBOT_MOVED_SPEED,
    RUN_AWAY_GAIN,
    RUN_AWAY_MIN_GAP,
    RUN_AWAY_SPEED,
)

LEAF_NAMES = [n.name for n in leaf_nodes()]
PORT_NAMES = {n.name: [p.name for p in n.ports if p.name != "name"] for n in leaf_nodes()}
MAX_PORTS = max(len(p) for p in PORT_NAMES.values())
GESTURE_OF_WORD = {word: code for code, word in HUMAN_GESTURES.items()}  # SaySomething (nodes_hunav2)


def _code(name: str) -> int:
    return LEAF_NAMES.index(name)


def _port(leaf: str, port: str) -> int:
    return PORT_NAMES[leaf].index(port)


# leaf codes (the node library's order: the trace's node_names) and the ports each one reads
IS_ROBOT_VISIBLE, IS_ROBOT_NEARBY, IS_ROBOT_BLOCKING = _code("IsRobotVisible"), _code("IsRobotNearby"), _code("IsRobotBlocking")
IS_GOAL_REACHED, TIME_EXPIRED, ROBOT_SAYS = _code("IsGoalReached"), _code("TimeExpiredCondition"), _code("RobotSays")
ROBOT_SAID, HUMAN_SAYS, ROBOT_MOVED = _code("RobotSaid"), _code("HumanSays"), _code("RobotMoved")
UPDATE_GOAL, MAKE_GESTURE, REGULAR_NAV = _code("UpdateGoal"), _code("MakeGesture"), _code("RegularNav")
LOOK_AT_ROBOT, FOLLOW_ROBOT, FOLLOW_HUMAN = _code("LookAtRobot"), _code("FollowRobot"), _code("FollowHuman")
RUN_AWAY, GIVE_WAY, BLOCK_ROBOT = _code("RunAwayFromRobot"), _code("GiveWaytoRobot"), _code("BlockRobot")
IS_ROBOT_CLOSE, SAY_SOMETHING, ALWAYS_SUCCESS = _code("IsRobotClose"), _code("SaySomething"), _code("AlwaysSuccess")
SURPRISED_NAV, CURIOUS_NAV, THREATENING_NAV = _code("SurprisedNav"), _code("CuriousNav"), _code("ThreateningNav")
FOLLOW_AGENT, AVOID_ROBOT = _code("FollowAgent"), _code("AvoidRobot")
P_DISTANCE = _port("IsRobotVisible", "distance")
assert P_DISTANCE == _port("IsRobotNearby", "distance") == _port("IsRobotBlocking", "distance")
P_SECONDS, P_TS, P_ONLY_ONCE = (_port("TimeExpiredCondition", p) for p in ("seconds", "ts", "only_once"))
P_MESSAGE = _port("RobotSays", "message")
assert P_MESSAGE == _port("RobotSaid", "message") == _port("MakeGesture", "message") == _port("SaySomething", "message")
P_TARGET, P_TARGET_MESSAGE = _port("HumanSays", "target_id"), _port("HumanSays", "message")
P_FOLLOW_TARGET = _port("FollowHuman", "target_id")
P_THRESHOLD = _port("IsRobotClose", "threshold")
P_STOP, P_AGENT_VEL = _port("CuriousNav", "stop_distance"), _port("CuriousNav", "agent_vel")
P_GOAL_DIST = _port("ThreateningNav", "goal_dist")
P_TARGET_AGENT, P_CLOSEST, P_MAX_VEL, P_FA_DURATION = (_port("FollowAgent", p) for p in
                                                        ("target_agent_id", "closest_dist", "max_vel", "duration"))
P_SAFE, P_RUNAWAY_VEL, P_AR_DURATION = (_port("AvoidRobot", p) for p in ("safe_distance", "runaway_vel", "duration"))


@no_alloc
def port(P, k, p):  # noqa: ANN001, ANN201
    """(value, type) of port p of node k; type < 0 where the reference's Leaf.get would raise."""
    s = P[3][k, p]
    if s >= 0:
        t = P[7][s]
        return P[6][s], (t if t != T_UNSET else -1)
    if s == PORT_LITERAL:
        return P[4][k, p], P[5][k, p]
    return 0.0, -1


@no_alloc
def follow(S, i, target, target_radius):  # noqa: ANN001, ANN201
    """nodes._follow."""
    S[5][HI_BSTATE][i] = 1
    d = target - S[0][0][i]
    r = abs(d)
    if r <= FOLLOW_STOP:
        turn(S, i, math.atan2(d.imag, d.real))
    else:
        walk(S, i, target, target_radius, FOLLOW_GAIN * r)


@no_alloc
def approach(S, i, target, radius, stop, max_vel):  # noqa: ANN001, ANN201
    """nodes_hunav2._approach."""
    S[5][HI_BSTATE][i] = 1
    d = target - S[0][0][i]
    r = abs(d)
    if r <= stop:
        turn(S, i, math.atan2(d.imag, d.real))
    else:
        walk(S, i, target, radius, max_vel * r / (r + stop))


@no_alloc
def push_away(S, i, gain_limit):  # noqa: ANN001, ANN201
    """RunAwayFromRobot's / AvoidRobot's extra force away from the robot (0 from `gain_limit` metres on)."""
    away = S[0][0][i] - S[9][RC_POS]
    r = abs(away)
    if 1e-9 < r < gain_limit:
        return np_div(RUN_AWAY_GAIN / max(r - S[1][1][i], RUN_AWAY_MIN_GAP) * away, r)
    return 0j


@no_alloc
def timed(P, k, p_duration, dt):  # noqa: ANN001, ANN201
    """nodes_hunav2._timed."""
    duration, t = port(P, k, p_duration)
    if t < 0:
        return ERROR
    elapsed = P[2][k] + dt
    if duration > 0 and elapsed >= duration:
        P[2][k] = 0.0
        return SUCCESS
    P[2][k] = elapsed
    return RUNNING


@no_alloc
def human_port(P, k, p, n, offset):  # noqa: ANN001, ANN201
    """An agent-id port (`target_id`; FollowAgent's 1-based id with offset 1) that must name a human."""
    v, t = port(P, k, p)
    if t != T_INT:
        return -1
    h = int(v) - offset
    return h if 0 <= h < n else -1


@no_alloc(inline=True)
def tick_leaf(code, k, i, S, W, P, dt):  # noqa: ANN001, ANN201, C901
    """One leaf of the library for agent i (sim.nodes / sim.nodes_hunav2: IMPLEMENTATIONS)."""
    cs, fs, hi, hf, rc, rf, ri = S[0], S[1], S[5], S[6], S[9], S[10], S[11]
    n = cs.shape[1]
    rdist = S[3][3]
    if code in (IS_ROBOT_VISIBLE, IS_ROBOT_NEARBY, IS_ROBOT_BLOCKING):
        d, t = port(P, k, P_DISTANCE)
        if t < 0:
            return ERROR
        if rdist[i] > d:
            return FAILURE
        if code == IS_ROBOT_NEARBY:
            return SUCCESS
        if code == IS_ROBOT_BLOCKING and abs(bearing(S, i)) > BLOCKING_CONE:
            return FAILURE
        return SUCCESS if in_sight(S, W, i) else FAILURE
    if code == IS_GOAL_REACHED:
        return SUCCESS if goal_reached(S, i) else FAILURE
    if code == TIME_EXPIRED:
        ts, t1 = port(P, k, P_TS)
        seconds, t2 = port(P, k, P_SECONDS)
        if t1 < 0 or t2 < 0:
            return ERROR
        acc = P[2][k] + ts
        if acc < seconds:
            P[2][k] = acc
            return FAILURE
        once, t3 = port(P, k, P_ONLY_ONCE)
        if t3 < 0:
            return ERROR
        P[2][k] = acc if once != 0 else 0.0
        return SUCCESS
    if code in (ROBOT_SAYS, ROBOT_SAID):
        m, t = port(P, k, P_MESSAGE)
        if t < 0:
            return ERROR
        if code == ROBOT_SAYS:
            return SUCCESS if ri[RI_GESTURE] == m else FAILURE
        said = 0 <= m < 63 and m == int(m) and (ri[RI_SAID] >> int(m)) & 1 == 1
        return SUCCESS if said else FAILURE
    if code == HUMAN_SAYS:
        h = human_port(P, k, P_TARGET, n, 0)
        m, t = port(P, k, P_TARGET_MESSAGE)
        if h < 0 or t < 0:
            return ERROR
        return SUCCESS if hi[HI_GESTURE][h] == m else FAILURE
    if code == ROBOT_MOVED:
        return SUCCESS if abs(rc[RC_VEL]) > ROBOT_MOVED_SPEED else FAILURE
    if code == IS_ROBOT_CLOSE:
        d, t = port(P, k, P_THRESHOLD)
        if t < 0:
            return ERROR
        return SUCCESS if rdist[i] < d else FAILURE
    if code == ALWAYS_SUCCESS:
        return SUCCESS
    if code == UPDATE_GOAL:
        pop_goal(S, i, True)
        refresh_goal(S, i)
        return SUCCESS
    if code in (MAKE_GESTURE, SAY_SOMETHING):
        m, t = port(P, k, P_MESSAGE)
        if t < 0:
            return ERROR
        hi[HI_GESTURE][i] = int(m)
        return SUCCESS
    if code == REGULAR_NAV:
        hi[HI_BSTATE][i] = 0
        if hi[HI_PAUSED][i]:
            stand(S, i)
        else:
            walk_goal(S, i, hf[HF_PACE][i], 0j)
        return SUCCESS
    if code in (LOOK_AT_ROBOT, SURPRISED_NAV):
        hi[HI_BSTATE][i] = 1
        beta = bearing(S, i)
        limit = LOOK_TURN_RATE * dt
        step = min(beta, limit) if beta > 0 else (max(beta, -limit) if beta < 0 else 0.0)
        turn(S, i, fs[0][i] + step)
        return SUCCESS
    if code == FOLLOW_ROBOT:
        aside = hi[HI_GW][i] == 1 and hi[HI_BSTATE][i] == 2 and hi[HI_GW_PHASE][i] != GW_RESUME
        if aside or in_robot_way(S, i):
            give_way(S, W, i)
            if hi[HI_GW_PHASE][i] != GW_RESUME:
                return SUCCESS
        follow(S, i, rc[RC_POS], rf[RF_RADIUS])
        return SUCCESS
    if code == FOLLOW_HUMAN:
        h = human_port(P, k, P_FOLLOW_TARGET, n, 0)
        if h < 0:
            return ERROR
        if h != i:
            follow(S, i, cs[0][h], fs[1][h])
        return SUCCESS
    if code == RUN_AWAY:
        hi[HI_BSTATE][i] = 1
        walk_goal(S, i, RUN_AWAY_SPEED, push_away(S, i, np.inf))
        return SUCCESS
    if code == GIVE_WAY:
        return give_way(S, W, i)
    if code in (BLOCK_ROBOT, THREATENING_NAV):
        ahead_m = BLOCK_AHEAD
        if code == THREATENING_NAV:
            ahead_m, t = port(P, k, P_GOAL_DIST)
            if t < 0:
                return ERROR
        hi[HI_BSTATE][i] = 1
        yaw = rf[RF_YAW]
        walk(S, i, rc[RC_POS] + ahead_m * complex(math.cos(yaw), math.sin(yaw)), BLOCK_RADIUS, BLOCK_SPEED)
        hi[HI_FACE][i] = 1
        hf[HF_FACE_WITHIN][i] = BLOCK_FACE
        return SUCCESS
    if code == CURIOUS_NAV:
        stop, t1 = port(P, k, P_STOP)
        vel, t2 = port(P, k, P_AGENT_VEL)
        if t1 < 0 or t2 < 0:
            return ERROR
        approach(S, i, rc[RC_POS], rf[RF_RADIUS], stop, vel)
        return SUCCESS
    if code == FOLLOW_AGENT:
        h = human_port(P, k, P_TARGET_AGENT, n, HUNAV2_FIRST_AGENT_ID)
        if h < 0:
            return ERROR
        if h != i:
            closest, t1 = port(P, k, P_CLOSEST)
            vel, t2 = port(P, k, P_MAX_VEL)
            if t1 < 0 or t2 < 0:
                return ERROR
            approach(S, i, cs[0][h], fs[1][h], closest, vel)
        return timed(P, k, P_FA_DURATION, dt)
    if code == AVOID_ROBOT:
        hi[HI_BSTATE][i] = 1
        safe, t1 = port(P, k, P_SAFE)
        vel, t2 = port(P, k, P_RUNAWAY_VEL)
        if t1 < 0 or t2 < 0:
            return ERROR
        walk_goal(S, i, vel, push_away(S, i, safe))
        return timed(P, k, P_AR_DURATION, dt)
    return ERROR
