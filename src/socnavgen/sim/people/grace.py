"""After the robot arrives: its followers finish their part (issue 25).

A run used to end the moment the robot reached its goal, so a person it led into a room was still a step behind it,
in the doorway or out in the hallway (home_09's second child, hospital_07's patient), whatever the scenario said. In
the real world (and in HuNavSim, where a user stops the run) people go on walking after the robot stops. So, in a
run (Simulation.run), once the robot has arrived (engine.step.ending) it stands at its goal, and whoever is following
it then (FollowRobot, or FollowHuman behind such a follower) comes in to its goal: they walk to a free spot round it
(people.spots: the robot stands on the point) and stand there facing the robot. The run goes on while one of them
still walks in, and ends as soon as nobody does, at the latest ARRIVAL_GRACE after the arrival. Nobody following the
robot: the run ends at the arrival, exactly as before. The metrics keep the arrival as the robot's
(sim.social_metrics.arrival_row).
"""

from __future__ import annotations

import math

from socnavgen.sim.jit import jit
from socnavgen.sim.people.state import ROUTE_ROBOT, goal_reached, refresh_goal, turn, walk_to_goal
from socnavgen.sim.trace import ROBOT_BEHAVIOR

# m: the farthest a follower has to come in - the trail distance behind the robot (people.leaves.follow_trail, up to
# 2 m) and a second follower in file behind the first (a body and the standing gap, ~1.1 m), with room to go round
COME_IN_REACH = 4.0
COME_IN_PACE = 0.4  # m/s: a slow walker (a patient with a walker, a dawdling child)
ARRIVAL_GRACE = COME_IN_REACH / COME_IN_PACE  # s (10): after the robot's arrival a run goes on at most this long


@jit
def follow_in(s, i, leader):  # noqa: ANN001, ANN201
    """A follower's part once whom they follow has arrived (`leader` -1: the robot, FollowRobot; else the person
    followed, FollowHuman, who follows the robot or came in after it): True when person i comes in to the robot's
    goal (or stands there, having come in; the leaf does nothing else this step); False: they follow as before.
    Marks them `coming` while they follow the robot or walk in (the run waits for them, engine.step.ending)."""
    p = s.people[i]
    if leader >= 0 and not (s.people[leader].came_in or s.people[leader].route == ROUTE_ROBOT):
        return False  # following someone who does not follow the robot: nothing to do with its arrival
    if not p.came_in:
        if s.clock[0].arrived < 0 or (leader >= 0 and not s.people[leader].came_in):
            p.coming = True  # the run would wait for them if the robot arrived now
            return False
        p.came_in = True  # their goal is the robot's now, for good
        p.queue_count, p.cyclic = 1, False
        s.goals[i, p.queue_start] = s.robot[0].goal
        refresh_goal(s.people, s.goals, i)
    p.behavior = ROBOT_BEHAVIOR
    if p.queue_count > 0 and not goal_reached(s.people, s.goals, i):
        p.coming = True
        walk_to_goal(s.people, i, p.max_speed, 0j)
    else:
        d = s.robot[0].pos - p.pos
        turn(s.people, i, math.atan2(d.imag, d.real))
    return True


@jit
def coming(s):  # noqa: ANN001, ANN201
    """Someone following the robot still walks in to its goal (marked this step)."""
    for i in range(s.people.shape[0]):  # noqa: SIM110 - numba compiles the loop, not any()
        if s.people[i].coming:
            return True
    return False
