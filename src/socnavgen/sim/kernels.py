"""Compiled per-step physics (numba, when installed): one call per simulation step.

numpy pays about a microsecond per call whatever the array size, a step of a 5-person scene needs
~100 of them, and a numba call pays per argument, so state travels in a few packed arrays. The
arithmetic is the same as `socnavgen.sim.sfm` (the readable reference and the fallback without
numba); tests/sim/test_kernels.py checks both paths give the same trace.

Packed layout (rows of (k, n) arrays, one column per human):
  cs  complex: 0 pos, 1 vel, 2 goal (front of the queue)
  fs  float:   0 yaw, 1 radius, 2 goal radius, 3 omega
  cc  complex: 0 command target, 1 extra force, 2 environment force (out)
  fc  float:   0 target radius, 1 desired speed v0, 2 turn yaw, 3 distance to the robot (out)
  bc  bool:    0 walks, 1 target is the real goal, 2 turns on the spot, 3 has a goal, 4 reached goal (out)
  prm: k_des, tau, k_gaze, k_coh, k_rep, k_obs, sigma_obs, k_soc, lambda, gamma, n, n', cutoff,
       obstacle range, has obstacles (0/1), metres per pixel
"""

from __future__ import annotations

import math
import os

import numpy as np

try:  # pragma: no cover - depends on the environment
    if os.environ.get("SOCNAVGEN_NO_NUMBA"):
        raise ImportError("disabled by SOCNAVGEN_NO_NUMBA")
    from numba import njit

    AVAILABLE = True
except ImportError:  # pragma: no cover
    AVAILABLE = False

    def njit(*args, **kwargs):  # noqa: ANN002, ANN003, ANN201 - identity decorator
        if args and callable(args[0]):
            return args[0]
        return lambda f: f


def no_alloc(fn=None, *, inline: bool = False):  # noqa: ANN001, ANN201
    """Compile a function that creates no array (and returns none) without reference counting (numba's
    _nrt=False): the compiled episode calls such helpers millions of times, and the reference counts of the
    arrays they touch cost ~40 ns per call where the call itself inlines to nothing. `inline`: numba inlines
    the function into its callers (for a big function called per step with the state tuples, whose arrays
    would otherwise be passed field by field on every call)."""
    if fn is None:
        return lambda f: no_alloc(f, inline=inline)
    options = {"inline": "always"} if inline else {}
    return njit(cache=True, _nrt=False, **options)(fn)


GRID_MIN = 64  # above this many humans, neighbours come from a grid of cut-off sized cells (linear cost)


@njit(cache=True, inline="always")
def _pair(d, dv, cut2, k_soc, lam, gamma, nn, npr):  # noqa: ANN001, ANN202
    """Social force on i from j (reference §6.4) for d = p_j - p_i, dv = v_i - v_j; 0 beyond the cut-off."""
    d2 = d.real * d.real + d.imag * d.imag
    if d2 == 0.0 or d2 > cut2:
        return 0j
    dist = math.sqrt(d2)
    dhat = d / dist
    t = lam * dv + dhat
    ell = abs(t)
    that = t / max(ell, 1e-12)
    b = gamma * ell
    prod = dhat * that.conjugate()
    theta = math.atan2(prod.imag, prod.real)
    if abs(theta) < 1e-9:  # f_theta jumps at 0 (sign): round-off must not pick a side
        theta = 0.0
    base = -dist / max(b, 1e-12)
    bt = b * theta
    f_v = math.exp(base - (npr * bt) ** 2)
    sgn = 1.0 if theta > 0 else (-1.0 if theta < 0 else 0.0)
    f_t = sgn * math.exp(base - (nn * bt) ** 2)
    return -k_soc * that * (f_v + 1j * f_t)


@njit(cache=True)
def _social_grid(pos, vel, cutoff, k_soc, lam, gamma, nn, npr, out):  # noqa: ANN001, ANN202
    """Human-human social forces with a uniform grid of cut-off sized cells: each agent only looks at the
    3 x 3 cells around it, so the cost grows linearly with the crowd at a given density."""
    n = pos.shape[0]
    xs, ys = pos.real, pos.imag
    x0, y0 = xs.min(), ys.min()
    nx = int((xs.max() - x0) / cutoff) + 1
    ny = int((ys.max() - y0) / cutoff) + 1
    if nx * ny > 4_000_000:  # absurdly sparse crowd: fall back to all pairs
        nx, ny = 1, 1
        cx = np.zeros(n, dtype=np.int64)
        cy = np.zeros(n, dtype=np.int64)
    else:
        cx = ((xs - x0) / cutoff).astype(np.int64)
        cy = ((ys - y0) / cutoff).astype(np.int64)
    cid = cx + nx * cy
    order = np.argsort(cid, kind="mergesort")
    start = np.zeros(nx * ny + 1, dtype=np.int64)
    for k in range(n):
        start[cid[k] + 1] += 1
    for c in range(nx * ny):
        start[c + 1] += start[c]
    cut2 = cutoff * cutoff
    for i in range(n):
        f = 0j
        for gy in range(max(cy[i] - 1, 0), min(cy[i] + 2, ny)):
            for gx in range(max(cx[i] - 1, 0), min(cx[i] + 2, nx)):
                c = gx + nx * gy
                for k in range(start[c], start[c + 1]):
                    j = order[k]
                    if j != i:
                        f += _pair(pos[j] - pos[i], vel[i] - vel[j], cut2, k_soc, lam, gamma, nn, npr)
        out[i] = f


@no_alloc
def _move(cs, fs, cc, fc, bc, labels, sizes, prm, dt, work):  # noqa: ANN001, ANN202
    """Desired + group forces and one SFM step for walkers, using the environment force of the previous call
    (walkers move, others get zero velocity, turners turn, reached goals are flagged). work rows 0, 1, 3:
    scratch for the unit desired directions, the forces and the group centres. Returns #goals reached."""
    n = cs.shape[1]
    pos, vel, goal = cs[0], cs[1], cs[2]
    yaw, radius, goal_r, omega = fs[0], fs[1], fs[2], fs[3]
    tgt, extra, f_env = cc[0], cc[1], cc[2]
    tgt_r, v0, turn_yaw = fc[0], fc[1], fc[2]
    move, use_goal, turn, has_goal, reached = bc[0], bc[1], bc[2], bc[3], bc[4]
    k_des, tau, k_gaze, k_coh, k_rep = prm[0], prm[1], prm[2], prm[3], prm[4]
    e, force, csum = work[0], work[1], work[3]
    n_reached = 0
    for i in range(n):
        e[i] = 0j
        if use_goal[i]:
            g, gr, hg = goal[i], goal_r[i], has_goal[i]
        else:
            g, gr, hg = tgt[i], tgt_r[i], True
        to = g - pos[i]
        dist = abs(to)
        if hg and dist > gr:
            e[i] = to / dist
            force[i] = k_des * (v0[i] * e[i] - vel[i]) / tau
        else:
            force[i] = -vel[i] / tau
        force[i] += f_env[i] + extra[i]
    ngroups = sizes.shape[0]
    if ngroups > 0:
        for g in range(ngroups):
            csum[g] = 0j
        for i in range(n):
            if labels[i] >= 0:
                csum[labels[i]] += pos[i]
        for i in range(n):
            lab = labels[i]
            if lab < 0:
                continue
            size = sizes[lab]
            centre = csum[lab] / size
            u = (size * centre - pos[i]) / (size - 1) - pos[i]
            em = e[i]
            dot = (em * u.conjugate()).real
            e2 = abs(em) ** 2
            if dot < 0 and e2 > 0:
                force[i] += k_gaze * dot / e2 * em
            wv = centre - pos[i]
            force[i] += k_coh * (math.tanh(abs(wv) - (size - 1) / 2) + 1) / 2 * wv
            rep = 0j
            for j in range(n):
                if j != i and labels[j] == lab:
                    dij = pos[i] - pos[j]
                    if abs(dij) < radius[i] + radius[j]:
                        rep += dij
            force[i] += k_rep * rep
    for i in range(n):
        old = yaw[i]
        reached[i] = False
        if move[i]:
            v = vel[i] + force[i] * dt
            speed = abs(v)
            if speed > v0[i]:
                v = v * (v0[i] / speed)
                speed = v0[i]
            if speed > 1e-9:
                yaw[i] = math.atan2(v.imag, v.real)
            pos[i] = pos[i] + v * dt
            vel[i] = v
            if use_goal[i] and has_goal[i] and abs(goal[i] - pos[i]) <= goal_r[i]:
                reached[i] = True
                n_reached += 1
        else:
            vel[i] = 0j
            if turn[i]:
                yaw[i] = (turn_yaw[i] + math.pi) % (2 * math.pi) - math.pi
        omega[i] = ((yaw[i] - old + math.pi) % (2 * math.pi) - math.pi) / dt
    return n_reached


@no_alloc
def _social_dense(pos, vel, prm, out, pairs):  # noqa: ANN001, ANN202
    """Human-human social forces over every pair, each pair's force computed once: the force is exactly
    antisymmetric (f_ji = -f_ij bit for bit: every step of _pair changes sign with d and dv or keeps it), and
    each sum runs over j in order as before. pairs: (n, n) scratch, or (0, 0) to compute each force twice."""
    n = pos.shape[0]
    cut2 = prm[12] * prm[12]
    if pairs.shape[0] < n:
        for i in range(n):
            f = 0j
            for j in range(n):
                if j != i:
                    f += _pair(pos[j] - pos[i], vel[i] - vel[j], cut2, prm[7], prm[8], prm[9], prm[10], prm[11])
            out[i] = f
        return
    for i in range(n):
        for j in range(i + 1, n):
            f = _pair(pos[j] - pos[i], vel[i] - vel[j], cut2, prm[7], prm[8], prm[9], prm[10], prm[11])
            pairs[i, j] = f
            pairs[j, i] = -f
    for i in range(n):
        f = 0j
        for j in range(n):
            if j != i:
                f += pairs[i, j]
        out[i] = f


@njit(cache=True, inline="always")
def obstacle_point(obs_table, affine, mpp, p):  # noqa: ANN001, ANN201
    """World.nearest_obstacles for one point: the nearest blocked pixel's centre (the pixel clamped to the
    map) moved half a pixel toward p, i.e. near the obstacle's surface."""
    h, w = obs_table.shape
    x, y = p.real, p.imag
    px = affine[0, 0] * x + affine[0, 1] * y + affine[0, 2]
    py = affine[1, 0] * x + affine[1, 1] * y + affine[1, 2]
    c = min(max(int(math.floor(px + 0.5)), 0), w - 1)
    r = min(max(int(math.floor(py + 0.5)), 0), h - 1)
    o = obs_table[r, c]
    d = p - o
    dist = abs(d)
    if dist > 0.5 * mpp:
        o = o + d * (0.5 * mpp / dist)
    return o


@no_alloc
def _environment(cs, fs, cc, fc, prm, obs_table, affine, rpos, rvel, social):  # noqa: ANN001, ANN202
    """Environment force (social incl. the robot, nearest obstacle) and distance to the robot of everyone."""
    n = cs.shape[1]
    pos, vel, radius, f_env, rdist = cs[0], cs[1], fs[1], cc[2], fc[3]
    k_obs, sigma, k_soc, lam, gamma, nn, npr, cutoff = prm[5], prm[6], prm[7], prm[8], prm[9], prm[10], prm[11], prm[12]
    obs_range, has_obs, mpp = prm[13], prm[14] > 0, prm[15]
    cut2 = cutoff * cutoff
    for i in range(n):
        pi = pos[i]
        f = social[i] + _pair(rpos - pi, vel[i] - rvel, cut2, k_soc, lam, gamma, nn, npr)
        if has_obs:
            dd = pi - obstacle_point(obs_table, affine, mpp, pi)
            dist = abs(dd)
            if dist <= obs_range and dist > 1e-9:
                f += k_obs * math.exp(-(dist - radius[i]) / sigma) * dd / dist
        f_env[i] = f
        rdist[i] = abs(rpos - pi)


def advance_work(n: int) -> np.ndarray:
    """Scratch for advance_small: rows e, force, social, group centres, then an (n, n) block of pair forces."""
    return np.zeros((4 + n, max(n, 1)), dtype=np.complex128)


@no_alloc
def advance_small(cs, fs, cc, fc, bc, labels, sizes, prm, obs_table, affine, rpos, rvel, dt, do_step, work):  # noqa: ANN001, ANN201
    """advance for crowds of at most GRID_MIN people, allocating nothing (work = advance_work(n))."""
    n_reached = _move(cs, fs, cc, fc, bc, labels, sizes, prm, dt, work) if do_step else 0
    _social_dense(cs[0], cs[1], prm, work[2], work[4:])
    _environment(cs, fs, cc, fc, prm, obs_table, affine, rpos, rvel, work[2])
    return n_reached


@njit(cache=True)
def advance(cs, fs, cc, fc, bc, labels, sizes, prm, obs_table, affine, rpos, rvel, dt, do_step):  # noqa: ANN001, ANN201
    """If do_step: desired + group forces and one SFM step for walkers using the environment force of the
    previous call (walkers move, others get zero velocity, turners turn, reached goals are flagged).
    Then: environment forces (social incl. the robot, nearest obstacle) for the current positions.
    Returns the number of agents that reached their real goal."""
    n = cs.shape[1]
    if n <= GRID_MIN:
        return advance_small(cs, fs, cc, fc, bc, labels, sizes, prm, obs_table, affine, rpos, rvel, dt, do_step,
                             np.zeros((4 + n, max(n, 1)), dtype=np.complex128))  # advance_work(n)
    work = np.zeros((4, n), dtype=np.complex128)
    n_reached = _move(cs, fs, cc, fc, bc, labels, sizes, prm, dt, work) if do_step else 0
    if prm[12] < 1e6:
        _social_grid(cs[0], cs[1], prm[12], prm[7], prm[8], prm[9], prm[10], prm[11], work[2])
    else:
        _social_dense(cs[0], cs[1], prm, work[2], work[:0, :0])
    _environment(cs, fs, cc, fc, prm, obs_table, affine, rpos, rvel, work[2])
    return n_reached


@njit(cache=True, inline="always")
def _clearance(clearance, affine, p):  # noqa: ANN001, ANN202
    """World.clearance_at_point: metres to the nearest wall at p's pixel, 0 outside the map."""
    x, y = p.real, p.imag
    c = int(math.floor(affine[0, 0] * x + affine[0, 1] * y + affine[0, 2] + 0.5))
    r = int(math.floor(affine[1, 0] * x + affine[1, 1] * y + affine[1, 2] + 0.5))
    if c < 0 or r < 0 or c >= clearance.shape[1] or r >= clearance.shape[0]:
        return 0.0
    return clearance[r, c]


@no_alloc
def resolve_contacts(pos, radius, move, before, rpos, robot_r, rdir, clearance, affine, slack, snap):  # noqa: ANN001, ANN201
    """Compiled Simulation._resolve_contacts (the reference and its rules are there): overlapping humans
    are pushed apart along their centre line (walkers take the correction from someone standing), then
    nobody ends deeper in the robot than the robot's own move put them. In place; returns whether anyone
    was moved. snap: scratch for the positions before any correction (overlaps are found on them)."""
    n = pos.shape[0]
    moved = False
    for i in range(n):
        snap[i] = pos[i]
    for i in range(n):
        for j in range(i + 1, n):
            if not radius[i] + radius[j] - abs(snap[i] - snap[j]) > 1e-6:
                continue
            d = pos[i] - pos[j]
            dist = abs(d)
            unit = d / dist if dist > 1e-9 else complex(math.cos(0.7 * (i + 1)), math.sin(0.7 * (j + 1)))
            depth = radius[i] + radius[j] - dist + 1e-4
            wi, wj = move[i], move[j]
            share_i = 0.5 if wi == wj else (1.0 if wi else 0.0)
            for side in range(2):
                k = i if side == 0 else j
                sign = 1.0 if side == 0 else -1.0
                share = share_i if side == 0 else 1.0 - share_i
                cand = pos[k] + sign * unit * depth * share
                if share > 0 and _clearance(clearance, affine, cand) >= 0.5 * radius[k]:
                    pos[k] = cand
                    moved = True
    for i in range(n):
        p_i = pos[i]
        reach = radius[i] + robot_r
        gap_new = abs(p_i - rpos) - reach
        if gap_new >= slack:
            continue
        allowed = min(abs(before[i] - rpos) - reach, slack)
        if gap_new < allowed - 1e-9:
            away = p_i - rpos
            dist = abs(away)
            unit = away / dist if dist > 1e-9 else -rdir
            cand = rpos + unit * (reach + allowed)
            if _clearance(clearance, affine, cand) < 0.5 * radius[i]:
                cand = before[i]
            pos[i] = cand
            moved = True
    return moved


@njit(cache=True, inline="always")
def segment_clear(blocked, affine, pa, pb, half_pixel):  # noqa: ANN001, ANN201
    """World.line_of_sight for one segment: sampled at max(2, ceil(length / half_pixel) + 1) evenly spaced
    points, as np.linspace spaces them; clear when no sample but the two ends falls on a blocked cell or off
    the map. Stops at the first blocked sample."""
    h, w = blocked.shape
    d = pb - pa
    count = max(2, int(math.ceil(abs(d) / half_pixel)) + 1)
    step = 1.0 / (count - 1)
    for k in range(1, count - 1):
        p = pa + d * (k * step)
        x, y = p.real, p.imag
        c = int(math.floor(affine[0, 0] * x + affine[0, 1] * y + affine[0, 2] + 0.5))
        r = int(math.floor(affine[1, 0] * x + affine[1, 1] * y + affine[1, 2] + 0.5))
        if c < 0 or r < 0 or c >= w or r >= h or blocked[r, c]:
            return False
    return True


@njit(cache=True)
def segments_clear(blocked, affine, a, b, half_pixel, out):  # noqa: ANN001, ANN201
    """Compiled World.segments_clear (the numpy reference is there): out[s] = segment_clear(a[s], b[s])."""
    for s in range(a.shape[0]):
        out[s] = segment_clear(blocked, affine, a[s], b[s], half_pixel)
