"""Where a person steps aside for the robot: the robot's upcoming path (its position followed by its waypoints
after the segment it is on, `path_point`: a turn of the robot is taken into account, not only its heading), whether
a body stands on it ahead of the robot, and the nearest spot beside it that a body reaches straight and that leaves
the robot room to pass (`plan_side_step`; a group's members plan together in people.group_way)."""

from __future__ import annotations

import math

import numpy as np

from socnavgen import proxemics
from socnavgen.bodies import STANDING
from socnavgen.sim.jit import jit
from socnavgen.sim.people.routing import project, robot_progress
from socnavgen.sim.trace import GIVE_WAY_BEHAVIOR
from socnavgen.sim.world.queries import clearance_at, free_along, free_opening

FOLLOW_WAY_AHEAD = 2.0  # m: a follower this close ahead of the robot, on its path, steps aside first
FOLLOW_WAY_MARGIN = proxemics.WAY_MARGIN_FOLLOW  # m beside the robot's path that still counts as in its way
GIVE_WAY_MARGIN = proxemics.GIVE_WAY_CLEARANCE  # m of free space between the person and the robot when aside
OUT_OF_WAY = proxemics.WAY_MARGIN_VERIFY  # m beyond both radii from the robot's path: out of its way (the
# verifier's corridor, inway/aside): a person standing outside it does not walk into it to get to a side-step spot
# (warehouse_22: a worker standing aside 0.87 m off the robot's next leg, made to make room as it turned at the
# corner, crossed in front of it to the far side of that leg and stood in its way again)
SIDE_STEP_DIRECTIONS = 16  # directions tried for the side step
SIDE_STEP_MAX = 3.0  # m: the farthest a person walks to get out of the robot's way
SIDE_STEP_SPACING = 0.1  # m: candidate spots every 0.1 m along each direction, from 0.1 m on
SIDE_STEP_TURN_COST = 0.3  # m of walk a radian away from straight sideways is worth
SIDE_STEP_FAR_COST = 0.05  # per m of walk, against clearance, when no spot is far enough
TIE = 1e-9  # m: spots and directions this close count as equally good; the first is taken
SPOT_ROOM = 0.05  # m between two bodies: a side-step spot this close to another person (or their spot) is taken
BACK_OUT_MAX = 12.0  # m along the robot's path: the farthest a person backs out to find room to stand aside
BACK_OUT_STEP = 0.2  # m: points of the robot's path tried every this far
BACK_OUT_GAP = 0.2  # m: a person backs out when no spot nearby leaves the robot this gap to pass them by
BACK_OUT_CLEARANCE = 0.3  # m from walls along the straight walk back (a body squeezes through a 0.9 m door)
ASIDE, WAIT, RESUME = 0, 1, 2  # give-way phases (ASIDE: by way of `aside_via` when backing out)
SIDE_UNITS = np.array([complex(math.cos(2 * math.pi * j / SIDE_STEP_DIRECTIONS),
                               math.sin(2 * math.pi * j / SIDE_STEP_DIRECTIONS)) for j in range(SIDE_STEP_DIRECTIONS)])
SIDE_TURNS = np.array([abs(math.remainder(2 * math.pi * j / SIDE_STEP_DIRECTIONS, 2 * math.pi))
                       for j in range(SIDE_STEP_DIRECTIONS)])


@jit
def path_size(s, seg, fallback):  # noqa: ANN001, ANN201
    """Points of the upcoming path (`fallback`: the robot and a point 1 cm ahead, when it has no path)."""
    return 2 if fallback else max(s.waypoints.shape[0] - seg, 1)


@jit
def path_point(s, seg, j, fallback):  # noqa: ANN001, ANN201
    if j == 0:
        return s.robot[0].pos
    return s.robot[0].pos + s.robot[0].heading * 0.01 if fallback else s.waypoints[seg + j]


@jit
def nearest_segment(s, p, seg, fallback, horizon):  # noqa: ANN001, ANN201
    """(index, along, distance) of the segment of the upcoming path's next `horizon` metres nearest to p: the first
    within TIE of the nearest (at a corner both segments are as near). A round trip passes a person twice: where
    the robot comes at them now is within the horizon, its way back at the end is not."""
    nearest, arc = np.inf, 0.0
    for j in range(path_size(s, seg, fallback) - 1):
        a, b = path_point(s, seg, j, fallback), path_point(s, seg, j + 1, fallback)
        if arc > horizon:
            break
        nearest = min(nearest, project(p, a, within(a, b, horizon - arc))[1])
        arc += abs(b - a)
    arc = 0.0
    for j in range(path_size(s, seg, fallback) - 1):
        a, b = path_point(s, seg, j, fallback), path_point(s, seg, j + 1, fallback)
        if arc > horizon:
            break
        along, dist = project(p, a, within(a, b, horizon - arc))
        if dist <= nearest + TIE:
            return j, along, dist
        arc += abs(b - a)
    return 0, 0.0, np.inf


@jit(inline=True)
def within(a, b, length):  # noqa: ANN001, ANN201
    """The segment a->b cut to its first `length` metres."""
    ab = b - a
    return b if abs(ab) <= length else a + ab * (max(length, 0.0) / abs(ab))


@jit
def arc_before(s, seg, k, fallback):  # noqa: ANN001, ANN201
    """Length of the upcoming path's first k segments."""
    total = 0.0
    for j in range(k):
        total += abs(path_point(s, seg, j + 1, fallback) - path_point(s, seg, j, fallback))
    return total


@jit
def in_robot_way(s, i):  # noqa: ANN001, ANN201
    """Person i stands on the robot's remaining path within its next FOLLOW_WAY_AHEAD metres (a follower the
    robot will pass only on its way back, at the end of a round trip, is not in its way now)."""
    return in_way_at(s, i, s.people[i].pos)


@jit
def in_way_at(s, i, point):  # noqa: ANN001, ANN201
    """Person i's body at `point` would be on the robot's remaining path within its next FOLLOW_WAY_AHEAD metres."""
    p, robot = s.people[i], s.robot[0]
    if abs(point - robot.pos) > FOLLOW_WAY_AHEAD or abs(robot.pos - robot.goal) <= robot.goal_tolerance:
        return False
    _, seg = robot_progress(s)
    if path_size(s, seg, False) < 2:
        return False
    reach, arc = p.radius + robot.radius + FOLLOW_WAY_MARGIN, 0.0
    for j in range(path_size(s, seg, False) - 1):
        a, b = path_point(s, seg, j, False), path_point(s, seg, j + 1, False)
        along, dist = project(point, a, b)
        if dist < reach and 0.0 < arc + along <= FOLLOW_WAY_AHEAD:
            return True
        arc += abs(b - a)
        if arc > FOLLOW_WAY_AHEAD:
            break
    return False


@jit
def taken(s, i, spot):  # noqa: ANN001, ANN201
    """Another person stands at `spot` (bodies SPOT_ROOM apart at least), or is stepping aside to it: people
    who give way together (a group in a corridor) each find a place of their own instead of walking into
    each other's and standing in the robot's way."""
    people = s.people
    for j in range(people.shape[0]):
        if j == i:
            continue
        q = people[j]
        where = q.aside if q.gives_way and q.behavior == GIVE_WAY_BEHAVIOR and q.give_way_phase != RESUME else q.pos
        if abs(where - spot) < people[i].radius + q.radius + SPOT_ROOM:
            return True
    return False


@jit
def path_distance(s, seg, fallback, spot):  # noqa: ANN001, ANN201
    """Distance from `spot` to the robot's upcoming path, and to the leg of its route it is on (a robot that
    swerved comes back to its line)."""
    d = np.inf
    for q in range(path_size(s, seg, fallback) - 1):
        d = min(d, project(spot, path_point(s, seg, q, fallback), path_point(s, seg, q + 1, fallback))[1])
    if not fallback and seg + 1 < s.waypoints.shape[0]:  # the leg from abreast of the robot on
        a, b = s.waypoints[seg], s.waypoints[seg + 1]
        along = project(s.robot[0].pos, a, b)[0]
        d = min(d, project(spot, a + (b - a) * (along / max(abs(b - a), 1e-9)), b)[1])
    return d


@jit(inline=True)
def short_of(origin, u, centre, reach):  # noqa: ANN001, ANN201
    """How far a body walks straight from `origin` along the unit `u` before its centre comes within `reach` of
    `centre` (inf: it never does)."""
    rel = centre - origin
    along = (rel * u.conjugate()).real
    across = abs((rel * u.conjugate()).imag)
    if along <= 0 or across >= reach:
        return np.inf
    return max(0.0, along - math.sqrt(reach * reach - across * across))


@jit
def short_of_robot(s, i, origin, u):  # noqa: ANN001, ANN201
    """How far person i walks straight from `origin` along the unit `u` before their body meets the robot's
    (inf: it never does): a side-step spot beyond the robot is not reached through it."""
    return short_of(origin, u, s.robot[0].pos, s.people[i].radius + s.robot[0].radius)


@jit
def short_of_standing(s, i, origin, u):  # noqa: ANN001, ANN201
    """How far person i walks straight from `origin` along `u` before their body meets someone standing (inf:
    nobody). Asked for a squeezed start only: a walker steps round someone in their way (people.spacing), but one
    pressed between a wall and the people beside them has no room to (home_05: a guest squeezed into a corner
    planned a spot on the far side of the guest beside her, walked into her and back toward the robot's way)."""
    people, least = s.people, np.inf
    for j in range(people.shape[0]):
        if j != i and abs(people[j].vel) < STANDING:
            least = min(least, short_of(origin, u, people[j].pos, people[i].radius + people[j].radius))
    return least


@jit
def side_spot(s, i, origin, prefer, want, seg, fallback):  # noqa: ANN001, ANN201
    """(rank, cost, spot) of the best spot a body walks to straight from `origin` within SIDE_STEP_MAX, not taken
    by someone else: rank 0 the nearest leaving `want` from the robot's upcoming path (straight toward `prefer`
    preferred), rank 1 (none is that far) the one farthest from it (shorter walks preferred); rank 2: none. From an
    `origin` out of the robot's way (OUT_OF_WAY) only spots reached without walking into it count. From an `origin`
    nearer a wall than the body's radius (squeezed there by others) the walk may start that near, in the directions
    that open up (free_opening), and only spots where the body has its room count: before, every direction was
    blocked at the start, no spot was found and they waited in the robot's way (home_05: a guest pushed into a
    corner 0.35 m from the wall, 0.72 m off the robot's route, waited there until it had crept past)."""
    p = s.people[i]
    distances = s.work[0]
    found, best_rank, best_cost, best = False, 2, 0.0, origin
    corridor = p.radius + s.robot[0].radius + OUT_OF_WAY
    outside = path_distance(s, seg, fallback, origin) >= corridor  # standing out of its way: no walk back into it
    squeezed = clearance_at(s.world, origin) < p.radius  # pressed nearer a wall than their body: they walk out first
    for j in range(SIDE_STEP_DIRECTIONS):
        u = prefer * SIDE_UNITS[j]
        room = min(free_opening(s.world, origin, u, SIDE_STEP_MAX, p.radius), short_of_robot(s, i, origin, u))
        if squeezed:
            room = min(room, short_of_standing(s, i, origin, u))
        count = int(math.ceil((room + 1e-9 - SIDE_STEP_SPACING) / SIDE_STEP_SPACING)) if room > 0 else 0
        if count <= 0:
            continue
        first_ok, farthest = -1, -np.inf
        for m in range(count):  # spots every SIDE_STEP_SPACING along u, from SIDE_STEP_SPACING on
            spot = origin + u * (SIDE_STEP_SPACING * (m + 1))
            d = path_distance(s, seg, fallback, spot)
            if outside and d < corridor:
                break  # this spot and those beyond it are reached through the robot's way
            free = not taken(s, i, spot) and (not squeezed or clearance_at(s.world, spot) >= p.radius)
            if d >= want and free:
                first_ok = m
                break
            distances[m] = d if free else -np.inf
            farthest = max(farthest, distances[m])
        if first_ok < 0 and farthest == -np.inf:  # every spot that way is taken
            continue
        if first_ok >= 0:
            walk = SIDE_STEP_SPACING * (first_ok + 1)
            rank, cost = 0, walk + SIDE_STEP_TURN_COST * SIDE_TURNS[j]
        else:
            m = 0
            while distances[m] < farthest - TIE:  # the first of the farthest spots
                m += 1
            walk = SIDE_STEP_SPACING * (m + 1)
            rank, cost = 1, -distances[m] + SIDE_STEP_FAR_COST * walk
        if not found or rank < best_rank or (rank == best_rank and cost < best_cost - TIE):
            found, best_rank, best_cost, best = True, rank, cost, origin + u * walk
    return best_rank, best_cost, best


@jit
def back_out(s, i, want, seg, fallback, k):  # noqa: ANN001, ANN201
    """With no room beside the robot's path (a 1 m aisle, a doorway): the nearest point straight ahead of the
    person along the robot's path (away from the robot: back the way they came when they meet it, on ahead when it
    comes up behind), at most BACK_OUT_MAX away and walkable keeping BACK_OUT_CLEARANCE from walls, from which a
    spot leaving `want` beside the path is reached: (found, that point, the spot, its arc along the upcoming
    path)."""
    p = s.people[i]
    a, b = path_point(s, seg, k, fallback), path_point(s, seg, k + 1, fallback)
    if abs(b - a) < 1e-9:
        return False, p.pos, p.pos, 0.0
    u = (b - a) / abs(b - a)
    room = free_along(s.world, p.pos, u, BACK_OUT_MAX, BACK_OUT_CLEARANCE)
    t = BACK_OUT_STEP
    while t <= room:
        q = p.pos + u * t
        t += BACK_OUT_STEP
        if taken(s, i, q):
            continue
        rank, _, spot = side_spot(s, i, q, u * 1j, want, seg, fallback)
        if rank == 0:
            j, along, _ = nearest_segment(s, q, seg, fallback, np.inf)
            return True, q, spot, arc_before(s, seg, j, fallback) + along
    return False, p.pos, p.pos, 0.0


@jit
def plan_side_step(s, i):  # noqa: ANN001, ANN201
    """Where to stand: the nearest reachable spot (walls respected, not taken by someone else) that leaves
    GIVE_WAY_MARGIN between the person and the robot all along the robot's upcoming path, preferring straight
    sideways on the side the person is on; with no such spot within SIDE_STEP_MAX, the spot farthest from the path
    (shorter walks preferred), unless that leaves the robot less than BACK_OUT_GAP to pass them: then the person
    backs out along the robot's path to the nearest place wide enough (`back_out`), if there is one."""
    p, robot = s.people[i], s.robot[0]
    want = p.radius + robot.radius + GIVE_WAY_MARGIN
    progress, seg = robot_progress(s)
    fallback = path_size(s, seg, False) < 2
    k, along, dist = nearest_segment(s, p.pos, seg, fallback, np.inf)
    # where the robot passes them: the place of its path it comes to first, not its way back at a round trip's end
    soon, along_soon, _ = nearest_segment(s, p.pos, seg, fallback, abs(p.pos - robot.pos) + want)
    p.aside_at = progress + arc_before(s, seg, soon, fallback) + along_soon
    p.give_way_phase = ASIDE
    p.aside = p.pos
    p.aside_via = p.pos
    p.aside_near, p.aside_stall = np.inf, 0.0  # on the way there (people.give_way's patience)
    if dist >= want:
        return
    a, b = path_point(s, seg, k, fallback), path_point(s, seg, k + 1, fallback)
    along_path = (b - a) / abs(b - a) if abs(b - a) > 1e-9 else robot.heading
    side = 1.0 if ((p.pos - a) * along_path.conjugate()).imag >= 0 else -1.0
    prefer = along_path * 1j * side  # away from the path on the person's side
    rank, _, best = side_spot(s, i, p.pos, prefer, want, seg, fallback)
    if rank != 0 and path_distance(s, seg, fallback, best) < p.radius + robot.radius + BACK_OUT_GAP:
        found, via, spot, arc = back_out(s, i, want, seg, fallback, k)
        if found:
            p.aside_via, best, p.aside_at = via, spot, progress + arc
    # a spot ahead of where they stood: the robot passes them there (where it comes to it first: a round trip's way
    j, along_best, _ = nearest_segment(s, best, seg, fallback, abs(best - robot.pos) + want)  # back is not it)
    p.aside_at = max(p.aside_at, progress + arc_before(s, seg, j, fallback) + along_best)
    p.aside = best
