"""Getting out of the robot's way: stepping aside to the spot people.side_step (alone) or people.group_way (a
group, together) plans, waiting there until the robot has gone by, and the leaves built on that (GiveWaytoRobot,
FollowRobot; RegularNav and RunAwayFromRobot keep someone who stepped aside there until the robot has gone by)."""

from __future__ import annotations

import math

from socnavgen.sim.jit import jit
from socnavgen.sim.people.grace import follow_in
from socnavgen.sim.people.group_way import plan_aside
from socnavgen.sim.people.leaves import (
    FOLLOW_MIN_SPEED,
    ROBOT_MOVED_SPEED,
    RUN_AWAY_SPEED,
    follow,
    leaf,
    push_away,
)
from socnavgen.sim.people.routing import robot_progress
from socnavgen.sim.people.side_step import (
    ASIDE,
    GIVE_WAY_MARGIN,
    RESUME,
    TIE,
    WAIT,
    in_robot_way,
    in_way_at,
)
from socnavgen.sim.people.spots import segment_distance
from socnavgen.sim.people.state import ROUTE_ROBOT, ROUTE_STRAIGHT, stand, turn, walk_to, walk_to_goal
from socnavgen.sim.people.trees import SUCCESS
from socnavgen.sim.trace import GIVE_WAY_BEHAVIOR, REGULAR_BEHAVIOR, ROBOT_BEHAVIOR

GIVE_WAY_ARRIVED = 0.15  # m
ASIDE_RADIUS = 0.05  # m: the side-step target is reached within this
ASIDE_GAIN = 0.05  # m nearer their side-step target: a person on the way there is getting on
ASIDE_PATIENCE = 1.5  # s without getting on: they plan their side step again from where they stand
PASSED_MARGIN = 0.3  # m beyond both radii: the robot has passed the person's spot on its path
FOLLOWER_REACH = 4.0  # m: someone following the robot this close to it walks with it (a giver-way lets them by too)
CROSS_LOOK = 2.0  # m: the stretch of a giver-way's walk on that must not cross between the robot and its follower
COMING = 0.05  # m/s: a follower closing in on a giver-way faster than this has not gone by them yet


@jit(inline=True)
def segments_apart(a, b, c, d):  # noqa: ANN001, ANN201
    """Distance between the segments a-b and c-d (0 when they cross)."""
    ab, cd = b - a, d - c
    den = (ab * cd.conjugate()).imag
    if abs(den) > 1e-12:
        t = ((c - a) * cd.conjugate()).imag / den
        u = ((c - a) * ab.conjugate()).imag / den
        if 0.0 <= t <= 1.0 and 0.0 <= u <= 1.0:
            return 0.0
    return min(min(segment_distance(a, c, d), segment_distance(b, c, d)),
               min(segment_distance(c, a, b), segment_distance(d, a, b)))


@jit
def follower_to_come(s, i):  # noqa: ANN001, ANN201
    """Someone following the robot (FollowRobot: walking or standing behind it by its route), within FOLLOWER_REACH
    of it, is still where person i's walk on toward their goal (its next CROSS_LOOK metres) would take them nearer
    the line from a body behind the follower to the robot, within the passing clearance of it, or across it; or the
    follower, within CROSS_LOOK of that clearance, still walks closer to them (faster than COMING). A person who stood aside for a
    robot leading someone lets both by, instead of stepping back across between them (the rehab nurse walked on
    0.1 m in front of the patient the robot guided)."""
    people, robot = s.people, s.robot[0]
    p = people[i]
    ahead = p.goal - p.pos
    if not p.has_goal or abs(ahead) < 1e-9:
        return False
    walk = p.pos + ahead * (min(abs(ahead), CROSS_LOOK) / abs(ahead))
    for j in range(people.shape[0]):
        q = people[j]
        if j == i or q.behavior != ROBOT_BEHAVIOR or q.route != ROUTE_ROBOT or abs(q.pos - robot.pos) > FOLLOWER_REACH:
            continue
        way = robot.pos - q.pos
        if abs(way) < 1e-9:
            continue
        back = q.pos - way / abs(way) * (p.radius + q.radius)  # the line from behind the follower's back to the robot
        near = segments_apart(p.pos, walk, back, robot.pos)  # the walk comes nearer that line than they stand
        clear = p.radius + q.radius + PASSED_MARGIN
        if near < clear and near < segment_distance(p.pos, back, robot.pos) - TIE:
            return True
        towards = p.pos - q.pos  # still coming closer, within a walk's reach: not gone by yet
        if abs(towards) < clear + CROSS_LOOK and (q.vel * towards.conjugate()).real > COMING * abs(towards):
            return True
    return False


@jit
def robot_has_passed(s, i, back):  # noqa: ANN001, ANN201
    """The robot has gone by person i, who stepped aside for it and goes back to `back` (their goal, or where they
    stood) next: it is beyond the point of its path they stepped away from (or at its goal), whoever follows it has
    gone by too (follower_to_come), and `back` is out of its way: not on its path ahead (in_way_at) and as far from
    its body as a side step leaves it (GIVE_WAY_MARGIN). One rule for everyone who stepped aside, whatever their
    path: a friend at a standing group's node walked back there 0.9 m behind a robot that had just turned there."""
    robot, p = s.robot[0], s.people[i]
    if abs(robot.pos - robot.goal) <= robot.goal_tolerance:
        return True
    progress, _ = robot_progress(s)
    clear = p.radius + robot.radius + PASSED_MARGIN
    if progress <= p.aside_at + clear or abs(robot.pos - p.pos) <= clear or follower_to_come(s, i):
        return False
    return abs(back - robot.pos) >= p.radius + robot.radius + GIVE_WAY_MARGIN and not in_way_at(s, i, back)


@jit
def robot_level(s, i):  # noqa: ANN001, ANN201
    """The robot has come level with the point of its path person i stepped away from (or is at its goal): from
    there on it drives away from them, so a follower who stood aside can fall in behind it."""
    robot, p = s.robot[0], s.people[i]
    if abs(robot.pos - robot.goal) <= robot.goal_tolerance:
        return True
    progress, _ = robot_progress(s)
    return progress >= p.aside_at


@jit
def give_way(s, i):  # noqa: ANN001, ANN201
    """Step off the robot's upcoming path, wait there facing the robot until it has passed, then walk on to
    the goal. A new side step is planned whenever the previous action was something else (a group member's with
    their group: people.group_way), and when they have come no nearer their spot for ASIDE_PATIENCE s (someone
    stands in the way: home_05's guest stood short of his spot, inside the robot's lane, for 20 s)."""
    p = s.people[i]
    if p.behavior != GIVE_WAY_BEHAVIOR or not p.gives_way:
        p.behavior = GIVE_WAY_BEHAVIOR
        p.gives_way = True
        plan_aside(s, i, False)
    if p.give_way_phase != RESUME and robot_has_passed(s, i, p.goal if p.has_goal else p.pos):
        p.give_way_phase = RESUME
        p.has_slot = False
    if p.give_way_phase == ASIDE:
        near = abs(p.aside_via - p.pos)
        if near < p.aside_near - ASIDE_GAIN:
            p.aside_near, p.aside_stall = near, 0.0
        else:
            p.aside_stall += s.clock[0].dt
        if p.aside_stall >= ASIDE_PATIENCE:
            plan_aside(s, i, True)
    if p.give_way_phase == ASIDE and abs(p.aside_via - p.pos) <= GIVE_WAY_ARRIVED:
        p.aside_via = p.aside  # backed out to where there is room: now to the side
    if p.give_way_phase == ASIDE and abs(p.aside - p.pos) <= GIVE_WAY_ARRIVED:
        p.give_way_phase = WAIT
    if p.give_way_phase == ASIDE:
        walk_to(s.people, i, p.aside_via, ASIDE_RADIUS, p.max_speed, ROUTE_STRAIGHT)
    elif p.give_way_phase == WAIT:
        d = s.robot[0].pos - p.pos
        turn(s.people, i, math.atan2(d.imag, d.real))
    else:
        walk_to_goal(s.people, i, p.max_speed, 0j)


@jit
def giving_way(p):  # noqa: ANN001, ANN201
    """Person p stepped aside (or is stepping aside) for the robot at the last step and it has not passed yet."""
    return p.gives_way and p.behavior == GIVE_WAY_BEHAVIOR and p.give_way_phase != RESUME


@leaf("RegularNav")
def regular_nav(s, node, i, a):  # noqa: ANN001, ANN201, ARG001
    """Social-force walking toward the goal; a person held at its interaction point stands (pacing). Someone who
    stepped aside for the robot stays aside until it has passed (a tree that stops giving way once the robot is
    no longer in front or near - it is passing them, or they turned to back out - would otherwise walk them back
    into its way, or close a group up again around it)."""
    p = s.people[i]
    if stays_aside(s, i):
        return SUCCESS
    p.behavior = REGULAR_BEHAVIOR
    if p.held:
        stand(s.people, i)
    else:
        walk_to_goal(s.people, i, p.pace, 0j)
    return SUCCESS


@jit
def stays_aside(s, i):  # noqa: ANN001, ANN201
    """Person i stepped aside for the robot and it has not gone by yet (robot_has_passed): this step goes on with
    the give-way (to their spot, or waiting there facing it) instead of the walk their tree ticks now. A walking leaf
    heads for their goal, which for someone who stood in the robot's way is in its way again (home_10, round 17:
    the scared walk after a give-way took a friend back to his node, 1.2 m in front of the waiting robot)."""
    p = s.people[i]
    if not giving_way(p):
        return False
    give_way(s, i)
    return p.give_way_phase != RESUME


@leaf("RunAwayFromRobot")
def run_away_from_robot(s, node, i, a):  # noqa: ANN001, ANN201, ARG001
    """Scared walking toward the goal, pushed away from the robot; someone standing aside at their side-step spot
    stays there (stays_aside). On the way to it the scared walk moves them: a spot they cannot reach (across their
    group, home_10's friend) would otherwise hold them in the robot's way for good."""
    if s.people[i].give_way_phase == WAIT and stays_aside(s, i):
        return SUCCESS
    s.people[i].behavior = ROBOT_BEHAVIOR
    walk_to_goal(s.people, i, RUN_AWAY_SPEED, push_away(s, i, math.inf))
    return SUCCESS


@leaf("GiveWaytoRobot")
def give_way_to_robot(s, node, i, a):  # noqa: ANN001, ANN201, ARG001
    give_way(s, i)
    return SUCCESS


@jit
def lets_robot_by(s, i):  # noqa: ANN001, ANN201
    """Person i, following the robot, starts stepping aside for it: they stand in its way (in_robot_way) and its
    script does not hold it (robot.held: it drives, or may: curious people walking up to a driving robot step aside
    on their way, as it moves aside to pass them; waiting for it to drive on toward them, card robot-crowding [home]
    stood three in front of it, rocking in place 73 s). While a cue holds it, someone walking up to it (faster than
    FOLLOW_MIN_SPEED toward it: came_up, to take something from it, a handover) comes up, stands facing it and steps
    aside only once it drives on toward them (faster than ROBOT_MOVED_SPEED); someone already standing there when it
    stopped (told FOLLOW ME) steps aside as before. Stepping aside at 2 m, the colleague who came for the first-aid
    kit stood 2.3 m off to the side (warehouse_17, round 22)."""
    p, robot = s.people[i], s.robot[0]
    d = p.pos - robot.pos
    if abs(d) < 1e-9 or not in_robot_way(s, i):
        p.came_up = False
        return False
    if not robot.held:
        return True
    u = d / abs(d)
    if -(p.vel * u.conjugate()).real > FOLLOW_MIN_SPEED:  # walking up to it
        p.came_up = True
        return False
    return not p.came_up or (robot.vel * u.conjugate()).real > ROBOT_MOVED_SPEED


@leaf("FollowRobot")
def follow_robot(s, node, i, a):  # noqa: ANN001, ANN201, ARG001
    """Follow the robot; a follower in the robot's way (ahead of it, on its remaining path) steps aside and lets
    it pass (lets_robot_by), as a person told FOLLOW ME by a robot coming up behind does; while a cue of its script
    holds it they come up to it (a handover), stand facing it and step aside once it drives on. Once it has come
    level with them they fall in behind it at once: they do not wait for its other followers to go by (they are
    one of them; people.spacing lines them up), nor for a robot that a give-way begun before they were told
    (GiveWaytoRobot) waits for but that drives away from them (home_09's older child stood 12 s aside, home_03's
    second guest 8 s at the door). Once the robot has arrived, someone whose path ends by its goal walks in there
    (people.grace)."""
    if follow_in(s, i, -1):
        return SUCCESS
    p = s.people[i]
    if giving_way(p) and robot_level(s, i) and not in_robot_way(s, i):
        p.give_way_phase = RESUME
    if giving_way(p) or lets_robot_by(s, i):
        give_way(s, i)
        if p.give_way_phase != RESUME:
            return SUCCESS
    follow(s, i, s.robot[0].pos, s.robot[0].radius, ROUTE_ROBOT)
    return SUCCESS
