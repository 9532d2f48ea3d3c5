"""The simulated people: one record each (body, motion, goal queue, this step's motion command, behaviour,
pacing, giving way), what a leaf may ask of a person's motion (walk, turn, stand), and the goal queue with
HuNavSim's semantics (reference §7) as a ring per person in `goals`."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from socnavgen.bodies import (
    PERSON_GOAL_RADIUS,
    PERSON_GOAL_SLACK,
    PERSON_MAX_SPEED,
    PERSON_PASS_GAP,
    PERSON_RADIUS,
    PERSON_STAND_GAP,
    STANDING,
)
from socnavgen.sim.jit import jit
from socnavgen.sim.people.spots import at_spot, spot_taken
from socnavgen.sim.records import layout, table

# a goal someone stands on (people coming to stand keep PERSON_STAND_GAP from them: nobody gets within the goal radius of
# a goal another body covers) is reached as close as the people standing at it let a person come: within
# QUEUE_REACH of it, within the gap + QUEUE_SLACK of someone standing nearer to it
QUEUE_REACH = PERSON_GOAL_RADIUS + 2 * PERSON_RADIUS + PERSON_STAND_GAP + 0.1  # m: one ring of people round it
QUEUE_SLACK = 0.5  # m: the social force alone holds a walker about this far off someone standing on their goal
DONE_SPEED = 0.05  # m/s: a person slower than this at its last goal has finished its walk
# how a walk finds its way (PERSON.route; people.routing): straight at the target, or around walls toward the
# person's goal, the robot, or person j (route = j >= 0)
ROUTE_STRAIGHT, ROUTE_GOAL, ROUTE_ROBOT = -1, -2, -3


@dataclass
class HumanSpec:
    """Everything needed to create one simulated person (world coordinates)."""

    name: str
    start: tuple[float, float]
    goals: list[tuple[float, float]]
    yaw: float = 0.0
    group_id: int = -1
    radius: float = PERSON_RADIUS
    max_vel: float = PERSON_MAX_SPEED
    goal_radius: float = PERSON_GOAL_RADIUS
    cyclic: bool = False
    interaction_point: tuple[float, float] | None = None
    path_nodes: list[str] = field(default_factory=list)
    start_delay: float = 0.0  # s: stands at its spawn point, facing its first goal, until then (its tree waits)
    pass_gap: float = PERSON_PASS_GAP  # m left passing the robot where there is room (people.avoid.pass_gap_for)


PERSON = layout([
    # body and motion
    ("pos", "c16"), ("vel", "c16"), ("yaw", "f8"), ("omega", "f8"), ("radius", "f8"), ("max_speed", "f8"),
    ("group", "i8"),  # label of its group (0..G-1, groups of two or more), -1 alone
    ("start_delay", "f8"),  # s: its tree is not ticked (it stands) before then
    ("pass_gap", "f8"),  # m: the gap it leaves passing the robot where there is room (people.avoid)
    ("goal_wait", "f8"),  # s it has been held back short of a goal the robot stands on (people.avoid.GOAL_PATIENCE)
    # goal queue: the front goal, and the ring goals[i, start:start + count] (wrapping)
    ("goal", "c16"), ("goal_radius", "f8"), ("has_goal", "?"), ("queue_start", "i8"), ("queue_count", "i8"),
    ("cyclic", "?"),
    # this step's motion command, set by the tree's actions: walk (to the goal or to `target`) or turn
    ("walks", "?"), ("to_goal", "?"), ("target", "c16"), ("target_radius", "f8"), ("desired_speed", "f8"),
    ("push", "c16"), ("turns", "?"), ("turn_to", "f8"), ("face_robot_within", "f8"),
    # the way there (people.routing): how it is found, the point headed for this step (via_step), the decision
    # kept until via_until for a target at via_for (via_mark: the landmark whose field leads, -1 straight), and
    # the landmark of the current goal (goal_mark, for the goal goal_mark_of)
    ("route", "i8"), ("via", "c16"), ("via_step", "i8"), ("via_until", "i8"), ("via_for", "c16"), ("via_mark", "i8"),
    ("goal_mark", "i8"), ("goal_mark_of", "c16"),
    # forces of the current positions (social incl. the robot, nearest wall; the wall's alone), distance to the robot
    ("env_force", "c16"), ("wall_force", "c16"), ("robot_distance", "f8"), ("reached", "?"),
    # behaviour: gesture shown, behavior_state code (0 regular, 1 robot-related, 2 giving way), sight of
    # the robot this step (-1 not asked yet), the trace's action and succeeded-leaves mask of this step
    ("gesture", "i8"), ("behavior", "i8"), ("sees_robot", "i8"), ("action", "i8"), ("action_moves", "?"),
    ("succeeded", "i8"), ("tree", "i8"), ("dt_slot", "i8"),
    # pacing at the interaction point (people.pacing)
    ("held", "?"), ("pace", "f8"), ("held_steps", "i8"), ("first_held", "i8"),
    # giving way (people.give_way): where it stands aside and from which arc position of the robot's path, and
    # the point of the robot's path it backs out to first where there is no room beside it
    ("gives_way", "?"), ("give_way_phase", "i8"), ("aside", "c16"), ("aside_at", "f8"), ("aside_via", "c16"),
    # ... the spot their group's one plan left them (people.group_way: has_slot), and how near they came to their
    # side-step target (aside_near) and for how long no nearer (aside_stall: a body in the way makes them re-plan)
    ("has_slot", "?"), ("aside_near", "f8"), ("aside_stall", "f8"),
    ("came_up", "?"),  # following the robot: walked up into its way (give_way.lets_robot_by): waits for it to drive on
    # making room for a robot that waits (people.make_room): stepping aside, and the spot to go back to
    ("makes_room", "i8"), ("room_home", "c16"),
    # a goal point someone else stands on (people.spots): the spot round it this person walks to instead
    ("has_spot", "?"), ("spot", "c16"), ("spot_for", "c16"),
    # after the robot's arrival (people.grace): still walking in to their path's end by its goal (this step), and
    # came in (for good: they walk their last leg, then stand facing the robot)
    ("coming", "?"), ("came_in", "?"),
    # letting someone out of where they go (people.spacing.let_out): who (-1: nobody)
    ("lets_out", "i8"),
])


def group_labels(group_ids: list[int]) -> tuple[np.ndarray, np.ndarray]:
    """(label per person, size per label): groups of two or more get labels 0..G-1, everyone else -1."""
    ids = np.asarray(group_ids, dtype=np.int64)
    kept = sorted({int(g) for g in ids if g != -1 and int((ids == g).sum()) >= 2})
    index = {g: k for k, g in enumerate(kept)}
    labels = np.array([index.get(int(g), -1) for g in ids], dtype=np.int64)
    sizes = np.array([(labels == k).sum() for k in range(len(kept))], dtype=float)
    return labels, sizes


def new_people(specs: list[HumanSpec]) -> tuple[np.recarray, np.ndarray, np.ndarray]:
    """(people, goal rings, group sizes) for these specs, each facing its `yaw`, its first goal in front."""
    n = len(specs)
    labels, sizes = group_labels([s.group_id for s in specs])
    people = table(PERSON, n, pos=[complex(*s.start) for s in specs], yaw=[s.yaw for s in specs],
                   radius=[s.radius for s in specs], max_speed=[s.max_vel for s in specs], group=labels,
                   goal_radius=[s.goal_radius for s in specs], cyclic=[s.cyclic for s in specs],
                   pace=[s.max_vel for s in specs], start_delay=[s.start_delay for s in specs], sees_robot=-1,
                   pass_gap=[s.pass_gap for s in specs],
                   action=-1, via_step=-1, via_mark=-1,
                   goal_mark=-1, lets_out=-1, route=ROUTE_GOAL)  # not 0: following person 0 (robot.lead reads it)
    capacity = max([len(s.goals) for s in specs] + [0]) + 2  # a cyclic queue re-appends before it pops
    goals = np.zeros((n, capacity), dtype=complex)
    for i, s in enumerate(specs):
        goals[i, :len(s.goals)] = [complex(*g) for g in s.goals]
        people[i].queue_count = len(s.goals)
        refresh_goal(people, goals, i)
    return people, goals, sizes


# ---- goal queue ---------------------------------------------------------------------------------------
@jit
def refresh_goal(people, goals, i):  # noqa: ANN001, ANN201
    """Mirror the front of person i's queue into its `goal` after the queue changed."""
    p = people[i]
    p.has_goal = p.queue_count > 0
    p.goal = goals[i, p.queue_start] if p.has_goal else p.pos


@jit
def pop_goal(people, goals, i, keep_last):  # noqa: ANN001, ANN201
    """UpdateGoal (keep_last: the last goal stays, fork rule) or the walking step's consumption of a goal
    reached: drop the front; a cyclic queue appends it again."""
    p = people[i]
    count = p.queue_count
    if count == 0:
        return
    capacity = goals.shape[1]
    start = p.queue_start
    front = goals[i, start]
    if not keep_last or count != 1:
        start = (start + 1) % capacity
        count -= 1
    if p.cyclic:
        goals[i, (start + count) % capacity] = front
        count += 1
    p.queue_start = start
    p.queue_count = count
    refresh_goal(people, goals, i)


@jit
def goal_reached(people, goals, i):  # noqa: ANN001, ANN201
    """IsGoalReached: a goal is left and the person is within its goal radius (+ slack) of the front one, or as
    close as the people standing at it let them (queued_at) - not while pacing holds them where they stand: they
    did not walk there (a patient starting 1 m from her meeting node, where another stood, counted it reached at
    once, walked on unpaced and stood 5 m down the corridor: hospital_11 of the new-request suite)."""
    p = people[i]
    if p.queue_count == 0:
        return False
    goal = goals[i, p.queue_start]
    if spot_taken(people, i, goal) and not p.held:  # a spot round it (people.spots): reached there, not on the way
        return at_spot(people, i)  # past the point (the first into a lift walks on to its back)
    return abs(goal - p.pos) <= p.goal_radius + PERSON_GOAL_SLACK or (not p.held and queued_at(people, i, goal))


@jit
def queued_at(people, i, goal):  # noqa: ANN001, ANN201
    """Person i is as close to `goal` as the people standing at it let them: at the spot they took round it
    (people.spots), or within QUEUE_REACH of it and at the
    standing gap (+ QUEUE_SLACK) from someone standing nearer to it (a team gathering at one bed, workers at one
    pallet: the later ones stop beside the first, not pressed into them)."""
    p = people[i]
    if spot_taken(people, i, goal):
        return at_spot(people, i)
    away = abs(goal - p.pos)
    if away > QUEUE_REACH:
        return False
    for j in range(people.shape[0]):
        q = people[j]
        if j == i or abs(q.vel) >= STANDING or abs(goal - q.pos) >= away:
            continue
        if abs(q.pos - p.pos) - p.radius - q.radius <= PERSON_STAND_GAP + QUEUE_SLACK:
            return True
    return False


@jit
def done(people, goals, i):  # noqa: ANN001, ANN201
    """Finished its walk: no goal left, or only its last goal, standing within reach of it."""
    p = people[i]
    if (p.cyclic and p.queue_count > 0) or p.queue_count > 1:
        return False
    return (p.queue_count == 0 or goal_reached(people, goals, i)) and abs(p.vel) < DONE_SPEED


# ---- motion commands (a leaf says what the person does this step; physics moves everyone at once) ----
@jit
def walk_to_goal(people, i, speed, push):  # noqa: ANN001, ANN201
    """Social-force walking toward the front goal at `speed`, with an extra force `push`."""
    p = people[i]
    p.walks, p.to_goal, p.turns, p.route = True, True, False, ROUTE_GOAL
    p.desired_speed, p.push = speed, push


@jit
def walk_to(people, i, target, radius, speed, route):  # noqa: ANN001, ANN201
    """Social-force walking toward `target` (arrived within `radius`) at `speed`, finding the way by `route`."""
    p = people[i]
    p.walks, p.to_goal, p.turns, p.route = True, False, False, route
    p.target, p.target_radius, p.desired_speed, p.push = target, radius, speed, 0j


@jit
def turn(people, i, yaw):  # noqa: ANN001, ANN201
    """Stand and face `yaw`."""
    p = people[i]
    p.walks, p.turns, p.turn_to = False, True, yaw


@jit
def stand(people, i):  # noqa: ANN001, ANN201
    p = people[i]
    p.walks, p.turns = False, False
