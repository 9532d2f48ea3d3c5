"""When each person of an exported scenario sets off: THE timing rule of every target that runs our trees
(socrates, hunav2), so that the encounter happens at its place whatever robot drives and however fast.

In our simulator a person is paced by the robot's ETA (sim.interaction). A target has no such pacing, so
the export puts the timing into the person's own tree, as conditions the target evaluates itself:

1. walk the path until the goal HOLD_BEFORE metres before the interaction node is reached (a goal of the
   path there, or one the export adds to the person's goals), counting goals with IsGoalReached - so the
   spot does not depend on how fast the target's people walk -, then stand there;
2. set off - and from then on run the person's own tree - once the robot is as far along its path from the node
   as the person's last HOLD_BEFORE metres take at the robot's OWN speed (bodies.walk_time at walking speed: the
   time by which the simulator's pacing lets a standing person set off, sim.people.pacing; at a door on the
   robot's way, as far again as the robot's lead there, scene.leads, pacing's door_lead: the person goes through
   the door first; the same lead where the door lies just past the node on the robot's next leg and the person
   comes through it, scene.doors_after: out of the elevator the robot enters). The target has only the robot's
   distance (IsRobotNearby / HuNavSim 2.x IsRobotClose) and a clock (TimeExpiredCondition), so the speed is told
   from the time the robot takes to come near: a clock runs from when it comes within `measure_distance` (from the
   start, for a robot within it there that never leaves it); for each speed of ROBOT_SPEEDS but the slowest, the
   person sets off at that speed's distance if the robot came there within the time a robot a little slower than it takes
   (`faster`); at `release_distance`, the slowest's, in any case. Where the waiting spot is in the robot's way
   (ahead of it, inside the corridor its body sweeps) every such distance is at least the one at which the robot
   first has them there within proxemics.HELD_UP_DISTANCE (where someone in its way holds the robot up; the
   simulator's pacing never holds a person that close either), so robot and person never wait for each other;
   at the latest after `timeout` seconds (a robot that never comes). The release is latched: the person never
   waits again.

Because the release reads the robot's position and its speed, not a time, a robot at half or 1.5 times the
nominal speed still meets the person at the node: only the last HOLD_BEFORE metres are walked without the robot,
and they end when the robot gets there (a release by one distance, for the cruise speed, let the person go ~4 s
early for a robot at half speed). Who is timed is the simulator's rule: a person without a group whose
interaction node is on the robot's path after its start and whose tree walks at the start (export.first_move:
pacing holds RegularNav only; the hold replaces the whole tree, so a follower held would leave the one it follows
for a waiting spot of its own). `holds()` computes the numbers, `hold_root()` builds the typed tree."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from socnavgen import proxemics
from socnavgen.bodies import (
    CLEAR_LEAD,
    PERSON_GOAL_RADIUS,
    PERSON_GOAL_SLACK,
    PERSON_MAX_SPEED,
    PERSON_RADIUS,
    ROBOT_RADIUS,
    walk_time,
)
from socnavgen.bt.model import Node
from socnavgen.bt.write import node
from socnavgen.export.first_move import WALK, first_move
from socnavgen.export.models import ExportScene, HumanExport, WorldPoint

HOLD_BEFORE = 2.0  # m along the person's path before the interaction node: where they wait for the robot
WALK_SPEED = PERSON_MAX_SPEED  # m/s: a person's walking speed (HuNavSim's max_vel)
GOAL_REACHED = PERSON_GOAL_RADIUS + PERSON_GOAL_SLACK  # m: IsGoalReached holds this close to a goal
REUSE_GOAL = 0.3  # m: a goal of the path this close to where the waiting goal would go is used instead
RELEASE_MARGIN = 0.1  # m: a person stops a few centimetres either side of its waiting spot
TIMEOUT_FACTOR, TIMEOUT_SLACK = 3.0, 10.0  # released at the latest after 3x the nominal time + 10 s
SAMPLE = 0.05  # m: the robot's path is sampled this finely to find where the release really happens
WAIT_KEY = "socnavgen_wait"  # the blackboard entry the waiting step writes (standing still does nothing else)
RELEASE_NODE, TIMEOUT_NODE, COUNT_NODE = "socnavgen_robot_close", "socnavgen_timeout", "socnavgen_goal_count"
AT_SPOT_NODE = "socnavgen_at_spot"  # the IsGoalReached a distance release of a person who walks to its spot asks first
# the robot's speeds (x its cruise speed) the release adapts to: a robot this fast or faster is let come only as close
# as its speed needs (the person's last HOLD_BEFORE take it that far); the slowest is the unconditional release
ROBOT_SPEEDS = (1.5, 1.25, 1.0, 0.75, 0.5)
TRUE_AT = 0.5  # m: the clock's distance must first hold no farther than this before where it is meant to
MEASURE = 2.0  # m of the robot's path before its earliest release over which its speed is told (a clock from there)


@dataclass(frozen=True)
class Hold:
    """How one person is timed (metres, seconds, map frame)."""

    human: str
    node: str  # the interaction node
    goals_first: int  # walk until this many goals are reached (0: wait where the person starts)
    wait_goal: WorldPoint | None  # the goal added to the person's goals to wait at (None: a goal of the path)
    wait_index: int  # where wait_goal goes in the person's goal list
    release_distance: float  # set off once the robot is this close (centre to centre)
    timeout: float  # set off at the latest after this long
    wait_at: tuple[float, float]  # where the person waits
    robot_at: tuple[float, float]  # where the robot is when it comes within release_distance (nominal)
    early_by: float  # m of its path by which the robot comes that close before the intended point (0: never)
    # the same release for a faster robot: (speed factor, distance, seconds) - set off once the robot is within
    # `distance` if it came there within `seconds` of first coming within `measure_distance` (it drives at least
    # about `factor` x its cruise speed); release_distance is the latest, for the slowest robot (min ROBOT_SPEEDS)
    faster: tuple[tuple[float, float, float], ...] = ()
    measure_distance: float = 0.0


class _Line:
    """A polyline with arc length."""

    def __init__(self, points: list[complex]) -> None:
        self.points = points
        self.arc = np.concatenate([[0.0], np.cumsum([abs(b - a) for a, b in zip(points, points[1:], strict=False)])])

    @property
    def length(self) -> float:
        return float(self.arc[-1])

    def at(self, s: float) -> complex:
        s = min(max(s, 0.0), self.length)
        if len(self.points) == 1:
            return self.points[0]
        k = min(max(int(np.searchsorted(self.arc, s, side="right")) - 1, 0), len(self.points) - 2)
        span = self.arc[k + 1] - self.arc[k]
        return self.points[k] if span < 1e-12 else self.points[k] + (self.points[k + 1] - self.points[k]) * (s - self.arc[k]) / span

    def gaps(self, p: complex, upto: float) -> tuple[np.ndarray, np.ndarray]:
        """(arc positions, distances to p) sampled from the start to `upto`."""
        s = np.arange(0.0, upto + SAMPLE, SAMPLE)
        return s, np.array([abs(self.at(x) - p) for x in s])


def held_up_from(robot: _Line, spot: complex, upto: float) -> float | None:
    """How far (centre to centre) from `spot` the robot, driving its path up to arc `upto`, first has a person
    standing there in its way within proxemics.HELD_UP_DISTANCE (ahead, inside the corridor its body sweeps
    widened by WAY_MARGIN_SCRIPT: where a robot waits for them); None when it never does."""
    s = np.arange(0.0, upto + SAMPLE, SAMPLE)
    if len(robot.points) < 2 or not len(s):
        return None
    here = np.array([robot.at(x) for x in s])
    ahead = np.array([robot.at(x + SAMPLE) for x in s]) - here
    norm = np.abs(ahead)
    ok = norm > 1e-9
    heading = np.where(ok, ahead / np.where(ok, norm, 1.0), 0.0)
    way = proxemics.in_way(here.real, here.imag, heading.real, heading.imag, spot.real, spot.imag, ROBOT_RADIUS,
                           PERSON_RADIUS, proxemics.WAY_MARGIN_SCRIPT)
    gap = np.abs(here - spot)
    held = ok & way & (gap <= proxemics.HELD_UP_DISTANCE)
    return float(gap[int(np.argmax(held))]) if held.any() else None


def script_stops(h: HumanExport, scene: ExportScene, robot: _Line, upto: float, wait_at: complex) -> list[complex]:
    """Where the robot's script stands it for this person on its way to their node (arc up to `upto`): a cue that
    stands it (a wait, wait_until_clear, let_pass) and is about them - near a point (at_encounter, at_node) of their
    encounter or node, or lets them pass, or fires when they (waiting at `wait_at`) are within its distance
    (human_within them) - where the robot first comes that close to the point (to `wait_at`). The robot waits there
    for them (sim.people.pacing: that wait is the meeting), so they are released by then."""
    if scene.spec is None:
        return []
    encounters = {e.id: e for e in scene.spec.encounters}
    out = []
    for cue in scene.spec.script.cues:
        trig = cue.trigger
        if not (cue.wait > 0 or cue.wait_until_clear or cue.let_pass):
            continue
        encounter = encounters.get(trig.encounter or "") if trig.when == "at_encounter" else None
        node = trig.node if trig.when == "at_node" else encounter.node if encounter is not None else None
        if trig.when == "human_within" and trig.human == h.name:
            point = wait_at
        elif node in scene.nodes and (cue.let_pass == h.name or node == h.interaction_point
                                      or (encounter is not None and h.name in {p.human for p in encounter.humans})):
            point = complex(*scene.nodes[node])
        else:
            continue
        samples, gaps = robot.gaps(point, upto)
        reach = gaps <= trig.distance + 1e-9
        if reach.any():
            out.append(robot.at(float(samples[int(np.argmax(reach))])))
    return out


def _route(h: HumanExport, scene: ExportScene) -> tuple[_Line, float] | None:
    """The person's route from where it starts through its goals, and how far along it the interaction node
    is; None when the node is not on the route."""
    ip = h.interaction_point
    start = complex(h.start.x, h.start.y)
    line = _Line([start] + [complex(g.x, g.y) for g in h.goals])
    if ip == h.path[0]:
        node = scene.nodes.get(ip)
        return line, abs(complex(*node) - start) if node is not None else 0.0
    for k, goal in enumerate(h.goals, start=1):
        if goal.node == ip:
            return line, float(line.arc[k])
    return None


def start_wait(scene: ExportScene) -> float:
    """Seconds the robot's script waits at the start (0 without a script)."""
    if scene.spec is None:
        return 0.0
    return sum(c.wait for c in scene.spec.script.cues if c.trigger.when == "start")


def timed(h: HumanExport, scene: ExportScene) -> bool:
    """The simulator's rule of whom to pace: no group, an interaction node the robot heads to, and a tree that
    walks at the start (pacing holds RegularNav only: not a person who first follows someone or stands)."""
    return (bool(h.interaction_point) and h.group_id == -1 and h.interaction_point in scene.robot.path[1:]
            and first_move(h.tree_xml) == WALK)


def _waiting_goal(h: HumanExport, route: _Line, to_node: float) -> tuple[int, WorldPoint | None, int, float]:
    """(goals to reach, the goal to add or None, where it goes in the goal list, how far along the route the
    person then stands)."""
    goal_s = to_node - HOLD_BEFORE + GOAL_REACHED  # reached GOAL_REACHED before it: waits HOLD_BEFORE before
    if to_node - HOLD_BEFORE <= SAMPLE:
        return 0, None, 0, 0.0
    for k in range(1, len(route.points)):
        if abs(route.arc[k] - goal_s) < REUSE_GOAL:
            return k, None, 0, float(route.arc[k]) - GOAL_REACHED
    j = max(int(np.searchsorted(route.arc, goal_s, side="left")) - 1, 0)  # goal_s lies on leg j -> j+1
    point = route.at(goal_s)
    goal = WorldPoint(node=f"{h.name}_wait", x=point.real, y=point.imag, yaw=h.goals[j].yaw)
    return j + 1, goal, j, goal_s - GOAL_REACHED


def hold_for(h: HumanExport, scene: ExportScene) -> Hold | None:
    """The timing of one person, or None when the person is not timed.

    The person waits HOLD_BEFORE before the node, at a goal: one of its path's when there is one there, else
    one added to its goals (`wait_goal`); it walks until it has reached that goal, counted with IsGoalReached -
    no clock, so the spot is the same whatever the simulator's walking speed."""
    if not timed(h, scene) or h.interaction_point is None:  # timed: it has one
        return None
    found = _route(h, scene)
    if found is None:
        return None
    route, to_node = found
    count, goal, index, wait_s = _waiting_goal(h, route, to_node)
    wait_at = route.at(wait_s)
    setting_off = walk_time(to_node - wait_s, WALK_SPEED)  # from the waiting spot to the node: pacing's own rule
    robot = _Line([complex(scene.robot.start.x, scene.robot.start.y)] + [complex(w.x, w.y) for w in scene.robot.waypoints])
    node_s = float(robot.arc[scene.robot.path.index(h.interaction_point, 1)])
    lead = scene.leads.get(h.interaction_point, 0.0)
    k = h.path.index(h.interaction_point)
    if k > 0 and scene.doors_after.get(h.interaction_point) == h.path[k - 1]:  # through the robot's door first
        lead = CLEAR_LEAD
    held_up = held_up_from(robot, wait_at, node_s)
    stops = [abs(p - wait_at) + RELEASE_MARGIN for p in script_stops(h, scene, robot, node_s, wait_at)]

    def release_at(factor: float) -> float:  # the robot's arc where a robot at factor x cruise lets the person go
        return max(0.0, node_s - lead - scene.robot_speed * factor * setting_off)

    def distance_at(s: float) -> float:
        distance = abs(robot.at(s) - wait_at) + RELEASE_MARGIN
        if held_up is not None:  # the person waits in the robot's way: released before it would wait for them
            distance = max(distance, held_up + RELEASE_MARGIN)
        return max([distance, *stops])  # released once the robot stands for them

    def first_within(distance: float, upto: float) -> float:  # where on its path the robot first comes that close
        samples, gaps = robot.gaps(wait_at, upto)
        reach = gaps <= distance + 1e-9
        return float(samples[int(np.argmax(reach))]) if reach.any() else upto

    release_s = release_at(1.0)
    robot_at = robot.at(release_s)
    first = first_within(distance_at(release_s), release_s)
    nominal = release_s / scene.robot_speed + start_wait(scene)
    factors = sorted(ROBOT_SPEEDS, reverse=True)
    measure_s = max(0.0, release_at(factors[0]) - MEASURE)
    measure = max(abs(robot.at(measure_s) - wait_at) + RELEASE_MARGIN, *(distance_at(release_at(f)) for f in factors))
    measure_first = first_within(measure, node_s)
    faster = []
    latest = distance_at(release_at(factors[-1]))
    for factor, slower in zip(factors, factors[1:], strict=False):
        distance = distance_at(release_at(factor))
        boundary = scene.robot_speed * float(np.sqrt(factor * slower))  # faster than this: the earlier release
        seconds = (first_within(distance, node_s) - measure_first) / boundary
        seconds += start_wait(scene) if measure_first <= SAMPLE else 0.0  # the clock runs from the start
        if seconds > SAMPLE / boundary:
            faster.append((factor, round(distance, 2), round(seconds, 2)))
    # the robot's distance tells its place on its path only where it keeps coming closer: where it comes within a
    # release's distance elsewhere first (a path bending round the spot), leaves the clock's distance once in it
    # (the clock would stop meanwhile), or drives less than MEASURE / 2 before the fastest release (no time to tell
    # its speed), one release, the cruise speed's, as a distance alone. A robot within the clock's distance from
    # its start (a lobby it turns away from first) is timed from the start: only its approach within the farthest
    # release must keep coming closer
    samples, gaps = robot.gaps(wait_at, release_at(factors[-1]))
    approach = gaps[samples >= measure_first - 1e-9]
    farthest = max([latest, *(d for _, d, _ in faster)])
    inside = np.flatnonzero(approach <= farthest + 1e-9)
    closing = approach[inside[0]:] if len(inside) else approach
    late_clock = measure_first < measure_s - TRUE_AT and measure_first > SAMPLE
    if (release_at(factors[0]) < MEASURE / 2 or late_clock or (approach > measure + 1e-9).any()
            or (np.diff(closing) > 1e-3).any()):
        faster, latest = [], distance_at(release_s)
    return Hold(human=h.name, node=h.interaction_point or "", goals_first=count, wait_goal=goal, wait_index=index,
                release_distance=round(latest, 2),
                timeout=round(TIMEOUT_FACTOR * nominal + TIMEOUT_SLACK, 1),
                wait_at=(round(wait_at.real, 3), round(wait_at.imag, 3)),
                robot_at=(round(robot_at.real, 3), round(robot_at.imag, 3)), early_by=round(max(0.0, release_s - first), 2),
                faster=tuple(faster), measure_distance=round(measure, 2))


def holds(scene: ExportScene) -> dict[str, Hold]:
    """Every timed person of the scene -> its Hold."""
    out = {}
    for h in scene.humans:
        hold = hold_for(h, scene)
        if hold is not None:
            out[h.name] = hold
    return out


def with_waiting_goals(scene: ExportScene) -> tuple[ExportScene, dict[str, Hold]]:
    """The scene with every added waiting goal in its person's goals (what a target that runs the timing
    exports), and the holds."""
    found = holds(scene)
    humans = []
    for h in scene.humans:
        hold = found.get(h.name)
        if hold is not None and hold.wait_goal is not None:
            goals = [*h.goals[:hold.wait_index], hold.wait_goal, *h.goals[hold.wait_index:]]
            h = h.model_copy(update={"goals": goals})
        humans.append(h)
    return scene.model_copy(update={"humans": humans}), found


# ---- the tree ------------------------------------------------------------------------------------------
def walk_node() -> Node:
    """One step of regular walking along the goal list (the RegularNavTree, written out)."""
    return node("Fallback",
                node("Sequence", node("Inverter", node("IsGoalReached", agent_id="{id}")),
                     node("RegularNav", agent_id="{id}", time_step="{dt}")),
                node("UpdateGoal", agent_id="{id}"))


def stand_node() -> Node:
    """A step in which the person does nothing: it stands (HuNavSim moves a person only in its actions)."""
    return node("SetBlackboard", output_key=WAIT_KEY, value="{id}")


def latch(condition: Node, after: Node, before: Node, keep: set[Node], label: str) -> Node:
    """`before` until `condition` first holds, `after` from then on, for good.

    ReactiveFallback[Sequence[condition, KeepRunningUntilFailure[ForceSuccess[after]]], before]: every tick
    the Sequence is ticked first; while the condition fails, `before` runs (it may be RUNNING: the reactive
    Fallback still starts again from the Sequence next tick); once the condition held, the Sequence is RUNNING
    in its second child for good (ForceSuccess under KeepRunningUntilFailure never finishes) and, being a
    Sequence with memory, never ticks the condition again; `before` is halted. That Sequence must keep its
    memory: it goes into `keep` (a translation must not make it reactive)."""
    seq = node("Sequence", condition, node("KeepRunningUntilFailure", node("ForceSuccess", after)),
               label=f"{label}_then")
    keep.add(seq)
    return node("ReactiveFallback", seq, before, label=label)


def hold_root(root: Node, hold: Hold, keep: set[Node]) -> Node:
    """`root` (the person's tree) run only once the hold of `hold` is over; until then walk, then wait.

    The goals are counted with a TimeExpiredCondition ticked only when IsGoalReached succeeds, with ts=1: it
    adds one per goal reached (the tick before UpdateGoal moves on) and latches at `goals_first`. The robot's
    distance is the target's from where the person IS: a person who walks to its waiting spot asks it only at a
    goal (IsGoalReached: standing at the spot), so a robot near where it starts neither lets it go on its way there
    nor starts the clocks of the faster releases (the distances are the spot's). The nodes the export adds are named socnavgen_*
    (Groot2 shows the names)."""

    def at_spot(label: str) -> list[Node]:
        return [node("IsGoalReached", agent_id="{id}", label=label)] if hold.goals_first else []

    faster = [node("Sequence", *at_spot(f"socnavgen_at_spot_{k}"),
                   node("IsRobotNearby", agent_id="{id}", distance=hold.measure_distance),
                   node("Inverter", node("TimeExpiredCondition", seconds=seconds, ts="{dt}", only_once=True,
                                         label=f"socnavgen_clock_{k}")),
                   node("IsRobotNearby", agent_id="{id}", distance=distance, label=f"socnavgen_robot_near_{k}"),
                   label=f"socnavgen_faster_{k}")
              for k, (_, distance, seconds) in enumerate(hold.faster)]
    close = node("IsRobotNearby", agent_id="{id}", distance=hold.release_distance, label=RELEASE_NODE)
    if hold.goals_first:
        close = node("Sequence", *at_spot(AT_SPOT_NODE), close, label="socnavgen_close_at_spot")
    release = node("Fallback",
                   close,
                   *faster,
                   node("TimeExpiredCondition", seconds=hold.timeout, ts="{dt}", only_once=True, label=TIMEOUT_NODE),
                   label="socnavgen_release")
    wait = stand_node()
    if hold.goals_first:
        counted = node("Sequence", node("IsGoalReached", agent_id="{id}", label="socnavgen_goal_reached"),
                       node("TimeExpiredCondition", seconds=float(hold.goals_first), ts=1.0, only_once=True,
                            label=COUNT_NODE),
                       label="socnavgen_at_waiting_goal")
        wait = latch(counted, wait, walk_node(), keep, "socnavgen_approach")
    return latch(release, root, wait, keep, "socnavgen_timing")


def describe(hold: Hold) -> str:
    """One line for an export's README."""
    added = " (added to its goals)" if hold.wait_goal is not None else ""
    approach = f"walks to its goal {hold.goals_first}{added}" if hold.goals_first else ""
    early = (f" (the robot's path passes that close {hold.early_by:g} m earlier: it may set off early)"
             if hold.early_by > 0.5 else "")
    sooner = "".join(f", {d:g} m if it came there within {t:g} s (a robot at {f:g}x its speed or faster)"
                     for f, d, t in hold.faster)
    clock = f" (the clock runs from when it is within {hold.measure_distance:g} m)" if hold.faster else ""
    return (f"{hold.human}: {approach + ', ' if approach else ''}waits at ({hold.wait_at[0]:.2f}, "
            f"{hold.wait_at[1]:.2f}) until the robot is within {hold.release_distance:g} m{sooner}{clock} (at the "
            f"latest {hold.timeout:g} s), then meets it at {hold.node}{early}")


__all__ = ["HOLD_BEFORE", "Hold", "held_up_from", "hold_for", "hold_root", "holds", "latch", "script_stops"]
