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


@njit(cache=True)
def advance(cs, fs, cc, fc, bc, labels, sizes, prm, obs_table, affine, rpos, rvel, dt, do_step):  # noqa: ANN001, ANN201
    """If do_step: desired + group forces and one SFM step for walkers using the environment force of the
    previous call (walkers move, others get zero velocity, turners turn, reached goals are flagged).
    Then: environment forces (social incl. the robot, nearest obstacle) for the current positions.
    Returns the number of agents that reached their real goal."""
    n = cs.shape[1]
    pos, vel, goal = cs[0], cs[1], cs[2]
    yaw, radius, goal_r, omega = fs[0], fs[1], fs[2], fs[3]
    tgt, extra, f_env = cc[0], cc[1], cc[2]
    tgt_r, v0, turn_yaw, rdist = fc[0], fc[1], fc[2], fc[3]
    move, use_goal, turn, has_goal, reached = bc[0], bc[1], bc[2], bc[3], bc[4]
    k_des, tau, k_gaze, k_coh, k_rep = prm[0], prm[1], prm[2], prm[3], prm[4]
    k_obs, sigma, k_soc, lam, gamma, nn, npr, cutoff = prm[5], prm[6], prm[7], prm[8], prm[9], prm[10], prm[11], prm[12]
    obs_range, has_obs, mpp = prm[13], prm[14] > 0, prm[15]
    n_reached = 0
    if do_step:
        e = np.zeros(n, dtype=np.complex128)
        force = np.zeros(n, dtype=np.complex128)
        for i in range(n):
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
            csum = np.zeros(ngroups, dtype=np.complex128)
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
    h, w = obs_table.shape
    for i in range(n):
        pi = pos[i]
        vi = vel[i]
        f = 0j
        for j in range(n + 1):
            if j == i:
                continue
            if j < n:
                pj = pos[j]
                vj = vel[j]
            else:
                pj = rpos
                vj = rvel
            d = pj - pi
            dist = abs(d)
            if dist == 0.0 or dist > cutoff:
                continue
            dhat = d / dist
            t = lam * (vi - vj) + dhat
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
            f += -k_soc * that * (f_v + 1j * f_t)
        if has_obs:
            x, y = pi.real, pi.imag
            px = affine[0, 0] * x + affine[0, 1] * y + affine[0, 2]
            py = affine[1, 0] * x + affine[1, 1] * y + affine[1, 2]
            c = min(max(int(math.floor(px + 0.5)), 0), w - 1)
            r = min(max(int(math.floor(py + 0.5)), 0), h - 1)
            o = obs_table[r, c]
            dd = pi - o
            dist = abs(dd)
            if dist > 0.5 * mpp:  # nearest blocked pixel centre moved half a pixel toward the agent (World)
                o = o + dd * (0.5 * mpp / dist)
                dd = pi - o
                dist = abs(dd)
            if dist <= obs_range and dist > 1e-9:
                f += k_obs * math.exp(-(dist - radius[i]) / sigma) * dd / dist
        f_env[i] = f
        rdist[i] = abs(rpos - pi)
    return n_reached
