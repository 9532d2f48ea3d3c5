"""One goal point, several people: the first one there stands on it, the others stand round them.

`aim` (people.routing.plan, for every walk to a goal, whatever tree node commands it): while someone else
stands on the walker's last goal point (within its goal radius), or is walking to it ahead of them, or the robot stands
on the last goal of their path (within the walker's passing gap of its body: people.avoid would hold them back
there), the walker takes
the nearest free spot beside it - on rings round the point, in sight of it, a body off the walls, a body and
bodies.PERSON_STAND_GAP (+ SLACK) from everyone standing and from the spots others took, a body and ROBOT_GAP from
the robot - and walks there instead (`p.spot`, kept while it stays free). Spots by the robot's way still to go
(within ROUTE_CLEAR of it) count OFF_ROUTE m farther: people stand round a shared goal beside the robot's route,
not on it; a group member's spot counts TOGETHER x its distance to the farthest of their group there farther (a
group gathers side by side, not across the point from each other). So a team of four gathers round a bed instead of queueing in its doorway, children fill a bedroom, a
crowd stands round the point it walked to, a person whose goal the robot stands on waits beside it. The spot
counts as the goal reached (state.queued_at). With no free spot within the rings they walk to the point itself,
and stop as close as the others let them (state.queued_at).

A point on their way (more goals after it) that the robot stands on is no place to stand: the walker goes on toward
it until going round the robot would bring them no nearer (`passes_by`), then on to their next goal, stepping round
the robot (people.avoid). (A spot beside such a point sent a neighbour to a spot behind her through a doorway, and
she dithered 0.3 m off the robot for 9 s until it drove off.)
"""

from __future__ import annotations

import math

from socnavgen.bodies import (
    PERSON_GOAL_SLACK,
    PERSON_KEEP_GAP,
    PERSON_PASS_GAP,
    PERSON_RADIUS,
    PERSON_ROBOT_GAP,
    PERSON_STAND_GAP,
    STANDING,
)
from socnavgen.sim.jit import jit
from socnavgen.sim.world.queries import clearance_at, line_of_sight

RINGS = 3  # rings of spots round the point ...
RING_STEP = 2 * PERSON_RADIUS + PERSON_STAND_GAP + 0.1  # m: ... this far apart (the first one body from the point)
ANGLES = 24  # spots per ring
SLACK = 0.05  # m: a spot is free with this much more than the standing gap to everyone
WALL_CLEARANCE = PERSON_RADIUS + 0.05  # m: a spot keeps a body off the walls
LOOK = 5.0  # m: a walker farther than this from the point does not look for a spot yet
REACH = 0.3  # m: a walker this close to their spot has reached it
NEARER = 3.0  # a spot one ring nearer the point is worth walking this many metres farther round it
ROBOT_GAP = PERSON_PASS_GAP  # m: a spot keeps this gap from the robot's body
ROUTE_CLEAR = PERSON_PASS_GAP  # m: a spot whose body comes within this of the robot's body on its way is by it ...
OFF_ROUTE = 6.0  # m: ... and counts this much farther
MIN_PASS_GAP = PERSON_ROBOT_GAP  # m: the least gap a person squeezes past a standing robot with
FIT_CLEARANCE = 0.35  # m: a body passing the robot keeps this off the walls (a person's 0.4 m, 5 cm slack)
TOGETHER = 1.0  # a group member's spot counts this many times its distance to the farthest member there farther
# A tight place (an elevator car, a small bedroom the robot stands in): no spot of the first ring fits, so the people
# sharing it stand as people do in a lift - a body off the walls, the keeping gap apart, the first in going deepest.
TIGHT_STEP = 0.3  # m: the rings of a tight place's spots are this far apart (the first on the point itself) ...
TIGHT_RINGS = 4  # ... out to this many steps
ROOM_STEP = TIGHT_STEP  # m: room_left also looks between the rings, this far apart (a small room's corners) ...
ROOM_RINGS = round(RINGS * RING_STEP / ROOM_STEP)  # ... out to the rings' reach
TIGHT_WALL = PERSON_RADIUS + 0.02  # m: a tight spot's clearance from walls
TIGHT_GAP = PERSON_KEEP_GAP  # m: between bodies on tight spots
PINCH = 0.1  # m: the way from a spot to its point narrows this much below both ends' clearance ...
DOOR_HALF_WIDTH = 0.75  # m: ... to less than half a wide door's 1.5 m: a doorway lies between them (another room)
BEYOND = 1.0  # m: past a spot, the floor it opens into (a spot in a door's mouth opens into the room behind it)


@jit(inline=True)
def segment_distance(p, a, b):  # noqa: ANN001, ANN201
    """Distance from point p to the segment a-b."""
    ab = b - a
    length = abs(ab)
    if length < 1e-9:
        return abs(p - a)
    along = min(max(((p - a) * ab.conjugate()).real / length, 0.0), length)
    return abs(p - (a + ab / length * along))


@jit
def by_route(s, spot, clear):  # noqa: ANN001, ANN201
    """`spot` is within `clear` of the robot's way still to go (from where it is along its waypoints to its goal);
    none once it has arrived (people.grace: its followers come in round it)."""
    robot, wps = s.robot[0], s.waypoints
    if s.clock[0].arrived >= 0:
        return False
    a = robot.pos
    for j in range(robot.search_from + 1, wps.shape[0]):
        if segment_distance(spot, a, wps[j]) < clear:
            return True
        a = wps[j]
    return abs(spot - a) < clear


@jit
def robot_on(s, i, goal):  # noqa: ANN001, ANN201
    """The robot stands on `goal` for person i: still, its body within their passing gap of the point."""
    p, robot = s.people[i], s.robot[0]
    return abs(robot.vel) < STANDING and abs(goal - robot.pos) < p.radius + robot.radius + p.pass_gap


@jit(inline=True)
def last_goal(p):  # noqa: ANN001, ANN201
    """Person p walks to the last goal of their path (a point to stand at, not one on their way)."""
    return p.queue_count <= 1 and not p.cyclic


@jit
def way_round(s, i):  # noqa: ANN001, ANN201
    """Walker i's body fits beside the robot's, MIN_PASS_GAP off it and off the walls (FIT_CLEARANCE), on one side
    or the other of their way on (from the robot to the goal after their current one)."""
    p, robot = s.people[i], s.robot[0]
    after = s.goals[i, (p.queue_start + 1) % s.goals.shape[1]]
    way = after - robot.pos
    if abs(way) < 1e-9:
        return True
    side = way / abs(way) * 1j * (p.radius + robot.radius + MIN_PASS_GAP)
    return clearance_at(s.world, robot.pos + side) >= FIT_CLEARANCE or \
        clearance_at(s.world, robot.pos - side) >= FIT_CLEARANCE


@jit
def robot_on_way(s, i):  # noqa: ANN001, ANN201
    """The robot stands on walker i's goal, a point on their way (more goals after it), and there is room to go
    round it (way_round): they walk round it. With no room (the robot at an elevator's mouth) the goal is taken: they
    wait at a spot beside it, off the robot's way, as at a last goal."""
    p = s.people[i]
    return p.has_goal and not last_goal(p) and robot_on(s, i, p.goal) and way_round(s, i)


@jit
def passes_by(s, i):  # noqa: ANN001, ANN201
    """The robot stands on walker i's goal, a point on their way (robot_on_way), and they are as near it as going
    round the robot with their passing gap brings them, the robot in sight: they pass it by and walk on to the next
    goal (people.routing drops it), as people walk round someone standing where their way goes."""
    p, robot = s.people[i], s.robot[0]
    if not robot_on_way(s, i):
        return False
    near = abs(p.goal - robot.pos) + p.radius + robot.radius + p.pass_gap
    return abs(p.goal - p.pos) <= near and line_of_sight(s.world, p.pos, robot.pos)


@jit
def occupied(s, i, goal):  # noqa: ANN001, ANN201
    """The last goal of person i's path: someone else stands on it (where person i would have reached it), or walks
    to it ahead of person i without a spot of their own; any goal: the robot stands on it when it is the last goal
    of their path or leaves no way round (one on their way is passed by: passes_by). A point on their way that
    another person reaches first is no place to queue round: a group walking in file took spots round each
    point on its way and stood in a knot short of it, the first waiting for the others behind."""
    people = s.people
    p = people[i]
    if robot_on(s, i, goal) and (last_goal(p) or not way_round(s, i)):
        return True
    if not last_goal(p):  # a point on their way: people walk through it one after another, nobody stands there
        return False
    away = abs(goal - p.pos)
    for j in range(people.shape[0]):
        if j == i:
            continue
        q = people[j]
        there = abs(goal - q.pos)
        if there <= p.goal_radius + PERSON_GOAL_SLACK + SLACK and (abs(q.vel) < STANDING or not q.walks):
            return True  # (one whose tree stopped walking them this step stands, though physics zeroes their
            # speed only when it moves everyone: hospital_04's resident behind the doctor dropped her spot in the
            # room the step he stopped at the bed, and stopped, queued behind him, in the door's mouth)
        if q.walks and q.to_goal and abs(q.goal - goal) < 1e-6 and not q.has_spot and there < away:
            return True
    return False


@jit
def clear_for(s, i, goal, spot, gap, robot_gap, robot_moving):  # noqa: ANN001, ANN201
    """`spot` keeps person i's body `gap` (+ SLACK) from everyone standing and from the spots others took round the
    same goal, and `robot_gap` from the robot's (only while it stands unless `robot_moving`)."""
    people, robot = s.people, s.robot[0]
    p = people[i]
    if (robot_moving or abs(robot.vel) < STANDING) and abs(robot.pos - spot) < p.radius + robot.radius + robot_gap:
        return False
    for j in range(people.shape[0]):
        if j == i:
            continue
        q = people[j]
        reach = p.radius + q.radius + gap + SLACK
        if abs(q.vel) < STANDING and abs(q.pos - spot) < reach:
            return False
        if q.has_spot and abs(q.spot_for - goal) < 1e-6 and abs(q.spot - spot) < reach:
            return False
    return True


@jit
def free(s, i, goal, spot):  # noqa: ANN001, ANN201
    """`spot` keeps person i's body the standing gap (+ SLACK) from everyone standing and from the spots others took
    round the same goal, and ROBOT_GAP from the robot standing."""
    return clear_for(s, i, goal, spot, PERSON_STAND_GAP, ROBOT_GAP, False)


@jit
def group_spread(people, i, goal, spot):  # noqa: ANN001, ANN201
    """How far `spot` is from the farthest member of person i's group already at `goal` (standing within a ring of
    spots of it, or holding a spot round it); 0 with none there."""
    p, far = people[i], 0.0
    for j in range(people.shape[0]):
        q = people[j]
        if j == i or q.group != p.group:
            continue
        if q.has_spot and abs(q.spot_for - goal) < 1e-6:
            far = max(far, abs(q.spot - spot))
        elif abs(q.vel) < STANDING and abs(q.pos - goal) < RING_STEP:
            far = max(far, abs(q.pos - spot))
    return far


@jit
def narrows(world, spot, point, skip, spot_slack):  # noqa: ANN001, ANN201
    """The straight way from `spot` to `point`, `skip` m off either end, passes somewhere narrower than
    DOOR_HALF_WIDTH, PINCH below the point's clearance and below the spot's own + `spot_slack`: a doorway lies between
    them, the spot is not in the point's own room (visitors going into an elevator car, its 1.2 m door between the
    lobby and the car, stood in the lobby: hospital_01, hospital_27)."""
    room = clearance_at(world, point) - PINCH
    near = clearance_at(world, spot) + spot_slack
    d = point - spot
    length = abs(d)
    count = max(2, int(math.ceil(length / (0.5 * world.mpp))) + 1)
    for k in range(1, count - 1):
        along = length * k / (count - 1)
        if along < skip or along > length - skip:
            continue
        c = clearance_at(world, spot + d * (k / (count - 1)))
        if c < room and c < DOOR_HALF_WIDTH and c < near:
            return True
    return False


@jit
def through_door(world, spot, point):  # noqa: ANN001, ANN201
    """A doorway between `point` and the body at `spot`: the straight way from the point on past the spot (BEYOND m,
    up to a wall) dips somewhere, from a body's radius off the point to the far side of the body, below
    DOOR_HALF_WIDTH and PINCH below the widest floor before it and after it (PINCH and a pixel after it: clearance on
    a pixel grid wavers that much along a slanting line; before it narrows further: a farther door). A dip, not a narrowing: the way into a corner of a car narrows and never widens again (the corner is in
    the car); a spot in the car's doorway, or in the hallway by a bedroom door near its wall, is behind the dip
    (hospital_01's second visitor took a spot in the car's door, home_09's children spots in the hallway: both ends
    of their ways were no wider than the door)."""
    d = spot - point
    length = abs(d)
    if length < 1e-9:
        return False
    ahead = d / length
    step = 0.5 * world.mpp
    count = int(math.ceil((length + BEYOND) / step)) + 1
    before, dip = 0.0, math.inf  # the widest floor so far; the narrowest dip below it so far (on the body's way)
    for k in range(count):
        along = k * step
        c = clearance_at(world, point + ahead * along)
        if along > length and c <= 0.0:  # past the spot: up to a wall
            break
        if c > dip + PINCH + world.mpp:  # wider again after a dip (by more than the clearance's pixel noise): a doorway
            return True
        if along > length + PERSON_RADIUS:
            if c < dip:  # narrower still past the body: a widening after that is a farther door's
                dip = math.inf
        elif along >= PERSON_RADIUS and c < DOOR_HALF_WIDTH and c < before - PINCH:
            dip = min(dip, c)
        before = max(before, c)
    return False


@jit(inline=True)
def ring_spot(goal, radius, k):  # noqa: ANN001, ANN201
    """The k-th of the ANGLES spots on the ring of `radius` round `goal` (the one lattice of spots round a point)."""
    a = 2 * math.pi * k / ANGLES
    return goal + radius * complex(math.cos(a), math.sin(a))


@jit
def in_room(world, spot, goal, wall):  # noqa: ANN001, ANN201
    """`spot` is a place to stand in `goal`'s own room: `wall` m off the walls, in sight of the point, no doorway
    between them (through_door)."""
    return clearance_at(world, spot) >= wall and line_of_sight(world, spot, goal) and \
        not through_door(world, spot, goal)


@jit
def pick(s, i, goal):  # noqa: ANN001, ANN201
    """The free spot round `goal` nearest to person i, the inner rings first (a walk NEARER m longer round the point
    beats a spot a ring farther out), off the robot's way (a spot by it counts OFF_ROUTE m farther) and never on its
    body; (found, spot)."""
    p, robot = s.people[i], s.robot[0]
    clear = p.radius + robot.radius + ROUTE_CLEAR
    best, found, score = goal, False, math.inf
    for ring in range(1, RINGS + 1):
        radius = ring * RING_STEP
        for k in range(ANGLES):
            spot = ring_spot(goal, radius, k)
            value = abs(spot - p.pos) + NEARER * radius
            if value >= score or clearance_at(s.world, spot) < WALL_CLEARANCE:
                continue
            if abs(spot - robot.pos) < p.radius + robot.radius + ROBOT_GAP:
                continue
            if by_route(s, spot, clear):
                value += OFF_ROUTE
            if p.group >= 0:
                value += TOGETHER * group_spread(s.people, i, goal, spot)
            if value >= score:
                continue
            if not free(s, i, goal, spot) or not line_of_sight(s.world, spot, goal):
                continue
            best, found, score = spot, True, value
    return found, best


@jit
def tight(world, goal):  # noqa: ANN001, ANN201
    """No spot of the first ring round `goal` keeps a body WALL_CLEARANCE off the walls in the point's own open space
    (narrows): a place too small for people to stand round the point at the standing gap (a car, a nook)."""
    for k in range(ANGLES):
        spot = ring_spot(goal, RING_STEP, k)
        if clearance_at(world, spot) >= WALL_CLEARANCE and line_of_sight(world, spot, goal) and \
                not narrows(world, spot, goal, 0.0, SLACK):
            return False
    return True


@jit
def tight_free(s, i, goal, spot):  # noqa: ANN001, ANN201
    """`spot` keeps person i's body TIGHT_GAP (+ SLACK) from everyone else standing or holding a spot round `goal`,
    and PERSON_ROBOT_GAP from the robot's."""
    return clear_for(s, i, goal, spot, TIGHT_GAP, PERSON_ROBOT_GAP, True)


@jit
def pick_tight(s, i, goal):  # noqa: ANN001, ANN201
    """(found, spot): the free tight spot round `goal` farthest from person i (the first in goes deepest, leaving the
    room by the door to those after them), a body off the walls, in sight of the point on its side of any door."""
    best, found, score = goal, False, -math.inf
    p = s.people[i]
    for ring in range(TIGHT_RINGS + 1):
        for k in range(ANGLES if ring else 1):
            spot = ring_spot(goal, ring * TIGHT_STEP, k)
            value = abs(spot - p.pos)
            if value <= score or not in_room(s.world, spot, goal, TIGHT_WALL):
                continue
            if not tight_free(s, i, goal, spot):
                continue
            best, found, score = spot, True, value
    return found, best


@jit
def room_left(world, goal, bodies, radii, robot, robot_radius, radius):  # noqa: ANN001, ANN201
    """A body of `radius` finds a free spot round `goal` in the point's own room, among people standing at `bodies`
    (complex, with `radii`) and the robot standing at `robot`: one of the spots pick_tight (a tight place, at the
    keeping gap), or a spot at the standing gap on finer rings (ROOM_STEP) than pick's (with the robot standing on
    the point, pick's whole first ring lies within its gap and its second may lie outside a small room: a room a
    person sees room in), on the point's side of any door. The verifier's "the room is full"
    (verify.way_end: a follower may end at the door of a car their guide fills, not of a roomy bedroom)."""
    small = tight(world, goal)
    wall = TIGHT_WALL if small else WALL_CLEARANCE
    gap = TIGHT_GAP if small else PERSON_STAND_GAP
    robot_gap = PERSON_ROBOT_GAP if small else ROBOT_GAP
    for ring in range(0 if small else 1, (TIGHT_RINGS if small else ROOM_RINGS) + 1):
        for k in range(ANGLES if ring else 1):
            spot = ring_spot(goal, ring * (TIGHT_STEP if small else ROOM_STEP), k)
            if abs(spot - robot) < radius + robot_radius + robot_gap:
                continue
            clear = True
            for j in range(bodies.shape[0]):
                if abs(bodies[j] - spot) < radius + radii[j] + gap + SLACK:
                    clear = False
                    break
            if clear and in_room(world, spot, goal, wall):
                return True
    return False


@jit
def shared(s, i, goal):  # noqa: ANN001, ANN201
    """Someone else's last goal is `goal` too, and they have not come to stand there yet."""
    people = s.people
    for j in range(people.shape[0]):
        q = people[j]
        if j != i and q.has_goal and last_goal(q) and abs(q.goal - goal) < 1e-6 and abs(q.vel) >= STANDING:
            return True
    return False


@jit
def crowded(s, i, goal):  # noqa: ANN001, ANN201
    """Someone else holds a spot round `goal` or stands within the tight rings of it (TIGHT_RINGS x TIGHT_STEP)."""
    people = s.people
    for j in range(people.shape[0]):
        q = people[j]
        if j == i:
            continue
        if (q.has_spot and abs(q.spot_for - goal) < 1e-6) or \
                (abs(q.vel) < STANDING and abs(q.pos - goal) <= TIGHT_RINGS * TIGHT_STEP):
            return True
    return False


@jit
def aim(s, i):  # noqa: ANN001, ANN201
    """Where walker i, walking to their goal, heads: their spot round it while it is taken, else the goal."""
    p = s.people[i]
    goal = p.goal
    if not p.has_goal:  # the walk is over (the goal reached at their spot is consumed): they stay at the spot
        return p.spot if p.has_spot else goal
    if abs(p.push) > 0.0 or abs(goal - p.pos) > LOOK:  # driven off (RunAwayFromRobot): no spot round a goal that
        p.has_spot = False  # is no pull
        return goal
    if not occupied(s, i, goal):
        if not (last_goal(p) and (shared(s, i, goal) or crowded(s, i, goal)) and tight(s.world, goal)):
            p.has_spot = False
            return goal
        # the first of several into a tight place goes deep, not onto the point (a lift's first passenger)
        if p.has_spot and abs(p.spot_for - goal) < 1e-6 and tight_free(s, i, goal, p.spot):
            return p.spot
        found, spot = pick_tight(s, i, goal)
        p.has_spot, p.spot, p.spot_for = found, spot, goal
        return spot if found else goal
    # a spot is kept while it stays free; a group member looks again as the others of the group settle
    kept = p.has_spot and abs(p.spot_for - goal) < 1e-6 and p.group < 0
    if kept and free(s, i, goal, p.spot):
        return p.spot
    small = tight(s.world, goal)  # no room at the standing gap: as in a lift, at the keeping gap
    if kept and small and tight_free(s, i, goal, p.spot):
        return p.spot
    # a tight place: a spot in it first; the rings round it lie outside it (through its door), where one waits when
    # it is full (hospital_01's second visitor took a ring spot in the car's door's mouth)
    found, spot = pick_tight(s, i, goal) if small else pick(s, i, goal)
    if not found and small:
        found, spot = pick(s, i, goal)
    p.has_spot = found
    p.spot = spot
    p.spot_for = goal
    return spot


@jit
def spot_taken(people, i, goal):  # noqa: ANN001, ANN201
    """Person i took a spot round `goal` (then reaching it is reaching the goal)."""
    p = people[i]
    return p.has_spot and abs(p.spot_for - goal) < 1e-6


@jit
def at_spot(people, i):  # noqa: ANN001, ANN201
    """Person i stands (or walks) within REACH of the spot they took."""
    p = people[i]
    return abs(p.spot - p.pos) <= REACH
