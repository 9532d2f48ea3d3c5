"""People and the robot's body: a walking person steers around the robot as people step around someone
standing or walking in their way, and never walks into it.

`steer_around_robot` (after the trees, on the step's snapshot): when the robot is in the way of the person's
walk - their velocity relative to the robot's would bring them within the passing gap of its body within
HORIZON s - they head along the tangent of the robot's body widened by that gap: on the side they are
already on, or on the other when that side leaves them no room (walls). The gap is PASS_GAP where there is
room (the person's own `pass_gap`: pass_gap_for their personal-space preference), down to MIN_PASS_GAP
past a standing robot in a tight spot (MOVING_PASS_GAP past a moving one); with
room on neither side they slow down to stand WAIT_GAP from the robot until it moves, or walk WAIT_GAP behind
it when it goes their way. A way round that would take them backwards (a robot crossing in front, moving
away along their side) is not taken: they stop and let it go by. A person whose walk is to the robot itself
(following, blocking, approaching it: route ROUTE_ROBOT) does not steer around it. A goal the robot passes
(or stands on, or next to) is no reason to walk into it: such a goal is approached to GOAL_GAP from the robot's
body (a goal on their way that it stands on is walked round: people.spots.passes_by), where they wait until it
has moved on, GOAL_PATIENCE s at most (a robot that waits for them in turn
would never move on): then they squeeze on to it. A walker who took a spot beside such a goal (people.spots: a
goal the robot stands on is taken, as one a person stands on) walks to the spot instead.

`keep_off` (the walking step, once the robot has moved): the part of a person's velocity that would bring
them closer than KEEP_GAP to the robot's body, moving or standing, is dropped, so they slide along it or stop;
where the walls leave them less room than that beside it (a 0.9 m door the robot stands or drives next to) they
squeeze by down to TIGHT_GAP (`keep_gap`). The contact step (physics.resolve_contacts) stays the last resort, for
people other people push.

HuNavSim's people only meet the robot through its social force (REGULAR agents; the SocRATES fork leaves even
that out for its trees), which does not keep them off it: the prompt tells the model that RegularNav treats
the robot as an obstacle, and people do walk around one.
"""

from __future__ import annotations

import cmath
import math

from socnavgen.bodies import PERSON_PASS_GAP, PERSON_ROBOT_GAP
from socnavgen.sim.jit import jit
from socnavgen.sim.people.spots import FIT_CLEARANCE, MIN_PASS_GAP, robot_on_way
from socnavgen.sim.people.state import ROUTE_ROBOT
from socnavgen.sim.world.queries import clearance_at, line_of_sight

PASS_GAP = PERSON_PASS_GAP  # m: the gap a person leaves passing the robot where there is room (beyond intimate space)
PREFERRED_SPACE = 1.0  # m: the personal-space preference PASS_GAP is for (a stranger's ~1 m, Hecht et al. 2019)
MOVING_PASS_GAP = 0.3  # m: the least gap a person overtakes or meets a moving robot with
BACK_ANGLE = 1.8  # rad: a way round the robot this far off the walking direction goes back the way they came
YIELD_ANGLE = 1.1  # rad: a way round a robot crossing (not oncoming) this far off means walking along with it
MOVING = 0.1  # m/s: a robot faster than this is moving
ROOM_STEP = 0.05  # m: passing gaps tried from PASS_GAP down
WAIT_GAP = 0.5  # m: with no room to pass, a person stands (or walks behind it) this far from the robot
WAIT_TIME = 1.0  # s: ... slowing down to get there in about this time
GOAL_GAP = 0.3  # m: a person whose goal the robot stands on (or next to) stops this far from its body ...
GOAL_PATIENCE = 5.0  # s: ... and is held back by it this long at most (all told) before squeezing on to the goal
KEEP_GAP = PERSON_ROBOT_GAP  # m: a person's own step never brings them closer than this to the robot's body ...
TIGHT_GAP = 0.1  # m: ... unless the walls leave less room beside it: then down to this (> CONTACT_MARGIN)
HORIZON = 3.0  # s: a robot the person would come that close to within this time is in their way
STEER_RANGE = 4.0  # m between centres: farther robots are not steered around
FIELD_OF_VIEW = 1.75  # rad either side of the walking direction (a person's visual field spans about 200 deg)


def pass_gap_for(personal_space: float) -> float:
    """The gap (m) a person whose personal-space preference is `personal_space` m leaves passing the robot where
    there is room: PASS_GAP scaled by the preference over PREFERRED_SPACE."""
    return PASS_GAP * float(personal_space) / PREFERRED_SPACE


@jit
def room_beside(s, normal, reach, least, most):  # noqa: ANN001, ANN201
    """The largest passing gap (`most` down to `least`) beside the robot on the side `normal` (unit)
    where a person's body fits off the walls; -1 when none does."""
    robot = s.robot[0]
    gap = most
    while gap >= least - 1e-9:
        if clearance_at(s.world, robot.pos + normal * (reach + gap)) >= FIT_CLEARANCE:
            return gap
        gap -= ROOM_STEP
    return -1.0


@jit
def sees(s, i):  # noqa: ANN001, ANN201
    """Line of sight from person i to the robot (computed at most once per step: p.sees_robot)."""
    p = s.people[i]
    if p.sees_robot < 0:
        p.sees_robot = 1 if line_of_sight(s.world, s.robot[0].pos, p.pos) else 0
    return p.sees_robot == 1


@jit
def steer_around_robot(s, i):  # noqa: ANN001, ANN201
    """Turn walker i's heading (p.via, p.desired_speed) around the robot when the robot is in their way."""
    p = s.people[i]
    if not steer(s, i):  # not held back by it this step: patience comes back as fast as it went
        p.goal_wait = max(0.0, p.goal_wait - s.clock[0].dt)


@jit
def steer(s, i):  # noqa: ANN001, ANN201
    """steer_around_robot; True while person i waits short of a goal the robot stands on."""
    p, robot = s.people[i], s.robot[0]
    rel = robot.pos - p.pos
    dist = abs(rel)
    reach = p.radius + robot.radius
    target = p.goal if p.to_goal else p.target
    if p.to_goal and p.has_spot and abs(p.spot_for - p.goal) < 1e-6:  # a spot beside a goal taken (people.spots)
        target = p.spot
    if dist > STEER_RANGE or dist < 1e-9 or p.route == ROUTE_ROBOT:  # the robot is where they walk to
        return False
    ahead = p.via - p.pos
    if abs(ahead) < 1e-9:
        return False
    e = ahead / abs(ahead)
    if (rel * e.conjugate()).real < dist * math.cos(FIELD_OF_VIEW) or not sees(s, i):
        return False
    # the robot stands on (or passes over) their goal; one standing on a point on their way is walked round
    if abs(target - robot.pos) < reach + p.pass_gap and not (p.to_goal and robot_on_way(s, i)):
        if abs(p.push) > 0.0:  # driven off by it (RunAwayFromRobot): their goal is no pull toward it
            return False
        if abs((rel * e.conjugate()).imag) >= reach + GOAL_GAP:
            return False  # walks past its body with room
        if p.goal_wait >= GOAL_PATIENCE:
            return True  # has waited long enough (the robot waits for them in turn): goes on to the goal
        held = max(0.0, swept_gap(p.pos, robot.pos, robot.vel, reach) - GOAL_GAP) / WAIT_TIME
        if held < p.desired_speed:  # held back by the robot
            p.desired_speed = held
            p.goal_wait += s.clock[0].dt
        return True
    if abs(target - p.pos) < dist - reach:  # arrives before reaching the robot
        return False
    w = p.desired_speed * e - robot.vel  # the walk relative to the robot
    speed_rel = abs(w)
    if speed_rel < 1e-6:
        return False
    frame = rel * (w / speed_rel).conjugate()  # the robot in the frame of the relative walk
    along, across = frame.real, frame.imag
    if along <= 0 or along > HORIZON * speed_rel:
        return False
    if abs(across) >= reach + p.pass_gap:  # it passes the robot with room to spare
        return False
    unit = rel / dist
    u = w / speed_rel  # room on a side: the person fits beside the robot as they see it, or abeam on their walk
    right, left = unit * -1j, unit * 1j
    # a moving robot is passed with more room, unless the person is already alongside it (they carry on past)
    alongside = (rel * e.conjugate()).real < reach
    least = MOVING_PASS_GAP if abs(robot.vel) > MOVING and not alongside else MIN_PASS_GAP
    most = max(p.pass_gap, least)
    room_right = max(room_beside(s, right, reach, least, most), room_beside(s, u * -1j, reach, least, most))
    room_left = max(room_beside(s, left, reach, least, most), room_beside(s, u * 1j, reach, least, most))
    # pass on the side the walk already leans to (the robot on the left: pass it on its right), else the roomier
    clockwise = across > 0 or (across == 0 and room_right >= room_left)
    room = room_right if clockwise else room_left
    if room < 0:
        clockwise, room = not clockwise, room_left if clockwise else room_right
    if room < 0:  # no room on either side: stand (or walk behind it) WAIT_GAP from it
        if abs(across) < reach + least:
            gap = dist - reach
            following = max(0.0, (robot.vel * e.conjugate()).real)
            p.desired_speed = min(p.desired_speed, max(0.0, gap - WAIT_GAP) / WAIT_TIME + following)
        return False
    if abs(across) >= reach + room:
        return False
    v = passing(robot.vel, unit, dist, reach + room, speed_rel, clockwise)
    # round a standing or oncoming robot any way but back; one crossing or going their way is let go by rather
    # than walked along with
    crossing = abs(robot.vel) > MOVING and (robot.vel * e.conjugate()).real >= 0.0  # not coming at them
    limit = YIELD_ANGLE if crossing else BACK_ANGLE
    if off_way(v, e, limit):  # pass on the other side, or stop and let it go by
        other = room_left if clockwise else room_right
        v = passing(robot.vel, unit, dist, reach + other, speed_rel, not clockwise) if other >= 0 else 0j
        if off_way(v, e, limit) or abs(v) < 1e-9:
            p.desired_speed = 0.0
            return False
    speed = abs(v)
    p.desired_speed = min(p.desired_speed, speed)
    p.via = p.pos + v / speed * max(abs(ahead), 1.0)
    return False


@jit(inline=True)
def swept_gap(pos, robot_pos, robot_vel, reach):  # noqa: ANN001, ANN201
    """The gap between a person at `pos` and the robot's body where it is or will be within HORIZON s, driving on
    at robot_vel (a moving robot is let by off its way, not only off where it is now)."""
    run = robot_vel * HORIZON
    length = abs(run)
    if length < 1e-9:
        return abs(pos - robot_pos) - reach
    along = min(max(((pos - robot_pos) * (run / length).conjugate()).real, 0.0), length)
    return abs(pos - (robot_pos + run / length * along)) - reach


@jit(inline=True)
def off_way(v, e, limit):  # noqa: ANN001, ANN201
    """Velocity v is more than `limit` radians off a person's walking direction e (unit)."""
    return (v * e.conjugate()).real < abs(v) * math.cos(limit)


@jit(inline=True)
def passing(robot_vel, unit, dist, clear, speed_rel, clockwise):  # noqa: ANN001, ANN201
    """The velocity that passes the robot (at `unit` * dist from the person, moving at robot_vel) at centre
    distance `clear`, on the given side, at relative speed speed_rel."""
    alpha = math.asin(min(1.0, clear / dist))
    return robot_vel + speed_rel * unit * cmath.exp(-1j * alpha if clockwise else 1j * alpha)


@jit(inline=True)
def keep_off(v, pos, robot_pos, reach, dt, keep):  # noqa: ANN001, ANN201
    """Velocity v of a person at `pos` without the part that would take them closer than `keep` to the
    robot's body (never closer than they are, when the robot came closer itself)."""
    away = pos - robot_pos
    dist = abs(away)
    if dist < 1e-9:
        return v
    gap = dist - reach
    if gap > keep + 2.0 * abs(v) * dt:
        return v
    unit = away / dist
    radial = (v * unit.conjugate()).real
    lowest = (min(keep, gap) - gap) / dt
    return v + (lowest - radial) * unit if radial < lowest else v


@jit(inline=True)
def keep_gap(world, pos, radius, gap):  # noqa: ANN001, ANN201
    """The gap keep_off keeps a person of `radius` at `pos`, `gap` from the robot's body, from it: KEEP_GAP where there
    is room, less where their body is closer to a wall than KEEP_GAP - gap (pressed between the robot and a door's
    jamb or an aisle's shelf, keeping KEEP_GAP would leave them no way on), TIGHT_GAP at the least."""
    free = clearance_at(world, pos) - radius
    return min(KEEP_GAP, max(TIGHT_GAP, gap + free))
