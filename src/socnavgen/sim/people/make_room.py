"""Making room: a person who stands still in the way of a robot that waits for them steps aside, as people do.

A person stands still when they stand (slower than STANDING) and their tree moves nobody this step: no walking
leaf (they are idle at the end of their path, wait, look, or talk), or RegularNav at their last goal, already there.
A walker whose tree takes the step between two goals (UpdateGoal) is not standing: a daughter walking past a
waiting robot to a doorway on her way was read as standing in its way there, and backed out 3 m the way she
came. A deliberate block is not standing still in this sense: a person whose tree's IsRobotBlocking holds this
step stands in the robot's way on purpose, and stays; so does someone whose BlockRobot-type leaf (BlockRobot,
ThreateningNav) holds them at their block point this step.

When such a person is in the robot's way (side_step.in_robot_way: on its remaining path, a few metres ahead)
and the robot has waited for ROBOT_WAITED s (the engine's clock.stalled: no progress along its route, standing
or edging about where it stopped), they step aside to the nearest spot that lets the robot by (side_step.plan_side_step), wait there facing it until it has
passed (give_way.robot_has_passed), and walk back to where they stood. They give way meanwhile (behaviour 2, the
side-step spot marked as theirs for others who look for one). Their tree keeps running every step; this rule
replaces its motion command while it lasts (engine.step calls `make_room` after the trees), and ends as soon
as the tree makes them walk somewhere else or blocks the robot on purpose. Someone whose tree walked nobody when
they stepped aside (standing talking) and now walks them to a goal away from where they stood has a walk of their
own: the side step ends with the rule, and they go (one at the end of their walk, round a goal they share, keeps
to the give-way as before: home_10's friends; hospital_04: a resident stepped aside into the mouth of the door
beside her for the robot waiting behind the team, and when her tree walked her in, the give-way kept her there for
good, the robot waiting for her to clear it and the two behind her unable to get through the door).

A walker held up by the robot makes room too: one whose tree walks them but who stands (slower than STANDING)
face to face with the waiting robot (within HELD_GAP of its body, ahead on their way) on its path - each waits for the other, as at a
0.9 m door where the robot comes out as they go in (HuNavSim's social-force people are pushed aside by its
body). They step aside as above (within SIDE_STEP_MAX: a walker never backs out far - in a corridor too narrow for
both, the robot backs out) and, once it has passed, walk on where their tree walks them (no walk back).
"""

from __future__ import annotations

import math

from socnavgen import proxemics
from socnavgen.bodies import PERSON_GOAL_SLACK
from socnavgen.sim.jit import jit
from socnavgen.sim.people.give_way import ASIDE_RADIUS, GIVE_WAY_ARRIVED, robot_has_passed
from socnavgen.sim.people.side_step import ASIDE, RESUME, SIDE_STEP_MAX, WAIT, in_robot_way, plan_side_step
from socnavgen.sim.people.state import ROUTE_ROBOT, ROUTE_STRAIGHT, STANDING, done, queued_at, turn, walk_to
from socnavgen.sim.people.trees import LEAF_NAMES
from socnavgen.sim.trace import GIVE_WAY_BEHAVIOR, ROBOT_BEHAVIOR
from socnavgen.sim.world.queries import line_of_sight
from socnavgen.sim.world.spots import nearer_spot

ROBOT_WAITED = 2.0  # s the robot has made no progress (clock.stalled) before a person standing in its way makes room
BACK_SPEED = 0.6  # m/s at most, walking back to their spot once the robot has passed
DELIBERATE = 1 << LEAF_NAMES.index("IsRobotBlocking")  # a succeeded-mask bit: standing in its way on purpose
BLOCKS = (LEAF_NAMES.index("BlockRobot"), LEAF_NAMES.index("ThreateningNav"))  # leaves that block it on purpose
HELD_GAP = 1.0  # m between bodies: a walker standing this close in front of the waiting robot is held up by it ...
HELD_ANGLE = 1.0  # rad: ... when it is no farther than this off the way they walk
# p.makes_room: not, a person standing in its way (at the end of their walk, or their tree walking them to where
# they stand), one standing idle before their walk (their tree walks nobody, goals still ahead), a walker held up by it
NONE, STEPPING, HELD, IDLE = 0, 1, 2, 3


@jit
def stands_still(s, i, spot):  # noqa: ANN001, ANN201
    """Person i's tree keeps them at `spot` this step (no walk, or a walk to their last goal, at `spot`), and
    does not block the robot on purpose (at a goal others stand on: as close as they let them, state.queued_at)."""
    p = s.people[i]
    if p.succeeded & DELIBERATE or p.action == BLOCKS[0] or p.action == BLOCKS[1]:
        return False
    if not p.walks or (p.to_goal and not p.has_goal):  # no walk, or their walk is over (at their spot round a
        return True  # goal others stand on, people.spots.aim: they stand there, on the robot's way for good)
    last = p.to_goal and p.has_goal and p.queue_count <= 1 and not p.cyclic
    return last and (abs(p.goal - spot) <= p.goal_radius + PERSON_GOAL_SLACK or queued_at(s.people, i, p.goal))


@jit
def held_up(s, i):  # noqa: ANN001, ANN201
    """Person i's tree walks them (not to the robot, not blocking it on purpose), yet they stand within HELD_GAP of
    the robot's body, which is ahead of them on their way (within HELD_ANGLE of it): held up by it. One who only
    slows for the step between two goals beside it (home_07's daughter crossing 1.5 m in front of it) is not."""
    p, robot = s.people[i], s.robot[0]
    if not p.walks or p.route == ROUTE_ROBOT or p.succeeded & DELIBERATE or p.action == BLOCKS[0] \
            or p.action == BLOCKS[1]:
        return False
    rel, ahead = robot.pos - p.pos, p.via - p.pos
    if abs(p.vel) >= STANDING or abs(rel) - p.radius - robot.radius >= HELD_GAP or abs(ahead) < 1e-9:
        return False
    return (rel * ahead.conjugate()).real >= abs(rel) * abs(ahead) * math.cos(HELD_ANGLE)


@jit(inline=True)
def walks_elsewhere(p):  # noqa: ANN001, ANN201
    """Person p's tree now walks them to a goal away from where they stood when they made room (their walk into a
    room after standing talking by its door): a new walk of their own, not the one that held them there."""
    return p.has_goal and abs(p.goal - p.room_home) > p.goal_radius + PERSON_GOAL_SLACK


@jit
def goes_on(s, i):  # noqa: ANN001, ANN201
    """Person i making room goes on with it: a walker held up while their tree still walks them (not blocking on
    purpose), someone standing in the way while their tree keeps them at their spot."""
    p = s.people[i]
    if p.makes_room == HELD:
        return p.walks and not (p.succeeded & DELIBERATE)
    return stands_still(s, i, p.room_home)


@jit
def step_aside(s, i):  # noqa: ANN001, ANN201
    """This step's motion of person i making room: to the side-step spot, wait there facing the robot, then
    back to where they stood; the rule ends once they are back."""
    p, robot = s.people[i], s.robot[0]
    if p.give_way_phase != RESUME and robot_has_passed(s, i, p.room_home):
        p.give_way_phase = RESUME
    if p.give_way_phase == ASIDE and abs(p.aside_via - p.pos) <= GIVE_WAY_ARRIVED:
        p.aside_via = p.aside  # backed out to where there is room (or never had to): now to the side
    if p.give_way_phase == ASIDE and abs(p.aside - p.pos) <= GIVE_WAY_ARRIVED:
        p.give_way_phase = WAIT
    if p.give_way_phase == RESUME:
        if p.makes_room == HELD or abs(p.room_home - p.pos) <= GIVE_WAY_ARRIVED:  # a walker walks on from there
            p.makes_room, p.gives_way = NONE, False
            return
        p.behavior = ROBOT_BEHAVIOR
        walk_to(s.people, i, p.room_home, ASIDE_RADIUS, min(p.max_speed, BACK_SPEED), ROUTE_STRAIGHT)
        return
    p.behavior = GIVE_WAY_BEHAVIOR
    if p.give_way_phase == ASIDE:
        # via aside_via as give_way.give_way walks: a tree that takes over this side step (RegularNav keeps
        # someone giving way aside) must not find aside_via still at the spot they left, and walk them back
        walk_to(s.people, i, p.aside_via, ASIDE_RADIUS, p.max_speed, ROUTE_STRAIGHT)
    else:
        d = robot.pos - p.pos
        turn(s.people, i, math.atan2(d.imag, d.real))


short_of_goal = jit(proxemics.short_of_goal)  # the one arrival short of a goal someone stands at, compiled


@jit
def stopped_short(s):  # noqa: ANN001, ANN201
    """The robot stands short of its goal at a social distance from someone standing there, and the people there
    leave no nearer free spot (world.spots.nearer_spot, as sim.arrival counts it): arrived."""
    robot, people = s.robot[0], s.people
    for i in range(people.shape[0]):
        q = people[i]
        if short_of_goal(abs(robot.goal - robot.pos), abs(q.pos - robot.goal), abs(q.pos - robot.pos) - q.radius
                         - robot.radius, abs(q.vel), abs(robot.vel), robot.radius, q.radius,
                         1.0 if line_of_sight(s.world, robot.pos, q.pos) else 0.0):
            found, _ = nearer_spot(s.world, robot.goal, robot.pos, robot.radius, people)
            return not found
    return False


@jit
def make_room(s, held):  # noqa: ANN001, ANN201
    """After the trees: who starts making room for the waiting robot, and the motion of everyone who does.
    `held`: the robot's script stands it now (a timed wait, letting someone go first): it waits by choice, not to
    get past anyone, so its ROBOT_WAITED s count only from when the script lets it go (hospital_04's nurse, whom
    the robot let go first, was made to step aside for it and walked off along the corridor)."""
    people, clock = s.people, s.clock[0]
    if held:
        clock.stalled = 0.0
    # a robot that stopped short of someone standing at its goal has arrived: it is not waiting to get past
    waited = clock.stalled >= ROBOT_WAITED and not stopped_short(s)
    for i in range(people.shape[0]):
        p = people[i]
        if clock.t < p.start_delay:
            continue
        if p.makes_room != NONE:
            if goes_on(s, i):
                step_aside(s, i)
            else:  # the tree walks them elsewhere, or blocks the robot: it has the say again
                if p.makes_room == IDLE and walks_elsewhere(p):
                    p.gives_way = False  # the side step ends with it (people.give_way.stays_aside would hold them)
                p.makes_room = NONE
        elif (waited and not (p.gives_way and p.behavior == GIVE_WAY_BEHAVIOR and p.give_way_phase != RESUME)  # not giving way
              and abs(p.vel) < STANDING and stands_still(s, i, p.pos)  # already (their tree's GiveWaytoRobot)
              and in_robot_way(s, i)):
            idle = not p.walks and not done(people, s.goals, i)  # standing before their walk, not at its end
            p.makes_room, p.room_home = IDLE if idle else STEPPING, p.pos
            p.behavior, p.gives_way = GIVE_WAY_BEHAVIOR, True
            plan_side_step(s, i)
            step_aside(s, i)
        elif waited and not p.gives_way and held_up(s, i) and in_robot_way(s, i):
            plan_side_step(s, i)
            if abs(p.aside_via - p.pos) + abs(p.aside - p.aside_via) > SIDE_STEP_MAX:
                continue  # no side step near: a walker does not back out far (in a corridor the robot backs out)
            p.makes_room, p.room_home = HELD, p.pos
            p.behavior, p.gives_way = GIVE_WAY_BEHAVIOR, True
            step_aside(s, i)
