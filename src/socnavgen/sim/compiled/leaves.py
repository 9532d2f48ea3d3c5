"""The library's leaves, compiled: the twins of sim.nodes and sim.nodes_hunav2 (the reference; each
function here names its twin, and the constants are theirs). A leaf sets motion commands for this step and
returns SUCCESS, FAILURE, RUNNING or ERROR (the reference would raise: the compiled run gives up)."""

from __future__ import annotations

import math

import numpy as np

from socnavgen.bt.library import HUMAN_GESTURES, HUNAV2_FIRST_AGENT_ID, leaf_nodes
from socnavgen.sim.agents import GOAL_SLACK
from socnavgen.sim.compiled.geometry import free_along, line_of_sight, np_div, pairwise_sum, project
from socnavgen.sim.compiled.layout import (
    ERROR,
    FAILURE,
    GW_ASIDE,
    GW_RESUME,
    GW_WAIT,
    HC_GW_TARGET,
    HF_FACE_WITHIN,
    HF_GW_AT,
    HF_MAXVEL,
    HF_PACE,
    HI_BSTATE,
    HI_FACE,
    HI_GESTURE,
    HI_GW,
    HI_GW_PHASE,
    HI_PAUSED,
    HI_QCYCLIC,
    HI_QLEN,
    HI_QSTART,
    HI_SIGHT,
    PORT_LITERAL,
    RC_DIR,
    RC_POS,
    RC_VEL,
    RF_GOAL_TOL,
    RF_PROGRESS,
    RF_RADIUS,
    RF_YAW,
    RI_GESTURE,
    RI_PROGRESS_SEG,
    RI_PROGRESS_STEP,
    RI_SAID,
    RI_SEG,
    RI_STEP,
    RUNNING,
    SF_A,
    SF_LEFT,
    SUCCESS,
    T_INT,
    T_UNSET,
)
from socnavgen.sim.kernels import no_alloc
from socnavgen.sim.nodes import (
    ASIDE_RADIUS,
    BLOCK_AHEAD,
    BLOCK_FACE,
    BLOCK_RADIUS,
    BLOCK_SPEED,
    BLOCKING_CONE,
    FOLLOW_GAIN,
    FOLLOW_STOP,
    FOLLOW_WAY_AHEAD,
    FOLLOW_WAY_MARGIN,
    GIVE_WAY_ARRIVED,
    GIVE_WAY_MARGIN,
    LOOK_TURN_RATE,
    PASSED_MARGIN,
    ROBOT_MOVED_SPEED,
    RUN_AWAY_GAIN,
    RUN_AWAY_MIN_GAP,
    RUN_AWAY_SPEED,
    SEGMENT_TIE,
    SIDE_STEP_DIRECTIONS,
    SIDE_STEP_FAR_COST,
    SIDE_STEP_MAX,
    SIDE_STEP_SPACING,
    SIDE_STEP_TURN_COST,
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

# GiveWaytoRobot's side-step directions and how far each turns from straight sideways (nodes._plan_side_step)
_ANGLES = [2 * math.pi * j / SIDE_STEP_DIRECTIONS for j in range(SIDE_STEP_DIRECTIONS)]
SIDE_UNITS = np.array([complex(math.cos(a), math.sin(a)) for a in _ANGLES])
SIDE_DEVIATIONS = np.array([abs(math.remainder(a, 2 * math.pi)) for a in _ANGLES])
PI2 = 2 * math.pi


@no_alloc
def wrap(a):  # noqa: ANN001, ANN201
    return (a + math.pi) % PI2 - math.pi


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


# ---- commands (Simulation.command_*) ------------------------------------------------------------------
@no_alloc
def walk_goal(S, i, v0, extra):  # noqa: ANN001, ANN201
    fc, bc, cc = S[3], S[4], S[2]
    bc[0][i] = True
    bc[1][i] = True
    fc[1][i] = v0
    cc[1][i] = extra
    bc[2][i] = False


@no_alloc
def walk(S, i, target, radius, v0):  # noqa: ANN001, ANN201
    fc, bc, cc = S[3], S[4], S[2]
    bc[0][i] = True
    bc[1][i] = False
    cc[0][i] = target
    fc[0][i] = radius
    fc[1][i] = v0
    cc[1][i] = 0j
    bc[2][i] = False


@no_alloc
def turn(S, i, yaw):  # noqa: ANN001, ANN201
    S[4][0][i] = False
    S[4][2][i] = True
    S[3][2][i] = yaw


@no_alloc
def stand(S, i):  # noqa: ANN001, ANN201
    S[4][0][i] = False
    S[4][2][i] = False


# ---- goal queues (agents.GoalQueue as a ring per human) ------------------------------------------------
@no_alloc
def refresh_goal(S, i):  # noqa: ANN001, ANN201
    """Crowd.refresh_goal."""
    cs, bc, hi, qbuf = S[0], S[4], S[5], S[8]
    if hi[HI_QLEN][i] > 0:
        bc[3][i] = True
        cs[2][i] = qbuf[i, hi[HI_QSTART][i]]
    else:
        bc[3][i] = False
        cs[2][i] = cs[0][i]


@no_alloc
def pop_goal(S, i, keep_last):  # noqa: ANN001, ANN201
    """GoalQueue.update_goal (keep_last) / consume: drop the front (not the only one with keep_last);
    a cyclic queue appends it again."""
    hi, qbuf = S[5], S[8]
    n = hi[HI_QLEN][i]
    if n == 0:
        return
    cap = qbuf.shape[1]
    start = hi[HI_QSTART][i]
    g = qbuf[i, start]
    if not keep_last or n != 1:
        start = (start + 1) % cap
        n -= 1
    if hi[HI_QCYCLIC][i]:
        qbuf[i, (start + n) % cap] = g
        n += 1
    hi[HI_QSTART][i] = start
    hi[HI_QLEN][i] = n


@no_alloc
def goal_reached(S, i):  # noqa: ANN001, ANN201
    """GoalQueue.reached (IsGoalReached)."""
    cs, fs, hi, qbuf = S[0], S[1], S[5], S[8]
    return hi[HI_QLEN][i] > 0 and abs(qbuf[i, hi[HI_QSTART][i]] - cs[0][i]) <= fs[2][i] + GOAL_SLACK


# ---- queries ----------------------------------------------------------------------------------------
@no_alloc
def in_sight(S, W, i):  # noqa: ANN001, ANN201
    """Simulation.robot_in_sight: computed at most once per human and step."""
    hi = S[5]
    seen = hi[HI_SIGHT][i]
    if seen < 0:
        seen = 1 if line_of_sight(W, S[9][RC_POS], S[0][0][i]) else 0
        hi[HI_SIGHT][i] = seen
    return seen == 1


@no_alloc
def bearing(S, i):  # noqa: ANN001, ANN201
    """nodes.robot_bearing."""
    d = S[9][RC_POS] - S[0][0][i]
    return wrap(math.atan2(d.imag, d.real) - S[1][0][i])


@no_alloc
def robot_progress(S):  # noqa: ANN001, ANN201
    """nodes.robot_progress: (arc length, segment) of the robot's projection on its path, searched from the
    last segment found; once per step."""
    rf, ri, wps, wpoff = S[10], S[11], S[12], S[13]
    if ri[RI_PROGRESS_STEP] == ri[RI_STEP]:
        return rf[RF_PROGRESS], ri[RI_PROGRESS_SEG]
    value, seg = 0.0, 0
    if wps.shape[0] >= 2:
        rp = S[9][RC_POS]
        first = ri[RI_SEG]
        nearest = np.inf
        for s in range(first, wps.shape[0] - 1):
            nearest = min(nearest, project(rp, wps[s], wps[s + 1])[1])
        for s in range(first, wps.shape[0] - 1):  # nodes.nearest_segment: the first within the tie
            along, dist = project(rp, wps[s], wps[s + 1])
            if dist <= nearest + SEGMENT_TIE:
                seg, value = s, wpoff[s] + along
                break
        ri[RI_SEG] = seg
    ri[RI_PROGRESS_STEP] = ri[RI_STEP]
    rf[RF_PROGRESS], ri[RI_PROGRESS_SEG] = value, seg
    return value, seg


@no_alloc
def path_size(S, seg, fallback):  # noqa: ANN001, ANN201
    """Points of the robot's upcoming path: its position, then its waypoints after segment `seg`
    (`fallback`: its position and a point 1 cm ahead, as _plan_side_step uses when there is no path)."""
    return 2 if fallback else max(S[12].shape[0] - seg, 1)


@no_alloc
def path_point(S, seg, j, fallback):  # noqa: ANN001, ANN201
    rp = S[9][RC_POS]
    if fallback:
        return rp if j == 0 else rp + S[9][RC_DIR] * 0.01
    return rp if j == 0 else S[12][seg + j]


@no_alloc
def nearest_segment(S, p, seg, fallback):  # noqa: ANN001, ANN201
    """(index, along, distance) of the upcoming path's segment nearest to p (nodes.nearest_segment: the
    first within SEGMENT_TIE of the nearest)."""
    nearest = np.inf
    for s in range(path_size(S, seg, fallback) - 1):
        nearest = min(nearest, project(p, path_point(S, seg, s, fallback), path_point(S, seg, s + 1, fallback))[1])
    for s in range(path_size(S, seg, fallback) - 1):
        along, dist = project(p, path_point(S, seg, s, fallback), path_point(S, seg, s + 1, fallback))
        if dist <= nearest + SEGMENT_TIE:
            return s, along, dist
    return 0, 0.0, np.inf


@no_alloc
def arc_before(S, seg, k, fallback):  # noqa: ANN001, ANN201
    """np.sum(np.abs(b[:k] - a[:k])) over the upcoming path's first k segments."""
    lengths = S[14][SF_A]
    for j in range(k):
        lengths[j] = abs(path_point(S, seg, j + 1, fallback) - path_point(S, seg, j, fallback))
    return pairwise_sum(lengths, 0, k, S[15], S[14][SF_LEFT])


@no_alloc
def in_robot_way(S, i):  # noqa: ANN001, ANN201
    """nodes._in_robot_way."""
    p, rp, wps = S[0][0][i], S[9][RC_POS], S[12]
    if abs(p - rp) > FOLLOW_WAY_AHEAD or abs(rp - wps[wps.shape[0] - 1]) <= S[10][RF_GOAL_TOL]:
        return False
    _, seg = robot_progress(S)
    if path_size(S, seg, False) < 2:
        return False
    k, along, dist = nearest_segment(S, p, seg, False)
    ahead = arc_before(S, seg, k, False) + along
    return dist < S[1][1][i] + S[10][RF_RADIUS] + FOLLOW_WAY_MARGIN and ahead > 0.0


# ---- give way (nodes.give_way_to_robot, _plan_side_step, _robot_has_passed) ------------------------------
@no_alloc
def plan_side_step(S, W, i):  # noqa: ANN001, ANN201
    """nodes._plan_side_step: sets the human's give-way target, phase and arc position."""
    cs, fs, hi, hf, hc = S[0], S[1], S[5], S[6], S[7]
    p = cs[0][i]
    radius = fs[1][i]
    want = radius + S[10][RF_RADIUS] + GIVE_WAY_MARGIN
    progress, seg = robot_progress(S)
    fallback = path_size(S, seg, False) < 2
    k, along, dist = nearest_segment(S, p, seg, fallback)
    hf[HF_GW_AT][i] = progress + arc_before(S, seg, k, fallback) + along
    hi[HI_GW_PHASE][i] = GW_ASIDE
    hc[HC_GW_TARGET][i] = p
    if dist >= want:
        return
    a_k, b_k = path_point(S, seg, k, fallback), path_point(S, seg, k + 1, fallback)
    seg_dir = b_k - a_k
    seg_dir = np_div(seg_dir, abs(seg_dir)) if abs(seg_dir) > 1e-9 else S[9][RC_DIR]
    lateral = ((p - a_k) * seg_dir.conjugate()).imag
    prefer = seg_dir * 1j * (1.0 if lateral >= 0 else -1.0)
    segments = path_size(S, seg, fallback) - 1
    found, best_rank, best_key, best = False, 0, 0.0, p
    for j in range(SIDE_STEP_DIRECTIONS):
        u = prefer * SIDE_UNITS[j]
        room = free_along(W, p, u, SIDE_STEP_MAX, radius)
        if room <= 0.0:
            continue
        # len(np.arange(SPACING, room + 1e-9, SPACING)); its values are SPACING + m * SPACING
        count = int(math.ceil((room + 1e-9 - SIDE_STEP_SPACING) / SIDE_STEP_SPACING))
        if count <= 0:
            continue
        first_ok, far_m, far_d = -1, 0, -np.inf
        for m in range(count):
            spot = p + u * (SIDE_STEP_SPACING + m * SIDE_STEP_SPACING)
            d = np.inf
            for s in range(segments):
                d = min(d, project(spot, path_point(S, seg, s, fallback), path_point(S, seg, s + 1, fallback))[1])
            if d >= want:
                first_ok = m
                break
            if d > far_d:
                far_m, far_d = m, d
        if first_ok >= 0:
            s_ok = SIDE_STEP_SPACING + first_ok * SIDE_STEP_SPACING
            rank, key, spot = 0, s_ok + SIDE_STEP_TURN_COST * SIDE_DEVIATIONS[j], p + u * s_ok
        else:
            s_far = SIDE_STEP_SPACING + far_m * SIDE_STEP_SPACING
            rank, key, spot = 1, -far_d + SIDE_STEP_FAR_COST * s_far, p + u * s_far
        if not found or rank < best_rank or (rank == best_rank and key < best_key):
            found, best_rank, best_key, best = True, rank, key, spot
    hc[HC_GW_TARGET][i] = best


@no_alloc
def robot_has_passed(S, i):  # noqa: ANN001, ANN201
    rp, wps, rf = S[9][RC_POS], S[12], S[10]
    if abs(rp - wps[wps.shape[0] - 1]) <= rf[RF_GOAL_TOL]:
        return True
    progress, _ = robot_progress(S)
    clear = S[1][1][i] + rf[RF_RADIUS] + PASSED_MARGIN
    return progress > S[6][HF_GW_AT][i] + clear and abs(rp - S[0][0][i]) > clear


@no_alloc
def give_way(S, W, i):  # noqa: ANN001, ANN201
    cs, hi, hf, hc = S[0], S[5], S[6], S[7]
    p = cs[0][i]
    if hi[HI_BSTATE][i] != 2 or hi[HI_GW][i] == 0:
        hi[HI_BSTATE][i] = 2
        hi[HI_GW][i] = 1
        plan_side_step(S, W, i)
    if hi[HI_GW_PHASE][i] != GW_RESUME and robot_has_passed(S, i):
        hi[HI_GW_PHASE][i] = GW_RESUME
    target = hc[HC_GW_TARGET][i]
    if hi[HI_GW_PHASE][i] == GW_ASIDE and abs(target - p) <= GIVE_WAY_ARRIVED:
        hi[HI_GW_PHASE][i] = GW_WAIT
    phase = hi[HI_GW_PHASE][i]
    if phase == GW_ASIDE:
        walk(S, i, target, ASIDE_RADIUS, hf[HF_MAXVEL][i])
    elif phase == GW_WAIT:
        d = S[9][RC_POS] - p
        turn(S, i, math.atan2(d.imag, d.real))
    else:
        walk_goal(S, i, hf[HF_MAXVEL][i], 0j)
    return SUCCESS


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


@no_alloc
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
