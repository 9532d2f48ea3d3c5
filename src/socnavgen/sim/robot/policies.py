"""The built-in robots, compiled into the step (`--robot scripted|waypoints|sfm|straight`; the classes of
robot.api carry their parameters). Their parameters and state are one POLICY record.

* waypoints: the paper's teleoperated robot - heads for its current waypoint in a straight line, slows down
  for people in its swept path and stops short of them, edges sideways past someone close beside it,
  slides along walls it grazes, and after waiting `patience` s behind someone who does not make way drives
  around them slowly where there is room (a social-force walker), skipping a waypoint someone stands on.
* scripted (default): plays the script (obs.cues: speed, waits, misbehave) and drives like waypoints, never
  moving into a person (keep_clear) and never backing away from its waypoint.
* sfm: a social-force robot (Helbing & Molnar 1995) following the planner's way to its waypoints, the walls
  pushing it only across that way (robot.social_force), with the same keep_clear safety layer.
* straight: deliberately rude, straight at each waypoint through people (slides along walls only).

Every built-in robot stands still for its first `start_delay` s (when its operator starts it); `keep_gap`
(m, NaN: none) is the surface gap its own moves never close to a person (keep_clear): the scripted and sfm
robots keep bodies.ROBOT_SOCIAL_GAP and PERSON_KEEP_GAP by default (robot.api), the waypoints robot none unless given one.
"""

from __future__ import annotations

import math

import numpy as np

from socnavgen import proxemics
from socnavgen.bodies import ROBOT_GOAL_TOLERANCE
from socnavgen.sim.jit import jit
from socnavgen.sim.people.make_room import short_of_goal, stopped_short  # noqa: F401 - step.py's import
from socnavgen.sim.records import layout
from socnavgen.sim.robot.brake import brake_limit
from socnavgen.sim.robot.lead import lead_speed
from socnavgen.sim.robot.planner import field_value, steer
from socnavgen.sim.robot.polite import (
    corner_speed,
    follow_speed,
    keep_clear,
    make_way,
    near_speed,
    pass_aside,
    social_clear,
    yield_to,
)
from socnavgen.sim.robot.social_force import GOAL_DECEL, sfm_toward
from socnavgen.sim.robot.wait_spot import off_their_way, wait_aside
from socnavgen.sim.world.queries import clearance_at, nearest_obstacle, path_clear
from socnavgen.sim.world.spots import nearer_spot

PYTHON, SCRIPTED, WAYPOINTS, SFM, STRAIGHT = range(5)  # PYTHON: a policy object of the user's, called per step
SWEPT_MARGIN = proxemics.WAY_MARGIN_DRIVE  # m beyond the two radii: a person this close to its path blocks it
NUDGE_BAND = 0.35  # m beyond the radii: the robot edges sideways away from a person this close to its path
NUDGE_SPEED = 0.25  # m/s
NUDGE_ROOM = 0.3  # m: edging sideways only where this much room is left beside the robot (not into a jamb)
CLOSE_REACH = 0.15  # m: a waypoint this close is reached whatever the walls
PASSED_REACH = 1.0  # m: an intermediate waypoint the robot has gone past this close counts as reached (track)
WALL_MARGIN = 0.05  # m: closer than radius + this to a wall, the robot slides along it instead of into it
LOOK_WALL = 0.3  # s of motion looked ahead for walls
WALL_PUSH = 0.15  # m/s at most, back out of a wall the robot grazes
AROUND_LOOK = 1.0  # m: room looked for on either side before going around someone
AROUND_BIAS = 0.1  # m/s sideways while going around (a person dead ahead pushes straight back otherwise)
OCCUPIED_REACH = proxemics.OCCUPIED_REACH  # m: an intermediate waypoint someone stands on is skipped this close
SKIP_DETOUR = 0.5  # m: ... by a planning robot also off a straight line, when its planned way on is no longer
APPROACH_SPEED = 0.1  # m/s: the least it drives toward someone standing in its path, until its stop gap (the linear
# slow-down alone nears it exponentially: home_10's robot crept 8 s 1 m short of a circle, never counted as waiting)
STOPPED_SHORT = 0.1  # m beyond its stop gap: the robot there is blocked by the person ahead (it waits, then acts)
KEEP_CLEAR = 0.03  # m: the sfm robot's protective field (its body's guard; robot.api.SFMPolicy)
CROWD_LOOK = 32  # with more people than this, only those within reach are looked at
ARRIVED = ROBOT_GOAL_TOLERANCE * 0.5  # m: the built-in robots stop this close to their goal

POLICY = layout([
    ("kind", "i8"), ("max_speed", "f8"), ("accel", "f8"), ("brake", "f8"), ("slow_gap", "f8"), ("stop_gap", "f8"),
    ("patience", "f8"), ("detour_speed", "f8"), ("waypoint_tolerance", "f8"),
    ("start_delay", "f8"), ("keep_gap", "f8"),  # s standing at the start; m kept from people (NaN: none)
    ("line_clearance", "f8"),  # NaN: a waypoint counts as reached within the tolerance whatever the walls
    ("rude_max_speed", "f8"), ("rude_tolerance", "f8"),  # the scripted robot's straight robot
    ("speed", "f8"), ("waited", "f8"), ("around_side", "f8"), ("pass_side", "f8"), ("pass_who", "i8"), ("has_heading", "?"), ("heading", "c16"),
    ("unicycle", "?"), ("forward", "f8"), ("turn", "f8"),  # a unicycle command (DWA) instead of a velocity
    ("speed_cap", "f8"),  # m/s: the scripted robot's cruise speed is the script's, at most this (inf: no cap)
    ("corner_speed", "f8"),  # m/s near blind turns of its route (robot.polite.corner_speed; inf: not slowed)
    ("decel", "f8"),  # m/s2: the most the body brakes this step (NaN: its own max_decel); robot.brake
    ("guard", "f8"),  # m: the body's protective field (robot.body.drive; NaN: none); the scripted robot's follows
    # the gap it keeps now (polite.social_clear)
    ("retreat_to", "i8"),  # making way (polite.make_way): the waypoint it backs toward (-1: none)
    ("pinned", "f8"),  # s its moves have been held back by its keep_gap (polite.social_clear)
    ("has_wait_spot", "?"), ("wait_spot", "c16"), ("wait_off", "f8"),  # letting someone pass: where it waits, how
    # far from their way (robot.wait_spot.off_their_way)
    ("plans", "?"), ("field_scale", "i8"),  # it follows the planner's way (robot.planner) where the line to its waypoint is blocked
    ("waypoint", "i8"), ("rude_waypoint", "i8")])


# ---- shared pieces ----------------------------------------------------------------------------------------
@jit(inline=True)
def gone_past(wps, k, p):  # noqa: ANN001, ANN201
    """The robot at `p` has gone past intermediate waypoint k (0 < k < last) without coming within its tolerance:
    within PASSED_REACH of it, beyond it along both the leg in from waypoint k - 1 and the leg on to k + 1 (so
    never at a turn back). Driving round someone 0.45 m off it, the robot turned back to it toward the peer who
    had just fallen in beside it and stood facing them (card accompanying-peer [warehouse], 100 s)."""
    w = wps[k]
    if abs(p - w) > PASSED_REACH:
        return False
    return ((p - w) * (w - wps[k - 1]).conjugate()).real > 0 and ((p - w) * (wps[k + 1] - w).conjugate()).real > 0


@jit
def track(s, rude):  # noqa: ANN001, ANN201
    """(current waypoint, is it the last), advancing past waypoints reached. A waypoint counts as reached
    within the tolerance or once gone past (gone_past), and with a line clearance only when the straight line on
    to the next one keeps that clearance from walls (else within CLOSE_REACH): cutting a doorway's corner would
    hit the jamb."""
    policy, wps, p = s.policy[0], s.waypoints, s.robot[0].pos
    last = wps.shape[0] - 1
    index = min(policy.rude_waypoint if rude else policy.waypoint, last)
    tolerance = policy.rude_tolerance if rude else policy.waypoint_tolerance
    line = math.nan if rude or policy.plans else policy.line_clearance
    while index < last:
        d = abs(wps[index] - p)
        if (d > tolerance and not (index > 0 and gone_past(wps, index, p))) or not (
                math.isnan(line) or d <= CLOSE_REACH or path_clear(s.world, p, wps[index + 1], line)):
            break
        index += 1
    if rude:
        policy.rude_waypoint = index
    else:
        policy.waypoint = index
    return wps[index], index == last


@jit
def slide_along_walls(s, v):  # noqa: ANN001, ANN201
    """`v` without its into-the-wall part when the robot is within WALL_MARGIN of touching a wall, plus a
    gentle push back out: a robot pressed against a corner slides along it instead of stopping for good."""
    p, r = s.robot[0].pos, s.robot[0].radius
    if clearance_at(s.world, p + v * LOOK_WALL) >= r + WALL_MARGIN:
        return v
    point, valid = nearest_obstacle(s.world, p)
    away = p - point
    if not valid or abs(away) < 1e-9:
        return v
    n = away / abs(away)
    into = (v * n.conjugate()).real
    if into < 0:
        v -= into * n
    clearance = clearance_at(s.world, p)
    if clearance < r:
        v += n * min(WALL_PUSH, (r - clearance) * 2.0)
    return v


# ---- the waypoints robot ----------------------------------------------------------------------------------
@jit
def look_ahead(s, direction, reach):  # noqa: ANN001, ANN201
    """(free distance to the nearest person in the swept path ahead, sideways nudge -1/0/+1 away from the
    nearest person standing close beside it, that person in the path: -1 for nobody). `reach`: where the robot
    will stop (its goal); someone beyond it is in the way only if they stand too close to that point."""
    policy, robot, people = s.policy[0], s.robot[0], s.people
    p, rr, back = robot.pos, robot.radius, direction.conjugate()
    n = people.shape[0]
    gap, nudge_at, nudge, who = np.inf, np.inf, 0.0, -1
    for i in range(n):
        q, r = people[i].pos, people[i].radius
        if n > CROWD_LOOK and not abs(q - p) < policy.slow_gap + 2.0:
            continue
        rel = (q - p) * back
        if rel.real <= 0:
            continue
        ahead = rel.real - r - rr
        margin = SWEPT_MARGIN if ahead > 0 else 0.0  # someone already beside it blocks only if bodies touch
        across = abs(rel.imag) if rel.real <= reach else abs(rel - reach)
        if across < r + rr + margin and ahead < gap:
            gap, who = ahead, i
        if r + rr + margin <= abs(rel.imag) < r + rr + NUDGE_BAND and ahead < policy.slow_gap and ahead < nudge_at:
            nudge_at, nudge = ahead, (-1.0 if rel.imag > 0 else 1.0)
    return gap, nudge, who


@jit
def reachable_goal(s, goal):  # noqa: ANN001, ANN201
    """(where to stop, how close): someone standing right next to the goal leaves the far edge of the goal's
    circle, which still counts as arrived."""
    people = s.people
    if people.shape[0] == 0:
        return goal, ARRIVED
    k, best = 0, np.inf
    for i in range(people.shape[0]):
        if abs(people[i].pos - goal) - people[i].radius < best:
            k, best = i, abs(people[i].pos - goal) - people[i].radius
    d = abs(people[k].pos - goal)
    if d >= people[k].radius + s.robot[0].radius + SWEPT_MARGIN + 0.1 or d < 1e-6:
        return goal, ARRIVED
    return goal + (goal - people[k].pos) / d * ROBOT_GOAL_TOLERANCE * 0.75, ROBOT_GOAL_TOLERANCE * 0.15




@jit
def goal_holder(s):  # noqa: ANN001, ANN201
    """The person standing on or next to the robot's goal nearest to the robot (proxemics.short_of_goal's
    first half), -1 when nobody is."""
    robot, people = s.robot[0], s.people
    who, best = -1, math.inf
    for i in range(people.shape[0]):
        q = people[i]
        if abs(q.pos - robot.goal) < robot.radius + q.radius + proxemics.GOAL_STOP_GAP and \
                abs(q.vel) < proxemics.STANDING_SPEED and abs(q.pos - robot.pos) < best:
            who, best = i, abs(q.pos - robot.pos)
    return who


@jit
def planned_past(s, k):  # noqa: ANN001, ANN201
    """A planning robot's way to waypoint k + 1 (its cost-to-go field) is no longer than by way of waypoint k, within
    SKIP_DETOUR: skipping k, it goes round what stands there, not another way (home_10's next waypoint was a door
    off the straight line)."""
    policy, p, wps = s.policy[0], s.robot[0].pos, s.waypoints
    if not policy.plans:
        return False
    scale = policy.field_scale
    on = field_value(s.fields, k + 1, scale, s.world, p)
    via = abs(wps[k] - p) + field_value(s.fields, k + 1, scale, s.world, wps[k])
    return on <= via + SKIP_DETOUR


@jit
def skip_occupied_waypoint(s, standing):  # noqa: ANN001, ANN201
    """Someone (`standing`: a member of a group standing still there) on an intermediate waypoint: head for the next
    one if it is in a clear line (or planned_past). A lone person standing on its way is asked to pass first (the
    pedestrian-obstruction card); a group chatting there is gone round, not broken up (home_10)."""
    policy, robot, wps = s.policy[0], s.robot[0], s.waypoints
    k = policy.waypoint
    if k >= wps.shape[0] - 1 or abs(wps[k] - robot.pos) > OCCUPIED_REACH:
        return False
    for i in range(s.people.shape[0]):
        if standing and (s.people[i].group < 0 or abs(s.people[i].vel) >= proxemics.STANDING_SPEED):
            continue
        if abs(s.people[i].pos - wps[k]) < s.people[i].radius + robot.radius + SWEPT_MARGIN:
            if path_clear(s.world, robot.pos, wps[k + 1], 0.5 * robot.radius + 0.05) or planned_past(s, k):
                policy.waypoint = k + 1
                return True
            return False
    return False


@jit
def waypoints_act(s):  # noqa: ANN001, ANN201
    policy, robot = s.policy[0], s.robot[0]
    target, last = track(s, False)
    p, dt = robot.pos, s.clock[0].dt
    arrive = ARRIVED
    if last and abs(target - p) < policy.slow_gap + 1.0:
        holder = goal_holder(s) if policy.kind == SCRIPTED else -1
        stop = target
        if holder >= 0:  # a free spot nearer the goal that keeps as far from everyone: it goes on there first
            found, spot = nearer_spot(s.world, target, p, robot.radius, s.people)
            if found:
                target, holder = spot, -1
        if holder >= 0:  # the polite robot stops at a social distance short of someone standing at its goal
            q = s.people[holder]
            away = p - q.pos
            reach = q.radius + robot.radius + proxemics.GOAL_STOP_GAP
            stop = q.pos + away / max(abs(away), 1e-9) * reach
        if holder >= 0 and abs(s.people[holder].pos - target) < min(abs(stop - target), abs(p - target)) \
                and abs(stop - target) <= reach:  # there it has arrived (proxemics.short_of_goal: short of them,
            target = stop  # they nearer the goal than it - than the robot itself, not only than the stop point: it
            # halts within ARRIVED of that point, and on its goal's side it stood for good, not arrived by the rule
            # the run ends by (card narrow-hallway [warehouse]: 1.14 m from the goal, the person 1.18 m, 100 s)
        else:
            target, arrive = reachable_goal(s, target)
    to = target - p
    dist = abs(to)
    if last and dist <= arrive:
        policy.speed = 0.0
        return 0j
    if policy.plans:  # around what stands between it and its waypoint
        target = steer(s, s.fields, policy.waypoint, target)
        to = target - p
    direction = to / abs(to) if abs(to) > 1e-9 else complex(math.cos(robot.yaw), math.sin(robot.yaw))
    policy.has_heading, policy.heading = True, direction
    gap, nudge, who = look_ahead(s, direction, dist if last else np.inf)
    want = policy.max_speed * min(1.0, max(0.0, (gap - policy.stop_gap) / (policy.slow_gap - policy.stop_gap)))
    if who >= 0 and abs(s.people[who].vel) < proxemics.STANDING_SPEED:  # up to its stop gap, then it waits there
        want = max(want, min(APPROACH_SPEED, policy.max_speed)) if gap - policy.stop_gap >= STOPPED_SHORT else 0.0
    if last:
        want = min(want, math.sqrt(2 * policy.accel * dist))
    blocked = gap - policy.stop_gap < STOPPED_SHORT and (not last or dist > gap + 0.5)
    policy.waited = policy.waited + dt if blocked else 0.0
    if not blocked:
        policy.around_side = 0.0
    if blocked and policy.waited >= policy.patience:
        if skip_occupied_waypoint(s, False):
            policy.waited = 0.0  # next step heads for the following waypoint
        else:
            if policy.around_side == 0.0:  # the side with more room (right on a tie): breaks the symmetry
                left = clearance_at(s.world, p + direction * 1j * AROUND_LOOK)
                right = clearance_at(s.world, p - direction * 1j * AROUND_LOOK)
                policy.around_side = 1.0 if left > right + 0.05 else -1.0
            v = sfm_toward(s, target, policy.detour_speed, False, False, ARRIVED)
            if abs(v) < AROUND_BIAS:  # pushed straight back by someone dead ahead: sidestep
                v += direction * 1j * policy.around_side * AROUND_BIAS
            v = slide_along_walls(s, v)
            policy.speed = abs(v)
            if policy.speed > 0.05:
                policy.heading = v / policy.speed
            return v
    speed = policy.speed
    policy.speed = min(want, speed + policy.accel * dt) if want >= speed else max(want, speed - policy.brake * dt)
    v = direction * policy.speed
    if nudge != 0.0 and clearance_at(s.world, p + direction * 1j * nudge * NUDGE_ROOM) >= robot.radius + 0.1:
        v += direction * 1j * nudge * NUDGE_SPEED
    return slide_along_walls(s, v)


@jit
def straight_act(s, max_speed, rude):  # noqa: ANN001, ANN201
    target, last = track(s, rude)
    to = target - s.robot[0].pos
    dist = abs(to)
    if last and dist <= ARRIVED:
        return 0j
    speed = min(max_speed, math.sqrt(2 * GOAL_DECEL * dist)) if last else max_speed
    return slide_along_walls(s, to / max(dist, 1e-9) * speed)


@jit
def way_ahead(s):  # noqa: ANN001, ANN201
    """The unit direction of the robot's way on to its current waypoint (0j there): the planner's (steer) where
    it plans. Measured against the straight line to the waypoint instead, a planned way round a wall that first
    leads away from the waypoint counted as retreating: the robot drove only its sideways part, into the wall,
    and crept along it at a few cm/s."""
    policy, p = s.policy[0], s.robot[0].pos
    target, _ = track(s, False)
    if policy.plans:
        target = steer(s, s.fields, policy.waypoint, target)
    ahead = target - p
    return ahead / abs(ahead) if abs(ahead) > 1e-9 else 0j


@jit
def scripted_act(s, now):  # noqa: ANN001, ANN201
    """Drives like waypoints with the manners of robot.polite: moves aside to pass people with room, slows
    down near them, backs away from someone walking into it, never comes within keep_gap (bodies.ROBOT_SOCIAL_GAP) of anyone."""
    policy = s.policy[0]
    if now.misbehave:
        return straight_act(s, policy.rude_max_speed, True)
    corner = corner_speed(s)
    policy.max_speed = min(now.speed, policy.speed_cap, corner)
    if now.wait:  # out of the way of anyone closing in; letting someone pass, off their way; in a timed wait, out
        policy.speed = 0.0  # of the walkway of someone coming
        v, _ = yield_to(s)
        if now.letting < 0:
            policy.has_wait_spot = False
        elif v == 0:
            v = off_their_way(s, now.letting)
        if v == 0 and now.timed and now.letting < 0:
            v = wait_aside(s)
        return social_clear(s, slide_along_walls(s, v))
    policy.has_wait_spot = False
    # a waypoint a group stands on (chatting round it) is skipped within OCCUPIED_REACH, as the Python robots'
    # Route does: it goes round them to the next instead of driving up to them to wait
    while skip_occupied_waypoint(s, True):
        pass
    forward = way_ahead(s)
    if abs(forward) > 1e-9:
        backing, v = make_way(s, forward)
        if backing:
            policy.speed = 0.0
            policy.has_heading, policy.heading = True, forward
            return social_clear(s, slide_along_walls(s, v))
    v = waypoints_act(s)
    direction = policy.heading if abs(policy.heading) > 0 else complex(math.cos(s.robot[0].yaw),
                                                                       math.sin(s.robot[0].yaw))
    u = way_ahead(s)
    if abs(u) > 1e-9:
        back = (v * u.conjugate()).real
        if back < 0:  # never retreat on its own: a crowd pushing it back would drive it the wrong way for good
            v -= back * u
    v += pass_aside(s, direction)
    along = (v * direction.conjugate()).real
    behind_them = follow_speed(s, direction)  # a same-way walker with no room to overtake: it follows them
    if along > behind_them:
        v -= (along - behind_them) * direction
    top = min(near_speed(s, v, policy.max_speed),  # slower the nearer it passes someone (personal to intimate space)
              lead_speed(s, policy.max_speed, direction))  # and while its followers fall behind
    if abs(v) > top:
        v = v * (top / abs(v))
    away, stops = yield_to(s)
    if stops:  # someone walking at it or closing in: it stops and steps out of their way (no progress meanwhile)
        v = away
    if abs(v) > corner:  # all of it (passing aside, yielding) within the blind corner's speed
        v = v * (corner / abs(v))
    v = social_clear(s, slide_along_walls(s, v))
    forward = (v * direction.conjugate()).real
    if forward < policy.speed:
        policy.speed = max(0.0, forward)
    return v


@jit
def kept_clear(s, first, v):  # noqa: ANN001, ANN201
    """`v` (the policy's wish was `first`) kept clear of people by the policy's keep_gap; the speed it keeps
    accelerating from follows when that slows it down."""
    policy = s.policy[0]
    out = keep_clear(s, v, policy.keep_gap)
    if abs(out) < abs(first) - 1e-9:
        policy.speed = min(policy.speed, abs(out))
    return out


@jit
def sfm_act(s):  # noqa: ANN001, ANN201
    """The social-force robot's step, with the scripted robot's way out of a standoff (polite.make_way): standing
    (slower than STANDING) face to face with someone who needs to get past it for `patience` s, it backs off the
    way it came. Without it, the robot and a walker at a blind corner of an extracted SocRATES map stood 0.09 m
    apart for 108 s, the social forces of the two balancing."""
    policy, robot = s.policy[0], s.robot[0]
    forward = way_ahead(s)
    if abs(forward) > 1e-9:
        backing, v = make_way(s, forward)
        if backing:
            policy.waited = 0.0
            return keep_clear(s, v, policy.keep_gap)
    target, last = track(s, False)
    if policy.plans:
        target = steer(s, s.fields, policy.waypoint, target)
    v = keep_clear(s, sfm_toward(s, target, policy.max_speed, last, policy.plans, ARRIVED), policy.keep_gap)
    stands = abs(robot.vel) < proxemics.STANDING_SPEED and abs(v) < proxemics.STANDING_SPEED
    policy.waited = policy.waited + s.clock[0].dt if stands else 0.0
    return v


@jit(inline=True)
def cruise(s, now):  # noqa: ANN001, ANN201
    """The speed the built-in robot drives at where nothing slows it (m/s; `now`: script.now[0]); -1 for a policy
    of the user's (unknown). Pacing's ETA of the robot reads it."""
    policy = s.policy[0]
    if policy.kind == PYTHON:
        return -1.0
    if policy.kind == SCRIPTED and now.misbehave:
        return policy.rude_max_speed
    return min(now.speed, policy.speed_cap) if policy.kind == SCRIPTED else policy.max_speed


@jit
def act(s, now):  # noqa: ANN001, ANN201
    """The built-in policy's velocity for this step (`now`: what the script asks, script.now[0])."""
    policy = s.policy[0]
    kind = policy.kind
    if s.clock[0].t < policy.start_delay:
        policy.speed = 0.0
        return 0j
    if kind == STRAIGHT:
        return straight_act(s, policy.max_speed, False)
    if kind == SFM:
        return sfm_act(s)
    if kind == WAYPOINTS:
        v = waypoints_act(s)
        return kept_clear(s, v, v)
    v = scripted_act(s, now)
    policy.decel = math.nan if now.misbehave else brake_limit(s)  # comfortable unless a collision is imminent
    return v
