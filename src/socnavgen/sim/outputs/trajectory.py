"""An episode's trajectories, compact: what a campaign keeps of every episode beside its row (the full trace is
~1 MB; this is ~10-30 kB), enough to plot the paths again or compute a metric of one's own.

Schema of the NPZ (numpy.load; every array little-endian, no pickled objects):

| array | shape, type | what |
|---|---|---|
| `t` | (N,) float32 | seconds since the start, resampled every 1 / hz s (the last step always kept) |
| `robot` | (N, 5) float32 | x, y (m, world frame), yaw (rad), vx, vy (m/s) |
| `humans` | (N, H, 5) float32 | the same per person, in agent order |
| `robot_gesture` | (N,) int8 | the robot's gesture code (bt.library.ROBOT_GESTURES) |
| `human_gesture` | (N, H) int8 | each person's gesture code |
| `meta` | (B,) uint8 | UTF-8 JSON: schema version, hz, dt of the simulation, human names, radii, robot radius, goal, waypoints, end reason |

Size bound: N <= hz x timeout + 1 samples (hz <= 50), so an episode's file is at most ~20 x N x (1 + H) bytes
before compression.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np

from socnavgen.sim.trace import VX, VY, YAW, Trace, X, Y, npz_bytes

SCHEMA = 1
MAX_HZ = 50.0
_COLUMNS = [X, Y, YAW, VX, VY]


def sample_steps(t: np.ndarray, hz: float) -> np.ndarray:
    """Indices of the steps kept at `hz` (the first step of each 1 / hz interval, and the last step)."""
    t = np.asarray(t, dtype=float)
    if not len(t):
        return np.arange(0)
    ticks = np.floor((t - t[0]) * hz + 1e-9).astype(np.int64)
    keep = np.flatnonzero(np.diff(ticks, prepend=-1) > 0)
    return np.unique(np.append(keep, len(t) - 1))


def trajectory_bytes(trace: Trace, hz: float = 10.0) -> bytes:
    """The NPZ file (bytes) of a trace's trajectories at `hz` samples per second."""
    if not 0 < hz <= MAX_HZ:
        raise ValueError(f"trajectory rate {hz} Hz: give a rate in (0, {MAX_HZ:g}]")
    k = sample_steps(trace.t, hz)
    meta = {"schema": SCHEMA, "hz": hz, "dt": trace.dt, "human_names": list(trace.human_names),
            "human_radii": [float(r) for r in np.asarray(trace.human_radii).ravel()],
            "robot_radius": float(trace.robot_radius), "group_ids": [int(g) for g in trace.group_ids],
            "robot_goal": list(trace.robot_goal) if trace.robot_goal is not None else None,
            "robot_waypoints": [list(w) for w in trace.robot_waypoints], "end_reason": trace.end_reason,
            "columns": ["x", "y", "yaw", "vx", "vy"]}
    return npz_bytes({
        "t": np.asarray(trace.t, dtype=np.float32)[k],
        "robot": np.asarray(trace.robot[k][:, _COLUMNS], dtype=np.float32),
        "humans": np.asarray(trace.humans[k][:, :, _COLUMNS], dtype=np.float32),
        "robot_gesture": np.asarray(trace.robot_gesture[k], dtype=np.int8),
        "human_gesture": np.asarray(trace.human_gesture[k], dtype=np.int8),
        "meta": np.frombuffer(json.dumps(meta).encode(), dtype=np.uint8)})



def read_trajectory(path: Path | str) -> dict[str, Any]:
    """The arrays of a trajectory file, `meta` decoded (no pickle: a file from elsewhere runs no code)."""
    with np.load(Path(path), allow_pickle=False) as data:
        out: dict[str, Any] = {name: data[name] for name in data.files if name != "meta"}
        out["meta"] = json.loads(bytes(data["meta"]).decode())
    return out
