"""Where a waiting robot stands (compiled): not in the way of the people it waits for.

* wait_aside: while a cue's timed wait holds it and someone near needs to get past it, it stands to the right of
  its way (keep right), out of the walkway, ASIDE m off its route's line or as far as the walls leave WALL_ROOM:
  not in the middle of a corridor.
* off_their_way: while a `let_pass` cue stands it for a person, it waits beside that person's way (their route on
  from where they are, through their next goals: the simulator knows it): at the nearest point within SPOT_REACH
  that leaves CLEAR_OF_WAY between its body and theirs walking it and that it can reach (walls, people), else the
  one farthest from their way. A robot waiting for someone to come through stood on the open floor right on her
  line, and she stalled half a metre in front of it, then squeezed past (home_06 of the new-request suite); a
  way straight across her line was blocked by the end of a wall there, a way round it was not.
"""

from __future__ import annotations

import math

from socnavgen.bodies import PERSON_PASS_GAP
from socnavgen.sim.jit import jit
from socnavgen.sim.people.routing import project
from socnavgen.sim.robot.polite import (
    LATERAL_GAIN,
    LATERAL_SPEED,
    ROUTE_LOOK,
    WALL_ROOM,
    coming_through,
    stands_clear,
)
from socnavgen.sim.world.queries import free_along

ASIDE = 1.0  # m right of its route's line at most, a waiting robot stands (wait_aside)
ASIDE_LOOK = 3.6  # m (gap, social space): someone this near who needs to get past makes a waiting robot step aside
CLEAR_OF_WAY = PERSON_PASS_GAP  # m between the bodies: a robot letting someone pass stands this far off their way
# (the gap a person leaves passing the robot where there is room: they walk on past it without swerving)
SPOT_REACH = 1.5  # m: a robot letting someone pass looks this far round it for where to wait (choose_spot) ...
SPOT_STEP = 0.25  # m: ... on rings this far apart ...
SPOT_ANGLES = 24  # ... at this many points round each
SPOT_BETTER = 0.05  # m farther from their way: a spot farther off is only taken for this much more
SPOT_SLACK = 0.1  # m: the spot is chosen again once their way comes this much nearer to it than when chosen
SETTLED = 0.02  # m: nearer than this to where it should stand, a waiting robot stays put


@jit
def wait_aside(s):  # noqa: ANN001, ANN201
    """Sideways velocity (complex) that takes a waiting robot to the right of its route's current leg, ASIDE m off
    its line or as far as the walls leave it WALL_ROOM, while someone within ASIDE_LOOK (gap) needs to get past
    it (coming_through: their goal or route lies beyond it); 0 once there, with nobody coming, or on a leg of no
    length."""
    policy, robot, wps = s.policy[0], s.robot[0], s.waypoints
    k = min(max(policy.waypoint, 1), wps.shape[0] - 1)
    leg = wps[k] - wps[k - 1]
    if abs(leg) < 1e-9:
        return 0j
    forward = leg / abs(leg)
    who, _ = coming_through(s, forward, ASIDE_LOOK, False)
    if who < 0:
        return 0j
    right = -1j * forward
    off = -((robot.pos - wps[k - 1]) * forward.conjugate()).imag  # m right of the leg's line now
    want = ASIDE - off
    if want <= SETTLED:
        return 0j
    go = min(want, free_along(s.world, robot.pos, right, want, robot.radius + WALL_ROOM))
    if go <= SETTLED:
        return 0j
    return right * min(LATERAL_SPEED, LATERAL_GAIN * go)


@jit
def way_distance(s, i, point):  # noqa: ANN001, ANN201
    """How far `point` is from person i's way on (from where they stand through their next ROUTE_LOOK goals, the
    simulator's route for them); inf when they have no goal left."""
    q, goals = s.people[i], s.goals[i]
    a, best = q.pos, math.inf
    for j in range(min(q.queue_count, ROUTE_LOOK) if q.has_goal else 0):
        b = goals[(q.queue_start + j) % goals.shape[0]]
        best = min(best, project(point, a, b)[1])
        a = b
    return best


@jit
def free_spot(s, i, spot):  # noqa: ANN001, ANN201
    """The robot can stand at `spot` (WALL_ROOM from walls, its social gap from everyone but person i, whom it
    lets pass) and drive there straight, not through person i."""
    robot, q = s.robot[0], s.people[i]
    keep = robot.radius + WALL_ROOM
    to = spot - robot.pos
    far = abs(to)
    if far > 1e-9 and free_along(s.world, robot.pos, to / far, far, keep) < far:
        return False
    if far > 1e-9 and project(q.pos, robot.pos, spot)[1] < robot.radius + q.radius:
        return False
    return stands_clear(s, i, spot)


@jit
def choose_spot(s, i):  # noqa: ANN001, ANN201
    """Where a robot letting person i pass waits: among the points within SPOT_REACH of it (rings SPOT_STEP apart,
    SPOT_ANGLES round) where it can stand and drive to (free_spot), the nearest that leaves CLEAR_OF_WAY between
    its body and theirs walking their way (of those, the farthest from them); with none, the farthest from their
    way (the nearer of two as far). Where it stands when that is as good."""
    robot, q = s.robot[0], s.people[i]
    need = robot.radius + q.radius + CLEAR_OF_WAY
    best, best_off = robot.pos, min(way_distance(s, i, robot.pos), need)
    if best_off >= need:
        return best
    rings = int(SPOT_REACH / SPOT_STEP + 0.5)
    for m in range(1, rings + 1):
        far = m * SPOT_STEP
        for k in range(SPOT_ANGLES):
            spot = robot.pos + far * complex(math.cos(2 * math.pi * k / SPOT_ANGLES),
                                             math.sin(2 * math.pi * k / SPOT_ANGLES))
            off = min(way_distance(s, i, spot), need)
            tie = off >= need and best_off >= need and abs(spot - q.pos) > abs(best - q.pos)  # the one farther
            if (off < best_off + SPOT_BETTER and not tie) or not free_spot(s, i, spot):  # from them, of two clear
                continue
            best, best_off = spot, off
        if best_off >= need:  # the nearest ring with a clear spot: no farther
            break
    return best


@jit
def off_their_way(s, i):  # noqa: ANN001, ANN201
    """Velocity (complex) that takes a robot waiting for person i to where it stands off their way (choose_spot,
    chosen once per wait and again only when their way comes within SPOT_SLACK of the spot's gap: no dithering
    between two spots as good); 0 there, or with nowhere better to go."""
    policy, robot = s.policy[0], s.robot[0]
    if i < 0 or i >= s.people.shape[0]:
        return 0j
    need = robot.radius + s.people[i].radius + CLEAR_OF_WAY
    if not policy.has_wait_spot or way_distance(s, i, policy.wait_spot) < min(
            policy.wait_off, need) - SPOT_SLACK:
        policy.wait_spot, policy.has_wait_spot = choose_spot(s, i), True
        policy.wait_off = min(way_distance(s, i, policy.wait_spot), need)
    to = policy.wait_spot - robot.pos
    go = abs(to)
    if go <= SETTLED:
        return 0j
    return to / go * min(LATERAL_SPEED, LATERAL_GAIN * go)
