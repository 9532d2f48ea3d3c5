"""Manners of the default robot (compiled): it keeps to one side to pass people with room, slows down near
them, steps back from someone walking into it, and never moves closer than a margin to anyone.

* pass_aside: someone ahead in (or near) its lane - coming, standing or slower - or someone faster catching
  up from behind: the robot moves sideways, to its right unless the person is clearly on its right or the
  right has no room, until the lateral distance between the two centres leaves PASS_GAP between the bodies
  (or as far as the walls allow). A head-on walker's social force has no sideways part when the two are
  exactly in line (lightsfm's angular term vanishes at theta = 0), so without this the two meet nose to nose.
* close_speed: at most CLOSE_SPEED while anyone is within PASS_GAP (intimate space, Hall's 0.45 m).
* yield_to: a person closing in within YIELD_GAP: the robot backs away from them (the robot gives way).
* keep_clear: the part of a move that would bring the robot closer than `gap` (surface to surface) to a
  person is dropped: it slides past or stops, and never pushes into anyone.
"""

from __future__ import annotations

import math

from socnavgen.bodies import CONTACT_MARGIN, INTIMATE_SPACE
from socnavgen.sim.jit import jit
from socnavgen.sim.world.queries import free_along

PASS_GAP = INTIMATE_SPACE  # m: the gap the robot tries to leave beside a person it passes
PASS_LOOK = 3.5  # m (gap) ahead: people this close ahead make the robot move aside
BEHIND_LOOK = 1.5  # m (gap) behind: someone this close and faster makes the robot move aside
PASS_CROSS = 1.5  # m (gap): the robot crosses to a person's side only while they are this far ahead
CATCHING_UP = 0.3  # m/s faster than the robot along its way: a person behind is overtaking
LATERAL_SPEED = 0.3  # m/s at most sideways
LATERAL_GAIN = 1.5  # 1/s: sideways speed per metre still to go
WALL_ROOM = 0.08  # m beyond its radius: the robot moves aside only where this much room from walls is left
CLOSE_SPEED = 0.3  # m/s at most while someone is within PASS_GAP
YIELD_GAP = 0.3  # m: someone closing in this close makes the robot back away
YIELD_SPEED = 0.35  # m/s at most, backing away
CLOSING = 0.1  # m/s: a person this fast toward the robot is closing in
POLITE_GAP = 3 * CONTACT_MARGIN  # m: the default robot never moves closer than this to anyone (0.15)


@jit
def pass_aside(s, direction):  # noqa: ANN001, ANN201
    """Sideways velocity (complex, perpendicular to the unit `direction` of travel) that makes room to pass
    the nearest person ahead in the robot's lane, or one catching up from behind; 0 when nobody is."""
    robot, people = s.robot[0], s.people
    p, rr = robot.pos, robot.radius
    back = direction.conjugate()
    vr = (robot.vel * back).real
    best, across, need = math.inf, 0.0, 0.0
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
        elif gap > BEHIND_LOOK or (q.vel * back).real - vr < CATCHING_UP:
            continue
        if gap < best:
            best, across, need = gap, rel.imag, want
    if best == math.inf:
        s.policy[0].pass_side = 0.0
        return 0j
    # the side away from the person (keep right when they are ahead in line); the side taken for this pass
    # is kept while it has room (no flip-flopping); crossing to the person's side only when they are far
    # ahead and the near side has no room
    policy = s.policy[0]
    away = -1.0 if across > -0.2 else 1.0
    first = policy.pass_side if policy.pass_side != 0.0 else away
    shift = need + first * across  # sideways distance that leaves `need` between the centres, across
    room = free_along(s.world, p, first * 1j * direction, shift, rr + WALL_ROOM)
    side = first
    if room < min(shift, 0.1) and best > PASS_CROSS:
        other = need - first * across
        other_room = free_along(s.world, p, -first * 1j * direction, other, rr + WALL_ROOM)
        if other_room > room:
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
def yield_to(s):  # noqa: ANN001, ANN201
    """Velocity out of the way of the people closing in within YIELD_GAP (0 when nobody is): sideways off the
    line they walk along, to the side the robot already is on (the other when that side has no room), and a
    little away from them."""
    robot, people = s.robot[0], s.people
    v = 0j
    for i in range(people.shape[0]):
        q = people[i]
        d = robot.pos - q.pos
        dist = abs(d)
        if dist < 1e-9 or dist - q.radius - robot.radius > YIELD_GAP:
            continue
        u = d / dist
        closing = ((q.vel - robot.vel) * u.conjugate()).real
        if closing <= CLOSING:
            continue
        w = q.vel / abs(q.vel) if abs(q.vel) > CLOSING else u
        lateral = (d * w.conjugate()).imag
        side = 1.0 if lateral >= 0 else -1.0
        if free_along(s.world, robot.pos, side * 1j * w, 0.3, robot.radius + WALL_ROOM) < 0.1:
            side = -side
        out = side * 1j * w + 0.5 * u
        v += out / abs(out) * YIELD_SPEED
    if abs(v) > YIELD_SPEED:
        v = v * (YIELD_SPEED / abs(v))
    return v


@jit
def keep_clear(s, v, gap):  # noqa: ANN001, ANN201
    """`v` without the part that would take the robot closer than `gap` (surface gap) to a person: it may
    slide past or back off, never push into someone."""
    people, robot = s.people, s.robot[0]
    n = people.shape[0]
    if v == 0 or n == 0:
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
