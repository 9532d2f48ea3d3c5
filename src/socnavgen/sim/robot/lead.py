"""Who goes with the robot: people whose way this step is the robot itself (following it, coming to block it)
or someone who does (a person following a follower). Their goal queue is not where they are going, so it says
nothing about needing to get past the robot: a guide never makes way for, nor waits out, its own followers; and it
lets those who walk after it keep up (lead_speed)."""

from __future__ import annotations

import math

from socnavgen.sim.jit import jit
from socnavgen.sim.people.state import ROUTE_ROBOT

LEAD_EASE = 3.0  # m (centres): a follower farther behind than this makes the robot slow down ... (followers stand
# people.leaves.FOLLOW_STOP = 1.3 m from it)
LEAD_LOST = 5.0  # m: ... to LEAD_SLOWEST of its cruise speed at this distance and farther
LEAD_SLOWEST = 0.3


@jit
def goes_with_robot(s, i):  # noqa: ANN001, ANN201
    """Person i walks to the robot (their route is the robot's: FollowRobot, BlockRobot) or follows, through a
    chain of followers, someone who does (FollowHuman). A chain is looked along at most the crowd's size."""
    people = s.people
    k = i
    for _ in range(people.shape[0]):
        route = people[k].route
        if route == ROUTE_ROBOT:
            return True
        if route < 0 or route >= people.shape[0] or route == k:
            return False
        k = route
    return False


@jit
def lead_speed(s, cruise, direction):  # noqa: ANN001, ANN201
    """The most the robot drives along the unit `direction` while it leads (inf: nobody follows it from afar): for
    each person walking after it (their target is the robot itself: FollowRobot), behind it, farther than LEAD_EASE
    (centres), `cruise` scaled down with the distance to LEAD_SLOWEST of it at LEAD_LOST and beyond. A guide lets its
    line keep up; it never stops for them: a follower who cannot come (stuck behind others, a wall) does not hold it
    for good. Someone coming to it from ahead is not falling behind."""
    robot, people = s.robot[0], s.people
    top = math.inf
    for i in range(people.shape[0]):
        q = people[i]
        behind = abs(q.pos - robot.pos)
        if behind <= LEAD_EASE or ((q.pos - robot.pos) * direction.conjugate()).real >= 0.0 or not (
                q.walks and q.route == ROUTE_ROBOT and abs(q.target - robot.pos) < 1e-6):
            continue
        share = 1.0 - (behind - LEAD_EASE) / (LEAD_LOST - LEAD_EASE)
        top = min(top, cruise * max(LEAD_SLOWEST, share))
    return top
