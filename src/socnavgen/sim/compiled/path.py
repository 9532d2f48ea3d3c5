"""The robot's path as the leaves see it, and stepping out of its way, compiled: the twins of
nodes.robot_progress, nodes._in_robot_way, nodes._plan_side_step, nodes._robot_has_passed and
nodes.give_way_to_robot (the reference). The upcoming path (the robot, then its waypoints after the
segment it is on) is read through path_point: nothing is allocated."""

from __future__ import annotations

import math

import numpy as np

from socnavgen.sim.compiled.geometry import free_along, np_div, pairwise_sum, project
from socnavgen.sim.compiled.layout import (
    GW_ASIDE,
    GW_RESUME,
    GW_WAIT,
    HC_GW_TARGET,
    HF_GW_AT,
    HF_MAXVEL,
    HI_BSTATE,
    HI_GW,
    HI_GW_PHASE,
    RC_DIR,
    RC_POS,
    RF_GOAL_TOL,
    RF_PROGRESS,
    RF_RADIUS,
    RI_PROGRESS_SEG,
    RI_PROGRESS_STEP,
    RI_SEG,
    RI_STEP,
    SF_A,
    SF_B,
    SF_LEFT,
    SUCCESS,
)
from socnavgen.sim.compiled.motion import turn, walk, walk_goal
from socnavgen.sim.kernels import no_alloc
from socnavgen.sim.nodes import (
    ASIDE_RADIUS,
    FOLLOW_WAY_AHEAD,
    FOLLOW_WAY_MARGIN,
    GIVE_WAY_ARRIVED,
    GIVE_WAY_MARGIN,
    PASSED_MARGIN,
    SEGMENT_TIE,
    SIDE_STEP_DIRECTIONS,
    SIDE_STEP_FAR_COST,
    SIDE_STEP_MAX,
    SIDE_STEP_SPACING,
    SIDE_STEP_TIE,
    SIDE_STEP_TURN_COST,
)

_ANGLES = [2 * math.pi * j / SIDE_STEP_DIRECTIONS for j in range(SIDE_STEP_DIRECTIONS)]
SIDE_UNITS = np.array([complex(math.cos(a), math.sin(a)) for a in _ANGLES])
SIDE_DEVIATIONS = np.array([abs(math.remainder(a, 2 * math.pi)) for a in _ANGLES])


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
        first_ok, far_d = -1, -np.inf
        ds = S[14][SF_B]  # each spot's distance from the path
        for m in range(count):
            spot = p + u * (SIDE_STEP_SPACING + m * SIDE_STEP_SPACING)
            d = np.inf
            for s in range(segments):
                d = min(d, project(spot, path_point(S, seg, s, fallback), path_point(S, seg, s + 1, fallback))[1])
            if d >= want:
                first_ok = m
                break
            ds[m] = d
            far_d = max(far_d, d)
        if first_ok >= 0:
            s_ok = SIDE_STEP_SPACING + first_ok * SIDE_STEP_SPACING
            rank, key, spot = 0, s_ok + SIDE_STEP_TURN_COST * SIDE_DEVIATIONS[j], p + u * s_ok
        else:
            far_m = 0
            while ds[far_m] < far_d - SIDE_STEP_TIE:  # the first of the farthest spots
                far_m += 1
            s_far = SIDE_STEP_SPACING + far_m * SIDE_STEP_SPACING
            rank, key, spot = 1, -ds[far_m] + SIDE_STEP_FAR_COST * s_far, p + u * s_far
        if not found or rank < best_rank or (rank == best_rank and key < best_key - SIDE_STEP_TIE):
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
