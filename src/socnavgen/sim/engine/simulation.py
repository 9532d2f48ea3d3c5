"""A simulation: its configuration, the state built once from people, trees, the robot's path, policy, script
and pacing, and the Python side of the episode - it resumes the compiled step generator (engine.step),
answers it with a Python policy's action when there is one, and turns the recorded rows into a Trace."""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any

import numpy as np

from socnavgen.bodies import ROBOT_GOAL_TOLERANCE, ROBOT_RADIUS
from socnavgen.bt.library import ROBOT_GESTURES, leaf_nodes
from socnavgen.errors import ValidationFailed
from socnavgen.limits import MAX_COORDINATE, MAX_SIM_PEOPLE, MAX_SIM_STEPS
from socnavgen.run.models import RobotGestureRule
from socnavgen.run.spec import RobotScript
from socnavgen.sim.engine import step as stepper
from socnavgen.sim.engine.budget import time_limit
from socnavgen.sim.engine.errors import tree_error
from socnavgen.sim.engine.state import (
    ACTION,
    CLOCK,
    END_REASONS,
    ROBOT,
    RUNNING,
    Episode,
    State,
    singleton,
    trace_columns,
)
from socnavgen.sim.jit import AVAILABLE
from socnavgen.sim.people.pacing import PacingPlan, lower_pacing
from socnavgen.sim.people.physics import SFMParams, advance, new_scratch
from socnavgen.sim.people.state import HumanSpec, new_people
from socnavgen.sim.people.trees import Program, lower_trees
from socnavgen.sim.records import Columns, RowWriter
from socnavgen.sim.robot import policies
from socnavgen.sim.robot.api import BuiltinPolicy, Observation, checked_action
from socnavgen.sim.robot.body import KINEMATICS, RobotBody
from socnavgen.sim.robot.fields import NO_FIELDS, field_scale, route_fields
from socnavgen.sim.robot.script import fired, lower_script
from socnavgen.sim.trace import Trace
from socnavgen.sim.world.grid import World
from socnavgen.sim.world.routes import landmarks_of, load_wanted, route_map

NODE_NAMES = [n.name for n in leaf_nodes()]
CONTACT_SLACK = 0.005  # m: bodies are kept at least this far apart by the contact step
PROGRESS_EVERY = 200  # steps between two progress callbacks of run()


@dataclass
class SimConfig:
    dt: float = 0.05
    timeout: float | None = None  # s; None: it follows the robot's route (engine.budget.time_limit)
    seed: int = 0
    sfm: SFMParams = field(default_factory=SFMParams)
    robot_radius: float = ROBOT_RADIUS
    goal_tolerance: float = ROBOT_GOAL_TOLERANCE
    idle_end: float = 10.0  # end when every person is done and the robot has not moved for this long
    body: RobotBody = field(default_factory=RobotBody)  # kinematics and limits (robot.body)

    def __post_init__(self) -> None:
        def bad(name: str, value: object, want: str) -> None:
            raise ValidationFailed(f"SimConfig.{name} = {value!r}: it must be {want}")

        for name, low, high in (("dt", 0.0, 1.0), ("robot_radius", 0.0, 5.0), ("goal_tolerance", 0.0, 100.0)):
            value = getattr(self, name)
            if not (isinstance(value, int | float) and math.isfinite(value) and low < value <= high):
                bad(name, value, f"a number in ({low:g}, {high:g}]")
        if self.timeout is not None and not (isinstance(self.timeout, int | float) and self.timeout > 0
                                             and self.timeout / self.dt <= MAX_SIM_STEPS):
            bad("timeout", self.timeout, f"positive and at most {MAX_SIM_STEPS} steps of dt")
        if not (isinstance(self.idle_end, int | float) and self.idle_end >= 0) or math.isnan(self.idle_end):
            bad("idle_end", self.idle_end, "zero or more seconds")
        if not isinstance(self.body, RobotBody):
            bad("body", self.body, "a RobotBody")
        if not isinstance(self.seed, int | np.integer):
            bad("seed", self.seed, "an integer")
        prm = SFMParams(*self.sfm)
        if any(not math.isfinite(v) for v in prm[:-1]) or not prm.cutoff > 0:
            bad("sfm", self.sfm, "finite force factors and a positive cut-off")
        self.sfm = prm


@dataclass
class RobotSpeech:
    """What the robot says on its own: spec.json's script (cues at encounter points) and paths.json's gesture
    rules (some at scene-graph nodes)."""

    script: RobotScript | None = None
    encounter_points: dict[str, complex] = field(default_factory=dict)
    rules: list[RobotGestureRule] = field(default_factory=list)
    node_points: dict[str, complex] = field(default_factory=dict)


def _points(name: str, points: Any) -> np.ndarray:
    array = np.array([complex(*p) for p in points], dtype=complex)
    if not (np.isfinite(array).all() and (np.abs(array) <= MAX_COORDINATE).all()):
        raise ValidationFailed(f"{name} holds a point that is not a finite world position: {points!r}"[:300])
    return array


def cruise_speed(policy: Any, body_speed: float) -> float:
    """The fastest the robot means to drive: its policy's max_speed (when it has one) within its body's."""
    speed = getattr(policy, "max_speed", None)
    if isinstance(speed, int | float) and math.isfinite(speed) and speed > 0:
        return min(float(speed), body_speed)
    return body_speed


class Simulation:
    def __init__(self, world: World, humans: list[HumanSpec], trees: list[str], robot_path: list[tuple[float, float]],
                 policy: Any, config: SimConfig | None = None, speech: RobotSpeech | None = None,
                 pacing: PacingPlan | None = None, tree_names: list[str] | None = None, meta: dict | None = None,
                 program: Program | None = None) -> None:
        """`program`: these trees already lowered (people.trees.lower_trees, kept per scenario by
        load_simulation); the Simulation copies what an episode changes."""
        if len(trees) != len(humans):
            raise ValueError("one tree per human")
        if len(humans) > MAX_SIM_PEOPLE:
            raise ValidationFailed(f"{len(humans)} people: a simulation takes at most {MAX_SIM_PEOPLE}")
        self.config = config = config or SimConfig()
        self.world, self.policy, self.meta = world, policy, dict(meta or {})
        self.humans, self.paced = humans, pacing is not None
        speech = speech or RobotSpeech()
        self.cue_list = list(speech.script.cues) if speech.script is not None else []
        for h in humans:
            _points(f"{h.name}'s start and goals", [h.start, *h.goals])
        waypoints = _points("the robot's path", robot_path)
        if len(waypoints) == 0:
            raise ValidationFailed("the robot needs at least one waypoint")
        self.program = program or lower_trees(trees, tree_names)
        n, dt = len(humans), float(config.dt)
        self.timeout, self.timeout_why = (float(config.timeout), "set by the caller") if config.timeout is not None \
            else time_limit(waypoints, cruise_speed(policy, config.body.max_speed), speech.script,
                            float(getattr(policy, "start_delay", 0.0) or 0.0), dt)
        people, goals, sizes = new_people(humans)
        people.tree, people.dt_slot = self.program.roots, self.program.dt_slots
        first_leg = waypoints[1] - waypoints[0] if len(waypoints) > 1 else 1 + 0j
        yaw = math.atan2(first_leg.imag, first_leg.real) if abs(first_leg) > 0 else 0.0
        self.robot_table = singleton(ROBOT, pos=waypoints[0], heading=complex(math.cos(yaw), math.sin(yaw)), yaw=yaw,
                                     radius=config.robot_radius, goal=waypoints[-1],
                                     goal_tolerance=config.goal_tolerance, progress_step=-1,
                                     kinematics=KINEMATICS[config.body.kinematics], max_speed=config.body.max_speed,
                                     max_accel=config.body.max_accel, max_decel=config.body.max_decel,
                                     max_omega=config.body.max_omega, max_alpha=config.body.max_alpha)
        python_policy = not isinstance(policy, BuiltinPolicy)
        clock = singleton(CLOCK, dt=dt, max_steps=self.max_steps, idle_end=config.idle_end,
                          contact_slack=CONTACT_SLACK, python_policy=python_policy, error_node=-1,
                          arrived=-1.0)
        pacing_state, self.pacing_notes = lower_pacing(pacing, [[complex(*g) for g in h.goals] for h in humans],
                                                        world, list(waypoints))
        landmarks, waypoint_marks = landmarks_of([[complex(*g) for g in h.goals] for h in humans], list(waypoints))
        rules = [r for r in speech.rules if r.gesture in ROBOT_GESTURES]
        if len(rules) != len(speech.rules):
            raise ValidationFailed("a robot gesture rule names a code that is not a robot gesture: "
                                   f"{sorted({r.gesture for r in speech.rules} - set(ROBOT_GESTURES))}")
        parameters = policy.parameters() if not python_policy else singleton(policies.POLICY, kind=policies.PYTHON)
        plans = bool(parameters[0].plans) and len(waypoints) > 1
        parameters[0].field_scale = field_scale(world)
        parameters[0].accel = min(parameters[0].accel, config.body.max_accel)  # it plans within what its body can
        parameters[0].brake = min(parameters[0].brake, config.body.max_decel)
        self.state = State(
            clock=clock, robot=self.robot_table, action=singleton(ACTION, gesture=-1), policy=parameters,
            people=people, goals=goals, group_sizes=sizes, waypoints=waypoints,
            offsets=np.concatenate([[0.0], np.cumsum(np.abs(np.diff(waypoints)))]), world=world.map,
            forces=config.sfm, work=np.zeros((2, max(len(waypoints), 64) + 8)),
            fields=route_fields(world, waypoints, config.robot_radius) if plans else NO_FIELDS,
            routes=route_map(world, landmarks, waypoint_marks))
        self.episode = Episode(
            self.state, self.program.fresh(),
            lower_script(speech.script, speech.encounter_points, rules, speech.node_points, n, self.max_steps),
            pacing_state, new_scratch(n, len(sizes)), trace_columns(self.max_steps + 1, n))
        self._generator: Any = None
        self._clock, self._action = Columns(self.state.clock), Columns(self.state.action)  # fast from Python
        self._write_action = RowWriter(self.state.action).write
        if n:
            advance(people, sizes, config.sfm, world.map, waypoints[0], 0j, config.robot_radius, dt,
                    self.episode.scratch, False)
        stepper.record(self.state, self.episode.trace)
        if python_policy and hasattr(policy, "reset"):
            policy.reset(self.obs)

    # -- what the state holds now ------------------------------------------------------------------
    @cached_property
    def obs(self) -> Observation:
        """What a policy sees: views of this simulation's state (made when first asked)."""
        return Observation(self)

    @property
    def max_steps(self) -> int:
        """Steps of a run that reaches its timeout."""
        return int(math.ceil(self.timeout / self.config.dt))

    @property
    def dt(self) -> float:
        return float(self.config.dt)

    @property
    def t(self) -> float:
        return self._clock.t.item(0)

    @property
    def people(self) -> np.recarray:
        """One record per person (people.state.PERSON): pos, vel, yaw, gesture, behavior, goal, ..."""
        return self.state.people

    @property
    def robot(self) -> np.record:
        """The robot's record (engine.state.ROBOT): pos, vel, yaw, heading, gesture, ..."""
        return self.state.robot[0]

    @property
    def cues(self) -> Any:
        return self.obs.cues

    @property
    def robot_said(self) -> set[int]:
        return self.obs.robot_said

    def goals_of(self, i: int) -> list[complex]:
        """Person i's goal queue, front first."""
        p = self.state.people[i]
        goals = self.state.goals[i]
        return [complex(goals[(p.queue_start + j) % goals.shape[0]]) for j in range(p.queue_count)]

    # -- running -----------------------------------------------------------------------------------
    def _resume(self, until: int, progress: Callable[[int, int], None] | None = None) -> None:
        """Resume the episode until the event `until` (STEPPED or ENDED), answering ACT with the policy."""
        if self._generator is None:
            self._generator = stepper.episode(self.episode)
        policy, action, clock = self.policy, self._action, self._clock
        obs = self.obs if clock.python_policy.item(0) else None  # only a Python policy is asked (ACT)
        write, ACT = self._write_action, stepper.ACT  # the answer's record in one store (records.RowWriter) ...
        forward, turn_rate, facing = action.forward.item(0), action.turn.item(0), action.heading.item(0)
        for event in self._generator:
            if event == ACT:
                v, gesture, turn = checked_action(policy.act(obs), policy)
                if turn is not None:  # ... where a field the answer does not set keeps its value
                    forward, turn_rate = v.real, turn
                heading = getattr(policy, "heading", None)
                turned = isinstance(heading, complex | float | int) and heading != 0
                if turned and heading is not None:
                    facing = complex(heading)
                write(v.real, v.imag, gesture, turned, facing.real, facing.imag, turn is not None, forward, turn_rate)
            elif event == stepper.ROUTES:
                load_wanted(self.state.routes, self.world)
            elif event == until:
                return
            elif event == stepper.PROGRESS and progress is not None:
                progress(clock.step.item(0), self.max_steps)
            elif event == stepper.FAILED:
                self._generator = None
                raise tree_error(self.state, self.program)
        self._generator = None  # it ended: the next call starts a new one from the state

    def step(self) -> None:
        """One time step: every tree ticks on the current snapshot, the robot acts on the same snapshot, then
        everyone moves at once."""
        clock = self._clock
        clock.each_step[0], clock.stop_at_end[0], clock.progress_every[0] = True, False, 0
        self._resume(stepper.STEPPED)

    def run(self, progress: Callable[[int, int], None] | None = None) -> Trace:
        """Run to the robot's goal, the timeout, or until nothing will change; return the trace."""
        clock = self._clock
        clock.each_step[0], clock.stop_at_end[0], clock.end[0] = False, True, RUNNING
        clock.progress_every[0] = PROGRESS_EVERY if progress is not None else 0
        self._generator = None
        self._resume(stepper.ENDED, progress)
        if progress is not None:
            progress(self.max_steps, self.max_steps)
        return self.trace()

    def robot_at_goal(self) -> bool:
        """At its goal (or stopped short of someone standing there: proxemics.short_of_goal), having come near
        its route's other waypoints in turn (engine.step.ending's rule)."""
        robot = self.state.robot[0]
        return (abs(robot.goal - robot.pos) <= robot.goal_tolerance
                or (not robot.held and bool(policies.stopped_short(self.state)))) \
            and int(robot.passed) >= self.state.waypoints.shape[0] - 2

    def trace(self) -> Trace:
        """The trace of every step recorded so far, with the run's meta."""
        s, config = self.state, self.config
        steps = min(int(s.clock[0].step) + 1, self.episode.trace.robot.shape[0])
        cols = self.episode.trace
        pos, vel = cols.pos[:steps], cols.vel[:steps]
        humans = np.stack([pos.real, pos.imag, cols.yaw[:steps], vel.real, vel.imag, cols.omega[:steps]], axis=-1)
        meta = dict(self.meta)
        meta.update(seed=config.seed, timeout=self.timeout, timeout_why=self.timeout_why,
                    robot_goal_radius=config.goal_tolerance,
                    kernels="numba" if AVAILABLE else "python", robot_body=config.body.meta(),
                    human_goals={h.name: [list(g) for g in h.goals] for h in self.humans})
        if s.clock[0].arrived >= 0 and steps > 0 and s.clock[0].arrived < (steps - 1) * self.dt - 1e-9:
            meta["robot_arrived"] = round(float(s.clock[0].arrived), 6)  # s: it went on for followers (people.grace)
        if self.cue_list:
            meta["script_cues_fired"] = [list(f) for f in fired(self.episode.script, self.cue_list)]
        if self.paced:
            held = sorted((int(p.first_held), i) for i, p in enumerate(s.people) if p.held_steps > 0)
            meta["held_seconds"] = {self.humans[i].name: int(s.people[i].held_steps) * self.dt for _, i in held}
            meta["throttle_skipped"] = list(self.pacing_notes)
        wps = s.waypoints
        return Trace(
            dt=self.dt, t=np.arange(steps) * self.dt, robot=cols.robot[:steps].copy(), humans=humans,
            human_names=[h.name for h in self.humans], group_ids=[int(h.group_id) for h in self.humans],
            human_radii=np.array([h.radius for h in self.humans], dtype=float), robot_radius=float(s.robot[0].radius),
            node_names=list(NODE_NAMES), action=cols.action[:steps].copy(), succeeded=cols.succeeded[:steps].copy(),
            human_gesture=cols.gesture[:steps].copy(), robot_gesture=cols.robot_gesture[:steps].copy(),
            behavior_state=cols.behavior[:steps].copy(), robot_goal=(float(wps[-1].real), float(wps[-1].imag)),
            robot_waypoints=[(float(w.real), float(w.imag)) for w in wps],
            end_reason=END_REASONS.get(int(s.clock[0].end), "timeout"), meta=meta)
