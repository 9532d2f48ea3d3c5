"""Pacing people to meet the robot at their interaction point, after SocRATES's scenario manager
(reference §11), both ways.

A person without a group whose path has an interaction node that is also on the robot's path is paced by
the robot's ETA at that node, re-estimated every step from what the robot does: its route left from where it
is, at its cruise speed now (the script's, changed by its cues), plus the time it will still stand for its
timed waits (a cue's `wait`, a late start; not a wait it stands on its way within `release_distance` of the node:
that wait is the meeting, the person comes during it) and the time it loses at slow spots on the way (`robot_late`, filled
by the robot's package every step: its blind corners, robot.polite.corner_late). Only RegularNav honours it, as `pause_nav` in the fork. Two rules:
* `eta` (default): a person standing (at the start, or held) stays where it is until walking to the node
  takes as long as the robot's ETA (bodies.walk_time, the time by which the export's timing sets people off
  too, at `set_off_pace` of its top speed: the rest is slack to catch up after corners), then walks there; a
  person walking slows down to arrive together with the robot and stands while that speed would be a crawl
  (`min_pace`), so it waits for a delayed robot, out of sight if it was. Never held where the robot would wait
  for them: in its way (ahead, in the corridor its body sweeps) within `release_distance`, or while it stands
  for no known time (`robot_waits` s or more without a timed wait: it waits for someone); there it walks on to
  the node at `min_pace`. Full speed once the robot is close to the node. So both arrive together and meet AT
  the node, whatever delays the robot had; at a narrow node (a door) the person is there while the robot is
  still `clear_lead` m before it, and clears it first.
* `socrates`: the fork's rule - hold on the leg before the node until the robot's current waypoint is the
  node (the robot counts a waypoint as passed within 1.5 m).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from socnavgen import bodies, proxemics
from socnavgen.sim.jit import jit
from socnavgen.sim.records import layout, table
from socnavgen.sim.trace import REGULAR_BEHAVIOR
from socnavgen.sim.world.grid import World

ETA, SOCRATES = 0, 1
RULES = {"eta": ETA, "socrates": SOCRATES}


@dataclass
class ThrottleConfig:
    enabled: bool = True
    waypoint_radius: float = 1.5  # m: the robot counts a waypoint as passed within this distance
    # m: never hold a person this close to the robot: the robot waits for someone in its way this close
    # (proxemics.HELD_UP_DISTANCE), so holding them there too would leave both waiting for each other
    release_distance: float = proxemics.HELD_UP_DISTANCE
    rule: str = "eta"  # "eta" or "socrates"
    robot_speed: float = 0.6  # m/s: nominal robot speed for the eta rule (the script's cruise speed)
    min_pace: float = 0.3  # m/s: a person who would walk slower than this stands instead (holds)
    robot_near: float = 0.5  # m: once the robot is this close to the node (along its path), full speed
    robot_waits: float = 1.0  # s: the robot standing this long (clock.standing), no timed wait: no ETA
    # a standing person sets off when walking at this share of its top speed gets it there with the robot (the
    # rest is its slack for corners and people on its way)
    set_off_pace: float = 0.8
    # m: at an interaction node that is a door on the robot's way (door_lead: narrower than `narrow_clearance`
    # from its centre to a wall, and not so `clear_lead` m before it on the robot's route) the person aims to be
    # at the node while the robot is still `clear_lead` m before it: they clear the door first
    narrow_clearance: float = bodies.TOUCH_DISTANCE
    clear_lead: float = bodies.CLEAR_LEAD


@dataclass
class PacingPlan:
    """Who is paced: (agent id, path node ids, interaction node or None, group id) per person, and the
    robot's path as node ids (its waypoints, first one included)."""

    config: ThrottleConfig
    robot_nodes: list[str]
    humans: list[tuple[int, list[str], str | None, int]]


SETTINGS = layout([("enabled", "?"), ("rule", "i8"), ("next_waypoint", "i8"), ("waypoint_radius", "f8"),
                   ("release_distance", "f8"), ("robot_speed", "f8"), ("min_pace", "f8"), ("robot_near", "f8"),
                   ("robot_waits", "f8"), ("set_off_pace", "f8"),
])
HELD = layout([("agent", "i8"), ("goals", "i8"), ("node_at", "i8"), ("spawn_is_node", "?"), ("robot_index", "i8"),
               ("lead", "f8")])  # lead: m before the robot reaches the node the person aims to be there (door_lead)


class Pacing(NamedTuple):
    settings: np.recarray  # SETTINGS (one row); next_waypoint indexes the robot's waypoints after its start
    held: np.recarray  # HELD per paced person
    points: np.ndarray  # (held, goals) complex: each paced person's goals
    goal_is_node: np.ndarray  # (held, goals) bool: which of its goals is its interaction node
    robot_goal_is_node: np.ndarray  # (held, robot goals) bool: which robot goal is its interaction node
    robot_late: np.ndarray  # (robot waypoints,) s the robot will lose at slow spots before each (set every step)


def door_lead(world: World, route: Sequence[complex], node: int, narrow: float = bodies.TOUCH_DISTANCE,
              lead: float = bodies.CLEAR_LEAD) -> float:
    """How far (m, along the robot's route) before the robot reaches its route point `node` a person meeting it
    there must be at it: `lead` where that point is a door on the robot's way - less than `narrow` from it to a
    wall, so robot and person cannot pass each other in it, while the route `lead` m before it is not (the robot
    comes from where they can) -, so that the person clears the door first instead of meeting the robot face to
    face in it; 0 elsewhere. THE rule of pacing and of the export's timing (export.timing)."""
    points = [complex(p) for p in route]
    if not 0 < node < len(points) or lead <= 0 or world.clearance_at_point(points[node]) >= narrow:
        return 0.0
    arc = np.concatenate([[0.0], np.cumsum(np.abs(np.diff(np.array(points[:node + 1]))))])
    back = float(arc[-1]) - lead
    if back <= 0:
        return 0.0  # the robot starts nearer the door than that
    j = int(np.searchsorted(arc, back, side="right"))  # back lies on the leg j-1 -> j
    span = arc[j] - arc[j - 1]
    before = points[j] if span <= 1e-9 else points[j - 1] + (points[j] - points[j - 1]) * ((back - arc[j - 1]) / span)
    return lead if world.clearance_at_point(before) >= narrow else 0.0


def lower_pacing(plan: PacingPlan | None, goals: list[list[complex]], world: World | None = None,
                 route: Sequence[complex] = ()) -> tuple[Pacing, list[str]]:
    """(Pacing, notes on people who cannot be paced) for a plan (None: nobody is paced); `world` and the robot's
    `route` (its waypoints, first one included) tell which interaction nodes are doors (door_lead)."""
    config = plan.config if plan is not None else ThrottleConfig(enabled=False)
    if config.rule not in RULES:
        raise ValueError(f"unknown pacing rule {config.rule!r} (use {', '.join(RULES)})")
    robot_goals = plan.robot_nodes[1:] if plan is not None else []
    held, skipped = [], []
    for agent, path, node, group in plan.humans if plan is not None else []:
        if node is None or group != -1 or not path:
            continue
        if node not in robot_goals:
            skipped.append(f"agent {agent}: interaction node {node} is not on the robot's path after its start")
            continue
        held.append((agent, path[1:] if len(path) > 1 else [path[0]], path[0], node))
    width = max([len(h[1]) for h in held] + [1])
    rows = table(HELD, max(len(held), 1))
    points = np.zeros((max(len(held), 1), width), dtype=complex)
    goal_is_node = np.zeros((max(len(held), 1), width), dtype=bool)
    robot_goal_is_node = np.zeros((max(len(held), 1), max(len(robot_goals), 1)), dtype=bool)
    for j, (agent, path_goals, spawn, node) in enumerate(held):
        row = rows[j]
        row.agent, row.goals, row.spawn_is_node = agent, len(path_goals), spawn == node
        row.node_at = path_goals.index(node) if node in path_goals else -1
        row.robot_index = robot_goals.index(node)
        row.lead = door_lead(world, route, row.robot_index + 1, config.narrow_clearance, config.clear_lead) \
            if world is not None and len(route) > row.robot_index + 1 else 0.0
        points[j, :len(goals[agent])] = goals[agent]
        goal_is_node[j, :len(path_goals)] = [g == node for g in path_goals]
        robot_goal_is_node[j, :len(robot_goals)] = [g == node for g in robot_goals]
    settings = table(SETTINGS, 1, enabled=config.enabled and bool(held), rule=RULES[config.rule],
                      waypoint_radius=config.waypoint_radius, release_distance=config.release_distance,
                      robot_speed=config.robot_speed, min_pace=config.min_pace, robot_near=config.robot_near,
                      robot_waits=config.robot_waits, set_off_pace=config.set_off_pace)
    late = np.zeros(max(len(route), len(robot_goals) + 1, 1))
    return Pacing(settings, rows[:len(held)], points, goal_is_node, robot_goal_is_node, late), skipped


walk_time = jit(bodies.walk_time)  # THE set-off time of a waiting person (socnavgen.bodies), compiled
in_way = jit(proxemics.in_way)  # the one "in the robot's way" (socnavgen.proxemics), compiled


@jit
def pace(s, pacing, cruise, waits, let_pass=-1, at_start=0.0):  # noqa: ANN001, ANN201, C901
    """Advance the robot's waypoint index; set `held` (and `pace`, the speed RegularNav walks at) of every
    paced person for this step. `cruise`: the robot's speed where nothing slows it (robot.policies.cruise; < 0:
    unknown, the config's robot_speed); `waits`: seconds it will still stand for its script's timed waits
    (robot.script.still_waits); `let_pass`: the person the robot stands for to let them go first
    (robot.script.waiting_for; -1: none), never held nor slowed: they go first at their own speed; `at_start`: the
    part of `waits` its start cues stand it (robot.script.start_waits)."""
    settings = pacing.settings[0]
    if not settings.enabled:
        return
    wps, robot = s.waypoints, s.robot[0]
    rp = robot.pos
    k = settings.next_waypoint  # index among the robot's goals (its waypoints after the first)
    while k < wps.shape[0] - 2 and abs(wps[k + 1] - rp) <= settings.waypoint_radius:
        k += 1
    settings.next_waypoint = k
    # the robot's ETA: its route left at its cruise speed, plus the time it will still stand (timed waits, a
    # late start); standing for no known time (for someone: wait until clear, its own manners) is not counted.
    # Standing, not idle: a robot edging about without progress is idle for the run's end (engine.step.ending)
    # but has an ETA (hospital_11: the robot edging back after a let_pass released the second patient early)
    drive = cruise if cruise > 0 else settings.robot_speed
    stands = waits + max(0.0, s.policy[0].start_delay - s.clock[0].t)
    untimed = stands <= 0.0 and s.clock[0].standing >= settings.robot_waits
    way = wps[k + 1] - rp
    heading = way / abs(way) if abs(way) > 1e-9 else robot.heading
    for h in range(pacing.held.shape[0]):
        paced = pacing.held[h]
        i = paced.agent
        p = s.people[i]
        at = paced.goals - p.queue_count  # index among its goals of the goal it walks to now
        node = paced.robot_index
        if i == let_pass:  # the robot stands for them: they go first, at their own pace
            p.pace, p.held = p.max_speed, False
            continue
        if settings.rule == SOCRATES:
            if p.queue_count == 0 or (p.queue_count == 1 and abs(p.goal - p.pos) <= p.goal_radius):
                continue  # SocRATES sends no entry: the previous value stays
            next_is_node = pacing.goal_is_node[h, at] if 0 <= at < paced.goals else False
            hold = (p.behavior == REGULAR_BEHAVIOR and p.robot_distance > settings.release_distance
                    and (next_is_node or paced.spawn_is_node) and k < node and not pacing.robot_goal_is_node[h, k])
        else:
            hold, speed = False, p.max_speed
            robot_left = 0.0 if k > node else abs(wps[k + 1] - rp) + s.offsets[node + 1] - s.offsets[k + 1]
            if (p.behavior == REGULAR_BEHAVIOR and p.queue_count > 0 and at >= 0 and (at <= paced.node_at or paced.spawn_is_node)
                    and robot_left > settings.robot_near):
                if paced.spawn_is_node or at > paced.node_at:
                    human_left = abs(wps[node + 1] - p.pos)
                else:
                    human_left = abs(pacing.points[h, at] - p.pos)
                    for j in range(at, paced.node_at):
                        human_left += abs(pacing.points[h, j + 1] - pacing.points[h, j])
                # a timed wait the robot stands this near the node is the meeting itself: the person comes during
                # it, not after it (warehouse_21, round 29: a picker paced to the end of the robot's stop at the
                # crossing stepped out as it drove on; the export's release by the robot's distance does the same)
                # (a start wait is no meeting: exiting-elevator's robot stands in the car 2 m from the node)
                starting = max(0.0, s.policy[0].start_delay - s.clock[0].t) + at_start
                there = stands if robot_left > settings.release_distance else min(starting, stands)
                robot_left = max(robot_left - paced.lead, 0.0)  # at a door: through it first (door_lead)
                eta = robot_left / max(drive, 1e-3) + there + pacing.robot_late[node + 1]  # + its slow corners
                # never held where the robot would wait for them: in its way, near it or while it stands for someone
                blocks = in_way(rp.real, rp.imag, heading.real, heading.imag, p.pos.real, p.pos.imag, robot.radius,
                                p.radius, proxemics.WAY_MARGIN_SCRIPT)
                may_hold = not blocks or (p.robot_distance > settings.release_distance and not untimed)
                want = human_left / max(eta, 1e-3)
                if p.held or abs(p.vel) < settings.min_pace:  # standing: set off at its own speed when that
                    hold = may_hold and eta > walk_time(human_left, p.max_speed * settings.set_off_pace)  # arrives with the robot
                else:  # walking: slower to arrive together; stand when that would be a crawl
                    hold = may_hold and want < settings.min_pace
                if not hold and want < settings.min_pace:  # too early but not to be held: on to the node slowly;
                    if not paced.spawn_is_node:  # someone who waited at the node sets off at their own speed
                        speed = min(speed, settings.min_pace)
                elif not hold:
                    speed = min(speed, want)
            p.pace = speed
        p.held = hold
        if hold:
            if p.held_steps == 0:
                p.first_held = s.clock[0].step
            p.held_steps += 1
