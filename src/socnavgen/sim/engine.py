"""The simulation loop: fixed time step, one tree tick per human per step, one vectorised social-force
step for everyone who walks, the robot plugin, scripted gestures, interaction throttling, and the trace.

Per step (reference §1.1, simplified to one process):
1. interaction holds are updated; every tree is ticked once, in agent-id order, on the current snapshot
   (distances to the robot and environment forces were computed for it at the end of the last step);
   actions only set motion commands;
2. the spec's script cues are updated; the robot plugin acts on the same snapshot (a move into a wall is
   refused);
3. one social-force step for every walking human (desired force toward its command target + social incl.
   the robot + obstacle + group forces); humans that did not walk report zero velocity (as in Gazebo);
   goals reached inside their radius are consumed; then the environment forces for the new state;
4. bodies that overlap are separated (humans never walk into the robot or each other);
5. the robot's gesture comes from the policy, the spec's script cues or the plan's rules; the new state
   is recorded.
Deterministic: the only randomness (spawn offsets) comes from a seeded numpy Generator.
Simulation.run() hands the whole episode to sim.compiled (one numba call) when it can; step() here is the
reference it is tested against, and the path for a robot policy of the user's.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from socnavgen.bodies import ROBOT_GOAL_TOLERANCE, ROBOT_RADIUS
from socnavgen.bt.library import leaf_nodes
from socnavgen.bt.tree import BTDocument
from socnavgen.errors import ValidationFailed
from socnavgen.sim import (
    kernels,
    nodes_hunav2,  # noqa: F401,E402 - registers the HuNavSim 2.x nodes (hunav2 exports)
)
from socnavgen.sim.agents import Crowd, HumanSpec
from socnavgen.sim.bt_build import build_tree
from socnavgen.sim.bt_runtime import BehaviorTree
from socnavgen.sim.gestures import CueState, RobotScriptRunner, ScriptedGestures
from socnavgen.sim.interaction import InteractionThrottle
from socnavgen.sim.nodes import IMPLEMENTATIONS
from socnavgen.sim.robot import Observation, RobotAction, RobotPolicy
from socnavgen.sim.sfm import Groups, SFMParams, desired_forces, integrate, obstacle_forces, social_forces
from socnavgen.sim.trace import Trace
from socnavgen.sim.world import World

NODE_NAMES = [n.name for n in leaf_nodes()]
NODE_INDEX = {name: k for k, name in enumerate(NODE_NAMES)}
CONTACT_SLACK = 0.005  # m: bodies are kept at least this far apart by the contact step


@dataclass
class SimConfig:
    dt: float = 0.05
    timeout: float = 120.0
    seed: int = 0
    sfm: SFMParams = field(default_factory=SFMParams)
    robot_radius: float = ROBOT_RADIUS
    goal_tolerance: float = ROBOT_GOAL_TOLERANCE
    idle_end: float = 10.0  # end when every human is done and the robot has not moved for this long


def _wrap(a: np.ndarray) -> np.ndarray:
    return (a + np.pi) % (2 * np.pi) - np.pi


class Simulation:
    def __init__(self, world: World, humans: list[HumanSpec], trees: list[str | BTDocument],
                 robot_path: list[tuple[float, float]], policy: RobotPolicy, config: SimConfig | None = None,
                 gestures: ScriptedGestures | None = None, throttle: InteractionThrottle | None = None,
                 tree_names: list[str] | None = None, base_dir: Path | None = None, meta: dict | None = None,
                 use_kernels: bool | None = None, script: RobotScriptRunner | None = None,
                 program: tuple | None = None) -> None:
        """`program`: these trees already built and lowered for the compiled run (compiled.lower.program_of,
        kept per scenario by load_simulation): the Python trees are then built only if the reference needs them."""
        if len(trees) != len(humans):
            raise ValueError("one tree per human")
        self.config = config or SimConfig()
        self.dt = float(self.config.dt)
        self.params = self.config.sfm
        self.world = world
        self.crowd = Crowd(humans)
        self.groups = Groups(self.crowd.group)
        self.policy = policy
        self.gestures = gestures
        self.throttle = throttle
        self.meta = dict(meta or {})
        n = self.crowd.n
        # robot
        self.robot_waypoints = np.array([complex(*p) for p in robot_path], dtype=complex)
        if len(self.robot_waypoints) == 0:
            raise ValueError("the robot needs at least one waypoint")
        self.robot_pos = complex(self.robot_waypoints[0])
        self._robot_goal = complex(self.robot_waypoints[-1])
        self.robot_vel = 0j
        first_leg = self.robot_waypoints[1] - self.robot_pos if len(self.robot_waypoints) > 1 else 1 + 0j
        self.robot_yaw = math.atan2(first_leg.imag, first_leg.real) if abs(first_leg) > 0 else 0.0
        self._robot_dir = complex(math.cos(self.robot_yaw), math.sin(self.robot_yaw))
        self.robot_omega = 0.0
        self.robot_radius = float(self.config.robot_radius)
        self.robot_gesture = 0
        self.robot_said: set[int] = set()  # every gesture the robot has shown so far (RobotSaid)
        self.script = script
        self.cues = script.state if script is not None else CueState()
        self.t = 0.0
        self.obs = Observation(self)
        # per-step scratch read by the nodes
        self.robot_dist: list[float] = [0.0] * n
        self._in_sight: dict[int, bool] = {}
        self._pairs: list[tuple[int, int]] | None = None
        self.give_way: list[dict | None] = [None] * n
        self.face_robot_after_step: dict[int, float] = {}
        self.tick_action = [-1] * n
        self.tick_action_motion = [False] * n
        self.tick_success = [0] * n
        # motion commands, packed for the kernel (see sim.kernels); named arrays are row views
        crowd = self.crowd
        self.cc = np.zeros((3, n), dtype=complex)
        self.fc = np.zeros((4, n))
        self.bc = np.zeros((5, n), dtype=bool)
        self.cmd_target, self.cmd_extra, self.f_env = self.cc[0], self.cc[1], self.cc[2]
        self.cmd_radius, self.cmd_v0, self.cmd_yaw, self._rdist = self.fc[0], self.fc[1], self.fc[2], self.fc[3]
        self.cmd_move, self.cmd_use_goal, self.cmd_turn, self.reached = self.bc[0], self.bc[1], self.bc[2], self.bc[4]
        self.bc[3] = crowd.has_goal
        crowd.has_goal = self.bc[3]
        self._tree_sources = (list(trees), tree_names, base_dir)
        self._trees: list[BehaviorTree] | None = None
        self.program = program
        if program is None:
            self._trees = self._build_trees()  # builds (and checks) every tree now
        # compiled kernel (numba) when available; the numpy path (sim.sfm) is the reference
        self._fast = kernels.AVAILABLE if use_kernels is None else (use_kernels and kernels.AVAILABLE)
        self.compiled = self._fast  # run() in one compiled call (sim.compiled); False: step by step in Python
        prm = self.params
        self._prm = np.array([prm.k_des, prm.tau, prm.k_gaze, prm.k_coh, prm.k_rep, prm.k_obs, prm.sigma_obs,
                              prm.k_soc, prm.lam, prm.gamma, prm.n, prm.n_prime,
                              np.inf if prm.cutoff is None else prm.cutoff, world.obstacle_range,
                              1.0 if world.has_obstacles else 0.0, world.mpp])
        self._obs_table = world.obstacle_table if world.has_obstacles else np.zeros((1, 1), dtype=complex)
        self._affine = world.transform.inverse.copy()
        self._labels = np.full(n, -1, dtype=np.int64)
        self._labels[self.groups.members] = self.groups.labels
        self._sizes = self.groups.sizes.astype(float)
        self._physics(do_step=False)
        if hasattr(policy, "reset"):
            policy.reset(self.obs)

    def _build_trees(self) -> list[BehaviorTree]:
        trees, names, base_dir = self._tree_sources
        return [build_tree(tree, self, i, IMPLEMENTATIONS, NODE_INDEX, base_dir=base_dir,
                           name=(names[i] if names else f"tree of agent {i}")) for i, tree in enumerate(trees)]

    @property
    def trees(self) -> list[BehaviorTree]:
        """Every human's behavior tree, bound to this simulation (built on first use when a program was given)."""
        if self._trees is None:
            self._trees = self._build_trees()
        return self._trees

    # -- queries used by the nodes ------------------------------------------------------------
    def robot_in_sight(self, i: int) -> bool:
        """Line of sight from human i to the robot, computed at most once per human and step (the nodes ask
        only after the cheap distance test passed)."""
        seen = self._in_sight.get(i)
        if seen is None:
            seen = self._in_sight[i] = bool(self.world.line_of_sight(self.robot_pos, self.crowd.pos[i])[0])
        return seen

    def robot_direction(self) -> complex:
        """Unit vector of the robot's travel (last motion, else its initial heading)."""
        return self._robot_dir

    # -- motion commands set by the actions ---------------------------------------------------
    def command_walk_goal(self, i: int, v0: float | None = None, extra: complex = 0j) -> None:
        self.cmd_move[i] = True
        self.cmd_use_goal[i] = True
        self.cmd_v0[i] = self.crowd.max_vel[i] if v0 is None else v0
        self.cmd_extra[i] = extra
        self.cmd_turn[i] = False

    def command_walk(self, i: int, target: complex, radius: float, v0: float, real_goal: bool = False) -> None:
        self.cmd_move[i] = True
        self.cmd_use_goal[i] = False
        self.cmd_target[i] = target
        self.cmd_radius[i] = radius
        self.cmd_v0[i] = v0
        self.cmd_extra[i] = 0j
        self.cmd_turn[i] = False

    def command_turn(self, i: int, yaw: float) -> None:
        self.cmd_move[i] = False
        self.cmd_turn[i] = True
        self.cmd_yaw[i] = yaw

    def command_stand(self, i: int) -> None:
        self.cmd_move[i] = False
        self.cmd_turn[i] = False

    # -- the loop -------------------------------------------------------------------------------
    def _physics(self, do_step: bool) -> int:
        """(do_step) move the humans per their commands; then environment forces for the new state."""
        crowd = self.crowd
        if crowd.n == 0:
            return 0
        if self._fast:
            reached = kernels.advance(crowd.cs, crowd.fs, self.cc, self.fc, self.bc, self._labels, self._sizes,
                                      self._prm, self._obs_table, self._affine, self.robot_pos, self.robot_vel,
                                      self.dt, do_step)
        else:
            reached = self._numpy_step() if do_step else 0
            prm, pos = self.params, crowd.pos
            self.f_env[:] = social_forces(np.append(pos, self.robot_pos), np.append(crowd.vel, self.robot_vel),
                                          prm)[:-1]
            obs_pt, obs_ok = self.world.nearest_obstacles(pos)
            self.f_env += obstacle_forces(pos, crowd.radius, obs_pt, obs_ok, prm)
            self._rdist[:] = np.abs(self.robot_pos - pos)
        self.robot_dist = self._rdist.tolist()
        return reached

    def _numpy_step(self) -> int:
        """Reference path without numba: desired + group forces, SFM step, in place; returns #goals reached."""
        crowd, prm, dt = self.crowd, self.params, self.dt
        pos, vel = crowd.pos, crowd.vel
        move, use_goal = self.cmd_move, self.cmd_use_goal
        target = np.where(use_goal, crowd.goal, self.cmd_target)
        radius = np.where(use_goal, crowd.goal_radius, self.cmd_radius)
        has_target = np.where(use_goal, crowd.has_goal, True)
        f_des, e = desired_forces(pos, vel, target, radius, has_target, self.cmd_v0, prm)
        force = f_des + self.f_env + self.cmd_extra
        if self.groups:
            force += self.groups.forces(pos, e, crowd.radius, prm)
        new_pos, new_vel, new_yaw = integrate(pos, vel, crowd.yaw, force, self.cmd_v0, dt)
        old_yaw = crowd.yaw.copy()
        pos[:] = np.where(move, new_pos, pos)
        vel[:] = np.where(move, new_vel, 0j)
        crowd.yaw[:] = np.where(move, new_yaw, np.where(self.cmd_turn, _wrap(self.cmd_yaw), old_yaw))
        crowd.omega[:] = _wrap(crowd.yaw - old_yaw) / dt
        self.reached[:] = move & use_goal & crowd.has_goal & (np.abs(crowd.goal - pos) <= crowd.goal_radius)
        return int(self.reached.sum())

    def step(self) -> None:
        """One time step: every tree ticks on the current snapshot, the robot acts on the same snapshot,
        then everyone moves at once."""
        crowd, n, dt = self.crowd, self.crowd.n, self.dt
        if n:
            self._in_sight.clear()
            if self.throttle is not None:
                self.throttle.update(self)
            self.cmd_move[:] = False
            self.cmd_turn[:] = False
            self.tick_action = [-1] * n
            self.tick_action_motion = [False] * n
            self.tick_success = [0] * n
            self.face_robot_after_step.clear()
            for tree in self.trees:
                tree.tick(dt)
        if self.script is not None:
            self.cues = self.script.update(self)
        action = self.policy.act(self.obs)
        self._apply_robot(action)
        if n:
            before = crowd.pos.copy()
            reached = self._physics(do_step=True)
            if self._resolve_contacts(before):
                self._rdist[:] = np.abs(self.robot_pos - crowd.pos)
                self.robot_dist = self._rdist.tolist()
            if reached:
                for i in np.flatnonzero(self.reached).tolist():
                    crowd.queues[i].consume()
                    crowd.refresh_goal(i)
            for i, within in self.face_robot_after_step.items():
                d = self.robot_pos - crowd.pos[i]
                if abs(d) <= within:
                    crowd.yaw[i] = math.atan2(d.imag, d.real)
        self.t += dt
        if action.gesture is not None:
            self.robot_gesture = int(action.gesture)
        elif self.cues.say:
            self.robot_gesture = self.cues.say
        elif self.gestures is not None:
            self.robot_gesture = self.gestures.gesture(self)
        elif self.script is not None:
            self.robot_gesture = 0  # the script's phrase is over
        if self.robot_gesture:
            self.robot_said.add(self.robot_gesture)

    def _resolve_contacts(self, before: np.ndarray) -> bool:
        """Bodies do not interpenetrate (HuNavSim's agents are solid in Gazebo): a human whose own step
        took it into the robot is put back on the robot's surface (never closer than it already was, so an
        overlap the ROBOT causes stays visible as a collision); two humans that overlap are pushed apart
        along the line of their centres, the walkers taking the whole correction from someone standing.
        Corrections that would end inside a wall are dropped (between humans) or the human's step is not
        taken (into the robot). Returns whether anyone was moved. This is the reference; the compiled twin
        sim.kernels.resolve_contacts runs when numba is there."""
        crowd, rp = self.crowd, self.robot_pos
        if self._fast:
            return kernels.resolve_contacts(crowd.pos, crowd.radius, self.cmd_move, before, rp, self.robot_radius,
                                            self._robot_dir, self.world.clearance, self._affine, CONTACT_SLACK,
                                            np.empty(crowd.n, dtype=complex))
        pos, radius = crowd.pos, crowd.radius
        moved = False
        n = crowd.n
        if n >= 2:
            if self._pairs is None or len(self._pairs) != n * (n - 1) // 2:
                self._pairs = [(i, j) for i in range(n) for j in range(i + 1, n)]  # every pair once, i < j
            pl, rl = pos.tolist(), radius.tolist()  # scalar checks: a handful of people, no numpy overhead
            hits = [(i, j) for i, j in self._pairs if rl[i] + rl[j] - abs(pl[i] - pl[j]) > 1e-6]
            for i, j in hits:
                d = pos[i] - pos[j]
                unit = d / abs(d) if abs(d) > 1e-9 else complex(math.cos(0.7 * (i + 1)), math.sin(0.7 * (j + 1)))
                depth = radius[i] + radius[j] - abs(d) + 1e-4  # just apart: no state exactly on the boundary
                wi, wj = bool(self.cmd_move[i]), bool(self.cmd_move[j])
                share_i = 0.5 if wi == wj else (1.0 if wi else 0.0)
                for k, sign, share in ((i, 1.0, share_i), (j, -1.0, 1.0 - share_i)):
                    cand = pos[k] + sign * unit * depth * share
                    if share > 0 and self.world.clearance_at_point(cand) >= 0.5 * radius[k]:
                        pos[k] = cand
                        moved = True
        # last, the robot: nobody ends a step deeper into it than the robot's own move put them
        robot_r = self.robot_radius
        for i, (p_i, r_i) in enumerate(zip(pos.tolist(), radius.tolist(), strict=True)):
            reach = r_i + robot_r
            gap_new = abs(p_i - rp) - reach
            if gap_new >= CONTACT_SLACK:
                continue
            allowed = min(abs(complex(before[i]) - rp) - reach, CONTACT_SLACK)
            if gap_new < allowed - 1e-9:
                away = p_i - rp
                unit = away / abs(away) if abs(away) > 1e-9 else -self._robot_dir
                cand = rp + unit * (reach + allowed)
                if self.world.clearance_at_point(cand) < 0.5 * r_i:
                    cand = complex(before[i])  # no room beside the robot (a wall): the step is not taken
                pos[i] = cand
                moved = True
        return moved

    def _apply_robot(self, action: RobotAction) -> None:
        if not isinstance(action, RobotAction):
            raise ValidationFailed(f"the robot policy {type(self.policy).__name__} returned "
                                   f"{type(action).__name__}, not a RobotAction",
                                   hint="return socnavgen.sim.robot.RobotAction(vx, vy, gesture=None) from act()")
        v = complex(float(action.vx), float(action.vy))
        if not (math.isfinite(v.real) and math.isfinite(v.imag)):
            v = 0j
        new = self.robot_pos + v * self.dt
        # the robot cannot drive into walls: a move that ends inside one is refused
        if v != 0 and self.world.clearance_at_point(new) < 0.5 * self.robot_radius:
            v, new = 0j, self.robot_pos
        old_yaw = self.robot_yaw
        heading = getattr(self.policy, "heading", None)
        if abs(v) > 0.05:
            facing = heading if isinstance(heading, complex) and abs(heading) > 0 else v
            self.robot_yaw = math.atan2(facing.imag, facing.real)
            self._robot_dir = facing / abs(facing)
        self.robot_omega = ((self.robot_yaw - old_yaw + math.pi) % (2 * math.pi) - math.pi) / self.dt
        self.robot_pos, self.robot_vel = new, v

    @property
    def max_steps(self) -> int:
        """Steps of a run that reaches its timeout."""
        return int(math.ceil(self.config.timeout / self.dt))

    def robot_at_goal(self) -> bool:
        return abs(self._robot_goal - self.robot_pos) <= self.config.goal_tolerance

    def run(self, progress: Callable[[int, int], None] | None = None) -> Trace:
        """Run to the robot's goal, the timeout, or until nothing will change; return the trace. Compiled in
        one call (sim.compiled) when numba is there and the policy and trees have compiled twins; else, or
        when a tree fails while running (the error is then raised here), step by step in Python."""
        if self.compiled and self._fast and self.t == 0.0:
            from socnavgen.sim.compiled.episode import run_compiled

            trace = run_compiled(self, progress)
            if trace is not None:
                return trace
        cfg, crowd, n = self.config, self.crowd, self.crowd.n
        max_steps = self.max_steps
        columns = self.trace_columns(max_steps + 1)
        pos, vel, yaw, omega, action, succeeded, gesture, bstate, robot, rgest = columns

        def record(k: int) -> None:
            pos[k], vel[k], yaw[k], omega[k] = crowd.pos, crowd.vel, crowd.yaw, crowd.omega
            action[k], succeeded[k] = self.tick_action, self.tick_success
            gesture[k], bstate[k] = crowd.gesture, crowd.behavior_state
            r = self.robot_pos
            robot[k] = (r.real, r.imag, self.robot_yaw, self.robot_vel.real, self.robot_vel.imag, self.robot_omega)
            rgest[k] = self.robot_gesture

        record(0)
        reason, idle, k = "timeout", 0.0, 0
        for k in range(1, max_steps + 1):
            self.step()
            record(k)
            if progress is not None and k % 200 == 0:
                progress(k, max_steps)
            if self.robot_at_goal():
                reason = "robot_goal"
                break
            idle = idle + self.dt if abs(self.robot_vel) < 1e-3 else 0.0
            if idle >= cfg.idle_end and all(crowd.done(i) for i in range(n)):
                reason = "all_done"
                break
        if progress is not None:
            progress(max_steps, max_steps)
        self.meta.setdefault("engine", "python")
        return self.trace_from(columns, k + 1, reason)

    def trace_columns(self, rows: int) -> list[np.ndarray]:
        """Empty trace columns for `rows` steps: pos, vel, yaw, omega, action, succeeded, gesture, behavior
        state (each (rows, humans)), robot (rows, 6), robot gesture (rows,)."""
        n = self.crowd.n
        return [np.zeros((rows, n), dtype=complex), np.zeros((rows, n), dtype=complex), np.zeros((rows, n)),
                np.zeros((rows, n)), np.full((rows, n), -1, dtype=np.int16), np.zeros((rows, n), dtype=np.int64),
                np.zeros((rows, n), dtype=np.int8), np.zeros((rows, n), dtype=np.int8), np.zeros((rows, 6)),
                np.zeros(rows, dtype=np.int8)]

    def trace_from(self, columns: list[np.ndarray], steps: int, reason: str) -> Trace:
        """The Trace of the first `steps` recorded rows, with the run's meta."""
        cfg, crowd, n = self.config, self.crowd, self.crowd.n
        pos, vel, yaw, omega, action, succeeded, gesture, bstate, robot, rgest = columns
        humans = np.stack([pos.real, pos.imag, yaw, vel.real, vel.imag, omega], axis=-1)[:steps]
        meta = dict(self.meta)
        meta.update(seed=cfg.seed, timeout=cfg.timeout, robot_goal_radius=cfg.goal_tolerance,
                    kernels="numba" if self._fast else "numpy",
                    human_goals={crowd.names[i]: [list(g) for g in crowd.specs[i].goals] for i in range(n)})
        if self.script is not None:
            meta["script_cues_fired"] = [list(f) for f in self.cues.fired]
        if self.throttle is not None:
            meta["held_seconds"] = {crowd.names[i]: s * self.dt for i, s in self.throttle.paused_steps.items()}
            meta["throttle_skipped"] = self.throttle.skipped
        return Trace(
            dt=self.dt, t=np.arange(steps) * self.dt, robot=robot[:steps], humans=humans, human_names=crowd.names,
            group_ids=[int(g) for g in crowd.group], human_radii=crowd.radius.copy(),
            robot_radius=self.robot_radius, node_names=list(NODE_NAMES), action=action[:steps],
            succeeded=succeeded[:steps], human_gesture=gesture[:steps], robot_gesture=rgest[:steps],
            behavior_state=bstate[:steps], robot_goal=tuple(map(float, (self.robot_waypoints[-1].real,
                                                                        self.robot_waypoints[-1].imag))),
            robot_waypoints=[(float(w.real), float(w.imag)) for w in self.robot_waypoints],
            end_reason=reason, meta=meta)
