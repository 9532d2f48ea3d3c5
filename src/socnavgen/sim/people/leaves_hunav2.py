"""HuNavSim 2.x nodes that socnavgen's hunav2 translations emit (bt.library.HUNAV2), with 2.x semantics, so
that an exported tree simulates and verifies like its socrates original.

From robotics-upo/hunav_sim (2.x agent manager and node sources; reference §5):
- IsRobotClose: robot centre closer than `threshold` (strict <).
- SaySomething: publishes `message`; here the message is the gesture word, shown as that gesture.
- SurprisedNav: one call of the agent manager's look-at-robot turn (no translation).
- CuriousNav / approximateRobot: within `stop_distance` turn to face the robot; else walk toward it at
  agent_vel * d / (d + stop_distance).
- ThreateningNav / blockRobot: walk to the point `goal_dist` ahead of the robot, face it when close.
- FollowAgent / AvoidRobot: stateful (RUNNING; SUCCESS once `duration` > 0 seconds have passed; 0 = run
  until halted). 2.x measures wall time; the simulator measures simulated time.
  FollowAgent: like CuriousNav with the other agent (target_agent_id is HuNavSim's 1-based id).
  AvoidRobot: goal-directed walking at runaway_vel with a push away from the robot while it is closer
  than safe_distance.
"""

from __future__ import annotations

import math

from socnavgen.bt.library import HUNAV2_FIRST_AGENT_ID
from socnavgen.sim.jit import jit
from socnavgen.sim.people.leaves import bad_port, block, human, leaf, look_at_robot_step, push_away
from socnavgen.sim.people.routing import head
from socnavgen.sim.people.state import ROUTE_ROBOT, turn, walk_to, walk_to_goal
from socnavgen.sim.people.trees import FAILURE, RUNNING, SUCCESS, Port
from socnavgen.sim.trace import ROBOT_BEHAVIOR


@leaf("IsRobotClose")
def is_robot_close(s, node, i, a):  # noqa: ANN001, ANN201, ARG001
    return SUCCESS if s.people[i].robot_distance < a[Port.threshold] else FAILURE


@leaf("SaySomething")
def say_something(s, node, i, a):  # noqa: ANN001, ANN201, ARG001
    s.people[i].gesture = int(a[Port.message])  # the word's gesture code (0 for any other text)
    return SUCCESS


@leaf("AlwaysSuccess")
def always_success(s, node, i, a):  # noqa: ANN001, ANN201, ARG001
    return SUCCESS


@leaf("SurprisedNav")
def surprised_nav(s, node, i, a):  # noqa: ANN001, ANN201, ARG001
    look_at_robot_step(s, i)
    return SUCCESS


@jit
def approach(s, i, target, radius, stop, max_speed, route):  # noqa: ANN001, ANN201
    s.people[i].behavior = ROBOT_BEHAVIOR
    _, r = head(s, i, target, route)
    if r <= stop:
        d = target - s.people[i].pos
        turn(s.people, i, math.atan2(d.imag, d.real))
    else:
        walk_to(s.people, i, target, radius, max_speed * r / (r + stop), route)


@jit
def timed(s, node, duration):  # noqa: ANN001, ANN201
    """A stateful 2.x node: RUNNING until `duration` (> 0) seconds of being ticked, then SUCCESS."""
    elapsed = node.memory + s.clock[0].dt
    if duration > 0 and elapsed >= duration:
        node.memory = 0.0
        return SUCCESS
    node.memory = elapsed
    return RUNNING


@leaf("CuriousNav")
def curious_nav(s, node, i, a):  # noqa: ANN001, ANN201, ARG001
    approach(s, i, s.robot[0].pos, s.robot[0].radius, a[Port.stop_distance], a[Port.agent_vel], ROUTE_ROBOT)
    return SUCCESS


@leaf("ThreateningNav")
def threatening_nav(s, node, i, a):  # noqa: ANN001, ANN201, ARG001
    block(s, i, a[Port.goal_dist])
    return SUCCESS


@leaf("FollowAgent")
def follow_agent(s, node, i, a):  # noqa: ANN001, ANN201, ARG001
    h = human(s, a, Port.target_agent_id, HUNAV2_FIRST_AGENT_ID)
    if h < 0:
        return bad_port(Port.target_agent_id)
    if h != i:
        approach(s, i, s.people[h].pos, s.people[h].radius, a[Port.closest_dist], a[Port.max_vel], h)
    return timed(s, node, a[Port.duration])


@leaf("AvoidRobot")
def avoid_robot(s, node, i, a):  # noqa: ANN001, ANN201, ARG001
    s.people[i].behavior = ROBOT_BEHAVIOR
    walk_to_goal(s.people, i, a[Port.runaway_vel], push_away(s, i, a[Port.safe_distance]))
    return timed(s, node, a[Port.duration])
