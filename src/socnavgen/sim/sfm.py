"""Social force model as HuNavSim configures lightsfm (reference §6), vectorised over agents.

2D vectors are complex numbers (x + iy): a difference, a norm, an angle or a 90-degree rotation is
one numpy call each, which is what keeps a small crowd fast. Forces are per unit mass.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree

# Dense all-pairs up to this many agents; a k-d tree neighbour search above (cost ~linear in agents).
DENSE_MAX = 40


@dataclass(frozen=True)
class SFMParams:
    """lightsfm factors with HuNavSim's override k_soc = 5.0 (library default 2.1)."""

    k_des: float = 2.0
    k_obs: float = 10.0
    sigma_obs: float = 0.2
    k_soc: float = 5.0
    k_gaze: float = 3.0
    k_coh: float = 2.0
    k_rep: float = 1.0
    lam: float = 2.0
    gamma: float = 0.35
    n: float = 2.0
    n_prime: float = 3.0
    tau: float = 0.5
    # Neighbour cut-off for the social force in metres (None = every pair, as lightsfm). At 8 m the force
    # of even a head-on walker at 1.5 m/s is below 4 % of the desired force.
    cutoff: float | None = 8.0


def _pair_force(d: np.ndarray, dv: np.ndarray, p: SFMParams) -> np.ndarray:
    """Force on i from j for arrays of d = p_j - p_i and dv = v_i - v_j (§6.4)."""
    dist = np.abs(d)
    dhat = d / dist
    t = p.lam * dv + dhat
    ell = np.abs(t)
    that = t / np.maximum(ell, 1e-12)
    b = p.gamma * ell
    theta = np.angle(dhat * that.conj())
    # f_theta jumps at theta = 0 (sign); round-off must not pick a side, so tiny angles count as 0
    theta = np.where(np.abs(theta) < 1e-9, 0.0, theta)
    base = -dist / np.maximum(b, 1e-12)
    bt = b * theta
    f_v = np.exp(base - (p.n_prime * bt) ** 2)
    f_theta = np.sign(theta) * np.exp(base - (p.n * bt) ** 2)
    return -p.k_soc * that * (f_v + 1j * f_theta)


def social_forces(pos: np.ndarray, vel: np.ndarray, p: SFMParams) -> np.ndarray:
    """Social force on every agent from every other agent (complex (n,)); radii are not used."""
    n = pos.shape[0]
    if n < 2:
        return np.zeros(n, dtype=complex)
    if n <= DENSE_MAX:
        d = pos[None, :] - pos[:, None]
        d = np.where(d == 0, 1e6, d)  # self-pairs and coincident agents exert nothing (lightsfm: 0 -> 0)
        f = _pair_force(d, vel[:, None] - vel[None, :], p)
        if p.cutoff is not None:
            f = f * (np.abs(d) <= p.cutoff)
        return f.sum(axis=1)
    if p.cutoff is None:
        i, j = np.nonzero(~np.eye(n, dtype=bool))
    else:
        pairs = cKDTree(np.column_stack([pos.real, pos.imag])).query_pairs(p.cutoff, output_type="ndarray")
        if pairs.size == 0:
            return np.zeros(n, dtype=complex)
        i = np.concatenate([pairs[:, 0], pairs[:, 1]])
        j = np.concatenate([pairs[:, 1], pairs[:, 0]])
    d = pos[j] - pos[i]
    d = np.where(d == 0, 1e6, d)  # coincident agents exert nothing (lightsfm normalises 0 to 0)
    f = _pair_force(d, vel[i] - vel[j], p)
    return np.bincount(i, weights=f.real, minlength=n) + 1j * np.bincount(i, weights=f.imag, minlength=n)


def obstacle_forces(pos: np.ndarray, radius: np.ndarray, obstacles: np.ndarray, valid: np.ndarray,
                    p: SFMParams) -> np.ndarray:
    """Repulsion from one obstacle point per agent (§6.3 with N = 1, as the Gazebo wrapper sends)."""
    d = pos - obstacles
    dist = np.abs(d)
    ok = valid & (dist > 1e-9)
    safe = np.where(ok, dist, 1.0)
    return np.where(ok, p.k_obs * np.exp(-(safe - radius) / p.sigma_obs) * d / safe, 0.0)


def desired_forces(pos: np.ndarray, vel: np.ndarray, target: np.ndarray, target_radius: np.ndarray,
                   has_target: np.ndarray, v0: np.ndarray, p: SFMParams) -> tuple[np.ndarray, np.ndarray]:
    """(force, desired direction e): toward the target at v0, or braking -v/tau inside its radius (§6.2)."""
    to_goal = target - pos
    dist = np.abs(to_goal)
    active = has_target & (dist > target_radius)
    e = np.where(active, to_goal / np.where(active, dist, 1.0), 0.0)
    force = np.where(active, p.k_des * (v0 * e - vel) / p.tau, -vel / p.tau)
    return force, e


class Groups:
    """Group membership fixed at start: labels 0..G-1 for members of groups with >= 2 members."""

    def __init__(self, group_ids: np.ndarray) -> None:
        ids = np.asarray(group_ids)
        valid = ids != -1
        uniq, counts = np.unique(ids[valid], return_counts=True)
        keep = set(uniq[counts >= 2].tolist())
        self.members = np.array([k for k in range(len(ids)) if int(ids[k]) in keep], dtype=np.intp)
        lookup = {g: k for k, g in enumerate(sorted(keep))}
        self.labels = np.array([lookup[int(ids[k])] for k in self.members], dtype=np.intp)
        self.count = len(keep)
        self.sizes = np.bincount(self.labels, minlength=self.count).astype(float) if self.count else np.zeros(0)

    def __bool__(self) -> bool:
        return self.count > 0

    def forces(self, pos: np.ndarray, e: np.ndarray, radius: np.ndarray, p: SFMParams) -> np.ndarray:
        """Gaze + coherence + repulsion for group members (§6.5); zero for everyone else."""
        out = np.zeros(pos.shape[0], dtype=complex)
        if not self.count:
            return out
        m, lab = self.members, self.labels
        pm, em = pos[m], e[m]
        size = self.sizes[lab]
        csum = np.bincount(lab, weights=pm.real, minlength=self.count) + \
            1j * np.bincount(lab, weights=pm.imag, minlength=self.count)
        centre = csum[lab] / size
        # gaze: push back along the walking direction when the others are behind (> 90 deg)
        others = (size * centre - pm) / (size - 1)
        u = others - pm
        dot = (em * u.conj()).real
        e2 = np.abs(em) ** 2
        gaze = np.where((dot < 0) & (e2 > 0), p.k_gaze * dot / np.where(e2 > 0, e2, 1.0) * em, 0.0)
        w = centre - pm
        coh = p.k_coh * (np.tanh(np.abs(w) - (size - 1) / 2) + 1) / 2 * w
        d = pm[:, None] - pm[None, :]
        same = (lab[:, None] == lab[None, :]) & (np.abs(d) < radius[m][:, None] + radius[m][None, :])
        np.fill_diagonal(same, False)
        rep = p.k_rep * (d * same).sum(axis=1)
        out[m] = gaze + coh + rep
        return out


def integrate(pos: np.ndarray, vel: np.ndarray, yaw: np.ndarray, force: np.ndarray, v0: np.ndarray,
              dt: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """One SFM step (§6.6 steps 1-4): v += F dt, cap at v0, yaw from v, p += v dt. Returns new p, v, yaw.

    A zero velocity keeps the previous yaw (lightsfm would report 0; a standing person keeps facing)."""
    v = vel + force * dt
    speed = np.abs(v)
    v = np.where(speed > v0, v * (v0 / np.where(speed > 0, speed, 1.0)), v)
    new_yaw = np.where(speed > 1e-9, np.angle(v), yaw)
    return pos + v * dt, v, new_yaw
