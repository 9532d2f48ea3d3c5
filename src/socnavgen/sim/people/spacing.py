"""People and each other's bodies: a walker never steps into another person.

`keep_apart` (the walking step, after the social force): the part of a walker's velocity that would bring them
closer than bodies.PERSON_KEEP_GAP to another person's body is dropped, so they slow down, slide along them or
stop, as pedestrians do (behind someone walking on ahead of them, they follow); one who walks straight into
someone standing or coming toward them (little of their walk left after that) steps round them on their own
right at SIDESTEP of their speed (two people meeting head-on both keep right and pass), unless that person's
body is where they walk to (following someone, a goal someone stands on): then they stop at the gap. The social
force (physics.pair_force) alone lets followers, group members held by the group force and walkers crossing at
one spot press together. The contact step (physics.resolve_contacts) stays the last resort, for people others
push, and restores the same gap.
"""

from __future__ import annotations

from socnavgen.bodies import PERSON_KEEP_GAP
from socnavgen.sim.jit import jit
from socnavgen.sim.people import neighbours

SIDESTEP = 0.5  # of their speed: a walker blocked head-on by someone steps round them on the right this fast
MOVING = 0.1  # m/s: someone walking away faster than this is followed, not stepped round
BLOCKED = 0.5  # of their speed: a walker left with less than this of their walk is blocked


@jit
def keep_apart(people, i, v, dt, grid):  # noqa: ANN001, ANN201
    """Walker i's velocity v without the parts that would take them closer than PERSON_KEEP_GAP to anyone (never
    closer than they are, when others came closer themselves), with a sidestep to the right when blocked."""
    p = people[i]
    speed = abs(v)
    if speed < 1e-9:
        return v
    target = p.goal if p.to_goal else p.target
    ahead = p.via - p.pos
    e = ahead / abs(ahead) if abs(ahead) > 1e-9 else v / speed
    for k in range(neighbours.near(grid, people, i)):
        q = people[grid.found[k]]
        away = p.pos - q.pos
        dist = abs(away)
        if dist < 1e-9:
            continue
        reach = p.radius + q.radius
        gap = dist - reach
        if gap > PERSON_KEEP_GAP + 2.0 * abs(v) * dt:
            continue
        unit = away / dist
        radial = (v * unit.conjugate()).real
        lowest = (min(PERSON_KEEP_GAP, gap) - gap) / dt
        if radial >= lowest:
            continue
        v = v + (lowest - radial) * unit
        if abs(v) < BLOCKED * speed and (q.vel * unit.conjugate()).real >= -MOVING and \
                abs(target - q.pos) > reach + PERSON_KEEP_GAP:
            side = unit * 1j  # along their body, to the walker's right
            if (side * (e * -1j).conjugate()).real < 0:
                side = -side
            v = v + side * max(SIDESTEP * speed - abs(v), 0.0)
    return v
