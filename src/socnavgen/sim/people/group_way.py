"""A group makes way together: one plan for its members (people sharing a group: a group node, or a group declared
in the scenario), all on one side of the robot's upcoming path, in file along it in the order they stand along it.

Planned alone, each member took the nearest free spot on its own side: hospital_13's family split to both walls of a
2.6 m corridor and left the robot no lane; home_05's pair planned 6 s apart and the second's spot made the first's
unreachable (he stood 0.03 m inside the robot's lane for 20 s while it waited); hospital_10's west visitor walked
for a spot 2.7 m away across her family and stood short of it, in the lane. So the first member to step aside plans
for every member in the robot's way (`plan_group`): the group's side (`group_side`), then member after member along
the path, the nearest the robot first, the first place beside the path (`slot_spot`) in a file centred on the
group (`lay_out`: at most SLOT_BACK nearer the robot than they stand, a body's width and SLOT_GAP past the
previous mate's), that leaves the robot room, and that they reach straight with walls, other people and the mates'
slots out of the way; a member left only a slot short of that margin takes a spot of their own that leaves it, if
they reach one. A mate keeps their slot until their own give-way begins (`has_slot`)."""

from __future__ import annotations

import numpy as np

from socnavgen.bodies import PERSON_KEEP_GAP, PERSON_STAND_GAP, ROBOT_SOCIAL_GAP, ROBOT_WALL_ROOM
from socnavgen.sim.jit import jit
from socnavgen.sim.people.routing import robot_progress
from socnavgen.sim.people.side_step import (
    ASIDE,
    BACK_OUT_GAP,
    GIVE_WAY_MARGIN,
    RESUME,
    SIDE_STEP_MAX,
    SIDE_STEP_SPACING,
    TIE,
    arc_before,
    nearest_segment,
    path_distance,
    path_point,
    path_size,
    plan_side_step,
    short_of_robot,
    side_spot,
    taken,
)
from socnavgen.sim.people.spots import segment_distance
from socnavgen.sim.trace import GIVE_WAY_BEHAVIOR
from socnavgen.sim.world.queries import free_along

SLOT_STEP = 0.1  # m along the path between the slots tried for a member
SLOT_GAP = PERSON_STAND_GAP  # m between the bodies of two mates standing in file beside the path (closer, the people's
# own forces hold the second 0.18 m short of their slot: test_group_gives_way's pair)
SLOT_BACK = 0.2  # m: a member's slot lies at most this much nearer the robot along its path than they stand (the file is
# centred on the group, not strung out ahead of it; a walking family does not walk back toward the robot)
SLOT_REACH = SIDE_STEP_MAX  # m along the path beyond where a member stands: the farthest slot tried for them


@jit
def arc_of(s, seg, fallback, point):  # noqa: ANN001, ANN201
    """How far along the robot's upcoming path `point` lies (its nearest place on it)."""
    j, along, _ = nearest_segment(s, point, seg, fallback, np.inf)
    return arc_before(s, seg, j, fallback) + along


@jit
def at_arc(s, seg, fallback, arc):  # noqa: ANN001, ANN201
    """(point, unit direction) of the robot's upcoming path `arc` metres along it (its end beyond it)."""
    n = path_size(s, seg, fallback)
    e, left, end = s.robot[0].heading, arc, s.robot[0].pos
    for j in range(n - 1):
        a, b = path_point(s, seg, j, fallback), path_point(s, seg, j + 1, fallback)
        length = abs(b - a)
        if length < 1e-9:
            continue
        e, end = (b - a) / length, b
        if left <= length:
            return a + e * max(left, 0.0), e
        left -= length
    return end, e


@jit
def group_side(s, i, seg, fallback, want):  # noqa: ANN001, ANN201
    """(side, its own): the side of the robot's path (1: left of its way, -1: right) person i's group makes way to:
    a mate's who is stepping aside already; else the side the group stands on (its members' centre) when a body has
    `want` of room from the path there, else the side with more room. `its own` is False when the centre stands
    within a body's radius of the path: the side is then a rounding error's (hospital_08's nurses stood on the
    corridor's line, and numba and plain Python sent them to opposite walls), and plan_group weighs both."""
    people, p = s.people, s.people[i]
    centre, count = 0j, 0
    for j in range(people.shape[0]):
        q = people[j]
        if q.group != p.group:
            continue
        if j != i and q.gives_way and q.behavior == GIVE_WAY_BEHAVIOR and q.give_way_phase != RESUME and abs(q.aside - q.pos) > TIE:
            foot, e = at_arc(s, seg, fallback, arc_of(s, seg, fallback, q.aside))
            return (1.0 if ((q.aside - foot) * e.conjugate()).imag >= 0 else -1.0), True
        centre += q.pos
        count += 1
    centre /= max(count, 1)
    foot, e = at_arc(s, seg, fallback, arc_of(s, seg, fallback, centre))
    off = ((centre - foot) * e.conjugate()).imag
    on = 1.0 if off >= 0 else -1.0
    own = abs(off) >= p.radius
    room_on = free_along(s.world, foot, e * 1j * on, SIDE_STEP_MAX, p.radius)
    if room_on >= want:
        return on, own
    return (on if room_on >= free_along(s.world, foot, -e * 1j * on, SIDE_STEP_MAX, p.radius) else -on), own


@jit
def walk_clear(s, i, a, b, mates):  # noqa: ANN001, ANN201
    """Person i walks straight from a to b: the walls leave their body room, the robot's body is not on the way, nor
    is anyone else's (their group's mates only with `mates`: planned together, mates make way at the same time)."""
    people, p = s.people, s.people[i]
    d = b - a
    length = abs(d)
    if length < 1e-9:
        return True
    u = d / length
    if free_along(s.world, a, u, length, p.radius) < length - 1e-6 or short_of_robot(s, i, a, u) < length:
        return False
    for j in range(people.shape[0]):
        q = people[j]
        if j == i or (not mates and p.group >= 0 and q.group == p.group):
            continue
        if segment_distance(q.pos, a, b) < p.radius + q.radius + PERSON_KEEP_GAP:
            return False
    return True


@jit
def lane_beside(s, i, spot, away):  # noqa: ANN001, ANN201
    """Person i standing at `spot` leaves the robot a lane beside them on the far side from `away` (a unit): its
    body passes them keeping bodies.ROBOT_SOCIAL_GAP, with the room from walls it moves aside within (bodies.ROBOT_WALL_ROOM)."""
    robot = s.robot[0]
    reach = s.people[i].radius + robot.radius + ROBOT_SOCIAL_GAP
    return free_along(s.world, spot, -away, reach, robot.radius + ROBOT_WALL_ROOM) >= reach - 1e-6


@jit
def slot_spot(s, i, seg, fallback, arc, side, want, mates):  # noqa: ANN001, ANN201
    """(rank, spot) beside the robot's path `arc` metres along it, on `side`, for person i: rank 0 the nearest
    leaving `want` from the path, rank 1 (none that far) the farthest the walls allow, if it leaves the robot
    BACK_OUT_GAP to pass on its line or a lane beside them (lane_beside: a 2.6 m corridor's wall, the robot passing
    on the other side), and never in its lane (hospital_10: a spot 0.10 m off its way just inside a 1.3 m door, a
    lane beside it in the room but none in the door); rank 2: no such spot, or it is taken, or i cannot walk there
    straight (walk_clear)."""
    p, robot = s.people[i], s.robot[0]
    c, e = at_arc(s, seg, fallback, arc)
    u = e * 1j * side
    room = free_along(s.world, c, u, SIDE_STEP_MAX + want, p.radius)
    rank, best, farthest, t = 2, c, -1.0, 0.0
    while t <= room + 1e-9:
        spot = c + u * t
        d = path_distance(s, seg, fallback, spot)
        if d >= want:
            rank, best = 0, spot
            break
        if d > farthest and d >= p.radius + robot.radius and (d >= p.radius + robot.radius + BACK_OUT_GAP
                                                              or lane_beside(s, i, spot, u)):
            rank, best, farthest = 1, spot, d
        t += SIDE_STEP_SPACING
    if rank == 2 or abs(best - p.pos) > SIDE_STEP_MAX or taken(s, i, best) or not walk_clear(s, i, p.pos, best, mates):
        return 2, c  # (a slot along the robot's next leg, round its turn, is no side step: warehouse_08)
    return rank, best


@jit
def next_member(s, i, seg, fallback, want, done, done_j):  # noqa: ANN001, ANN201
    """(index, arc) of the member of i's group in the robot's way who comes next along its path after (done, done_j)
    (arc, then index): someone stepping aside already keeps their spot (it is taken), and so does anyone whose
    behaviour is the robot's already (making room); (-1, inf) when nobody is left."""
    people, p = s.people, s.people[i]
    best, best_arc = -1, np.inf
    for j in range(people.shape[0]):
        q = people[j]
        if q.group != p.group or (j != i and q.behavior == GIVE_WAY_BEHAVIOR):
            continue
        if path_distance(s, seg, fallback, q.pos) >= want:
            continue
        a = arc_of(s, seg, fallback, q.pos)
        later = a > done + TIE or (abs(a - done) <= TIE and j > done_j)
        sooner = a < best_arc - TIE or (abs(a - best_arc) <= TIE and j < best)
        if later and sooner:
            best, best_arc = j, a
    return best, best_arc


@jit
def beside(s, seg, fallback, point, side):  # noqa: ANN001, ANN201
    """How far `point` lies from the robot's upcoming path toward `side` (negative: on the other side)."""
    foot, e = at_arc(s, seg, fallback, arc_of(s, seg, fallback, point))
    return ((point - foot) * e.conjugate()).imag * side


@jit
def clear_of_slots(a, b, radius, spots, radii, count):  # noqa: ANN001, ANN201
    """A body of `radius` walking straight from a to b keeps PERSON_KEEP_GAP from the first `count` slots planned
    for mates, or comes no nearer them than it starts (they will stand there: test_give_way_narrow's third chatter
    walked round a mate already at her slot, 1.7 m, and came late)."""
    for k in range(count):  # (nearer than where they start, or within the gap: one standing by it moves off)
        if segment_distance(spots[k], a, b) < min(abs(spots[k] - a), radius + radii[k] + PERSON_KEEP_GAP) - TIE:
            return False
    return True


@jit(alloc=True)
def lay_out(s, i, want, progress, seg, fallback, stuck, side, commit):  # noqa: ANN001, ANN201
    """The group's file on `side` (see plan_group): give the members in the robot's way their slots (only with
    `commit`; without, every mate's body counts on their way, as it stands now). (person i got one, how many
    members got none that leaves `want`)."""
    people = s.people
    n = people.shape[0]
    order, arcs = np.empty(n, np.int64), np.empty(n, np.float64)
    count, done, done_j = 0, -np.inf, -1
    for _ in range(n):  # the members in the robot's way, in order along its path
        j, own = next_member(s, i, seg, fallback, want, done, done_j)
        if j < 0:
            break
        order[count], arcs[count] = j, own
        done, done_j = own, j
        count += 1
    if count == 0:
        return False, 0
    for _ in range(count):  # mates abreast on the path: the one on the group's side first (the other walks behind)
        for k in range(count - 1):
            if arcs[k + 1] - arcs[k] < people[order[k]].radius and (
                    beside(s, seg, fallback, people[order[k + 1]].pos, side)
                    > beside(s, seg, fallback, people[order[k]].pos, side) + TIE):
                order[k], order[k + 1] = order[k + 1], order[k]
                arcs[k], arcs[k + 1] = arcs[k + 1], arcs[k]
    centre, length = 0.0, 0.0
    for k in range(count):
        centre += arcs[k] / count
        if k + 1 < count:
            length += 2 * people[order[k]].radius + SLOT_GAP
    spots, radii = np.empty(n, np.complex128), np.empty(n, np.float64)
    placed, last, planned, short = 0, centre - length / 2, False, 0
    for k in range(count):
        j, own = order[k], arcs[k]
        q = people[j]
        mates = (stuck and j == i) or not commit
        first_rank, first_spot, first_arc = 2, 0j, 0.0
        a = max(last, own - SLOT_BACK)
        while a <= own + SLOT_REACH:
            rank, spot = slot_spot(s, j, seg, fallback, a, side, want, mates)
            if rank < 2 and not clear_of_slots(q.pos, spot, q.radius, spots, radii, placed):
                rank = 2
            if rank < first_rank:
                first_rank, first_spot, first_arc = rank, spot, a
            if rank == 0:
                break
            a += SLOT_STEP
        if first_rank == 1:  # no slot leaves the robot its margin: a spot of their own that does, if there is one
            c, e = at_arc(s, seg, fallback, own)  # (home_05's second guest, a table beside the path past her)
            rank, _, spot = side_spot(s, j, q.pos, e * 1j * side, want, seg, fallback)
            if (rank == 0 and walk_clear(s, j, q.pos, spot, mates)
                    and clear_of_slots(q.pos, spot, q.radius, spots, radii, placed)):
                first_rank, first_spot, first_arc = 0, spot, max(own, arc_of(s, seg, fallback, spot))
        if first_rank != 0:
            short += 1
        if first_rank == 2:
            continue  # no slot: they plan alone when their give-way begins
        spots[placed] = first_spot
        radii[placed] = q.radius
        placed += 1
        last = first_arc + 2 * q.radius + SLOT_GAP
        planned = planned or j == i
        if commit:
            q.aside, q.aside_via, q.has_slot = first_spot, first_spot, j != i
            q.aside_at = progress + first_arc  # where the robot passes them
    return planned, short


@jit
def plan_group(s, i, want, progress, seg, fallback, stuck):  # noqa: ANN001, ANN201
    """Person i's side step as their group's one plan (see the module): True when it gave i a spot (aside,
    aside_via, aside_at set). A slot the plan left i earlier is kept while the robot has not passed it, nobody else
    stands there and i still walks there straight. `stuck`: i could not reach their spot, mates' bodies count."""
    p = s.people[i]
    if p.has_slot:
        p.has_slot = False
        if not stuck and progress < p.aside_at and not taken(s, i, p.aside) and walk_clear(s, i, p.pos, p.aside, False):
            p.aside_via = p.aside
            return True
    side, own = group_side(s, i, seg, fallback, want)
    if not own and lay_out(s, i, want, progress, seg, fallback, stuck, -side, False)[1] < \
            lay_out(s, i, want, progress, seg, fallback, stuck, side, False)[1]:
        side = -side  # standing on its path: the side where more of them get clear of the robot's way (hospital_08)
    return lay_out(s, i, want, progress, seg, fallback, stuck, side, True)[0]


@jit
def plan_aside(s, i, stuck):  # noqa: ANN001, ANN201
    """Where person i steps aside for the robot now: their group's one plan (plan_group) for a member in its way,
    else their own (side_step.plan_side_step). `stuck`: they could not reach the spot planned before."""
    p, robot = s.people[i], s.robot[0]
    p.aside_near, p.aside_stall = np.inf, 0.0
    if p.group >= 0:
        want = p.radius + robot.radius + GIVE_WAY_MARGIN
        progress, seg = robot_progress(s)
        fallback = path_size(s, seg, False) < 2
        if path_distance(s, seg, fallback, p.pos) < want and plan_group(s, i, want, progress, seg, fallback, stuck):
            p.give_way_phase = ASIDE
            return
    p.has_slot = False
    plan_side_step(s, i)
