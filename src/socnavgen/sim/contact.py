"""THE definition of robot-human distance, gap and collision, used by the `simulate` summary,
metrics.json (`collisions`, `minimum_distance_to_people`) and the verifier, so that one run shows one
number everywhere.

- centre distance: Euclidean distance between the robot's and a human's centres (m);
- gap: centre distance minus both radii (surface to surface; negative when the discs overlap);
- collision: a step on which the robot's disc overlaps some human's disc by more than
  OVERLAP_TOLERANCE (1 cm, so a robot that stops exactly touching a person is not a collision);
  counted in steps (every step of the trace, never a sampled subset).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from socnavgen.sim.trace import Trace
from socnavgen.text import count

OVERLAP_TOLERANCE = 0.01  # m: discs overlapping by more than this are a collision


def lengths(v: np.ndarray) -> np.ndarray:
    """Lengths of (..., 2) vectors: sqrt(x*x + y*y), bit for bit what np.linalg.norm(v, axis=-1) computes
    (it squares, adds the two squares, takes the root), without its temporaries."""
    x, y = v[..., 0], v[..., 1]
    return np.sqrt(x * x + y * y)


def centre_distances(robot_xy: np.ndarray, humans_xy: np.ndarray) -> np.ndarray:
    """(T, H) centre distances from (T, 2) robot and (T, H, 2) human positions: sqrt(dx*dx + dy*dy) per
    component, the very operations np.linalg.norm(humans - robot, axis=-1) performs, without its (T, H, 2)
    temporaries."""
    robot_xy = np.asarray(robot_xy, dtype=float)
    humans_xy = np.asarray(humans_xy, dtype=float)
    dx = humans_xy[..., 0] - robot_xy[:, None, 0]
    dy = humans_xy[..., 1] - robot_xy[:, None, 1]
    return np.sqrt(dx * dx + dy * dy)


def gaps_from(robot_xy: np.ndarray, humans_xy: np.ndarray, robot_radius: float,
              human_radii: np.ndarray) -> np.ndarray:
    """(T, H) surface gaps (negative = overlap) from positions and radii."""
    radii = float(robot_radius) + np.asarray(human_radii, dtype=float).reshape(1, -1)
    return centre_distances(robot_xy, humans_xy) - radii


def trace_distances(trace: Trace) -> np.ndarray:
    """(T, H) robot-human centre distances of a trace."""
    return centre_distances(trace.robot[:, :2], trace.humans[:, :, :2])


def trace_gaps(trace: Trace) -> np.ndarray:
    """(T, H) robot-human surface gaps of a trace."""
    return gaps_from(trace.robot[:, :2], trace.humans[:, :, :2], trace.robot_radius, trace.human_radii)


def overlapping(gaps: np.ndarray) -> np.ndarray:
    """Boolean mask, same shape as `gaps`: which (step, human) pairs collide."""
    return np.asarray(gaps) < -OVERLAP_TOLERANCE


@dataclass(frozen=True)
class ContactSummary:
    """Everything a report says about contacts between the robot and people, computed once."""

    collision_steps: int  # steps on which the robot overlaps at least one human
    collision_seconds: float
    first_collision_time: float | None
    first_collision_human: str | None
    worst_overlap: float  # m, >= 0 (0 when nobody overlapped)
    min_gap: float | None  # m, closest surface gap over the run (None without humans)
    min_gap_time: float | None
    min_gap_human: str | None
    steps_per_human: dict[str, int]

    @property
    def collided(self) -> bool:
        return self.collision_steps > 0

    def describe(self) -> str:
        """One line for summaries: the closest gap and, if any, the collisions."""
        if self.min_gap is None:
            return "no humans"
        text = f"closest gap {self.min_gap:.2f} m to {self.min_gap_human} at t={self.min_gap_time:.1f} s"
        if self.collided:
            text += (f"; {count(self.collision_steps, 'step')} with a collision ({self.collision_seconds:.1f} s), first with "
                     f"{self.first_collision_human} at t={self.first_collision_time:.1f} s, worst overlap "
                     f"{self.worst_overlap:.2f} m")
        return text


def collision_steps(gaps: np.ndarray) -> int:
    """How many steps of (T, H) `gaps` have a collision."""
    return int(np.count_nonzero(overlapping(gaps).any(axis=1)))


def summarize(trace: Trace, gaps: np.ndarray | None = None) -> ContactSummary:
    """Contacts of a whole trace (every step). `gaps`: trace_gaps(trace), when the caller has it already."""
    h = trace.humans.shape[1] if trace.humans.ndim == 3 else 0
    if trace.steps == 0 or h == 0:
        return ContactSummary(0, 0.0, None, None, 0.0, None, None, None, {})
    gaps = trace_gaps(trace) if gaps is None else gaps
    hits = overlapping(gaps)
    per_step = hits.any(axis=1)
    steps = int(per_step.sum())
    k, j = np.unravel_index(int(np.argmin(gaps)), gaps.shape)
    first_t = first_h = None
    if steps:
        f = int(np.argmax(per_step))
        first_t = float(trace.t[f])
        first_h = trace.human_names[int(np.argmin(gaps[f]))]
    return ContactSummary(
        collision_steps=steps, collision_seconds=round(steps * float(trace.dt), 6), first_collision_time=first_t,
        first_collision_human=first_h, worst_overlap=float(max(0.0, -gaps.min())),
        min_gap=float(gaps[k, j]), min_gap_time=float(trace.t[k]), min_gap_human=trace.human_names[j],
        steps_per_human={n: int(hits[:, i].sum()) for i, n in enumerate(trace.human_names)})
