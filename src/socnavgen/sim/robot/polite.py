"""Manners of the default robot (compiled): it keeps to one side to pass people with room, slows down near
them, steps back from someone walking into it, and never moves closer than a margin to anyone.

* pass_aside: someone ahead in (or near) its lane - coming, standing or slower - or someone faster catching
  up from behind, or walking its way close behind it (tails: held behind it, they are never seen catching up,
  and the two walked a corridor's length 0.5 m apart, neither passing): the robot moves sideways, to its right unless the person is clearly on its right or the
  right has no room, until the lateral distance between the two centres leaves PASS_GAP between the bodies
  (or as far as the walls allow). A head-on walker's social force has no sideways part when the two are
  exactly in line (lightsfm's angular term vanishes at theta = 0), so without this the two meet nose to nose.
* near_speed: toward anyone within EASE_GAP (personal space) it slows with the gap, down to CLOSE_SPEED at PASS_GAP
  (intimate space, Hall's 0.45 m) and nearer: where it cannot pass at a social distance it passes slowly; moving
  away from them is not slowed (someone walking into its back or side is left behind, not waited for).
* yield_to: a person closing in within YIELD_GAP, or walking at the robot within YIELD_LOOK on a line that would
  bring them within ROBOT_SOCIAL_GAP of it (someone coming out of a door next to which it waits): the robot
  steps off their line and away from them (the robot gives way, before they brush it); for someone coming to it
  (a follower, a blocker: robot.lead) it only stops.
* make_way: someone who needs to get past it (their goal, or their own route through their next goals, lies
  past the robot: a person the robot's presence stopped in a doorway or a hallway), face to face within
  FACE_GAP for `patience` s (both waiting): it backs away along the way it came while they are near, and steps
  aside where there is room.
* corner_speed (when the policy's corner_speed is set): near a blind turn of its route (the legs' points
  BLIND_SIGHT_M / 2 before and after the turn do not see each other on the map: the place inventory's blind
  turn), it drives at most corner_speed, approaching and leaving the turn within CORNER_REACH (braking into
  it at CORNER_DECEL): someone may come round it.
* where a waiting robot stands (wait_aside, off_their_way): robot.wait_spot.
* keep_clear: the part of a move that would bring the robot closer than `gap` (surface to surface) to a
  person is dropped: it slides past or stops, and never pushes into anyone.
* follow_speed: within personal space behind or abreast of someone walking its way with less than PASS_GAP beside
  them (no room to overtake with that gap), it drives along its way no faster than they walk it (it follows), and
  slower while not yet behind them: it falls in behind rather than drive abreast of them. It stops (lets them
  ahead) for someone walking its way beside it within intimate space at any pace (the two crawled abreast at
  0.1 m for 45 s: each held back for the other), and for someone who tails it (close behind, walking its way) where
  the walls leave them room past it standing but not moving (people.avoid: MIN_PASS_GAP vs MOVING_PASS_GAP).
* social_clear: keep_clear with the policy's keep_gap (bodies.ROBOT_SOCIAL_GAP for the default robot): it never
  drives closer than that to anyone, waiting behind them instead (where the way beside someone is narrower, it does
  not pass); held back so for PINNED_PATIENCE s while people press on it (pressed: someone came within that gap, or
  walks at it within PASS_GAP of it), it keeps only POLITE_GAP, so that a crowd never pins it for good. The body's
  protective field (policy.guard, robot.body.drive) follows the gap it keeps: a differential drive turning toward
  its wish does not cut closer either.
"""

from __future__ import annotations

import math

from socnavgen.bodies import CONTACT_MARGIN, INTIMATE_SPACE, PERSONAL_SPACE, ROBOT_SOCIAL_GAP, ROBOT_WALL_ROOM
from socnavgen.location.inventory import BLIND_SIGHT_M
from socnavgen.location.places import CORNER_TURN_DEG
from socnavgen.sim.jit import jit
from socnavgen.sim.people.give_way import giving_way
from socnavgen.sim.people.routing import project
from socnavgen.sim.robot.lead import goes_with_robot
from socnavgen.sim.robot.let_by import ABREAST_WALKING, SAME_WAY, WALKING, let_by, tails
from socnavgen.sim.world.queries import clearance_at, free_along, line_of_sight

PASS_GAP = INTIMATE_SPACE  # m: the gap the robot tries to leave beside a person it passes
PASS_LOOK = 3.5  # m (gap) ahead: people this close ahead make the robot move aside
BEHIND_LOOK = 1.5  # m (gap) behind: someone this close and faster makes the robot move aside
PASS_CROSS = 1.5  # m (gap): the robot crosses to a person's side only while they are this far ahead
KEPT_SIDE = 0.25  # m: a pass's side is kept unless the nearer person ahead stands this far to that side
CATCHING_UP = 0.3  # m/s faster than the robot along its way: a person behind is overtaking
LATERAL_SPEED = 0.3  # m/s at most sideways
LATERAL_GAIN = 1.5  # 1/s: sideways speed per metre still to go
WALL_ROOM = ROBOT_WALL_ROOM  # m beyond its radius: the robot moves aside only where this much room from walls is left
CLOSE_SPEED = 0.3  # m/s at most while someone is within PASS_GAP
EASE_GAP = PERSONAL_SPACE  # m: nearer than this to someone it drives toward, the robot slows (near_speed)
YIELD_GAP = 0.3  # m: someone closing in this close makes the robot back away
YIELD_LOOK = 1.0  # m (gap): someone walking at the robot this close, on a line within ROBOT_SOCIAL_GAP of its body,
# makes it step off their line
YIELD_SPEED = 0.35  # m/s at most, backing away
CLOSING = 0.1  # m/s: a person this fast toward the robot is closing in
POLITE_GAP = 3 * CONTACT_MARGIN  # m: the default robot never moves closer than this to anyone (0.15)
PINNED_PATIENCE = 4.0  # s held back by its keep_gap, pressed, before the robot settles for POLITE_GAP (social_clear)
PRESSED = 0.02  # m inside its keep_gap: someone this far in came there themselves (its moves keep out of it)
FALL_BACK = 0.5  # share of a same-way walker's speed the robot keeps while not yet behind them (follow_speed)
MAKE_WAY_GAP = 1.5  # m: someone walking toward the robot this close, face to face, may make it give way
MAKE_WAY_KEEP = 1.0  # m beyond MAKE_WAY_GAP: making way goes on while they are this near, wherever they are
FACE_GAP = 0.8  # m: standing face to face this close for `patience` s also makes it give way
MAKE_WAY_SPEED = 0.5  # m/s making way (faster than robot.body.REVERSE_SPEED: a differential drive turns round)
MAKE_WAY_REACH = 0.3  # m: a previous waypoint this close is passed on the way back
CORNER_SPEED = 0.3  # m/s: the suggested ScriptedPolicy(corner_speed=...) near a blind turn of its route
CORNER_REACH = 2.5  # m from the turn's waypoint, before and after it
CORNER_DECEL = 0.8  # m/s2: it brakes into that speed at this rate (under the 1.5 m/s2 comfort limit)
CORNER_COS = math.cos(math.radians(CORNER_TURN_DEG))  # a turn sharper than the inventory's corner
ROUTE_LOOK = 4  # goals of a person's queue looked along for whether their route goes through the robot


@jit
def stands_clear(s, skip, point):  # noqa: ANN001, ANN201
    """The robot's body at `point` keeps WALL_ROOM from the walls and its social gap from everyone but person `skip`
    (whom it passes or lets pass): where it may stand."""
    robot = s.robot[0]
    if clearance_at(s.world, point) < robot.radius + WALL_ROOM:
        return False
    for k in range(s.people.shape[0]):
        if k != skip and abs(s.people[k].pos - point) < robot.radius + s.people[k].radius + ROBOT_SOCIAL_GAP:
            return False
    return True


@jit
def lane_there(s, direction, side, shift, room):  # noqa: ANN001, ANN201
    """Moving `shift` sideways to `side` (walls leave `room`) gives the robot a lane past everyone ahead within
    PASS_LOOK: the walls let it go to within PASS_GAP - ROBOT_SOCIAL_GAP of that, and nobody ahead stands within
    its social gap of the line it would drive along from there."""
    robot = s.robot[0]
    if room < shift - (PASS_GAP - ROBOT_SOCIAL_GAP):
        return False
    there, back = robot.pos + side * 1j * direction * min(shift, room), direction.conjugate()
    for i in range(s.people.shape[0]):
        q = s.people[i]
        rel = (q.pos - robot.pos) * back
        if rel.real <= 0 or abs(rel) - robot.radius - q.radius > PASS_LOOK:
            continue
        if abs(((q.pos - there) * back).imag) < robot.radius + q.radius + ROBOT_SOCIAL_GAP:
            return False
    return True


@jit(inline=True)
def walks_its_way(q, back):  # noqa: ANN001, ANN201
    """Person q of a group walks the robot's way (`back`: its unit direction, conjugated): faster than CLOSING
    along it, to a goal ahead along it. Drifting back from the robot as it comes is no walk its way (hospital_01:
    a visitor going to the elevator it came out of, pushed back 0.2 m/s, stopped its moving aside for the pair)."""
    return q.group >= 0 and (q.vel * back).real > CLOSING and q.has_goal and ((q.goal - q.pos) * back).real > 0.0


@jit
def pass_aside(s, direction):  # noqa: ANN001, ANN201
    """Sideways velocity (complex, perpendicular to the unit `direction` of travel) that makes room to pass
    the nearest person ahead in the robot's lane, or one catching up from behind; 0 when nobody is."""
    robot, people = s.robot[0], s.people
    p, rr = robot.pos, robot.radius
    back = direction.conjugate()
    vr = (robot.vel * back).real
    best, across, need, who = math.inf, 0.0, 0.0, -1
    for i in range(people.shape[0]):
        q = people[i]
        rel = (q.pos - p) * back  # real: ahead, imag: to the left
        want = rr + q.radius + PASS_GAP
        if abs(rel.imag) >= want:
            continue
        gap = abs(rel) - rr - q.radius
        if rel.real > 0:
            if gap > PASS_LOOK:
                continue
        elif gap > BEHIND_LOOK or ((q.vel * back).real - vr < CATCHING_UP and not tails(s, i, back, gap)):
            continue
        if gap < best:
            best, across, need, who = gap, rel.imag, want, i
    if best == math.inf:
        s.policy[0].pass_side, s.policy[0].pass_who = 0.0, -1
        return 0j
    # the side away from the person (keep right when they are ahead in line); the side taken for this pass
    # is kept while it has room (no flip-flopping); crossing to the person's side only when they are far
    # ahead and the near side has no room
    policy = s.policy[0]
    away = -1.0 if across > -0.2 else 1.0
    first = policy.pass_side if policy.pass_side != 0.0 else away
    if who != policy.pass_who and first * across > KEPT_SIDE and best <= PASS_CROSS:  # the side kept from passing someone else would cross in
        first = away  # front of this nearer person, clearly on that side (in a crowd it sent the robot metres
    policy.pass_who = who  # sideways, back and forth); or they stepped aside to it (home_05's first guest)
    shift = need + first * across  # sideways distance that leaves `need` between the centres, across
    room = free_along(s.world, p, first * 1j * direction, shift, rr + WALL_ROOM)
    other = need - first * across
    other_room = free_along(s.world, p, -first * 1j * direction, other, rr + WALL_ROOM)
    walking = walks_its_way(people[who], back)
    if walking and not lane_there(s, direction, first, shift, room) \
            and not lane_there(s, direction, -first, other, other_room):  # no side has room to pass them (a family
        policy.pass_side = 0.0  # across a corridor): it follows on its way instead of swinging from wall to wall as
        return 0j  # the nearest of them changes (hospital_13: 36 s); round a group standing it still goes
    side = first
    if room < min(shift, 0.1) and best > PASS_CROSS and other_room > room:
        side, shift, room = -first, other, other_room
    policy.pass_side = side
    go = min(shift, room)
    if go <= 0.02:
        return 0j
    return side * 1j * direction * min(LATERAL_SPEED, LATERAL_GAIN * go)


@jit
def nearest_gap(s):  # noqa: ANN001, ANN201
    """The smallest robot-person gap now (inf with nobody)."""
    robot, people = s.robot[0], s.people
    best = math.inf
    for i in range(people.shape[0]):
        best = min(best, abs(people[i].pos - robot.pos) - people[i].radius - robot.radius)
    return best


@jit
def near_speed(s, v, cruise):  # noqa: ANN001, ANN201
    """The most the robot drives with velocity `v` (inf: no limit): for each person it moves toward within EASE_GAP
    (surface gap), `cruise` scaled down linearly with the gap to CLOSE_SPEED at PASS_GAP and nearer."""
    robot, people = s.robot[0], s.people
    top = math.inf
    for i in range(people.shape[0]):
        d = people[i].pos - robot.pos
        gap = abs(d) - people[i].radius - robot.radius
        if gap < EASE_GAP and (v * d.conjugate()).real > 0:
            share = min(1.0, max(0.0, (gap - PASS_GAP) / (EASE_GAP - PASS_GAP)))
            top = min(top, CLOSE_SPEED + max(0.0, cruise - CLOSE_SPEED) * share)
    return top


@jit
def yield_to(s):  # noqa: ANN001, ANN201
    """(velocity, stops): out of the way of the people closing in within YIELD_GAP, or walking at the robot within
    YIELD_LOOK on a line that passes within ROBOT_SOCIAL_GAP of its body (0 when nobody is): sideways off the line
    they walk along, to the side the robot already is on (the other when that side has no room), and a little away
    from them. `stops`: it should stand meanwhile (it yields, or someone who goes with it - robot.lead - walks up
    to it: it waits for them on its way, without stepping aside)."""
    robot, people = s.robot[0], s.people
    v, stop = 0j, False
    for i in range(people.shape[0]):
        q = people[i]
        d = robot.pos - q.pos
        dist = abs(d)
        gap = dist - q.radius - robot.radius
        if dist < 1e-9 or gap > YIELD_LOOK:
            continue
        u = d / dist
        closing = ((q.vel - robot.vel) * u.conjugate()).real
        if closing <= CLOSING:
            continue
        w = q.vel / abs(q.vel) if abs(q.vel) > CLOSING else u
        lateral = (d * w.conjugate()).imag
        if gap > YIELD_GAP and not (abs(q.vel) > CLOSING and abs(lateral) < q.radius + robot.radius + ROBOT_SOCIAL_GAP):
            continue  # farther off: only someone walking at it, whose line would bring them too close
        if gap > YIELD_GAP and (q.vel * robot.vel.conjugate()).real > 0:
            continue  # farther off and walking the way it drives (catching up from behind): pass_aside's
        if gap > YIELD_GAP and goes_with_robot(s, i):  # coming to it (a follower, a blocker): they stop short of
            stop = True  # it; it stops for them, on its way (stepping off their line, it veered beside a blocker)
            continue
        side = 1.0 if lateral >= 0 else -1.0
        if free_along(s.world, robot.pos, side * 1j * w, 0.3, robot.radius + WALL_ROOM) < 0.1:
            side = -side
        if gap > YIELD_GAP:  # stepping off their line early: sideways only (never along their way), not toward
            to_goal = q.goal - robot.pos  # their goal (where they turn to) when it lies beyond the robot, where
            if abs(q.goal - q.pos) > dist and (to_goal * (side * 1j * w).conjugate()).real > 0:  # there is room
                side = -side
            if free_along(s.world, robot.pos, side * 1j * w, 0.3, robot.radius + WALL_ROOM) < 0.1:
                continue
            v += side * 1j * w * YIELD_SPEED
            continue
        out = side * 1j * w + 0.5 * u
        v += out / abs(out) * YIELD_SPEED
    if abs(v) > YIELD_SPEED:
        v = v * (YIELD_SPEED / abs(v))
    return v, stop or v != 0


@jit
def keep_clear(s, v, gap):  # noqa: ANN001, ANN201
    """`v` without the part that would take the robot closer than `gap` (surface gap) to a person: it may
    slide past or back off, never push into someone."""
    people, robot = s.people, s.robot[0]
    n = people.shape[0]
    if v == 0 or n == 0 or math.isnan(gap):  # NaN: no limit (a policy whose keep_gap is none)
        return v
    p, dt = robot.pos, s.clock[0].dt
    for _ in range(3):  # a second person may be met after sliding along the first
        ahead = p + v * dt
        close = False
        for k in range(n):
            if abs(people[k].pos - ahead) < people[k].radius + robot.radius + gap:
                close = True
                d = people[k].pos - p
                if abs(d) >= 1e-9:
                    u = d / abs(d)
                    toward = (v * u.conjugate()).real
                    if toward > 0:
                        v -= toward * u
        if not close:
            return v
    ahead = p + v * dt
    for k in range(n):
        if not abs(people[k].pos - ahead) >= min(people[k].radius + robot.radius + gap, abs(people[k].pos - p)):
            return 0j
    return v


@jit
def follow_speed(s, direction):  # noqa: ANN001, ANN201
    """The most the robot drives along the unit `direction` (inf: no limit): for each person walking that way (faster
    than WALKING along it, within SAME_WAY of it: not someone milling about or crossing) within EASE_GAP (personal
    space) of it with less than PASS_GAP between the two sideways, not behind it: their speed along it while they
    are ahead of it, FALL_BACK of that while they are abreast (it falls in behind them). Farther off, look-ahead's
    slowing for people in its path is all (a robot following a guide). 0 (it stops, lets them ahead) for someone
    beside it within intimate space walking its way faster than ABREAST_WALKING, and for someone who tails it
    (tails) with room past it standing but not moving."""
    robot, people = s.robot[0], s.people
    back = direction.conjugate()
    top = math.inf
    for i in range(people.shape[0]):
        q = people[i]
        along = (q.vel * back).real
        if along <= ABREAST_WALKING or along < SAME_WAY * abs(q.vel):
            continue
        rel = (q.pos - robot.pos) * back
        touch = q.radius + robot.radius
        gap = abs(rel) - touch
        if rel.real <= touch and not goes_with_robot(s, i) and (
                (rel.real >= -touch and gap < PASS_GAP) or (tails(s, i, back, gap) and let_by(s, i, direction))):
            return 0.0
        if along <= WALKING or abs(rel.imag) - touch >= PASS_GAP or rel.real < -touch or gap >= EASE_GAP:
            continue
        top = min(top, along if rel.real > touch else FALL_BACK * along)
    return top


@jit
def pressed(s, gap):  # noqa: ANN001, ANN201
    """Someone presses on the robot: within `gap` of it by more than PRESSED (its own moves keep out of that), or
    walking at it within `gap` + PASS_GAP."""
    robot, people = s.robot[0], s.people
    for i in range(people.shape[0]):
        q = people[i]
        d = robot.pos - q.pos
        dist = abs(d)
        between = dist - q.radius - robot.radius
        if between < gap - PRESSED:
            return True
        if between < gap + PASS_GAP and dist > 1e-9 and ((q.vel - robot.vel) * (d / dist).conjugate()).real > CLOSING:
            return True
    return False


@jit
def social_clear(s, v):  # noqa: ANN001, ANN201
    """`v` kept clear of people by the policy's keep_gap (keep_clear); after PINNED_PATIENCE s in which that gap held
    most of the robot's wish back while people pressed on it (pressed), by POLITE_GAP only (no less than that, never
    into anyone). Held back with nobody pressing it waits: it does not squeeze past anyone. The body's protective
    field (policy.guard) is set to the gap kept."""
    policy = s.policy[0]
    if not policy.keep_gap > POLITE_GAP:
        return keep_clear(s, v, policy.keep_gap)
    out = keep_clear(s, v, policy.keep_gap)
    if abs(v) < 0.05 or abs(out) >= 0.3 * abs(v):
        policy.pinned, policy.guard = 0.0, policy.keep_gap
        return out
    if pressed(s, policy.keep_gap):
        policy.pinned += s.clock[0].dt
    if policy.pinned < PINNED_PATIENCE:
        policy.guard = policy.keep_gap
        return out
    policy.guard = POLITE_GAP
    return keep_clear(s, v, POLITE_GAP)


@jit
def route_through(s, i, point, clear):  # noqa: ANN001, ANN201
    """Person i's own route (from where they are through their next ROUTE_LOOK goals) passes within `clear`
    of `point` before it ends: someone standing there is in their way (they may have stopped because of it)."""
    q, goals = s.people[i], s.goals[i]
    a, n = q.pos, min(q.queue_count, ROUTE_LOOK)
    for j in range(n):
        b = goals[(q.queue_start + j) % goals.shape[0]]
        along, d = project(point, a, b)
        if d < clear and (j < n - 1 or along < abs(b - a) - clear):
            return True
        a = b
    return False


@jit
def coming_through(s, forward, reach, in_line):  # noqa: ANN001, ANN201
    """(who, walking): the nearest person within `reach` (gap) of the robot (`in_line`: ahead along the unit
    `forward`, its way on, in line with it) whose goal lies beyond the robot or whose route goes through it
    (route_through: they need to get past it), or who follows someone beyond it; -1 when nobody is. Not someone
    stepping aside for it (giving_way): they make room for the robot, it does not back off from them.
    `walking`: they walk toward the robot now (not standing, waiting)."""
    robot, people = s.robot[0], s.people
    p, back = robot.pos, forward.conjugate()
    who, best, walking = -1, math.inf, False
    for i in range(people.shape[0]):
        q = people[i]
        rel = (q.pos - p) * back
        gap = abs(rel) - q.radius - robot.radius
        if gap > reach or not q.has_goal or goes_with_robot(s, i) or giving_way(q) or (in_line and (rel.real <= 0 or abs(rel.imag) > q.radius + robot.radius
                                                          + PASS_GAP)):
            continue
        toward = p - q.pos
        u = toward / max(abs(toward), 1e-9)
        if 0 <= q.route < people.shape[0]:  # following someone: their goal queue is not where they go (home_16: the
            if ((people[q.route].pos - q.pos) * u.conjugate()).real <= abs(toward):  # seeker by the hider; the robot
                continue  # backed away from her stale route for 8 s); they go past only after someone past it
        elif ((q.goal - q.pos) * u.conjugate()).real <= abs(toward) and not route_through(
                s, i, p, q.radius + robot.radius + PASS_GAP):  # their goal is short of the robot, their route too
            continue
        if gap < best:
            who, best, walking = i, gap, (q.vel * u.conjugate()).real > CLOSING
    return who, walking


@jit
def room_beside(s, forward, need, who):  # noqa: ANN001, ANN201
    """The side (+1 left, -1 right, 0 none) away from person `who` where the robot can step `need` metres
    aside, off their way (right when they are in line)."""
    robot = s.robot[0]
    across = ((s.people[who].pos - robot.pos) * forward.conjugate()).imag
    side = -1.0 if across > -0.2 else 1.0
    if free_along(s.world, robot.pos, side * 1j * forward, need, robot.radius + WALL_ROOM) >= need:
        return side
    return 0.0


@jit
def behind(s):  # noqa: ANN001, ANN201
    """The waypoint behind the robot on its route: the start of the passed segment it is nearest to (one
    earlier when it stands on it)."""
    robot, wps = s.robot[0], s.waypoints
    p, last = robot.pos, min(s.policy[0].waypoint, wps.shape[0] - 1)
    j, best = 0, math.inf
    for k in range(last):
        a, b = wps[k], wps[k + 1]
        ab = b - a
        t = 0.0 if abs(ab) < 1e-9 else min(1.0, max(0.0, ((p - a) * ab.conjugate()).real / abs(ab) ** 2))
        d = abs(a + t * ab - p)
        if d < best:
            j, best = k, d
    while j > 0 and abs(wps[j] - p) < MAKE_WAY_REACH:
        j -= 1
    return j


@jit
def make_way(s, forward):  # noqa: ANN001, ANN201
    """(backing off?, velocity): someone who needs to get past the robot (coming_through: their goal or their own
    route lies past it) has stood face to face with it, within FACE_GAP, for `patience` s: it goes back the way
    it came (toward its previous waypoints) at MAKE_WAY_SPEED while they are within MAKE_WAY_GAP +
    MAKE_WAY_KEEP, and steps aside, off their way, where the passage has room. A person and a robot that both
    wait for the other are a deadlock; the robot gives way."""
    policy, robot, wps = s.policy[0], s.robot[0], s.waypoints
    if policy.retreat_to < 0:  # someone ahead, in line; once making way: them, wherever, until they are through
        who, walking = coming_through(s, forward, MAKE_WAY_GAP, True)
    else:
        who, walking = coming_through(s, forward, MAKE_WAY_GAP + MAKE_WAY_KEEP, False)
    if who < 0:
        policy.retreat_to = -1
        return False, 0j
    p = robot.pos
    need = 2 * s.people[who].radius + PASS_GAP
    if policy.retreat_to < 0:
        j = behind(s)
        back = wps[j] - p
        if abs(back) < MAKE_WAY_REACH:
            return False, 0j  # at its start: nowhere to back off to
        gap = abs(s.people[who].pos - p) - s.people[who].radius - robot.radius
        if not (policy.waited >= policy.patience and gap <= FACE_GAP):  # face to face, both waiting
            return False, 0j
        policy.retreat_to = j
    target = wps[policy.retreat_to]
    while abs(target - p) < MAKE_WAY_REACH and policy.retreat_to > 0:
        policy.retreat_to -= 1
        target = wps[policy.retreat_to]
    if abs(target - p) < MAKE_WAY_REACH:  # back at its start: nowhere further to go
        policy.retreat_to, policy.waited = -1, 0.0
        return False, 0j
    back = (target - p) / abs(target - p)
    side = room_beside(s, back, need, who)
    if side != 0.0:
        return True, side * 1j * back * LATERAL_SPEED
    return True, back * MAKE_WAY_SPEED


@jit
def blind_turn(s, k):  # noqa: ANN001, ANN201
    """Waypoint k turns the route by more than a corner (CORNER_TURN_DEG) and the points BLIND_SIGHT_M / 2 before
    and after it along the two legs (or the legs' ends) do not see each other: the robot cannot see round it."""
    wps = s.waypoints
    if k <= 0 or k >= wps.shape[0] - 1:
        return False
    a, c, b = wps[k - 1], wps[k], wps[k + 1]
    into, out = c - a, b - c
    if abs(into) < 1e-9 or abs(out) < 1e-9 or ((out * into.conjugate()).real > CORNER_COS * abs(into) * abs(out)):
        return False
    look = 0.5 * BLIND_SIGHT_M
    return not line_of_sight(s.world, c - into / abs(into) * min(look, abs(into)),
                             c + out / abs(out) * min(look, abs(out)))


@jit
def corner_speed(s):  # noqa: ANN001, ANN201
    """The most the robot drives now for the blind turns of its route near it (inf: none near, or the policy's
    corner_speed is off): its corner_speed (CORNER_SPEED suggested) within CORNER_REACH of the turn it heads
    for or has just passed, braking at CORNER_DECEL before that."""
    policy, p = s.policy[0], s.robot[0].pos
    top, slow = math.inf, policy.corner_speed
    if not slow < math.inf:  # off (the policy's corner_speed is inf or NaN)
        return top
    for k in range(max(policy.waypoint - 1, 1), min(policy.waypoint + 1, s.waypoints.shape[0] - 1)):
        d = abs(s.waypoints[k] - p)
        if d < CORNER_REACH + 1.0 and blind_turn(s, k):
            top = min(top, math.sqrt(slow ** 2 + 2 * CORNER_DECEL * max(0.0, d - CORNER_REACH)))
    return top


@jit
def corner_late(s, cruise, out):  # noqa: ANN001, ANN201
    """Fill out[m] with the seconds the robot loses at the blind turns of its route (corner_speed) between where
    it is and its waypoint m, driving at `cruise` elsewhere (0 where it is not slowed: corner_speed off, a cruise
    no faster): pacing adds it to the robot's ETA, so a person paced to meet it is not early by the corners."""
    policy, wps, offs = s.policy[0], s.waypoints, s.offsets
    out[:] = 0.0
    slow = policy.corner_speed
    n = min(out.shape[0], wps.shape[0])
    if not slow < cruise or n < 3:
        return
    per_m = 1.0 / slow - 1.0 / cruise  # s lost per metre driven at the corner's speed
    k = min(max(policy.waypoint, 1), n - 1)
    here = offs[k] - abs(wps[k] - s.robot[0].pos)  # the robot's arc position along its route
    for j in range(max(k - 1, 1), n - 1):
        if not blind_turn(s, j):
            continue
        lo, hi = max(here, offs[j] - CORNER_REACH), offs[j] + CORNER_REACH
        for m in range(j, n):
            out[m] += max(0.0, min(hi, offs[m]) - lo) * per_m
