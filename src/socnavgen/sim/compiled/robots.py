"""The built-in robot policies, compiled: the twins of sim.robot's ScriptedPolicy, WaypointsPolicy,
SFMPolicy and StraightPolicy (the reference: each function names its twin, the constants are theirs).

R = (kind, pf float (PF_*), pi int64 (PI_*), pc complex (PC_*), sfm float (SP_*)): a policy's parameters
and state; `robot_params` reads them off a policy object (so a policy built with other parameters runs
compiled too) and REGISTRY says which classes have a twin."""

from __future__ import annotations

import math

import numpy as np

from socnavgen.bodies import ROBOT_GOAL_TOLERANCE
from socnavgen.sim.compiled.geometry import (
    clearance_at,
    nearest_obstacle,
    np_div,
    pairwise_sum_complex,
    path_clear,
)
from socnavgen.sim.compiled.layout import (
    RC_POS,
    RC_VEL,
    RF_DT,
    RF_RADIUS,
    RF_YAW,
    SF_A,
    SF_B,
    SF_FLAGS,
    SF_LEFT,
    SF_LEFT_IM,
)
from socnavgen.sim.compiled.script import Q_MISBEHAVE, Q_SPEED, Q_WAIT
from socnavgen.sim.kernels import no_alloc
from socnavgen.sim.robot import (
    AROUND_BIAS,
    AROUND_LOOK,
    CLOSE_REACH,
    GOAL_DECEL,
    KEEP_CLEAR,
    LOOK_WALL,
    NUDGE_BAND,
    NUDGE_ROOM,
    NUDGE_SPEED,
    OCCUPIED_REACH,
    SWEPT_MARGIN,
    WALL_MARGIN,
    WALL_PUSH,
    ScriptedPolicy,
    SFMPolicy,
    StraightPolicy,
    WaypointsPolicy,
)

SCRIPTED, WAYPOINTS, SFM, STRAIGHT = range(4)
REGISTRY = {ScriptedPolicy: SCRIPTED, WaypointsPolicy: WAYPOINTS, SFMPolicy: SFM, StraightPolicy: STRAIGHT}
# pf rows: parameters, state, the two waypoint trackers (main, the scripted robot's rude one)
PF_MAX_SPEED, PF_ACCEL, PF_BRAKE, PF_SLOW_GAP, PF_STOP_GAP, PF_PATIENCE = range(6)
PF_SPEED, PF_WAITED, PF_AROUND_SIDE, PF_AROUND_MAX, PF_RUDE_MAX = range(6, 11)
PF_T1_TOL, PF_T1_CLEAR, PF_T2_TOL, PF_T2_CLEAR = range(11, 15)  # CLEAR NaN: no line clearance
PF_ROWS = 15
PI_T1_INDEX, PI_T2_INDEX, PI_HAS_HEADING = range(3)
PC_HEADING = 0
# sfm rows (SFMParams of the policy, or of the waypoints robot's way around people)
SP_K_DES, SP_TAU, SP_CUTOFF, SP_K_OBS, SP_SIGMA, SP_K_SOC, SP_LAM, SP_GAMMA, SP_N, SP_N_PRIME = range(10)


def _tracker(tracker) -> tuple[float, float, int]:  # noqa: ANN001
    clear = math.nan if tracker.line_clearance is None else float(tracker.line_clearance)
    return float(tracker.tolerance), clear, int(tracker.index)


def _sfm(params) -> np.ndarray:  # noqa: ANN001
    # the cut-off as SFMPolicy.toward reads it: (cutoff or inf)
    return np.array([params.k_des, params.tau, params.cutoff or math.inf, params.k_obs,
                     params.sigma_obs, params.k_soc, params.lam, params.gamma, params.n, params.n_prime])


def robot_params(policy) -> tuple | None:  # noqa: ANN001
    """R for a built-in policy object (its current parameters and state); None without a compiled twin."""
    kind = REGISTRY.get(type(policy))
    if kind is None:
        return None
    pf, pi, pc = np.zeros(PF_ROWS), np.zeros(3, dtype=np.int64), np.zeros(1, dtype=complex)
    pf[PF_T2_CLEAR] = math.nan
    pf[PF_T1_TOL], pf[PF_T1_CLEAR], pi[PI_T1_INDEX] = _tracker(policy.tracker)
    pf[PF_MAX_SPEED] = policy.max_speed
    if kind in (SCRIPTED, WAYPOINTS):
        pf[PF_ACCEL], pf[PF_BRAKE], pf[PF_SLOW_GAP] = policy.accel, policy.brake, policy.slow_gap
        pf[PF_STOP_GAP], pf[PF_PATIENCE] = policy.stop_gap, policy.patience
        pf[PF_SPEED], pf[PF_WAITED], pf[PF_AROUND_SIDE] = policy.speed, policy.waited, policy.around_side
        pf[PF_AROUND_MAX] = policy._around.max_speed
        if policy.heading is not None:
            pi[PI_HAS_HEADING], pc[PC_HEADING] = 1, complex(policy.heading)
        sfm = _sfm(policy._around.params)
    else:
        sfm = _sfm(policy.params) if kind == SFM else _sfm(SFMPolicy().params)
    if kind == SCRIPTED:
        pf[PF_RUDE_MAX] = policy._rude.max_speed
        pf[PF_T2_TOL], pf[PF_T2_CLEAR], pi[PI_T2_INDEX] = _tracker(policy._rude.tracker)
    return (kind, pf, pi, pc, sfm)


def store_params(policy, R: tuple) -> None:  # noqa: ANN001
    """Write the compiled run's final policy state back onto the policy object."""
    kind, pf, pi, pc, _ = R
    policy.tracker.index = int(pi[PI_T1_INDEX])
    if kind in (SCRIPTED, WAYPOINTS):
        policy.speed, policy.waited, policy.around_side = float(pf[PF_SPEED]), float(pf[PF_WAITED]), float(pf[PF_AROUND_SIDE])
        policy.max_speed = float(pf[PF_MAX_SPEED])
        policy.heading = complex(pc[PC_HEADING]) if pi[PI_HAS_HEADING] else None
    if kind == SCRIPTED:
        policy._rude.tracker.index = int(pi[PI_T2_INDEX])


# ---- shared pieces -----------------------------------------------------------------------------------
@no_alloc
def track(S, W, R, second):  # noqa: ANN001, ANN201
    """_WaypointTracker.target: (current waypoint, is it the last), advancing past waypoints reached."""
    pf, pi = R[1], R[2]
    row = PI_T2_INDEX if second else PI_T1_INDEX
    tol = pf[PF_T2_TOL] if second else pf[PF_T1_TOL]
    line = pf[PF_T2_CLEAR] if second else pf[PF_T1_CLEAR]
    wps = S[12]
    last = wps.shape[0] - 1
    p = S[9][RC_POS]
    if last < 0:
        return p, True
    index = min(pi[row], last)
    while index < last:
        d = abs(wps[index] - p)
        if d > tol:
            break
        if not (math.isnan(line) or d <= CLOSE_REACH or path_clear(W, p, wps[index + 1], line)):
            break
        index += 1
    pi[row] = index
    return wps[index], index == last


@no_alloc
def slide_along_walls(S, W, v):  # noqa: ANN001, ANN201
    """robot.slide_along_walls."""
    p, r = S[9][RC_POS], S[10][RF_RADIUS]
    if clearance_at(W, p + v * LOOK_WALL) >= r + WALL_MARGIN:
        return v
    clearance = clearance_at(W, p)
    point, valid = nearest_obstacle(W, p)
    away = p - point
    if not valid or abs(away) < 1e-9:
        return v
    n = away / abs(away)
    into = (v * n.conjugate()).real
    if into < 0:
        v -= into * n
    if clearance < r:
        v += n * min(WALL_PUSH, (r - clearance) * 2.0)
    return v


@no_alloc
def keep_clear(S, v):  # noqa: ANN001, ANN201
    """robot.keep_clear: v without the part that takes the robot within KEEP_CLEAR of a person."""
    cs, fs = S[0], S[1]
    close = S[14][SF_FLAGS]
    n = cs.shape[1]
    if v == 0 or n == 0:
        return v
    p, dt, rr = S[9][RC_POS], S[10][RF_DT], S[10][RF_RADIUS]
    people = cs[0]
    for _ in range(3):
        nxt = p + v * dt
        anyone = False
        for k in range(n):
            close[k] = 1.0 if abs(people[k] - nxt) < fs[1][k] + rr + KEEP_CLEAR else 0.0
            anyone = anyone or close[k] == 1.0
        if not anyone:
            return v
        for k in range(n):
            if close[k] == 0.0:
                continue
            d = people[k] - p
            if abs(d) < 1e-9:
                continue
            u = d / abs(d)
            toward = (v * u.conjugate()).real
            if toward > 0:
                v -= toward * u
    nxt = p + v * dt
    for k in range(n):
        if not abs(people[k] - nxt) >= min(fs[1][k] + rr + KEEP_CLEAR, abs(people[k] - p)):
            return 0j
    return v


@no_alloc
def pair_force(d, dv, sfm):  # noqa: ANN001, ANN201
    """sfm._pair_force for one pair (numpy's order of operations)."""
    dist = abs(d)
    dhat = np_div(d, dist)
    t = sfm[SP_LAM] * dv + dhat
    ell = abs(t)
    that = np_div(t, max(ell, 1e-12))
    b = sfm[SP_GAMMA] * ell
    prod = dhat * that.conjugate()
    theta = math.atan2(prod.imag, prod.real)
    if abs(theta) < 1e-9:
        theta = 0.0
    base = -dist / max(b, 1e-12)
    bt = b * theta
    f_v = math.exp(base - (sfm[SP_N_PRIME] * bt) ** 2)
    sgn = 1.0 if theta > 0 else (-1.0 if theta < 0 else 0.0)
    f_t = sgn * math.exp(base - (sfm[SP_N] * bt) ** 2)
    return -sfm[SP_K_SOC] * that * (f_v + 1j * f_t)


@no_alloc
def sfm_toward(S, W, R, target, max_speed, last):  # noqa: ANN001, ANN201
    """SFMPolicy.toward: one social-force step toward `target`."""
    sfm = R[4]
    cs = S[0]
    p, v, dt = S[9][RC_POS], S[9][RC_VEL], S[10][RF_DT]
    to = target - p
    dist = abs(to)
    if last and dist <= ROBOT_GOAL_TOLERANCE * 0.5:
        return 0j
    v0 = min(max_speed, math.sqrt(2 * GOAL_DECEL * dist)) if last else max_speed
    force = sfm[SP_K_DES] * (v0 * to / max(dist, 1e-9) - v) / sfm[SP_TAU]
    n = cs.shape[1]
    if n:
        sf = S[14]
        m = 0
        for i in range(n):
            d = cs[0][i] - p
            if abs(d) <= sfm[SP_CUTOFF]:
                f = pair_force(d, v - cs[1][i], sfm)
                sf[SF_A][m], sf[SF_B][m] = f.real, f.imag
                m += 1
        if m:
            force += pairwise_sum_complex(sf[SF_A], sf[SF_B], m, S[15], sf[SF_LEFT], sf[SF_LEFT_IM])
    point, valid = nearest_obstacle(W, p)
    if valid:
        dd = p - point
        r = abs(dd)
        if r > 1e-9:
            force += np_div(sfm[SP_K_OBS] * math.exp(-(r - S[10][RF_RADIUS]) / sfm[SP_SIGMA]) * dd, r)
    v = v + force * dt
    if abs(v) > v0:
        v = v * (v0 / abs(v))
    return v


# ---- the policies --------------------------------------------------------------------------------------
@no_alloc
def look_ahead(S, R, direction, reach):  # noqa: ANN001, ANN201
    """WaypointsPolicy.look_ahead: (free distance to the nearest person in the swept path, sideways nudge)."""
    pf = R[1]
    cs, fs = S[0], S[1]
    p, rr = S[9][RC_POS], S[10][RF_RADIUS]
    back = direction.conjugate()
    slow_gap = pf[PF_SLOW_GAP]
    n = cs.shape[1]
    gap, nudge_at, nudge = np.inf, np.inf, 0.0
    for i in range(n):
        q, r = cs[0][i], fs[1][i]
        if n > 32 and not abs(q - p) < slow_gap + 2.0:
            continue
        rel = (q - p) * back
        if rel.real <= 0:
            continue
        ahead = rel.real - r - rr
        margin = SWEPT_MARGIN if ahead > 0 else 0.0
        across = abs(rel.imag) if rel.real <= reach else abs(rel - reach)
        if across < r + rr + margin and ahead < gap:
            gap = ahead
        side = abs(rel.imag)
        if r + rr + margin <= side < r + rr + NUDGE_BAND and ahead < slow_gap and ahead < nudge_at:
            nudge_at, nudge = ahead, (-1.0 if rel.imag > 0 else 1.0)
    return gap, nudge


@no_alloc
def reachable_goal(S, goal):  # noqa: ANN001, ANN201
    """WaypointsPolicy._reachable_goal: where to stop when someone stands next to the goal, and how close."""
    cs, fs = S[0], S[1]
    n = cs.shape[1]
    if n == 0:
        return goal, ROBOT_GOAL_TOLERANCE * 0.5
    k, best = 0, np.inf
    for i in range(n):
        key = abs(cs[0][i] - goal) - fs[1][i]
        if key < best:
            k, best = i, key
    dk = abs(cs[0][k] - goal)
    if dk >= fs[1][k] + S[10][RF_RADIUS] + SWEPT_MARGIN + 0.1 or dk < 1e-6:
        return goal, ROBOT_GOAL_TOLERANCE * 0.5
    away = (goal - cs[0][k]) / dk
    return goal + away * ROBOT_GOAL_TOLERANCE * 0.75, ROBOT_GOAL_TOLERANCE * 0.15


@no_alloc
def skip_occupied_waypoint(S, W, R):  # noqa: ANN001, ANN201
    """WaypointsPolicy._skip_occupied_waypoint."""
    pi = R[2]
    wps, k, p = S[12], R[2][PI_T1_INDEX], S[9][RC_POS]
    cs, fs, rr = S[0], S[1], S[10][RF_RADIUS]
    if k >= wps.shape[0] - 1 or abs(wps[k] - p) > OCCUPIED_REACH or cs.shape[1] == 0:
        return False
    occupied = False
    for i in range(cs.shape[1]):
        if abs(cs[0][i] - wps[k]) < fs[1][i] + rr + SWEPT_MARGIN:
            occupied = True
    if occupied and path_clear(W, p, wps[k + 1], 0.5 * rr + 0.05):
        pi[PI_T1_INDEX] = k + 1
        return True
    return False


@no_alloc
def waypoints_act(S, W, R):  # noqa: ANN001, ANN201, C901
    """WaypointsPolicy.act."""
    pf, pi, pc = R[1], R[2], R[3]
    target, last = track(S, W, R, False)
    p, dt = S[9][RC_POS], S[10][RF_DT]
    arrive = ROBOT_GOAL_TOLERANCE * 0.5
    if last and abs(target - p) < pf[PF_SLOW_GAP] + 1.0:
        target, arrive = reachable_goal(S, target)
    to = target - p
    dist = abs(to)
    if last and dist <= arrive:
        pf[PF_SPEED] = 0.0
        return 0j
    yaw = S[10][RF_YAW]
    direction = to / dist if dist > 1e-9 else complex(math.cos(yaw), math.sin(yaw))
    pi[PI_HAS_HEADING], pc[PC_HEADING] = 1, direction
    gap, nudge = look_ahead(S, R, direction, dist if last else np.inf)
    slow, stop = pf[PF_SLOW_GAP], pf[PF_STOP_GAP]
    want = pf[PF_MAX_SPEED] * min(1.0, max(0.0, (gap - stop) / (slow - stop)))
    if last:
        want = min(want, math.sqrt(2 * pf[PF_ACCEL] * dist))
    blocked = gap - stop < 0.1 and (not last or dist > gap + 0.5)
    pf[PF_WAITED] = pf[PF_WAITED] + dt if blocked else 0.0
    if not blocked:
        pf[PF_AROUND_SIDE] = 0.0
    if blocked and pf[PF_WAITED] >= pf[PF_PATIENCE]:
        if skip_occupied_waypoint(S, W, R):
            pf[PF_WAITED] = 0.0
        else:
            if not pf[PF_AROUND_SIDE]:
                left = clearance_at(W, p + direction * 1j * 1 * AROUND_LOOK)
                right = clearance_at(W, p + direction * 1j * -1 * AROUND_LOOK)
                pf[PF_AROUND_SIDE] = 1.0 if left > right + 0.05 else -1.0
            v = sfm_toward(S, W, R, target, pf[PF_AROUND_MAX], False)
            if abs(v) < AROUND_BIAS:
                v += direction * 1j * pf[PF_AROUND_SIDE] * AROUND_BIAS
            v = slide_along_walls(S, W, v)
            pf[PF_SPEED] = abs(v)
            if pf[PF_SPEED] > 0.05:
                pc[PC_HEADING] = v / pf[PF_SPEED]
            return v
    speed = pf[PF_SPEED]
    speed = min(want, speed + pf[PF_ACCEL] * dt) if want >= speed else max(want, speed - pf[PF_BRAKE] * dt)
    pf[PF_SPEED] = speed
    v = direction * speed
    if nudge:
        side = direction * 1j * nudge
        if clearance_at(W, p + side * NUDGE_ROOM) >= S[10][RF_RADIUS] + 0.1:
            v += side * NUDGE_SPEED
    return slide_along_walls(S, W, v)


@no_alloc
def straight_act(S, W, R, max_speed, second):  # noqa: ANN001, ANN201
    """StraightPolicy.act."""
    target, last = track(S, W, R, second)
    to = target - S[9][RC_POS]
    dist = abs(to)
    if last and dist <= ROBOT_GOAL_TOLERANCE * 0.5:
        return 0j
    speed = min(max_speed, math.sqrt(2 * GOAL_DECEL * dist)) if last else max_speed
    return slide_along_walls(S, W, to / max(dist, 1e-9) * speed)


@no_alloc
def policy_act(S, W, R, cues):  # noqa: ANN001, ANN201
    """The policy's velocity command for this step (its `act`)."""
    kind, pf = R[0], R[1]
    if kind == STRAIGHT:
        return straight_act(S, W, R, pf[PF_MAX_SPEED], False)
    if kind == SFM:
        target, last = track(S, W, R, False)
        return keep_clear(S, sfm_toward(S, W, R, target, pf[PF_MAX_SPEED], last))
    if kind == WAYPOINTS:
        return waypoints_act(S, W, R)
    # SCRIPTED (ScriptedPolicy.act)
    if cues[Q_MISBEHAVE] != 0:
        return straight_act(S, W, R, pf[PF_RUDE_MAX], True)
    pf[PF_MAX_SPEED] = cues[Q_SPEED]
    if cues[Q_WAIT] != 0:
        pf[PF_SPEED] = 0.0
        return 0j
    first = waypoints_act(S, W, R)
    v = first
    target, _ = track(S, W, R, False)
    ahead = target - S[9][RC_POS]
    if abs(ahead) > 1e-9 and (v * (ahead / abs(ahead)).conjugate()).real < 0:
        v -= (v * (ahead / abs(ahead)).conjugate()).real * ahead / abs(ahead)
    v = keep_clear(S, v)
    if abs(v) < abs(first) - 1e-9:
        pf[PF_SPEED] = min(pf[PF_SPEED], abs(v))
    return v


@no_alloc
def heading_kind(kind):  # noqa: ANN001, ANN201
    """Whether the policy has a `heading` the engine faces (the waypoints family)."""
    return kind in (SCRIPTED, WAYPOINTS)
