"""Social force model (reference §6) against hand computation: pair force, cut-off, the grid neighbour search,
wall, desired and group forces, the integration step."""

from __future__ import annotations

import math

import numpy as np
import pytest

from socnavgen.sim import HumanSpec, empty_room
from socnavgen.sim.people.neighbours import build, new_grid
from socnavgen.sim.people.physics import (
    SFMParams,
    group_forces,
    move,
    new_scratch,
    pair_force,
    social_dense,
    social_grid,
    wall_force,
)
from socnavgen.sim.people.state import new_people


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


def crowd(points, velocities=None, groups=None):  # noqa: ANN001, ANN201
    specs = [HumanSpec(name=f"human{k + 1}", start=(p.real, p.imag), goals=[(p.real, p.imag)],
                       group_id=-1 if groups is None else groups[k]) for k, p in enumerate(points)]
    people, goals, sizes = new_people(specs)
    if velocities is not None:
        people.vel = velocities
    return people, goals, sizes


def test_social_force_between_two_agents_matches_the_formula():
    pi, vi, pj, vj = (0.0, 0.0), (1.0, 0.0), (2.0, 1.0), (-0.5, 0.2)
    got = pair_force(complex(*pj) - complex(*pi), complex(*vi) - complex(*vj), SFMParams())
    fx, fy = hand_social(pi, vi, pj, vj)
    assert got.real == pytest.approx(fx, abs=1e-12) and got.imag == pytest.approx(fy, abs=1e-12)
    # worked by hand: t = (3.894, 0.047), B = 1.363, theta = 0.4515 -> f_v = -0.0064, f_theta = -0.0426
    # F = 5 (f_v t^ + f_theta t^perp) = (-0.0295, -0.213): j is ahead-left, i is pushed right and back
    assert got.real == pytest.approx(-0.0295, abs=5e-4) and got.imag == pytest.approx(-0.213, abs=2e-3)
    # the other way round, from j's side, by the same formula
    back = pair_force(complex(*pi) - complex(*pj), complex(*vj) - complex(*vi), SFMParams())
    assert (back.real, back.imag) == pytest.approx(hand_social(pj, vj, pi, vi), abs=1e-12)


def test_social_force_cutoff_and_every_pair_mode():
    d, dv = 9 + 0j, 3 + 0j
    assert pair_force(d, dv, SFMParams()) == 0  # beyond the 8 m cut-off
    exact = pair_force(d, dv, SFMParams(cutoff=math.inf))
    assert 0 < abs(exact) < 0.2 * 4.0 * 1.5  # small next to the desired force
    assert pair_force(0j, dv, SFMParams()) == 0  # coincident bodies exert nothing


@pytest.mark.parametrize("n", [12, 80])
def test_grid_neighbours_give_the_sum_over_every_pair(n):
    """The grid search (large crowds) and the all-pairs sum (small ones) are the same force, and both equal
    the hand formula summed over neighbours within the cut-off."""
    rng = np.random.default_rng(n)
    pos = rng.uniform(0, 30, n) + 1j * rng.uniform(0, 30, n)
    vel = rng.normal(0, 0.7, n) + 1j * rng.normal(0, 0.7, n)
    people, _, _ = crowd(pos, vel)
    prm = SFMParams()
    dense, grid = np.zeros(n, complex), np.zeros(n, complex)
    social_dense(people, prm, dense)
    cells = new_grid(n, cells=True)
    build(cells, people, prm.cutoff)
    social_grid(people, prm, cells, grid)
    hand = np.array([sum(complex(*hand_social((pos[i].real, pos[i].imag), (vel[i].real, vel[i].imag),
                                              (pos[j].real, pos[j].imag), (vel[j].real, vel[j].imag)))
                         for j in range(n) if j != i and abs(pos[j] - pos[i]) <= 8.0) for i in range(n)])
    assert np.allclose(dense, hand, atol=1e-9) and np.allclose(grid, hand, atol=1e-9)
    assert (np.abs(hand) > 0).sum() > n // 2  # most people have neighbours


def test_wall_force_desired_force_and_integration_match_the_formulas():
    prm = SFMParams()
    world = empty_room(20.0, 10.0)
    near_floor = 5 + 1.0j  # the floor wall's surface is at y = 0.05
    f = wall_force(near_floor, 0.4, world.map, prm)
    assert f.imag == pytest.approx(10.0 * math.exp(-(0.95 - 0.4) / 0.2), rel=0.02) and abs(f.real) < 0.05 * abs(f)
    assert wall_force(10 + 5j, 0.4, empty_room(40.0, 40.0, resolution=0.1).map, prm) != 0
    assert wall_force(20 + 20j, 0.4, empty_room(40.0, 40.0, resolution=0.1).map, prm) == 0  # beyond 10 m
    people, _, sizes = crowd([10 + 5j], [0.5 + 0j])
    p = people[0]
    p.walks, p.to_goal, p.target, p.target_radius, p.desired_speed = True, False, 10 + 9j, 0.5, 1.5
    p.via = p.target  # where routing (people.routing) heads them: straight at it in the open
    scratch = new_scratch(1, 0)
    far = 100 + 100j  # the robot, out of the way
    move(people, sizes, prm, world.map, 0.1, scratch, far, 0.35)
    assert scratch.force[0] == pytest.approx(2.0 * (1.5j - 0.5) / 0.5)  # toward the target at 1.5 m/s
    v = 0.5 + scratch.force[0] * 0.1
    v = v * min(1.0, 1.5 / abs(v))  # capped at the desired speed
    assert p.vel == pytest.approx(v) and p.pos == pytest.approx(10 + 5j + v * 0.1)
    assert p.yaw == pytest.approx(math.atan2(v.imag, v.real))
    q = people[0]
    q.vel, q.target = 0.5 + 0j, q.pos + 0.3  # inside the target's radius: brake -v/tau
    move(people, sizes, prm, world.map, 0.1, scratch, far, 0.35)
    assert scratch.force[0] == pytest.approx(-1.0)


def test_group_forces_pull_members_together():
    people, _, sizes = crowd([0j, 4 + 0j, 2 + 2j], groups=[3, 3, -1])
    people.walks[:], people.to_goal[:] = True, True  # all three walk their walk (RegularNav)
    direction = np.array([-1 + 0j, 1 + 0j, 0j])  # both members walking away from each other
    force = np.zeros(3, complex)
    group_forces(people, SFMParams(), direction, force, np.zeros(1, complex), np.zeros(1))
    assert force[2] == 0
    # coherence toward the centre (2, 0): k_coh * (tanh(2 - 0.5) + 1)/2 * 2; gaze brakes along e: 3 * (-4)/1 * e
    coh = 2.0 * (math.tanh(2 - 0.5) + 1) / 2 * 2
    assert force[0].real == pytest.approx(coh + 3.0 * 4.0)
    assert force[1].real == pytest.approx(-coh - 3.0 * 4.0)


@pytest.mark.parametrize("other", ["robot-related", "stands"])
def test_a_member_whose_tree_does_something_else_leaves_the_group_forces(other: str):
    """A member whose tree makes them react to the robot (behavior 1: follow, run away...) or stand leaves
    the group's forces; the others are no longer held back by them (a group of one feels none)."""
    people, _, sizes = crowd([0j, 4 + 0j], groups=[3, 3])
    people.walks[:], people.to_goal[:] = True, True
    if other == "robot-related":
        people.behavior[1] = 1
    else:
        people.walks[1] = False
    force = np.zeros(2, complex)
    group_forces(people, SFMParams(), np.array([-1 + 0j, 1 + 0j]), force, np.zeros(1, complex), np.zeros(1))
    assert force[0] == 0 and force[1] == 0
