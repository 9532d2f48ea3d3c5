"""The social-force robot's step (compiled): the `sfm` policy, and the waypoints robot's detour round someone.

Helbing & Molnar (1995), "Social force model for pedestrian dynamics", Phys. Rev. E 51(5):4282, eq. (1)-(6),
with lightsfm's factors (people.physics.SFMParams):

    dv/dt = k_des (v0 e - v) / tau  +  sum_j f_ij  +  sum_B f_iB                                  (HM eq. 6)

* the drive toward the target (e: its unit direction, v0 the desired speed, tau the relaxation time);
* f_ij the people's social forces (people.physics.pair_force, lightsfm's form of HM eq. 3-4);
* f_iB the borders' repulsion, one term per border B from its point nearest the robot:

      f_iB = -grad U_iB(|r_iB|),  U_iB(d) = U0 B exp(-(d - r) / B)  =>  f_iB = k_obs exp((r - d_B) / sigma) n_B   (HM eq. 5)

  with d_B the distance to border B, n_B the unit vector from it to the robot (k_obs = U0, sigma = B).

The pedestrians' one-point wall term (people.physics.wall_force, as HuNavSim's Gazebo wrapper sends only the
nearest obstacle point) is HM eq. 5 for a single border. In an aisle barely wider than the robot the nearest
point jumps from one wall to the other each time the robot crosses the aisle's middle: a full push (~5 m/s2 in a
1.0 m aisle) one way, then the other, never a balance - the robot rocked from side to side and, being a
differential drive that must turn to move sideways, crawled (~4 m in 40 s on the warehouse's narrow hallway).

So the planning robot's border term (`across_walls`) follows HM's sum over borders: each border is found as a
local minimum of a range scan (SCAN_BEAMS rays; a wall face's nearest point, a door jamb's corner), and the sum
acts only across the robot's way (the planner keeps its way clear of walls: a wall ahead or behind it must not
hold it back or push it on). The two walls of a passage then balance in its middle; the across-way sum is
bounded by the robot's own drive (k_des v0 / tau, WALL_CAP), and damped critically for the spring it makes:

      F_across = clip(sum_B (f_iB . n) n, k_des v0 / tau) - c (v . n) n,   c = 2 sqrt(K),  K = sum_B |f_iB| (n_B . n)^2 / sigma

(n: the unit normal of the way; K: the stiffness d F / d y of the sum across the way, a damped oscillator's
critical damping 2 sqrt(K) for unit mass), with c at most 1 / dt so that an explicit step never overshoots.
"""

from __future__ import annotations

import math

from socnavgen.sim.jit import jit
from socnavgen.sim.people.physics import pair_force, wall_force
from socnavgen.sim.world.queries import cell_of, clearance_at, inside

GOAL_DECEL = 0.8  # m/s2: the social-force and the straight robots slow down for their goal at this rate
SCAN_BEAMS = 36  # rays of the border scan (10 degrees apart: a wall's nearest point within 0.4 % of its distance)
WALL_LOOK = 1.5  # m: borders farther than this are not looked for (their push is under 1 % of k_obs)


@jit(inline=True)
def wall_distance(world, p, u, reach):  # noqa: ANN001, ANN201
    """Metres from p along the unit `u` to the first blocked cell or the map's edge (`reach` if none within it):
    jumps by the clearance where it is large (sphere tracing), then samples every half cell."""
    half = 0.5 * world.mpp
    t = 0.0
    while t < reach:
        q = p + u * t
        row, col = cell_of(world, q)
        if not inside(world, row, col) or world.blocked[row, col]:
            return max(t - half, 0.0)
        c = clearance_at(world, q)
        t += max(c - 2.0 * world.mpp, half)
    return reach


@jit
def across_walls(s, e, v0):  # noqa: ANN001, ANN201
    """The border force on the robot across its way (unit `e`), damped and bounded (the module's docstring)."""
    robot, prm, world = s.robot[0], s.forces, s.world
    if not world.has_obstacles:
        return 0j
    p, r, n = robot.pos, robot.radius, e * 1j
    prev = wall_distance(world, p, complex(math.cos(-2 * math.pi / SCAN_BEAMS), math.sin(-2 * math.pi / SCAN_BEAMS)),
                         WALL_LOOK)
    here = wall_distance(world, p, 1 + 0j, WALL_LOOK)
    first = here
    push, stiffness = 0.0, 0.0
    for k in range(SCAN_BEAMS):
        u = complex(math.cos(2 * math.pi * k / SCAN_BEAMS), math.sin(2 * math.pi * k / SCAN_BEAMS))
        if k + 1 < SCAN_BEAMS:
            a = 2 * math.pi * (k + 1) / SCAN_BEAMS
            after = wall_distance(world, p, complex(math.cos(a), math.sin(a)), WALL_LOOK)
        else:
            after = first
        if here < WALL_LOOK and here < prev and here <= after:  # the nearest point of one border
            f = prm.k_obs * math.exp((r - here) / prm.sigma_obs)
            across = -(u * n.conjugate()).real  # n_B = -u: from the border to the robot
            push += f * across
            stiffness += f * across * across / prm.sigma_obs
        prev, here = here, after
    cap = prm.k_des * v0 / prm.tau
    push = min(max(push, -cap), cap)
    damping = min(2.0 * math.sqrt(stiffness), 1.0 / s.clock[0].dt)
    return (push - damping * (robot.vel * n.conjugate()).real) * n


@jit
def sfm_toward(s, target, max_speed, last, planned, arrived):  # noqa: ANN001, ANN201
    """One social-force step of the robot toward `target` (slowing down for it when it is the `last`, stopping
    within `arrived`). `planned`: the target is the planner's carrot (a way its disc fits), so the borders act
    only across its way (across_walls); otherwise the pedestrians' one-point wall term, whole."""
    robot, prm = s.robot[0], s.forces
    to = target - robot.pos
    dist = abs(to)
    if last and dist <= arrived:
        return 0j
    e = to / max(dist, 1e-9)
    v0 = min(max_speed, math.sqrt(2 * GOAL_DECEL * dist)) if last else max_speed
    force = prm.k_des * (v0 * e - robot.vel) / prm.tau
    for i in range(s.people.shape[0]):
        force += pair_force(s.people[i].pos - robot.pos, robot.vel - s.people[i].vel, prm)
    if planned:
        force += across_walls(s, e, max_speed)
    else:
        force += wall_force(robot.pos, robot.radius, s.world, prm)
    v = robot.vel + force * s.clock[0].dt
    if abs(v) > v0:
        v = v * (v0 / abs(v))
    return v
