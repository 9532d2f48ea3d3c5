"""Walking: HuNavSim's social force model as it configures lightsfm (reference §6), and bodies kept apart.

Per step, everyone whose tree made them walk takes one force step at once (a Jacobi update: all see the
same snapshot): desired force toward their command's target, the environment force of the current
positions (social, the robot included, plus the nearest wall point), the group forces; speed capped at the
command's speed. Then the environment force of the new positions. Forces are per unit mass; 2D vectors
are complex numbers. The contact step afterwards separates bodies that overlap.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from socnavgen.bodies import PERSON_KEEP_GAP
from socnavgen.sim.jit import jit
from socnavgen.sim.people import neighbours
from socnavgen.sim.people.avoid import keep_gap, keep_off
from socnavgen.sim.people.neighbours import Grid, new_grid, span
from socnavgen.sim.people.spacing import keep_apart, let_out
from socnavgen.sim.people.spots import REACH as SPOT_REACH
from socnavgen.sim.people.spots import RING_STEP, TIGHT_STEP, spot_taken
from socnavgen.sim.people.state import queued_at
from socnavgen.sim.trace import REGULAR_BEHAVIOR
from socnavgen.sim.world.queries import clearance_at, nearest_obstacle

CONTACT_SWEEPS = 4  # passes of the contact step over the overlapping pairs, while one still moved someone
HEELS_GAP = 0.2  # m: a group-mate this much beyond the keep gap behind a member is on its heels (on_heels)
SPOT_BRAKE = 0.5 * SPOT_REACH  # m: a walker brakes this close to their spot round a taken goal (people.spots)
WALL_HOLD_BACK = 0.5  # the wall force holds a walker back by at most this fraction of their drive (wall_relief)


class SFMParams(NamedTuple):
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
    # Neighbour cut-off of the social force (m; inf = every pair, as lightsfm). At 8 m even a head-on
    # walker at 1.5 m/s pushes less than 4 % of the desired force.
    cutoff: float = 8.0


class Scratch(NamedTuple):
    """Work arrays of one simulation (the step allocates nothing)."""

    direction: np.ndarray  # (n,) complex: desired direction
    force: np.ndarray  # (n,) complex
    social: np.ndarray  # (n,) complex: people-people social force
    centres: np.ndarray  # (groups,) complex: sums of members' positions
    counts: np.ndarray  # (groups,) float: members walking together
    before: np.ndarray  # (n,) complex: positions before the step (contacts)
    snap: np.ndarray  # (n,) complex: positions before the contact corrections
    grid: Grid  # the cell list of a large crowd (people.neighbours)


def new_scratch(n: int, groups: int) -> Scratch:
    return Scratch(np.zeros(n, complex), np.zeros(n, complex), np.zeros(n, complex), np.zeros(max(groups, 1), complex),
                   np.zeros(max(groups, 1)), np.zeros(n, complex), np.zeros(n, complex), new_grid(n))


@jit(inline=True)
def pair_force(d, dv, prm):  # noqa: ANN001, ANN201
    """Social force on i from j (reference §6.4) for d = p_j - p_i, dv = v_i - v_j; 0 beyond the cut-off
    and between coincident bodies."""
    d2 = d.real * d.real + d.imag * d.imag
    if d2 == 0.0 or d2 > prm.cutoff * prm.cutoff:
        return 0j
    dist = math.sqrt(d2)
    dhat = complex(d.real / dist, d.imag / dist)  # componentwise: the same value as d / dist, no complex division
    t = prm.lam * dv + dhat
    ell = abs(t)
    scale = max(ell, 1e-12)
    that = complex(t.real / scale, t.imag / scale)
    b = prm.gamma * ell
    prod = dhat * that.conjugate()
    theta = math.atan2(prod.imag, prod.real)
    if abs(theta) < 1e-9:  # f_theta jumps at 0 (sign): round-off must not pick a side
        theta = 0.0
    base = -dist / max(b, 1e-12)
    bt = b * theta
    f_v = math.exp(base - (prm.n_prime * bt) ** 2)
    sign = 1.0 if theta > 0 else (-1.0 if theta < 0 else 0.0)
    f_theta = sign * math.exp(base - (prm.n * bt) ** 2)
    return -prm.k_soc * that * (f_v + 1j * f_theta)


@jit(inline=True)
def wall_force(p, radius, world, prm):  # noqa: ANN001, ANN201
    """Repulsion of the nearest wall point (reference §6.3 with one point, as the Gazebo wrapper sends)."""
    point, valid = nearest_obstacle(world, p)
    d = p - point
    dist = abs(d)
    if not valid or dist <= 1e-9:
        return 0j
    return prm.k_obs * math.exp(-(dist - radius) / prm.sigma_obs) * d / dist


@jit(inline=True)
def wall_relief(p, e, prm):  # noqa: ANN001, ANN201
    """What takes back the part of the wall force against a walker's way (unit e) beyond WALL_HOLD_BACK of their
    drive (k_des * desired speed / tau): the way (people.routing) keeps clear of walls, and the door jambs
    either side of a 0.9 m door would otherwise stop a slow walker (a person with a cane, 0.4 m/s) in front of
    it. Sideways the wall force is whole: it keeps them in the middle of the door."""
    against = -(p.wall_force * e.conjugate()).real
    most = WALL_HOLD_BACK * prm.k_des * p.desired_speed / prm.tau
    return (against - most) * e if against > most else 0j


@jit
def social_dense(people, prm, out):  # noqa: ANN001, ANN201
    """People-people social forces over every pair, each pair computed once (the force is antisymmetric);
    each person's sum runs over the others in index order."""
    n = people.shape[0]
    for i in range(n):
        out[i] = 0j
    for i in range(n):
        pi, vi = people[i].pos, people[i].vel
        for j in range(i + 1, n):
            f = pair_force(people[j].pos - pi, vi - people[j].vel, prm)
            out[i] += f
            out[j] -= f


@jit
def social_grid(people, prm, grid, out):  # noqa: ANN001, ANN201
    """People-people social forces from the cell list (people.neighbours), each pair computed once: a person
    meets the later members of their cell and the people of the cells ahead of theirs (the rest of their row,
    the rows above) within the cut-off's reach, so the cost grows linearly with the crowd at a given density.
    The loops run over the cell list's sorted copies of positions and velocities (contiguous reads)."""
    nx, reach, order, start = grid.dims[neighbours.NX], grid.dims[neighbours.REACH_SOCIAL], grid.order, grid.start
    pos, vel, acc = grid.pos, grid.vel, grid.acc
    for a in range(people.shape[0]):
        acc[a] = 0j
    for c in range(nx * grid.dims[neighbours.NY]):
        cx, cy = c % nx, c // nx
        for a in range(start[c], start[c + 1]):
            pi, vi = pos[a], vel[a]
            fi = 0j
            for gy in range(cy, cy + reach + 1):
                if gy == cy:  # the later members of a's cell, then the next cells of its row: one slice
                    lo, hi = a + 1, start[min(cx + reach, nx - 1) + nx * cy + 1]
                else:
                    lo, hi = span(grid, gy, cx - reach, cx + reach)
                for k in range(lo, hi):
                    f = pair_force(pos[k] - pi, vi - vel[k], prm)
                    fi += f
                    acc[k] -= f
            acc[a] += fi
    for a in range(people.shape[0]):
        out[order[a]] = acc[a]


@jit
def environment(people, prm, world, robot_pos, robot_vel, social):  # noqa: ANN001, ANN201
    """Each person's environment force (social incl. the robot, nearest wall) and distance to the robot."""
    for i in range(people.shape[0]):
        p = people[i]
        p.wall_force = wall_force(p.pos, p.radius, world, prm)
        p.env_force = social[i] + pair_force(robot_pos - p.pos, p.vel - robot_vel, prm) + p.wall_force
        p.robot_distance = abs(robot_pos - p.pos)


@jit(inline=True)
def in_group_walk(p):  # noqa: ANN001, ANN201
    """A member takes part in its group's forces while it walks the group's walk (RegularNav to its goal); a
    member its tree makes do something else (run away, follow, give way, stand) leaves the group meanwhile, and so does
    one whose walk ended on a tight place's spot (people.spots.pick_tight, nearer the point than the first ring): the
    first of a group into an elevator car was drawn back out to the one still in its door."""
    if not p.has_goal and p.has_spot and abs(p.spot - p.spot_for) < RING_STEP - TIGHT_STEP / 2:
        return False
    return p.group >= 0 and p.walks and p.to_goal and p.behavior == REGULAR_BEHAVIOR


@jit(inline=True)
def on_heels(people, i, e):  # noqa: ANN001, ANN201
    """A member of i's group walking together with it is right behind i (gap under PERSON_KEEP_GAP + HEELS_GAP,
    behind along i's direction e): i does not stand waiting for the others then - the one behind cannot pass
    (a team going through a door one by one would stand in it, the first waiting for the ones it holds up)."""
    p = people[i]
    for j in range(people.shape[0]):
        q = people[j]
        if j == i or q.group != p.group or not in_group_walk(q):
            continue
        d = p.pos - q.pos
        if (d * e.conjugate()).real > 0 and abs(d) - p.radius - q.radius < PERSON_KEEP_GAP + HEELS_GAP:
            return True
    return False


@jit
def group_forces(people, prm, direction, force, centres, counts):  # noqa: ANN001, ANN201
    """Gaze, coherence and repulsion among the members of a group walking together (reference §6.5), added to
    `force`."""
    n = people.shape[0]
    for g in range(centres.shape[0]):
        centres[g] = 0j
        counts[g] = 0.0
    for i in range(n):
        if in_group_walk(people[i]):
            centres[people[i].group] += people[i].pos
            counts[people[i].group] += 1.0
    for i in range(n):
        p = people[i]
        if not in_group_walk(p) or counts[p.group] < 2:
            continue
        size = counts[p.group]
        centre = centres[p.group] / size
        others = (size * centre - p.pos) / (size - 1) - p.pos
        e = direction[i]
        along = (e * others.conjugate()).real
        e2 = abs(e) ** 2
        if along < 0 and e2 > 0 and not on_heels(people, i, e):  # the others are behind: slow down
            force[i] += prm.k_gaze * along / e2 * e
        w = centre - p.pos
        force[i] += prm.k_coh * (math.tanh(abs(w) - (size - 1) / 2) + 1) / 2 * w
        rep = 0j
        for j in range(n):
            if j != i and people[j].group == p.group and in_group_walk(people[j]):
                d = p.pos - people[j].pos
                if abs(d) < p.radius + people[j].radius:
                    rep += d
        force[i] += prm.k_rep * rep


@jit
def move(people, group_sizes, prm, world, dt, scratch, robot_pos, robot_radius):  # noqa: ANN001, ANN201
    """One force step for the walkers (using the environment force of the previous call), each heading for
    its point of this step (`via`: people.routing), never stepping into someone (people.spacing) nor into the
    robot (people.avoid); the
    others stand (zero velocity) or turn. Flags people that reached their real goal; returns how many."""
    n = people.shape[0]
    direction, force = scratch.direction, scratch.force
    for i in range(n):
        p = people[i]
        direction[i] = 0j
        if p.to_goal and p.has_spot:  # a spot round a goal someone else stands on (people.spots)
            target, radius, has = p.spot, SPOT_BRAKE, p.has_goal
        elif p.to_goal:
            target, radius, has = p.goal, p.goal_radius, p.has_goal
        else:
            target, radius, has = p.target, p.target_radius, True
        dist = abs(target - p.pos)
        ahead = p.via - p.pos if p.walks else target - p.pos
        if has and dist > radius and abs(ahead) > 1e-12:
            direction[i] = ahead / abs(ahead)
            out = let_out(people, i, direction[i], world, scratch.grid)  # someone coming out of where they go
            if out != 0j:
                direction[i] = out
            force[i] = prm.k_des * (p.desired_speed * direction[i] - p.vel) / prm.tau
        else:
            force[i] = -p.vel / prm.tau  # within the target's radius: brake
        if not (p.to_goal and p.has_spot and (dist <= radius or not has)):  # at their spot round a taken goal: they stand
            force[i] += p.env_force + p.push + wall_relief(p, direction[i], prm)
    if group_sizes.shape[0] > 0:
        group_forces(people, prm, direction, force, scratch.centres, scratch.counts)
    reached = 0
    for i in range(n):
        p = people[i]
        old = p.yaw
        p.reached = False
        if p.walks:
            v = p.vel + force[i] * dt
            speed = abs(v)
            if speed > p.desired_speed:
                v = v * (p.desired_speed / speed)
            v = keep_apart(people, i, v, direction[i], dt, scratch.grid)
            reach = p.radius + robot_radius
            keep = keep_gap(world, p.pos, p.radius, abs(p.pos - robot_pos) - reach)
            v = keep_off(v, p.pos, robot_pos, reach, dt, keep)
            speed = abs(v)
            if speed > 1e-9:
                p.yaw = math.atan2(v.imag, v.real)
            p.pos = p.pos + v * dt
            p.vel = v
            if p.to_goal and p.has_goal and ((abs(p.goal - p.pos) <= p.goal_radius and not spot_taken(people, i, p.goal))
                                             or queued_at(people, i, p.goal)):  # with a spot: reached there
                p.reached = True
                reached += 1
        else:
            p.vel = 0j  # as in Gazebo, someone whose tree did not make it walk reports zero velocity
            if p.turns:
                p.yaw = (p.turn_to + math.pi) % (2 * math.pi) - math.pi
        p.omega = ((p.yaw - old + math.pi) % (2 * math.pi) - math.pi) / dt
    return reached


@jit
def advance(people, group_sizes, prm, world, robot_pos, robot_vel, robot_radius, dt, scratch, step):  # noqa: ANN001, ANN201
    """(step) move the walkers; then the environment forces of the (new) positions. Returns how many people
    reached their real goal."""
    reached = move(people, group_sizes, prm, world, dt, scratch, robot_pos, robot_radius) if step else 0
    if neighbours.active(scratch.grid, people.shape[0]):
        neighbours.build(scratch.grid, people, prm.cutoff)  # the contact step uses it too
        social_grid(people, prm, scratch.grid, scratch.social)
    else:
        social_dense(people, prm, scratch.social)
    environment(people, prm, world, robot_pos, robot_vel, scratch.social)
    return reached


@jit(inline=True)
def separate(people, world, i, j):  # noqa: ANN001, ANN201
    """Push i and j apart along the line of their centres to just past PERSON_KEEP_GAP (they came closer): halves
    between two walkers or two standing, all of it by the walker when one stands; a share that would end in a
    wall (closer than half a body) is taken by the other instead (someone pressed against a wall is not pushed
    into it, and the one who walked into them steps back the whole way); returns whether anyone moved."""
    a, b = people[i], people[j]
    d = a.pos - b.pos
    dist = abs(d)
    unit = d / dist if dist > 1e-9 else complex(math.cos(0.7 * (i + 1)), math.sin(0.7 * (j + 1)))
    depth = a.radius + b.radius + PERSON_KEEP_GAP - dist + 1e-4  # just past the gap: no state on the boundary
    share_a = 0.5 if a.walks == b.walks else (1.0 if a.walks else 0.0)
    a_free = clearance_at(world, a.pos + unit * depth * share_a) >= 0.5 * a.radius
    b_free = clearance_at(world, b.pos - unit * depth * (1 - share_a)) >= 0.5 * b.radius
    if not a_free and share_a > 0 and clearance_at(world, b.pos - unit * depth) >= 0.5 * b.radius:
        share_a, a_free, b_free = 0.0, True, True
    elif not b_free and share_a < 1 and clearance_at(world, a.pos + unit * depth) >= 0.5 * a.radius:
        share_a, a_free, b_free = 1.0, True, True
    moved = False
    if share_a > 0 and a_free:
        a.pos = a.pos + unit * depth * share_a
        moved = True
    if share_a < 1 and b_free:
        b.pos = b.pos - unit * depth * (1 - share_a)
        moved = True
    return moved


@jit
def resolve_contacts(people, robot, world, slack, before, snap, grid):  # noqa: ANN001, ANN201
    """Bodies do not interpenetrate (HuNavSim's agents are solid in Gazebo). Two people closer than
    PERSON_KEEP_GAP are pushed apart along the line of their centres to that gap, the walkers taking the whole
    correction from someone standing, pair after pair in index order, in up to CONTACT_SWEEPS sweeps (someone
    arriving among people standing close together is pushed from one into the next) (a large crowd finds its overlapping
    pairs with the cell list of this step's positions, people.neighbours); then a person whose step (their own,
    or others pushing them) took them within the gap they keep from the robot (avoid.keep_gap) is put back that far from it (never farther
    than the robot's own move left them: an overlap the ROBOT causes stays, and counts as a collision). Corrections that would end inside a wall
    are dropped (between people) or the person's step is not taken (into the robot). Returns whether anyone
    was moved."""
    n = people.shape[0]
    moved = False
    for _ in range(CONTACT_SWEEPS):  # again while a separation pushed someone into a third person
        pushed = False
        for i in range(n):
            snap[i] = people[i].pos
        for i in range(n):
            for k in range(neighbours.later_overlaps(grid, people, snap, i)):
                pushed = separate(people, world, i, grid.found[k]) or pushed
        moved = moved or pushed
        if not pushed:
            break
    for i in range(n):
        p = people[i]
        reach = p.radius + robot.radius
        gap = abs(p.pos - robot.pos) - reach
        was = abs(before[i] - robot.pos) - reach
        keep = max(slack, keep_gap(world, before[i], p.radius, was))  # what keep_off kept their own steps to
        if gap >= keep:
            continue
        allowed = min(was, keep)
        if gap < allowed - 1e-9:
            away = p.pos - robot.pos
            unit = away / abs(away) if abs(away) > 1e-9 else -robot.heading
            spot = robot.pos + unit * (reach + allowed)
            p.pos = spot if clearance_at(world, spot) >= 0.5 * p.radius else before[i]
            moved = True
    return moved
