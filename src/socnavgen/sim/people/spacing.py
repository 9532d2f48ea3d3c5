"""People and each other's bodies: a walker never steps into another person.

`keep_apart` (the walking step, after the social force): the part of a walker's velocity that would bring them
closer than the keep gap to another person's body is dropped, so they slow down, slide along them or stop, as
pedestrians do (behind someone walking on ahead of them, they follow). The keep gap is bodies.PERSON_KEEP_GAP
between walkers, bodies.PERSON_STAND_GAP from anyone when the walker comes to stand (near the end of their walk)
and from someone standing where the walker's walk ends (on their goal); walkers passing keep PERSON_KEEP_GAP.
One who walks straight into someone standing or coming toward them (little of their walk left after that) steps
round them on their own right at SIDESTEP of the speed they mean to walk at (their desired speed: a walker slowed
by the crowd still steps round at a walking pace, so the sidestep never dies away; two people meeting head-on both
keep right and pass), unless that person's body is where they walk to (following someone, a goal someone stands
on) or both follow the robot (they line up behind each other at PERSON_STAND_GAP): then they stop at the gap.
Someone whose walk has ended (no goal left, or within their target's radius: they brake) only drifts; they are
not blocked on any way and never step round (warehouse_22: two listeners standing at their spots 0.3 m apart,
drifting 0.1 m/s on the social force, were each turned into a 0.75 m/s sidestep round the other and walked off
5 m along the aisle side by side, the sidestep keeping itself alive).
One who would step round on the right back against their way (the one in the way stands ahead on their right,
more than FAR_SIDE off their way) into someone else standing there (within SIDE_ROOM of their body) steps round
on the left, on along their way, where that side is free (a crew's leader, boxed in
between the member ahead on his right, the one behind him and a wall, stepped back into the one behind, again and
again, and the crew stood 40 s). The social force (physics.pair_force) alone lets followers, group members held by
the group force and walkers crossing at one spot press together. The contact step (physics.resolve_contacts) stays
the last resort, for people others push, and restores PERSON_KEEP_GAP.

Let people out before going in (`let_out`, before the force step): a walker going in to their last goal, where someone stands
(within their bodies and the standing gap) who now walks out toward them, the walker on their way, steps aside off
that way where there is room, else back the way they came, until the other is past or off their way. Without it,
in a passage narrower than two bodies (a 1.4 m strip to a room on SocRATES's hospital) the one going in stopped at
the gap before their goal and the one coming out swayed on its sidestep against the walls for 110 s; a third
person waiting behind them stood on the robot's way for good. The one going in yields, as at a lift door: the one
coming out has nowhere to go back to.
"""

from __future__ import annotations

from socnavgen.bodies import PERSON_KEEP_GAP, PERSON_STAND_GAP, STANDING
from socnavgen.sim.jit import jit
from socnavgen.sim.people import neighbours
from socnavgen.sim.people.state import ROUTE_ROBOT
from socnavgen.sim.trace import ROBOT_BEHAVIOR
from socnavgen.sim.world.queries import clearance_at

SIDESTEP = 0.5  # of their desired speed: a walker blocked head-on by someone steps round them on the right this fast
MOVING = 0.1  # m/s: someone walking away faster than this is followed, not stepped round
BLOCKED = 0.5  # of their desired speed: a walker left with less than this of their walk is blocked
ARRIVING = 1.0  # m: a walker this close to the end of their walk is coming to stand
SIDE_ROOM = 0.2  # m beyond the keep gap: someone else this close on the side a walker would step round to blocks it
LET_OUT_GAP = 1.0  # m between bodies: someone walking out of where a walker goes, this close, makes them let them out
LET_OUT_KEEP = 0.5  # m beyond LET_OUT_GAP: ... and the walker keeps letting them out while they come this near
FAR_SIDE = 0.5  # a step round on the right going back against the walker's way by more than this (the one in the way
#   stands over 30 degrees to their right) may go round on the left instead (when someone blocks the right)


@jit(inline=True)
def fellow_followers(p, q):  # noqa: ANN001, ANN201
    """Walker p walks to the robot (following it) and q follows it too (walking or standing behind it): p lines up
    behind q at the standing gap instead of stepping round them (home_03's second guest, told FOLLOW ME, walked
    back and forth for 4 s in the doorway behind the first one, who stood 1.3 m behind the robot; followers in
    file read as touching at 0.1 m)."""
    return p.route == ROUTE_ROBOT and q.route == ROUTE_ROBOT and q.behavior == ROBOT_BEHAVIOR


@jit(inline=True)
def walk_end(p):  # noqa: ANN001, ANN201
    """Where person p's walk ends: the spot round their goal (people.spots), their goal, or their target."""
    if p.to_goal and p.has_spot:
        return p.spot
    return p.goal if p.to_goal else p.target


@jit(inline=True)
def keep_gap(p, q, end):  # noqa: ANN001, ANN201
    """The gap walker p keeps from q's body: PERSON_STAND_GAP when p comes to stand (within ARRIVING of the end of
    their walk, `end`), q stands where p's walk ends (on their goal) or both follow the robot, else PERSON_KEEP_GAP
    (walking past)."""
    if abs(end - p.pos) < ARRIVING or fellow_followers(p, q):
        return PERSON_STAND_GAP
    if abs(q.vel) < STANDING and abs(end - q.pos) < p.radius + q.radius:
        return PERSON_STAND_GAP
    return PERSON_KEEP_GAP


@jit
def side_taken(people, i, grid, count, skip, side, keep):  # noqa: ANN001, ANN201
    """Someone other than `skip` stands on walker i's `side` (unit), their bodies within keep + SIDE_ROOM: a step
    round that way runs into them (the `count` neighbours found for i this step: grid.found)."""
    p = people[i]
    for k in range(count):
        j = grid.found[k]
        if j == skip:
            continue
        d = people[j].pos - p.pos
        if abs(d) - p.radius - people[j].radius < keep + SIDE_ROOM and (d * side.conjugate()).real > 0:
            return True
    return False


@jit
def keep_apart(people, i, v, way, dt, grid):  # noqa: ANN001, ANN201
    """Walker i's velocity v without the parts that would take them closer than their keep gap to anyone (never
    closer than they are, when others came closer themselves), with a sidestep to the right when blocked on
    their `way` (the unit direction they walk this step; 0 when their walk has ended and they brake: only
    drifting, they have no way to be blocked on and nobody to step round)."""
    p = people[i]
    speed = abs(v)
    if speed < 1e-9:
        return v
    pace = max(speed, p.desired_speed)  # the walk they mean: a crawl does not shrink their sidestep
    target = p.goal if p.to_goal else p.target
    end = walk_end(p)
    e = way
    count = neighbours.near(grid, people, i)
    for k in range(count):
        q = people[grid.found[k]]
        away = p.pos - q.pos
        dist = abs(away)
        if dist < 1e-9:
            continue
        reach = p.radius + q.radius
        gap = dist - reach
        keep = keep_gap(p, q, end)
        if gap > keep + 2.0 * abs(v) * dt:
            continue
        unit = away / dist
        radial = (v * unit.conjugate()).real
        lowest = (min(keep, gap) - gap) / dt
        if radial >= lowest:
            continue
        v = v + (lowest - radial) * unit
        if abs(e) > 0.0 and abs(v) < BLOCKED * pace and (q.vel * unit.conjugate()).real >= -MOVING and \
                abs(target - q.pos) > reach + keep and abs(end - q.pos) > reach + keep and \
                not fellow_followers(p, q):
            side = unit * 1j  # along their body, to the walker's right
            if (side * (e * -1j).conjugate()).real < 0:
                side = -side
            if (side * e.conjugate()).real < -FAR_SIDE and side_taken(people, i, grid, count, grid.found[k], side, keep) \
                    and not side_taken(people, i, grid, count, grid.found[k], -side, keep):
                side = -side  # back into someone else standing on their right: round on the left
            v = v + side * max(SIDESTEP * pace - abs(v), 0.0)
    return v


@jit(inline=True)
def same_goal(p, q, reach):  # noqa: ANN001, ANN201
    """q walks to p's goal too (to a spot round it, or within `reach` of it): they are going in, not coming out."""
    if q.to_goal and q.has_spot and abs(q.spot_for - p.goal) < 1e-6:
        return True
    return abs((q.goal if q.to_goal else q.target) - p.goal) < reach


@jit(inline=True)
def in_way_of(p, q, near):  # noqa: ANN001, ANN201
    """(whether walker q walks toward p with p's body on their way, within `near` of their bodies, p's offset to the
    left of q's way in m): q heads for q.via this step."""
    out = q.via - q.pos
    if not q.walks or abs(out) < 1e-9:
        return False, 0.0
    rel = (p.pos - q.pos) * (out / abs(out)).conjugate()
    reach = p.radius + q.radius
    return rel.real > 0 and abs(rel.imag) < reach + PERSON_KEEP_GAP and abs(rel) - reach < near, rel.imag


@jit
def let_out(people, i, way, world, grid):  # noqa: ANN001, ANN201
    """The unit direction walker i steps in to let someone out of the last goal they walk to (module docstring), 0j
    when nobody comes out (someone who passes a goal on their way to another does not wait there). `way`: i's own unit direction this step (toward their walk's end)."""
    p = people[i]
    if not p.to_goal or p.queue_count > 1 or p.cyclic:  # passing through on the way elsewhere: not going in
        p.lets_out = -1
        return 0j
    end = walk_end(p)
    j = p.lets_out
    if j >= 0:
        going, _ = in_way_of(p, people[j], LET_OUT_GAP + LET_OUT_KEEP)
        if not going:
            j = -1
    if j < 0:
        for k in range(neighbours.near(grid, people, i)):
            q = people[grid.found[k]]
            reach = p.radius + q.radius + PERSON_STAND_GAP
            going, _ = in_way_of(p, q, LET_OUT_GAP)
            there = min(abs(end - q.pos), abs(p.goal - q.pos)) < reach  # on i's goal (or the spot i takes round it)
            if going and there and not same_goal(p, q, reach) and not (p.group >= 0 and q.group == p.group):
                j = grid.found[k]
                break
    p.lets_out = j
    if j < 0:
        return 0j
    q = people[j]
    _, left = in_way_of(p, q, LET_OUT_GAP + LET_OUT_KEEP)
    out = (q.via - q.pos) / abs(q.via - q.pos)
    first = 1.0 if left >= 0 else -1.0  # the nearer side off their way (head-on: i's right)
    for side in (first, -first):
        need = p.radius + q.radius + PERSON_KEEP_GAP - side * left  # across q's way until clear of their body
        step = out * 1j * side
        if clearance_at(world, p.pos + step * need) >= p.radius and clearance_at(world, p.pos + step * 0.5 * need) \
                >= p.radius:
            return step
    return -way if abs(way) > 0 else out  # no room beside: back the way they came
