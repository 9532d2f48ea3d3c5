"""The simulation trace: per step poses, velocities, BT activity and gestures, stored columnar
(compressed .npz) so metrics, plots, animation and the verifier read one format."""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from socnavgen.safeio import atomic_write_bytes

# Columns of `robot` and `humans` state arrays.
X, Y, YAW, VX, VY, OMEGA = range(6)
STATE_COLUMNS = ("x", "y", "yaw", "vx", "vy", "omega")


@dataclass
class Trace:
    dt: float
    t: np.ndarray  # (T,) seconds
    robot: np.ndarray  # (T, 6) x, y, yaw, vx, vy, omega (world frame)
    humans: np.ndarray  # (T, H, 6)
    human_names: list[str]  # human1..humanH (agent id = index)
    group_ids: list[int]  # (H,)
    human_radii: np.ndarray  # (H,)
    robot_radius: float
    node_names: list[str]  # library leaf names indexed by `action` and the bits of `succeeded`
    action: np.ndarray  # (T, H) int16: index into node_names of the action executed this step, -1 none
    succeeded: np.ndarray  # (T, H) int64 bitmask over node_names: leaves that returned SUCCESS this step
    human_gesture: np.ndarray  # (T, H) int8
    robot_gesture: np.ndarray  # (T,) int8
    behavior_state: np.ndarray  # (T, H) int8 (0 regular, 1 robot-related, 2 give way)
    robot_goal: tuple[float, float] | None = None
    robot_waypoints: list[tuple[float, float]] = field(default_factory=list)
    end_reason: str = ""
    meta: dict = field(default_factory=dict)

    @property
    def steps(self) -> int:
        return int(self.t.shape[0])

    def node_index(self, name: str) -> int:
        return self.node_names.index(name)

    def executed(self, human: int, name: str) -> np.ndarray:
        """(T,) bool: steps on which human executed action `name`."""
        if name not in self.node_names:
            return np.zeros(self.steps, dtype=bool)
        return self.action[:, human] == self.node_index(name)

    def fired(self, human: int, name: str) -> np.ndarray:
        """(T,) bool: steps on which leaf `name` returned SUCCESS for this human."""
        if name not in self.node_names:
            return np.zeros(self.steps, dtype=bool)
        bit = np.int64(1) << np.int64(self.node_index(name))
        return (self.succeeded[:, human] & bit) != 0

    def save(self, path: Path) -> None:
        import io

        meta = {
            "dt": self.dt, "human_names": self.human_names, "group_ids": self.group_ids,
            "robot_radius": self.robot_radius, "node_names": self.node_names,
            "robot_goal": self.robot_goal, "robot_waypoints": self.robot_waypoints,
            "end_reason": self.end_reason, "meta": self.meta,
        }
        buf = io.BytesIO()
        np.savez_compressed(
            buf, t=self.t, robot=self.robot, humans=self.humans, human_radii=self.human_radii,
            action=self.action, succeeded=self.succeeded, human_gesture=self.human_gesture,
            robot_gesture=self.robot_gesture, behavior_state=self.behavior_state,
            meta=np.frombuffer(json.dumps(meta).encode(), dtype=np.uint8))
        atomic_write_bytes(Path(path), buf.getvalue())

    @classmethod
    def load(cls, path: Path) -> Trace:
        with np.load(Path(path), allow_pickle=False) as data:
            meta = json.loads(bytes(data["meta"]).decode())
            goal = meta["robot_goal"]
            return cls(
                dt=meta["dt"], t=data["t"], robot=data["robot"], humans=data["humans"],
                human_names=meta["human_names"], group_ids=meta["group_ids"], human_radii=data["human_radii"],
                robot_radius=meta["robot_radius"], node_names=meta["node_names"], action=data["action"],
                succeeded=data["succeeded"], human_gesture=data["human_gesture"],
                robot_gesture=data["robot_gesture"], behavior_state=data["behavior_state"],
                robot_goal=tuple(goal) if goal else None,
                robot_waypoints=[tuple(w) for w in meta["robot_waypoints"]],
                end_reason=meta["end_reason"], meta=meta["meta"])
