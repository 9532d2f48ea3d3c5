"""A Gymnasium environment over a run folder, a list of them, or a campaign's scenarios, so learned policies
train and are evaluated on the very scenarios the campaigns run.

Observation (Dict):
  robot        (5,)  x, y, yaw, vx, vy in the world frame (m, rad, m/s)
  goal         (2,)  goal - robot position (m)
  people       (K,5) the K nearest people: dx, dy (relative to the robot), vx, vy, gesture code; zero padded
  people_mask  (K,)  1 where a row of `people` is a real person
  cue          int   the gesture the scenario's script would make now (0 = none; codes of ROBOT_GESTURES)
Action (Dict):
  velocity     (2,)  vx, vy in m/s, clipped to the policy's max speed
  gesture      int   robot gesture code (ROBOT_GESTURES) shown this step
Reward: metres gained toward the goal, -1 per step in contact with a person, +10 on reaching the goal,
-0.01 per step. Terminated at the goal, truncated at the scenario's timeout."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np
from gymnasium import spaces

from socnavgen.bt.library import ROBOT_GESTURES
from socnavgen.campaign.episode import WorkerCache
from socnavgen.sim import Observation, RobotAction

BOUND = 1e4
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
                 timeout: float = 60.0, throttle: bool = True, max_speed: float = 1.0) -> None:
        """`scenarios`: a run folder, a list of run folders, or a campaign output folder (its scenarios.json)."""
        super().__init__()
        if isinstance(scenarios, str | Path) and (Path(scenarios) / "scenarios.json").is_file():
            listed = json.loads((Path(scenarios) / "scenarios.json").read_text())["scenarios"]
            self.scenarios = [(s["run_dir"], s["location_dir"]) for s in listed]
        else:
            runs = [scenarios] if isinstance(scenarios, str | Path) else list(scenarios)
            self.scenarios = _locations([Path(r) for r in runs])
        if not self.scenarios:
            raise ValueError("no scenarios")
        self.max_people, self.dt, self.timeout, self.throttle = max_people, dt, timeout, throttle
        self.max_speed = max_speed
        self.cache = WorkerCache()
        k, g = max_people, len(ROBOT_GESTURES)
        self.observation_space = spaces.Dict({
            "robot": spaces.Box(-BOUND, BOUND, (5,), np.float32),
            "goal": spaces.Box(-BOUND, BOUND, (2,), np.float32),
            "people": spaces.Box(-BOUND, BOUND, (k, 5), np.float32),
            "people_mask": spaces.MultiBinary(k),
            "cue": spaces.Discrete(g),
        })
        self.action_space = spaces.Dict({
            "velocity": spaces.Box(-max_speed, max_speed, (2,), np.float32),
            "gesture": spaces.Discrete(g),
        })
        self.sim: Any = None
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
                                                                                   seed=sim_seed),
                                   ThrottleConfig(enabled=self.throttle), location=location, world=world)
        self._dist = self._goal_distance()
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
        return {"robot": np.array([r.real, r.imag, obs.yaw, v.real, v.imag], dtype=np.float32).clip(-BOUND, BOUND),
                "goal": np.array([goal.real, goal.imag], dtype=np.float32).clip(-BOUND, BOUND),
                "people": people.clip(-BOUND, BOUND), "people_mask": mask, "cue": obs.scripted_gesture}

    def _checked(self, action: Any) -> RobotAction:
        """The env's action as a RobotAction; ValueError naming what is wrong when it is not in the action
        space (a velocity of another shape, a gesture outside the Discrete space, ...)."""
        if not isinstance(action, dict) or set(action) != {"velocity", "gesture"}:
            raise ValueError(f"an action is a dict with keys 'velocity' and 'gesture', got {str(action)[:80]}")
        try:
            v = np.asarray(action["velocity"], dtype=float)
        except (TypeError, ValueError):
            raise ValueError(f"action['velocity'] must be 2 numbers, got {str(action['velocity'])[:80]}") from None
        if v.shape != (2,) or not np.isfinite(v).all():
            raise ValueError(f"action['velocity'] must be 2 finite numbers (vx, vy), got shape {v.shape}: "
                             f"{str(action['velocity'])[:80]}")
        gesture = action["gesture"]
        if isinstance(gesture, np.ndarray) and gesture.shape == ():
            gesture = gesture.item()
        codes = self.action_space["gesture"].n
        if isinstance(gesture, bool) or not isinstance(gesture, int | np.integer) or not 0 <= int(gesture) < codes:
            raise ValueError(f"action['gesture'] must be a code 0..{codes - 1} (ROBOT_GESTURES), got {str(gesture)[:40]}")
        v = np.clip(v, -self.max_speed, self.max_speed)
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
        terminated = dist <= sim.config.goal_tolerance
        if terminated:
            reward += GOAL_REWARD
        truncated = not terminated and sim.t >= self.timeout - 1e-9
        return self._observation(), float(reward), bool(terminated), bool(truncated), {"contact": contact,
                                                                                        "t": sim.t}
