"""A Gymnasium environment over a run folder, a list of them, or a campaign's scenarios, so learned policies
train and are evaluated on the very scenarios the campaigns run.

Observation (Dict; world frame unless said otherwise):
  robot        (5,)  x, y, yaw, vx, vy (m, rad, m/s)
  goal         (2,)  goal - robot position (m)
  people       (K,5) the K nearest people: dx, dy (relative to the robot), vx, vy, gesture code; zero padded
  people_mask  (K,)  1 where a row of `people` is a real person
  cue          int   the gesture the scenario's script would make now (0 = none; codes of ROBOT_GESTURES)
  scan         (N,)  a 2D range scan in the robot's frame (robot.sensors.range_scan): metres to the nearest wall
                     or person along N beams, beam 0 along the robot's heading, then counter-clockwise every
                     360/N degrees; scan_range where nothing is hit (absent with scan_beams=0)
  route        (R,2) the next R points of the planner's global path (robot.sensors.route_ahead), route_spacing m
                     apart, minus the robot's position (m); the goal repeats near the end (absent with
                     route_points=0)
Action (Dict), with action="velocity" (default):
  velocity     (2,)  vx, vy in m/s (world frame), clipped to max_speed; the body tracks it (a differential-drive
                     body turns toward it)
or with action="unicycle" (a differential-drive command):
  unicycle     (2,)  forward speed (m/s, negative: backwards) clipped to max_speed, turn rate (rad/s,
                     counter-clockwise) clipped to the body's max_omega
and in both:
  gesture      int   robot gesture code (ROBOT_GESTURES) shown this step
Reward: metres gained toward the goal, -1 per step in contact with a person, +10 on reaching the goal,
-0.01 per step. Terminated at the goal (as the simulator ends a run there: a round trip's robot must have
passed near its other waypoints first), truncated at the scenario's timeout."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any, Literal

import gymnasium as gym
import numpy as np
from gymnasium import spaces

from socnavgen.bt.library import ROBOT_GESTURES
from socnavgen.campaign.episode import WorkerCache
from socnavgen.sim import Observation, RobotAction
from socnavgen.sim.robot.body import RobotBody
from socnavgen.sim.robot.route import Route
from socnavgen.sim.robot.sensors import range_scan, route_ahead

BOUND = 1e4
ACTIONS = ("velocity", "unicycle")  # the action spaces (module docstring)
GOAL_REWARD, CONTACT_PENALTY, STEP_PENALTY = 10.0, 1.0, 0.01


class _External:
    """The robot policy slot of the simulation, filled by env.step()."""

    def __init__(self) -> None:
        self.action = RobotAction(0.0, 0.0)

    def act(self, obs: Observation) -> RobotAction:  # noqa: ARG002 - the env decided already
        return self.action


def _locations(run_dirs: list[Path]) -> list[tuple[str, str]]:
    from socnavgen.run import RunFolder

    return [(str(d), str(RunFolder(d).location().root)) for d in run_dirs]


class SocNavEnv(gym.Env):
    metadata = {"render_modes": []}

    def __init__(self, scenarios: Path | str | list[Path | str], *, max_people: int = 8, dt: float = 0.05,
                 timeout: float = 60.0, throttle: bool = True, max_speed: float = 1.0, scan_beams: int = 64,
                 scan_range: float = 8.0, route_points: int = 8, route_spacing: float = 0.5,
                 action: Literal["velocity", "unicycle"] = "velocity", body: RobotBody | None = None) -> None:
        """`scenarios`: a run folder, a list of run folders, or a campaign output folder (its scenarios.json);
        `body`: the robot's kinematics and limits (default RobotBody(): differential drive)."""
        super().__init__()
        if action not in ACTIONS:
            raise ValueError(f"action {action!r}: use one of {', '.join(ACTIONS)}")
        for name, value in (("scan_beams", scan_beams), ("route_points", route_points)):
            if isinstance(value, bool) or not isinstance(value, int) or not 0 <= value <= 4096:
                raise ValueError(f"{name} = {value!r}: a whole number from 0 to 4096")
        for name, value in (("scan_range", scan_range), ("route_spacing", route_spacing)):
            if not (isinstance(value, int | float) and 0 < value < BOUND):
                raise ValueError(f"{name} = {value!r}: a positive number of metres")
        if isinstance(scenarios, str | Path) and (Path(scenarios) / "scenarios.json").is_file():
            listed = json.loads((Path(scenarios) / "scenarios.json").read_text())["scenarios"]
            self.scenarios = [(s["run_dir"], s["location_dir"]) for s in listed]
        else:
            runs = [scenarios] if isinstance(scenarios, str | Path) else list(scenarios)
            self.scenarios = _locations([Path(r) for r in runs])
        if not self.scenarios:
            raise ValueError("no scenarios")
        self.max_people, self.dt, self.timeout, self.throttle = max_people, dt, timeout, throttle
        self.max_speed, self.body, self.motion = max_speed, body or RobotBody(), action
        self.scan_beams, self.scan_range = scan_beams, float(scan_range)
        self.route_points, self.route_spacing = route_points, float(route_spacing)
        self.cache = WorkerCache()
        k, g = max_people, len(ROBOT_GESTURES)
        observed = {
            "robot": spaces.Box(-BOUND, BOUND, (5,), np.float32),
            "goal": spaces.Box(-BOUND, BOUND, (2,), np.float32),
            "people": spaces.Box(-BOUND, BOUND, (k, 5), np.float32),
            "people_mask": spaces.MultiBinary(k),
            "cue": spaces.Discrete(g),
        }
        if scan_beams:
            observed["scan"] = spaces.Box(0.0, self.scan_range, (scan_beams,), np.float32)
        if route_points:
            observed["route"] = spaces.Box(-BOUND, BOUND, (route_points, 2), np.float32)
        self.observation_space = spaces.Dict(observed)
        if action == "velocity":
            motion = spaces.Box(-max_speed, max_speed, (2,), np.float32)
        else:
            omega = self.body.max_omega
            motion = spaces.Box(np.array([-max_speed, -omega], np.float32), np.array([max_speed, omega], np.float32))
        self.action_space = spaces.Dict({action: motion, "gesture": spaces.Discrete(g)})
        self.sim: Any = None
        self.route: Route | None = None
        self.scenario_index = 0

    def reset(self, *, seed: int | None = None, options: dict | None = None) -> tuple[dict, dict]:
        from socnavgen.sim import SimConfig, ThrottleConfig, load_simulation

        super().reset(seed=seed)
        options = options or {}
        self.scenario_index = int(options.get("scenario", self.np_random.integers(len(self.scenarios))))
        run_dir, location_dir = self.scenarios[self.scenario_index]
        location, world = self.cache.location(location_dir)
        self.policy = _External()
        sim_seed = int(options.get("sim_seed", self.np_random.integers(2**31 - 1)))
        self.sim = load_simulation(self.cache.run(run_dir), self.policy, SimConfig(dt=self.dt, timeout=self.timeout,
                                                                                   seed=sim_seed, body=self.body),
                                   ThrottleConfig(enabled=self.throttle), location=location, world=world)
        self._dist = self._goal_distance()
        self.route = Route(self.sim.obs) if self.route_points else None
        return self._observation(), {"scenario": run_dir, "sim_seed": sim_seed}

    def _goal_distance(self) -> float:
        obs = self.sim.obs
        return abs(obs.waypoints_c[-1] - obs.position_c)

    def _observation(self) -> dict:
        obs = self.sim.obs
        r, v = obs.position_c, obs.velocity_c
        people = np.zeros((self.max_people, 5), dtype=np.float32)
        mask = np.zeros(self.max_people, dtype=np.int8)
        if obs.human_count:
            rel = obs.human_positions_c - r
            order = np.argsort(np.abs(rel))[: self.max_people]
            k = len(order)
            people[:k, 0], people[:k, 1] = rel[order].real, rel[order].imag
            people[:k, 2:4] = obs.human_velocities[order]
            people[:k, 4] = obs.human_gestures[order]
            mask[:k] = 1
        goal = obs.waypoints_c[-1] - r
        seen = {"robot": np.array([r.real, r.imag, obs.yaw, v.real, v.imag], dtype=np.float32).clip(-BOUND, BOUND),
                "goal": np.array([goal.real, goal.imag], dtype=np.float32).clip(-BOUND, BOUND),
                "people": people.clip(-BOUND, BOUND), "people_mask": mask, "cue": obs.scripted_gesture}
        if self.scan_beams:
            seen["scan"] = range_scan(obs.world, r, obs.yaw, self.scan_beams, self.scan_range, obs.human_positions_c,
                                      obs.human_radii)
        if self.route is not None:
            seen["route"] = self._route(r)
        return seen

    def _route(self, r: complex) -> np.ndarray:
        """The route ahead minus the robot's position, (route_points, 2) float32."""
        route, obs = self.route, self.sim.obs
        assert route is not None
        route.target(r, obs.human_positions_c, obs.human_radii)  # passes the waypoints reached
        if route.fields is None:
            ahead = np.full(self.route_points, route.goal)
        else:
            ahead = route_ahead(route.world, route.fields, route.scale, route.waypoints, route.index, r,
                                self.route_points, self.route_spacing)
        rel = ahead - r
        return np.stack([rel.real, rel.imag], axis=1).astype(np.float32).clip(-BOUND, BOUND)

    def _checked(self, action: Any) -> RobotAction:
        """The env's action as a RobotAction; ValueError naming what is wrong when it is not in the action
        space (a velocity of another shape, a gesture outside the Discrete space, ...)."""
        key = self.motion
        if not isinstance(action, dict) or set(action) != {key, "gesture"}:
            raise ValueError(f"an action is a dict with keys '{key}' and 'gesture', got {str(action)[:80]}")
        try:
            v = np.asarray(action[key], dtype=float)
        except (TypeError, ValueError):
            raise ValueError(f"action['{key}'] must be 2 numbers, got {str(action[key])[:80]}") from None
        if v.shape != (2,) or not np.isfinite(v).all():
            what = "vx, vy" if key == "velocity" else "forward speed, turn rate"
            raise ValueError(f"action['{key}'] must be 2 finite numbers ({what}), got shape {v.shape}: "
                             f"{str(action[key])[:80]}")
        gesture = action["gesture"]
        if isinstance(gesture, np.ndarray) and gesture.shape == ():
            gesture = gesture.item()
        codes = self.action_space["gesture"].n
        if isinstance(gesture, bool) or not isinstance(gesture, int | np.integer) or not 0 <= int(gesture) < codes:
            raise ValueError(f"action['gesture'] must be a code 0..{codes - 1} (ROBOT_GESTURES), got {str(gesture)[:40]}")
        box = self.action_space[key]
        v = np.clip(v, box.low, box.high)
        if key == "unicycle":
            return RobotAction.unicycle(float(v[0]), float(v[1]), gesture=int(gesture))
        return RobotAction(float(v[0]), float(v[1]), gesture=int(gesture))

    def step(self, action: dict) -> tuple[dict, float, bool, bool, dict]:
        if self.sim is None:
            raise RuntimeError("call reset() first")
        self.policy.action = self._checked(action)
        self.sim.step()
        sim = self.sim
        dist = self._goal_distance()
        obs = sim.obs
        contact = bool(obs.human_count and (np.abs(obs.human_positions_c - obs.position_c) < obs.human_radii
                                            + obs.radius).any())
        reward = (self._dist - dist) - STEP_PENALTY - (CONTACT_PENALTY if contact else 0.0)
        self._dist = dist
        terminated = sim.robot_at_goal()  # near the goal, having passed near every waypoint of a round trip
        if terminated:
            reward += GOAL_REWARD
        truncated = not terminated and sim.t >= self.timeout - 1e-9
        return self._observation(), float(reward), bool(terminated), bool(truncated), {"contact": contact,
                                                                                        "t": sim.t}
