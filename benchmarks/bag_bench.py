"""How long a ROS 2 bag of a 60 s episode takes to write (`simulate --bag`) and to read back into a Trace
(`verify --bag`): the warehouse, dt 0.05 s (1,200 steps), 1 / 5 / 20 humans walking the robot's path backwards,
every topic written (agent markers at 20 Hz); and a 1 kHz recording, the rate of HuNavSim's Gazebo wrapper
(60,000 human states, read and resampled to 0.05 s).

    python benchmarks/bag_bench.py
"""

from __future__ import annotations

import tempfile
import time
from pathlib import Path

import numpy as np

from socnavgen.bag import BagReadOptions, BagWriteOptions, bag_to_trace, write_bag
from socnavgen.location import load_location
from socnavgen.run import HumanPlan, PathPlan
from socnavgen.sim.trace import Trace

WAREHOUSE = Path(__file__).resolve().parents[1] / "examples" / "locations" / "warehouse"


def episode(location, n_humans: int, steps: int, dt: float) -> tuple[Trace, PathPlan]:  # noqa: ANN001
    nodes = location.scene_graph.node_ids()
    path = [nodes[0], nodes[-1]]
    t = np.arange(steps) * dt
    start, end = np.array(location.node_world(path[0])), np.array(location.node_world(path[1]))
    xy = start + (end - start) * (t / t[-1])[:, None]
    vel = np.gradient(xy, t, axis=0)
    robot = np.concatenate([xy, np.zeros((steps, 1)), vel, np.zeros((steps, 1))], axis=1)
    humans = np.stack([np.concatenate([xy[::-1] + 0.1 * k, np.zeros((steps, 1)), -vel, np.zeros((steps, 1))],
                                      axis=1) for k in range(n_humans)], axis=1)
    names = [f"human{k + 1}" for k in range(n_humans)]
    trace = Trace(dt=dt, t=t, robot=robot, humans=humans, human_names=names, group_ids=[-1] * n_humans,
                  human_radii=np.full(n_humans, 0.4), robot_radius=0.35, node_names=["RegularNav"],
                  action=np.zeros((steps, n_humans), np.int16), succeeded=np.zeros((steps, n_humans), np.int64),
                  human_gesture=np.zeros((steps, n_humans), np.int8), robot_gesture=np.zeros(steps, np.int8),
                  behavior_state=np.zeros((steps, n_humans), np.int8), robot_goal=tuple(end),
                  robot_waypoints=[tuple(start), tuple(end)], end_reason="robot_goal")
    plan = PathPlan(robot=path, humans=[HumanPlan(name=n, path=path[::-1]) for n in names])
    return trace, plan


def row(location, n_humans: int, steps: int, dt: float, tmp: Path, label: str) -> tuple[str, ...]:  # noqa: ANN001
    trace, plan = episode(location, n_humans, steps, dt)
    out = tmp / f"bag_{n_humans}_{steps}"
    markers_every = max(1, round(0.05 / dt))  # agent markers at 20 Hz
    t0 = time.perf_counter()
    mcap = write_bag(trace, out, location=location, plan=plan, options=BagWriteOptions(markers_every=markers_every))
    wrote = time.perf_counter() - t0
    t0 = time.perf_counter()
    back = bag_to_trace(out, plan, location, BagReadOptions(dt=0.05)).trace
    read = time.perf_counter() - t0
    return (label, str(n_humans), f"{wrote:.2f} s", f"{read:.2f} s", f"{mcap.stat().st_size / 1e6:.1f} MB",
            str(back.steps))


def main() -> None:
    location = load_location(WAREHOUSE)
    with tempfile.TemporaryDirectory() as tmp:
        rows = [row(location, n, 1200, 0.05, Path(tmp), "60 s at 20 Hz") for n in (1, 5, 20)]
        rows.append(row(location, 5, 60_000, 0.001, Path(tmp), "60 s at 1 kHz"))
    header = ("episode", "humans", "write", "read + resample", "bag size", "trace steps")
    widths = [max(len(r[i]) for r in [header, *rows]) for i in range(len(header))]
    for r in [header, *rows]:
        print("  ".join(c.ljust(w) for c, w in zip(r, widths, strict=True)))


if __name__ == "__main__":
    main()
