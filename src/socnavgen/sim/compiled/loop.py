"""The episode loop, compiled: the twin of Simulation.step / _apply_robot / run (sim.engine, the reference,
whose docstring lists the order of a step). The physics and the contacts are sim.kernels' own functions.

K = (labels, sizes, prm, obstacle table, affine) as kernels.advance takes them, and its work array;
cols = the trace columns (pos, vel, yaw, omega, action, succeeded, gesture, behavior state, robot, robot gesture);
cfg = (dt, max steps, idle end, goal tolerance, contact slack, has throttle, has script, has rules).
"""

from __future__ import annotations

import math

from socnavgen.sim.compiled.geometry import clearance_at
from socnavgen.sim.compiled.layout import (
    ERROR,
    HF_FACE_WITHIN,
    HI_ACTION,
    HI_BSTATE,
    HI_FACE,
    HI_GESTURE,
    HI_MOTION,
    HI_QCYCLIC,
    HI_QLEN,
    HI_SIGHT,
    HI_SUCCESS,
    RC_DIR,
    RC_POS,
    RC_VEL,
    RF_DT,
    RF_OMEGA,
    RF_RADIUS,
    RF_T,
    RF_YAW,
    RI_GESTURE,
    RI_SAID,
    RI_STEP,
    SC_BEFORE,
    SC_SNAP,
)
from socnavgen.sim.compiled.motion import goal_reached, pop_goal, refresh_goal
from socnavgen.sim.compiled.robots import PC_HEADING, PI_HAS_HEADING, heading_kind, policy_act
from socnavgen.sim.compiled.script import Q_SAY, rules_gesture, script_update, throttle_update
from socnavgen.sim.compiled.vm import tick_tree
from socnavgen.sim.kernels import GRID_MIN, advance, advance_small, njit, no_alloc, resolve_contacts

REASON_TIMEOUT, REASON_GOAL, REASON_ALL_DONE = 0, 1, 2
CF_DT, CF_MAX_STEPS, CF_IDLE_END, CF_GOAL_TOL, CF_SLACK, CF_THROTTLE, CF_SCRIPT, CF_RULES = range(8)


@no_alloc
def apply_robot(S, W, R, v):  # noqa: ANN001, ANN201
    """Simulation._apply_robot: a move into a wall is refused; the robot faces its policy's heading."""
    rc, rf = S[9], S[10]
    if not (math.isfinite(v.real) and math.isfinite(v.imag)):
        v = 0j
    dt = rf[RF_DT]
    new = rc[RC_POS] + v * dt
    if v != 0 and clearance_at(W, new) < 0.5 * rf[RF_RADIUS]:
        v, new = 0j, rc[RC_POS]
    old_yaw = rf[RF_YAW]
    if abs(v) > 0.05:
        facing = v
        if heading_kind(R[0]) and R[2][PI_HAS_HEADING] == 1 and abs(R[3][PC_HEADING]) > 0:
            facing = R[3][PC_HEADING]
        rf[RF_YAW] = math.atan2(facing.imag, facing.real)
        rc[RC_DIR] = facing / abs(facing)
    rf[RF_OMEGA] = ((rf[RF_YAW] - old_yaw + math.pi) % (2 * math.pi) - math.pi) / dt
    rc[RC_POS], rc[RC_VEL] = new, v


@no_alloc
def before_physics(S, W, P, R, T, C, cfg):  # noqa: ANN001, ANN201
    """Simulation.step up to the physics: pacing, every tree, the script, the robot; ERROR when a tree fails
    (the reference raises there)."""
    cs, bc, hi = S[0], S[4], S[5]
    n = cs.shape[1]
    dt = cfg[CF_DT]
    if n:
        for i in range(n):
            hi[HI_SIGHT][i] = -1
        if cfg[CF_THROTTLE]:
            throttle_update(S, T)
        for i in range(n):
            bc[0][i] = False
            bc[2][i] = False
            hi[HI_ACTION][i] = -1
            hi[HI_MOTION][i] = 0
            hi[HI_SUCCESS][i] = 0
            hi[HI_FACE][i] = 0
        for i in range(n):
            if tick_tree(i, S, W, P, dt) == ERROR:
                return ERROR
    if cfg[CF_SCRIPT]:
        script_update(S, C)
    apply_robot(S, W, R, policy_act(S, W, R, C[5]))
    before = S[16][SC_BEFORE]
    for i in range(n):
        before[i] = cs[0][i]
    return 0


@no_alloc
def after_physics(S, W, C, G, cfg, reached):  # noqa: ANN001, ANN201
    """Simulation.step after the physics: contacts, goals reached, faces turned, the clock, the robot's
    gesture."""
    cs, fs, fc, bc, hi, hf = S[0], S[1], S[3], S[4], S[5], S[6]
    rc, rf, ri = S[9], S[10], S[11]
    n = cs.shape[1]
    if n:
        if resolve_contacts(cs[0], fs[1], bc[0], S[16][SC_BEFORE][:n], rc[RC_POS], rf[RF_RADIUS], rc[RC_DIR], W[0],
                            W[3], cfg[CF_SLACK], S[16][SC_SNAP]):
            for i in range(n):
                fc[3][i] = abs(rc[RC_POS] - cs[0][i])
        if reached:
            for i in range(n):
                if bc[4][i]:
                    pop_goal(S, i, False)
                    refresh_goal(S, i)
        for i in range(n):
            if hi[HI_FACE][i]:
                d = rc[RC_POS] - cs[0][i]
                if abs(d) <= hf[HF_FACE_WITHIN][i]:
                    fs[0][i] = math.atan2(d.imag, d.real)
    rf[RF_T] += cfg[CF_DT]
    ri[RI_STEP] += 1
    say = C[5][Q_SAY]
    if say != 0:
        ri[RI_GESTURE] = int(say)
    elif cfg[CF_RULES]:
        ri[RI_GESTURE] = rules_gesture(S, G)
    elif cfg[CF_SCRIPT]:
        ri[RI_GESTURE] = 0
    if ri[RI_GESTURE] != 0:
        ri[RI_SAID] |= 1 << ri[RI_GESTURE]


@no_alloc
def record(S, cols, k):  # noqa: ANN001, ANN201
    cs, fs, hi, rc, rf, ri = S[0], S[1], S[5], S[9], S[10], S[11]
    for i in range(cs.shape[1]):
        cols[0][k, i], cols[1][k, i], cols[2][k, i], cols[3][k, i] = cs[0][i], cs[1][i], fs[0][i], fs[3][i]
        cols[4][k, i], cols[5][k, i] = hi[HI_ACTION][i], hi[HI_SUCCESS][i]
        cols[6][k, i], cols[7][k, i] = hi[HI_GESTURE][i], hi[HI_BSTATE][i]
    r, v = rc[RC_POS], rc[RC_VEL]
    robot = cols[8]
    robot[k, 0], robot[k, 1], robot[k, 2] = r.real, r.imag, rf[RF_YAW]
    robot[k, 3], robot[k, 4], robot[k, 5] = v.real, v.imag, rf[RF_OMEGA]
    cols[9][k] = ri[RI_GESTURE]


@no_alloc
def human_done(S, i):  # noqa: ANN001, ANN201
    """Crowd.done: no goal left, or only its last goal and standing within reach of it."""
    hi = S[5]
    qlen = hi[HI_QLEN][i]
    if hi[HI_QCYCLIC][i] and qlen > 0:
        return False
    if qlen > 1:
        return False
    return (qlen == 0 or goal_reached(S, i)) and abs(S[0][1][i]) < 0.05


@njit(cache=True)
def run_episode(S, W, P, K, R, T, C, G, cols, cfg, goal):  # noqa: ANN001, ANN201
    """Simulation.run: to the robot's goal, the timeout, or until nothing will change. Returns (steps,
    reason), steps = ERROR when a tree failed. The physics of a small crowd allocates nothing (K's work)."""
    cs, fs, cc, fc, bc, rc = S[0], S[1], S[2], S[3], S[4], S[9]
    labels, sizes, prm, table, affine, work = K
    n = cs.shape[1]
    dt, idle_end, tol = cfg[CF_DT], cfg[CF_IDLE_END], cfg[CF_GOAL_TOL]
    total = int(cfg[CF_MAX_STEPS]) + 1
    record(S, cols, 0)
    reason, idle, k = REASON_TIMEOUT, 0.0, 0
    for k in range(1, total):
        if before_physics(S, W, P, R, T, C, cfg) == ERROR:
            return ERROR, 0
        reached = 0
        if n > GRID_MIN:
            reached = advance(cs, fs, cc, fc, bc, labels, sizes, prm, table, affine, rc[RC_POS], rc[RC_VEL], dt, True)
        elif n:
            reached = advance_small(cs, fs, cc, fc, bc, labels, sizes, prm, table, affine, rc[RC_POS], rc[RC_VEL], dt,
                                    True, work)
        after_physics(S, W, C, G, cfg, reached)
        record(S, cols, k)
        if abs(goal - rc[RC_POS]) <= tol:
            reason = REASON_GOAL
            break
        idle = idle + dt if abs(rc[RC_VEL]) < 1e-3 else 0.0
        if idle >= idle_end and all_done(S):
            reason = REASON_ALL_DONE
            break
    return k + 1, reason


@no_alloc
def all_done(S):  # noqa: ANN001, ANN201
    """Crowd.done for everyone (a loop: numba compiles no generator into all())."""
    for i in range(S[0].shape[1]):  # noqa: SIM110
        if not human_done(S, i):
            return False
    return True
