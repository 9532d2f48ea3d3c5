"""Pacing, the robot's script and its gesture rules, compiled: the twins of sim.interaction
(InteractionThrottle), sim.gestures (RobotScriptRunner, ScriptedGestures, person_in_way). Arrays are built
by compiled.lower; the cue log records (time, cue, event) and is turned into the reference's text there.

T (throttle) = (ti int64 (TI_*, held), points complex (held, goals), goal_is_node bool (held, goals),
               robot_goal_is_node bool (held, robot goals), robot_points complex, cumulative float,
               conf float (TC_*), state int64 (TS_*: k, enabled, rule, held count))
C (cues)     = (ci int64 (C, CI_*), cf float (C, CF_*), points complex (C,), state int64 (C, CS_*),
               times float (C, CT_*), cue_state float (Q_*), log_t float (E,), log_i int64 (E, 2),
               counts int64 (log entries, cues))
G (rules)    = (gi int64 (R, 2: when, gesture), gf float (R, 2: distance, duration), points complex (R,),
               has point bool (R,), last_true float (R,))
"""

from __future__ import annotations

import math

import numpy as np

from socnavgen.sim.compiled.layout import (
    HF_MAXVEL,
    HF_PACE,
    HI_BSTATE,
    HI_FIRST_PAUSE,
    HI_GESTURE,
    HI_PAUSED,
    HI_PAUSED_STEPS,
    HI_QLEN,
    HI_QSTART,
    RC_DIR,
    RC_POS,
    RF_RADIUS,
    RF_T,
    RI_STEP,
)
from socnavgen.sim.gestures import CLEAR_DISTANCE, CLEAR_PATIENCE, CLEAR_REPEATS, FRONT_CONE, SWEPT_MARGIN
from socnavgen.sim.kernels import no_alloc

# throttle
TI_AGENT, TI_GOALS, TI_NODE_AT, TI_SPAWN_IS_NODE, TI_ROBOT_INDEX = range(5)
TC_WAYPOINT_RADIUS, TC_RELEASE, TC_ROBOT_SPEED, TC_MIN_PACE, TC_ROBOT_NEAR = range(5)
TS_K, TS_ENABLED, TS_RULE, TS_HELD = range(4)
RULE_ETA, RULE_SOCRATES = 0, 1
# cues
WHEN_START, WHEN_AFTER, WHEN_AT_ENCOUNTER, WHEN_BLOCKED, WHEN_HUMAN_WITHIN, WHEN_HUMAN_SAYS = range(6)
CUE_WHEN = {"start": WHEN_START, "after": WHEN_AFTER, "at_encounter": WHEN_AT_ENCOUNTER, "blocked": WHEN_BLOCKED,
            "human_within": WHEN_HUMAN_WITHIN, "human_says": WHEN_HUMAN_SAYS}
CI_WHEN, CI_WHO, CI_PHRASE, CI_SAY, CI_ONCE, CI_UNTIL_CLEAR, CI_HAS_POINT = range(7)
CF_SECONDS, CF_DISTANCE, CF_HOLD, CF_WAIT, CF_SPEED = range(5)  # CF_SPEED NaN: no speed change
CS_FIRED, CS_WAS_TRUE, CS_UNTIL_CLEAR, CS_REPEATS = range(4)
CT_SAY_UNTIL, CT_WAIT_UNTIL, CT_CLEAR_SINCE = range(3)
Q_SAY, Q_WAIT, Q_SPEED, Q_MISBEHAVE = range(4)
LOG_FIRED, LOG_ASK_AGAIN, LOG_GIVE_UP = range(3)
# gesture rules
RULE_WHEN = {"always": 0, "at_node": 1, "near_human": 2, "blocked": 3}


@no_alloc
def person_in_way(S, distance, swept_only):  # noqa: ANN001, ANN201
    """gestures.person_in_way."""
    cs, fs = S[0], S[1]
    rp, rdir, rr = S[9][RC_POS], S[9][RC_DIR], S[10][RF_RADIUS]
    back = rdir.conjugate()
    for i in range(cs.shape[1]):
        rel = cs[0][i] - rp
        if not abs(rel) <= distance:
            continue
        local = rel * back
        swept = local.real > 0 and abs(local.imag) < fs[1][i] + rr + SWEPT_MARGIN
        if swept or (not swept_only and abs(math.atan2(local.imag, local.real)) <= FRONT_CONE):
            return True
    return False


# ---- interaction throttle ------------------------------------------------------------------------------
@no_alloc
def throttle_update(S, T):  # noqa: ANN001, ANN201
    """InteractionThrottle.update: advance the robot's waypoint index, set paused and pace of the held."""
    ti, points, goal_is_node, robot_goal_is_node, rpoints, cumulative, conf, ts = T
    if ts[TS_ENABLED] == 0 or ts[TS_HELD] == 0:
        return
    cs, hi, hf, rdist = S[0], S[5], S[6], S[3][3]
    rp = S[9][RC_POS]
    k = ts[TS_K]
    while k < rpoints.shape[0] - 1 and abs(rpoints[k] - rp) <= conf[TC_WAYPOINT_RADIUS]:
        k += 1
    ts[TS_K] = k
    for h in range(ts[TS_HELD]):
        i = ti[TI_AGENT, h]
        qlen = hi[HI_QLEN][i]
        idx = ti[TI_GOALS, h] - qlen
        if ts[TS_RULE] == RULE_SOCRATES:
            if qlen == 0 or (qlen == 1 and abs(S[8][i, hi[HI_QSTART][i]] - cs[0][i]) <= S[1][2][i]):
                continue
            next_is_node = goal_is_node[h, idx] if 0 <= idx < ti[TI_GOALS, h] else False
            ri = ti[TI_ROBOT_INDEX, h]
            pause = (hi[HI_BSTATE][i] == 0 and rdist[i] > conf[TC_RELEASE]
                     and (next_is_node or ti[TI_SPAWN_IS_NODE, h] == 1) and k < ri and not robot_goal_is_node[h, k])
            hi[HI_PAUSED][i] = pause
        else:
            pause, pace = False, hf[HF_MAXVEL][i]
            node_at = ti[TI_NODE_AT, h]
            ri = ti[TI_ROBOT_INDEX, h]
            robot_left = 0.0 if k > ri else abs(rpoints[k] - rp) + cumulative[ri] - cumulative[k]
            spawn_is_node = ti[TI_SPAWN_IS_NODE, h] == 1
            if (hi[HI_BSTATE][i] == 0 and qlen > 0 and idx >= 0 and (idx <= node_at or spawn_is_node)
                    and robot_left > conf[TC_ROBOT_NEAR] and rdist[i] > conf[TC_RELEASE]):
                if spawn_is_node or idx > node_at:
                    human_left = abs(rpoints[ri] - cs[0][i])
                else:
                    rest = 0.0
                    for j in range(idx, node_at):
                        rest += abs(points[h, j + 1] - points[h, j])
                    human_left = abs(points[h, idx] - cs[0][i]) + rest
                eta = robot_left / max(conf[TC_ROBOT_SPEED], 1e-3)
                want = human_left / max(eta, 1e-3)
                if want < conf[TC_MIN_PACE]:
                    pause = True
                else:
                    pace = min(pace, want)
            hi[HI_PAUSED][i] = pause
            hf[HF_PACE][i] = pace
        if pause:
            if hi[HI_PAUSED_STEPS][i] == 0:
                hi[HI_FIRST_PAUSE][i] = S[11][RI_STEP]
            hi[HI_PAUSED_STEPS][i] += 1


# ---- the robot's script --------------------------------------------------------------------------------
@no_alloc
def cue_holds(c, S, C):  # noqa: ANN001, ANN201
    """RobotScriptRunner._holds."""
    ci, cf, cpoints = C[0], C[1], C[2]
    when = ci[c, CI_WHEN]
    cs, rp = S[0], S[9][RC_POS]
    n = cs.shape[1]
    if when == WHEN_START:
        return True
    if when == WHEN_AFTER:
        return S[10][RF_T] >= cf[c, CF_SECONDS]
    if when == WHEN_AT_ENCOUNTER:
        return ci[c, CI_HAS_POINT] == 1 and abs(cpoints[c] - rp) <= cf[c, CF_DISTANCE]
    if when == WHEN_BLOCKED:
        return person_in_way(S, cf[c, CF_DISTANCE], False)
    who = ci[c, CI_WHO]
    if who >= n:
        who = -1
    for i in range(n):
        if who >= 0 and i != who:
            continue
        if when == WHEN_HUMAN_WITHIN:
            if abs(cs[0][i] - rp) <= cf[c, CF_DISTANCE]:
                return True
        elif S[5][HI_GESTURE][i] == ci[c, CI_PHRASE]:
            return True
    return False


@no_alloc
def _log(C, t, c, event):  # noqa: ANN001, ANN201
    log_t, log_i, log_n = C[6], C[7], C[8]
    m = log_n[0]
    if m < log_t.shape[0]:
        log_t[m] = t
        log_i[m, 0], log_i[m, 1] = c, event
    log_n[0] = m + 1


@no_alloc
def script_update(S, C):  # noqa: ANN001, ANN201
    """RobotScriptRunner.update: fire the cues whose trigger became true, then what the robot says, whether
    it waits and its cruise speed (C's cue_state)."""
    ci, cf, state, times, q = C[0], C[1], C[3], C[4], C[5]
    t = S[10][RF_T]
    ncues = C[8][1]  # ci has one unused row when there are no cues
    for c in range(ncues):
        now = cue_holds(c, S, C)
        rising = now and state[c, CS_WAS_TRUE] == 0
        state[c, CS_WAS_TRUE] = 1 if now else 0
        if not rising or (ci[c, CI_ONCE] == 1 and state[c, CS_FIRED] > 0):
            continue
        state[c, CS_FIRED] += 1
        if ci[c, CI_SAY] != 0:
            times[c, CT_SAY_UNTIL] = t + cf[c, CF_HOLD]
        if cf[c, CF_WAIT] != 0:
            times[c, CT_WAIT_UNTIL] = t + cf[c, CF_WAIT]
        state[c, CS_UNTIL_CLEAR] = ci[c, CI_UNTIL_CLEAR]
        times[c, CT_CLEAR_SINCE] = t
        state[c, CS_REPEATS] = 0
        if not math.isnan(cf[c, CF_SPEED]):
            q[Q_SPEED] = cf[c, CF_SPEED]
        _log(C, t, c, LOG_FIRED)
    say, wait = 0, False
    for c in range(ncues):
        if ci[c, CI_SAY] != 0 and t < times[c, CT_SAY_UNTIL]:
            say = ci[c, CI_SAY]
        if t < times[c, CT_WAIT_UNTIL]:
            wait = True
        elif state[c, CS_UNTIL_CLEAR] == 1:
            blocked = person_in_way(S, max(cf[c, CF_DISTANCE], CLEAR_DISTANCE), True)
            state[c, CS_UNTIL_CLEAR] = 1 if blocked else 0
            if blocked and t - times[c, CT_CLEAR_SINCE] >= CLEAR_PATIENCE:
                if ci[c, CI_SAY] != 0 and state[c, CS_REPEATS] < CLEAR_REPEATS:
                    state[c, CS_REPEATS] += 1
                    times[c, CT_CLEAR_SINCE] = t
                    times[c, CT_SAY_UNTIL] = t + cf[c, CF_HOLD]
                    _log(C, t, c, LOG_ASK_AGAIN)
                else:
                    state[c, CS_UNTIL_CLEAR] = 0
                    _log(C, t, c, LOG_GIVE_UP)
            wait = wait or state[c, CS_UNTIL_CLEAR] == 1
    q[Q_SAY] = say
    q[Q_WAIT] = 1.0 if wait else 0.0


@no_alloc
def rules_gesture(S, G):  # noqa: ANN001, ANN201
    """ScriptedGestures.gesture: the first rule whose condition held within its last `duration` seconds."""
    gi, gf, gpoints, has_point, last_true = G
    t = S[10][RF_T]
    cs, rp = S[0], S[9][RC_POS]
    n = cs.shape[1]
    for r in range(gi.shape[0]):
        when = gi[r, 0]
        if when == 0:
            holds = True
        elif when == 1:
            holds = has_point[r] and abs(gpoints[r] - rp) <= 1.0
        elif n == 0:
            holds = False
        elif when == 2:
            holds = False
            for i in range(n):
                if abs(cs[0][i] - rp) <= gf[r, 0]:
                    holds = True
        else:
            holds = person_in_way(S, gf[r, 0], False)
        if holds:
            last_true[r] = t
        if t - last_true[r] <= gf[r, 1]:
            return gi[r, 1]
    return 0


def empty_rules() -> tuple:
    """G for a simulation without gesture rules."""
    return (np.zeros((0, 2), dtype=np.int64), np.zeros((0, 2)), np.zeros(0, dtype=complex), np.zeros(0, dtype=bool),
            np.zeros(0))
