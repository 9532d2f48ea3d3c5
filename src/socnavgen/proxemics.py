""""In the robot's way": the ONE predicate the simulator (robot driving, script cues, gesture rules) and the
verifier share, with one named margin per use. Body sizes come from socnavgen.bodies.

A person is in the robot's way when the person's centre is ahead of the robot's centre along the robot's
heading and inside the corridor the robot's body sweeps, widened by the person's radius and a margin:

    along  = (p - r) . h          > 0
    across = |(p - r) x h|        < robot_radius + person_radius + margin

(r, p: robot and person centres; h: the robot's unit heading). `in_front` is the wider notion a robot uses
to notice people coming (within a cone around its heading), and `blocking` the script's "blocked": within a
centre distance and (in the way or in front).

Every function is self-contained (it calls no other function of this module, so each can be compiled alone)
plain scalar arithmetic (comparisons, +, -, *, abs, ** 0.5, and `&` / `|` on the
booleans): numba compiles it as it is (the simulator wraps it in its own njit), and the same function works
elementwise on numpy arrays (the verifier calls it on whole traces at once). No `if`, `and` or `or` on
values, so keep it that way when editing (tests/test_proxemics.py runs all three ways).
"""

from __future__ import annotations

import math
from typing import Any

# -- margins of the corridor, metres beyond the two radii, one per use ----------------------------------
WAY_MARGIN_DRIVE = 0.05  # the robot's own driving (waypoints, scripted, sfm): slows and stops for such a person
WAY_MARGIN_SCRIPT = 0.1  # script cues and gesture rules `blocked`, `wait_until_clear` (sim.robot.script)
WAY_MARGIN_VERIFY = 0.1  # the verifier's inway_<human>: gives_way, blocks_robot, deadlock; and so where someone who
#   gives way walks: a person standing out of this corridor never walks into it on the way to their side-step spot
#   (sim.people.side_step.OUT_OF_WAY)
WAY_MARGIN_FOLLOW = 0.2  # a FollowRobot follower this close to the robot's remaining path steps aside first
FRONT_CONE_SCRIPT = 0.6  # rad: "in front of the robot" for the script's `blocked` (noticing people coming)
HELD_UP_DISTANCE = 3.0  # m centre to centre: someone in the robot's way this close holds it up, the ONE notion of
#   "stuck in front of someone": the script's `wait_until_clear` waits for such a person, and the verifier's
#   deadlock counts the time the robot makes no progress while one is there (a robot waiting 2 m short of a
#   person who never steps aside is held up by that person, although they are not touching)
OCCUPIED_REACH = 2.0  # m: an intermediate waypoint someone stands on is skipped by the robots this close, so the
# verifier counts a waypoint as passed this close too (a round trip's goal counts only after its other waypoints)
GIVE_WAY_CLEARANCE = 0.5  # m: a person who gave way leaves this much free space beside the robot's body
# -- arriving at a goal someone stands on or next to (short_of_goal) -------------------------------------
GOAL_STOP_GAP = 1.2  # m gap: the robot stops this far from a person standing at its goal (Hall's personal space
#   ends here: bodies.PERSONAL_SPACE; about 2 m centre to centre), and that counts as arrived
GOAL_STOP_SLACK = 0.15  # m: ... within this much more
STANDING_SPEED = 0.2  # m/s: a person (or the robot) slower than this stands (people jitter in place at ~0.1 m/s)
GOAL_STOP_DWELL = 3.0  # s: the simulator ends a run when the robot has stood short of its goal this long, and
#   the metrics and the verifier count a stop short of it as arriving only after it stood there this long (or
#   until the run ended): a robot slowing for a moment on its way past is not arriving

NEARER_SPOT = 0.5  # m: stopping short of an occupied goal counts as arriving only where the people there leave no free
#   spot this much nearer the goal that keeps as far from them (sim.arrival.no_nearer_spot): a robot parked in a
#   doorway 1.4 m off while the middle of the room around its goal is free has not arrived
SPOT_GRID = 0.1  # m: the spacing of the spots tried

Num = Any  # a float, or a numpy array of floats (elementwise)


def way_coordinates(rx: Num, ry: Num, hx: Num, hy: Num, px: Num, py: Num) -> tuple[Num, Num]:
    """(along, across) of the person at (px, py) in the robot's frame: robot at (rx, ry) heading along the
    unit vector (hx, hy); `along` > 0 ahead, `across` >= 0 the distance from the robot's line of travel."""
    dx = px - rx
    dy = py - ry
    return dx * hx + dy * hy, abs(dy * hx - dx * hy)


def in_way(rx: Num, ry: Num, hx: Num, hy: Num, px: Num, py: Num, robot_radius: Num, person_radius: Num,
           margin: Num) -> Num:
    """The person is ahead of the robot inside the corridor its body sweeps, widened by `margin` (one of the
    WAY_MARGIN_* of this module)."""
    dx = px - rx
    dy = py - ry
    return (dx * hx + dy * hy > 0.0) & (abs(dy * hx - dx * hy) < robot_radius + person_radius + margin)


def in_front(rx: Num, ry: Num, hx: Num, hy: Num, px: Num, py: Num, cone: Num) -> Num:
    """The person's centre is within `cone` radians (0 to pi) of the robot's heading, seen from the robot's
    centre (a person exactly on the robot's centre counts)."""
    dx = px - rx
    dy = py - ry
    return dx * hx + dy * hy >= (dx * dx + dy * dy) ** 0.5 * math.cos(cone)


def blocking(rx: Num, ry: Num, hx: Num, hy: Num, px: Num, py: Num, robot_radius: Num, person_radius: Num,
             distance: Num, margin: Num, cone: Num) -> Num:
    """The script's "blocked": the person within `distance` (centres) and in the robot's way (margin) or in
    front of it (cone; a negative cone: only in the way, as `wait_until_clear` asks)."""
    dx = px - rx
    dy = py - ry
    along = dx * hx + dy * hy
    centre = (dx * dx + dy * dy) ** 0.5
    swept = (along > 0.0) & (abs(dy * hx - dx * hy) < robot_radius + person_radius + margin)
    front = (cone >= 0.0) & (along >= centre * math.cos(cone))
    return (centre <= distance) & (swept | front)


def short_of_goal(robot_to_goal: Num, person_to_goal: Num, gap: Num, person_speed: Num, robot_speed: Num,
                  robot_radius: Num, person_radius: Num, seen: Num) -> Num:
    """The robot has arrived short of its goal: a person stands on or next to the goal (a robot at the goal
    would be inside their personal space: their centre within reach = robot_radius + person_radius +
    GOAL_STOP_GAP of it, and nearer it than the robot: it stops short of them), and the robot stands at most GOAL_STOP_GAP (+ GOAL_STOP_SLACK) from them (`gap`,
    surface to surface) and within reach (+ slack) of its goal (not in another room beyond them), and sees them
    (`seen`: no wall between the two centres; a robot parked in a corridor corner beside a doorway goal, the
    person behind the wall in the room, is not at the goal's place). The ONE
    arrival rule besides the goal tolerance: the simulator's end of run, the polite robot's stopping point and
    the verifier's robot_reaches_goal all use it."""
    reach = robot_radius + person_radius + GOAL_STOP_GAP
    held = (person_to_goal < reach) & (person_speed < STANDING_SPEED) & (person_to_goal < robot_to_goal)
    near = (gap <= GOAL_STOP_GAP + GOAL_STOP_SLACK) & (robot_to_goal <= reach + GOAL_STOP_SLACK) & (seen > 0)
    return held & near & (robot_speed < STANDING_SPEED)
