"""The whole state of one simulation, named: the records and tables every compiled function of the step
reads (`s.robot[0].pos`, `s.people[i].goal`, `s.clock[0].t`), gathered in one State. A Simulation builds it once;
the step changes it in place; the Observation, the trace and the Simulation's properties are views of it."""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from socnavgen.sim.people.pacing import Pacing
from socnavgen.sim.people.physics import Scratch, SFMParams
from socnavgen.sim.people.trees import Trees
from socnavgen.sim.records import layout, table
from socnavgen.sim.robot.script import Script
from socnavgen.sim.world.queries import WorldMap
from socnavgen.sim.world.routes import RouteMap

# why a run ended (clock.end)
RUNNING, TIMEOUT, ROBOT_GOAL, ALL_DONE = 0, 1, 2, 3
END_REASONS = {TIMEOUT: "timeout", ROBOT_GOAL: "robot_goal", ALL_DONE: "all_done"}

CLOCK = layout([
    ("t", "f8"), ("dt", "f8"), ("step", "i8"), ("max_steps", "i8"), ("idle", "f8"), ("idle_end", "f8"),
    ("end", "i8"), ("contact_slack", "f8"),
    # s the robot has made no progress along its route, near stalled_at (engine.step.STALL_PROGRESS, STALL_REACH)
    ("stalled", "f8"), ("best_progress", "f8"), ("stalled_at", "c16"),
    # s the robot has stood (slower than bodies.STANDING) without a break: pacing's "it stands for someone"; not
    # `idle`, which also counts creeping about without progress (the run's end: engine.step.ending)
    ("standing", "f8"),
    ("arrived", "f8"),  # s: when the robot arrived at its goal in a run (-1: not yet; engine.step.ending, people.grace)
    # how the episode hands control back to Python (engine.step's events)
    ("python_policy", "?"), ("each_step", "?"), ("progress_every", "i8"), ("stop_at_end", "?"),
    # a tree that could not go on: its node, what went wrong, the port column and the value it held
    ("error_node", "i8"), ("error_kind", "i8"), ("error_port", "i8"), ("error_value", "f8")])
ROBOT = layout([
    ("pos", "c16"), ("vel", "c16"), ("heading", "c16"),  # heading: unit direction it last moved (or faces)
    ("yaw", "f8"), ("omega", "f8"), ("radius", "f8"), ("goal", "c16"), ("goal_tolerance", "f8"),
    # its body (robot.body): kinematics, limits, and its signed forward speed now
    ("kinematics", "i8"), ("max_speed", "f8"), ("max_accel", "f8"), ("max_decel", "f8"), ("max_omega", "f8"),
    ("max_alpha", "f8"), ("speed", "f8"),
    ("gesture", "i8"), ("said", "i8"),  # said: bit g set once it has shown gesture g (RobotSaid)
    ("scripted", "i8"),  # the gesture the script and the gesture rules make now
    ("held", "?"),  # its script stands it now (a timed `wait`, a `let_pass`): not arrived short of its goal;
    # a follower who walked up into its way waits for it only then (people.give_way.lets_robot_by)
    # its progress along its waypoints (people.routing.robot_progress), computed once per step
    ("progress", "f8"), ("progress_segment", "i8"), ("progress_step", "i8"), ("search_from", "i8"),
    ("passed", "i8")])  # how many of its intermediate waypoints it has come near, in turn (engine.step.ending)
ACTION = layout([("vx", "f8"), ("vy", "f8"), ("gesture", "i8"), ("has_heading", "?"), ("heading", "c16"),
                 ("unicycle", "?"), ("forward", "f8"), ("turn", "f8")])  # unicycle: forward m/s, turn rad/s


class TraceColumns(NamedTuple):
    """One row per step (row 0: the initial state); engine.simulation turns them into a Trace."""

    pos: np.ndarray  # (T, n) complex
    vel: np.ndarray  # (T, n) complex
    yaw: np.ndarray  # (T, n)
    omega: np.ndarray  # (T, n)
    action: np.ndarray  # (T, n) int16: library leaf of the action executed, -1 none
    succeeded: np.ndarray  # (T, n) int64: bit mask of the leaves that returned SUCCESS
    gesture: np.ndarray  # (T, n) int8
    behavior: np.ndarray  # (T, n) int8
    robot: np.ndarray  # (T, 6): x, y, yaw, vx, vy, omega
    robot_gesture: np.ndarray  # (T,) int8


def trace_columns(rows: int, n: int) -> TraceColumns:
    return TraceColumns(np.zeros((rows, n), complex), np.zeros((rows, n), complex), np.zeros((rows, n)),
                        np.zeros((rows, n)), np.full((rows, n), -1, np.int16), np.zeros((rows, n), np.int64),
                        np.zeros((rows, n), np.int8), np.zeros((rows, n), np.int8), np.zeros((rows, 6)),
                        np.zeros(rows, np.int8))


class State(NamedTuple):
    """What every part of the step reads: the clock, the robot, the people and the map."""

    clock: np.recarray  # CLOCK (one row; single records live in one-row tables: s.robot[0].pos)
    robot: np.recarray  # ROBOT
    action: np.recarray  # ACTION: the answer of a policy of the user's
    policy: np.recarray  # robot.policies.POLICY: a built-in robot's parameters and state
    people: np.recarray  # people.state.PERSON per person
    goals: np.ndarray  # (n, capacity) complex: each person's goal queue (a ring)
    group_sizes: np.ndarray  # (groups,) float
    waypoints: np.ndarray  # (W,) complex: the robot's path, its goal last
    offsets: np.ndarray  # (W,) arc length of the path at each waypoint
    world: WorldMap
    forces: SFMParams
    work: np.ndarray  # (2, m) float scratch of the path geometry (people.give_way)
    fields: np.ndarray  # (W, rows, cols) float32: the planner's cost-to-go to each waypoint (robot.fields)
    routes: RouteMap  # route fields of the goals and waypoints (world.routes, people.routing)


class Episode(NamedTuple):
    """The State and what only one part reads: the trees, the script, pacing, physics scratch, the trace.
    Compiled functions take the parts they need: passing a tuple of arrays costs per array, every call."""

    state: State
    trees: Trees
    script: Script
    pacing: Pacing
    scratch: Scratch
    trace: TraceColumns


def singleton(dtype: np.dtype, **fields: object) -> np.recarray:
    """A one-row table (its row is the record the state holds; the table gives numpy views of its fields)."""
    return table(dtype, 1, **fields)
