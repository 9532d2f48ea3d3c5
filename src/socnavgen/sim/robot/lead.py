"""Who goes with the robot: people whose way this step is the robot itself (following it, coming to block it)
or someone who does (a person following a follower). Their goal queue is not where they are going, so it says
nothing about needing to get past the robot: a guide never makes way for, nor waits out, its own followers."""

from __future__ import annotations

from socnavgen.sim.jit import jit
from socnavgen.sim.people.state import ROUTE_ROBOT


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
