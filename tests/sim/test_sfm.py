"""Social force model (reference §6) against hand computation, and the compiled kernel against the numpy
reference path."""

from __future__ import annotations

import math

import numpy as np
import pytest

from socnavgen.sim import kernels
from socnavgen.sim.sfm import Groups, SFMParams, desired_forces, integrate, obstacle_forces, social_forces
from socnavgen.sim.world import empty_room

from .simhelpers import REGULAR, Drive, human, make_sim, tree_xml


def hand_social(pi, vi, pj, vj, k=5.0, lam=2.0, gamma=0.35, n=2.0, n_prime=3.0):  # noqa: ANN001, ANN201
    """§6.4 written out with plain floats, step by step."""
    dx, dy = pj[0] - pi[0], pj[1] - pi[1]
    dist = math.hypot(dx, dy)
    ex, ey = dx / dist, dy / dist
    tx, ty = lam * (vi[0] - vj[0]) + ex, lam * (vi[1] - vj[1]) + ey
    ell = math.hypot(tx, ty)
    tx, ty = tx / ell, ty / ell
    b = gamma * ell
    theta = math.atan2(ey, ex) - math.atan2(ty, tx)
    theta = (theta + math.pi) % (2 * math.pi) - math.pi
    fv = -math.exp(-dist / b - (n_prime * b * theta) ** 2)
    ft = -math.copysign(1.0, theta) * math.exp(-dist / b - (n * b * theta) ** 2)
    return k * (fv * tx + ft * -ty), k * (fv * ty + ft * tx)


def test_social_force_between_two_agents_matches_the_formula():
    pi, vi, pj, vj = (0.0, 0.0), (1.0, 0.0), (2.0, 1.0), (-0.5, 0.2)
    f = social_forces(np.array([complex(*pi), complex(*pj)]), np.array([complex(*vi), complex(*vj)]), SFMParams())
    for got, (p, v, q, w) in zip(f, [(pi, vi, pj, vj), (pj, vj, pi, vi)], strict=True):
        fx, fy = hand_social(p, v, q, w)
        assert got.real == pytest.approx(fx, abs=1e-12) and got.imag == pytest.approx(fy, abs=1e-12)
    # worked by hand: t = (3.894, 0.047), B = 1.363, theta = 0.4515 -> f_v = -0.0064, f_theta = -0.0426
    # F = 5 (f_v t^ + f_theta t^perp) = (-0.0295, -0.213): j is ahead-left, i is pushed right and back
    assert f[0].real == pytest.approx(-0.0295, abs=5e-4) and f[0].imag == pytest.approx(-0.213, abs=2e-3)


def test_social_force_cutoff_and_exact_mode():
    pos = np.array([0j, 9 + 0j])
    vel = np.array([1.5 + 0j, -1.5 + 0j])
    assert np.all(social_forces(pos, vel, SFMParams()) == 0)  # beyond the 8 m cut-off
    exact = social_forces(pos, vel, SFMParams(cutoff=None))
    assert 0 < abs(exact[0]) < 0.2 * 4.0 * 1.5  # small next to the desired force


def test_sparse_path_equals_dense_path():
    rng = np.random.default_rng(1)
    pos = rng.uniform(0, 30, 80) + 1j * rng.uniform(0, 30, 80)
    vel = rng.normal(0, 0.7, 80) + 1j * rng.normal(0, 0.7, 80)
    sparse = social_forces(pos, vel, SFMParams())  # 80 agents -> k-d tree path
    dense = np.array([sum(complex(*hand_social((pos[i].real, pos[i].imag), (vel[i].real, vel[i].imag),
                                                 (pos[j].real, pos[j].imag), (vel[j].real, vel[j].imag)))
                          for j in range(80) if j != i and abs(pos[j] - pos[i]) <= 8.0) for i in range(80)])
    assert np.allclose(sparse, dense, atol=1e-9)


def test_obstacle_desired_and_integration_match_the_formulas():
    prm = SFMParams()
    f = obstacle_forces(np.array([1 + 0j]), np.array([0.4]), np.array([0j]), np.array([True]), prm)
    assert f[0] == pytest.approx(10.0 * math.exp(-(1.0 - 0.4) / 0.2))
    fd, e = desired_forces(np.array([0j]), np.array([0.5 + 0j]), np.array([0 + 4j]), np.array([0.5]),
                           np.array([True]), np.array([1.5]), prm)
    assert fd[0] == pytest.approx(2.0 * (1.5j - 0.5) / 0.5) and e[0] == pytest.approx(1j)
    fd, _ = desired_forces(np.array([0j]), np.array([0.5 + 0j]), np.array([0.3 + 0j]), np.array([0.5]),
                           np.array([True]), np.array([1.5]), prm)
    assert fd[0] == pytest.approx(-1.0)  # inside the goal radius: brake -v/tau
    p, v, yaw = integrate(np.array([0j]), np.array([1 + 0j]), np.array([0.0]), np.array([100j]), np.array([1.5]), 0.1)
    assert abs(v[0]) == pytest.approx(1.5) and yaw[0] == pytest.approx(math.atan2(10, 1))
    assert p[0] == pytest.approx(v[0] * 0.1)


def test_group_forces_pull_members_together():
    groups = Groups(np.array([3, 3, -1]))
    pos = np.array([0j, 4 + 0j, 2 + 2j])
    e = np.array([-1 + 0j, 1 + 0j, 0j])  # both walking away from each other
    f = groups.forces(pos, e, np.full(3, 0.4), SFMParams())
    assert f[2] == 0
    # coherence toward the centre (2, 0): k_coh * (tanh(2 - 0.5) + 1)/2 * 2; gaze brakes along e: 3 * (-4)/1 * e
    coh = 2.0 * (math.tanh(2 - 0.5) + 1) / 2 * 2
    assert f[0].real == pytest.approx(coh + 3.0 * 4.0)
    assert f[1].real == pytest.approx(-coh - 3.0 * 4.0)


@pytest.mark.skipif(not kernels.AVAILABLE, reason="numba not installed: only the numpy path exists")
def test_compiled_kernel_gives_the_numpy_trace():
    world = empty_room(20.0, 10.0, walls=[(9.0, 0.0, 10.0, 4.0)])
    humans = [human(f"human{i + 1}", start=(2 + 0.5 * i, 2 + i % 3), goals=[(18 - 0.3 * i, 8), (3, 3)],
                    group_id=1 if i < 3 else -1) for i in range(6)]
    traces = [make_sim(humans, [tree_xml(REGULAR)] * 6, [(1.0, 5.0), (19.0, 5.0)], Drive(0.5), world=world,
                       timeout=20).run() for _ in range(2)]
    fast = make_sim(humans, [tree_xml(REGULAR)] * 6, [(1.0, 5.0), (19.0, 5.0)], Drive(0.5), world=world, timeout=20)
    slow = make_sim(humans, [tree_xml(REGULAR)] * 6, [(1.0, 5.0), (19.0, 5.0)], Drive(0.5), world=world, timeout=20)
    slow._fast = False
    a, b = fast.run(), slow.run()
    assert a.steps == b.steps == traces[0].steps
    assert np.abs(a.humans - b.humans).max() < 1e-9
    assert (a.action == b.action).all()


@pytest.mark.skipif(not kernels.AVAILABLE, reason="numba not installed: only the numpy path exists")
@pytest.mark.parametrize("n", [10, 150])  # all pairs, then the cell grid
def test_kernel_environment_forces_equal_the_reference(n):
    rng = np.random.default_rng(n)
    world = empty_room(40.0, 40.0, resolution=0.1)
    pos = rng.uniform(1, 39, n) + 1j * rng.uniform(1, 39, n)
    vel = rng.normal(0, 0.7, n) + 1j * rng.normal(0, 0.7, n)
    rpos, rvel = 20 + 20j, 0.3 - 0.2j
    radius = np.full(n, 0.4)
    prm = SFMParams()
    ref = social_forces(np.append(pos, rpos), np.append(vel, rvel), prm)[:n]
    obs, ok = world.nearest_obstacles(pos)
    ref += obstacle_forces(pos, radius, obs, ok, prm)
    cs = np.array([pos, vel, pos]); fs = np.array([np.zeros(n), radius, np.full(n, 0.5), np.zeros(n)])  # noqa: E702
    cc, fc, bc = np.zeros((3, n), complex), np.zeros((4, n)), np.zeros((5, n), bool)
    packed = np.array([prm.k_des, prm.tau, prm.k_gaze, prm.k_coh, prm.k_rep, prm.k_obs, prm.sigma_obs, prm.k_soc,
                       prm.lam, prm.gamma, prm.n, prm.n_prime, prm.cutoff, 10.0, 1.0, world.mpp])
    kernels.advance(cs, fs, cc, fc, bc, np.full(n, -1), np.zeros(0), packed, world.obstacle_table,
                    world.transform.inverse.copy(), rpos, rvel, 0.05, False)
    assert np.allclose(cc[2], ref, atol=1e-9)
    assert np.allclose(fc[3], np.abs(rpos - pos))


@pytest.mark.skipif(not kernels.AVAILABLE, reason="numba not installed: only the numpy path exists")
@pytest.mark.parametrize("seed", range(6))
def test_compiled_contacts_equal_the_reference(seed):
    """Crowds packed tight beside a wall and the robot: the compiled contact step moves the same people to the
    same places as the reference (both run on copies of one state)."""
    rng = np.random.default_rng(seed)
    world = empty_room(10.0, 6.0, walls=[(4.0, 0.0, 4.4, 3.0)])
    n = 8
    humans = [human(f"human{i + 1}", start=(3.0 + rng.uniform(-0.6, 0.6), 3.0 + rng.uniform(-0.8, 0.8)),
                    goals=[(8.0, 5.0)]) for i in range(n)]
    sims = [make_sim(humans, [tree_xml(REGULAR)] * n, [(2.6, 3.1), (9.0, 3.0)], Drive(0.5), world=world)
            for _ in range(2)]
    sims[1]._fast = False
    before = sims[0].crowd.pos + rng.normal(0, 0.2, n) + 1j * rng.normal(0, 0.2, n)
    walking = rng.random(n) < 0.5
    results = []
    for sim in sims:
        sim.cmd_move[:] = walking
        results.append((sim._resolve_contacts(before.copy()), sim.crowd.pos.copy()))
    (moved_fast, pos_fast), (moved_ref, pos_ref) = results
    assert moved_fast and moved_ref  # eight people within 1.6 m of each other: some overlap
    assert np.abs(pos_fast - pos_ref).max() < 1e-12
    assert np.abs(pos_fast - humans_start(humans)).max() > 0.01  # it did separate someone


def humans_start(humans):  # noqa: ANN001, ANN201
    return np.array([complex(*h.start) for h in humans])
