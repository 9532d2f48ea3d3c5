"""THE definition of robot-human distance, gap and contact, used by the `simulate` summary, metrics.json
(`collisions`, `success`, HuNavSim's `robot_on_person_collision` / `person_on_robot_collision`,
`minimum_distance_to_people`) and the verifier (`no_collision`), so that one run shows one number everywhere.

- centre distance: Euclidean distance between the robot's and a human's centres (m);
- gap: centre distance minus both radii (surface to surface; negative when the discs overlap);
- contact: a (step, human) pair whose gap is at most bodies.CONTACT_MARGIN (5 cm): the bodies touch or
  nearly touch. A step with a contact counts as a collision step, on every step of the trace (never a
  sampled subset). A robot that stops 2 cm from a person has touched them; one that keeps 6 cm has not.
- intimate space: how long the closest gap was under bodies.INTIMATE_SPACE (Hall's intimate zone, the
  evaluator's `intimate_space_intrusions` threshold), reported beside the contacts.

`overlapping` is the physics' question (do two discs interpenetrate by more than 1 cm?), asked by the
simulator's own tests; it is not contact and no report counts it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from socnavgen.bodies import CONTACT_MARGIN, INTIMATE_SPACE
from socnavgen.sim.trace import Trace
from socnavgen.text import count

OVERLAP_TOLERANCE = 0.01  # m: discs overlapping by more than this interpenetrate (physics tests only)


def lengths(v: np.ndarray) -> np.ndarray:
    """Lengths of (..., 2) vectors: sqrt(x*x + y*y), bit for bit what np.linalg.norm(v, axis=-1) computes
    (it squares, adds the two squares, takes the root), without its temporaries."""
    x, y = v[..., 0], v[..., 1]
    return np.sqrt(x * x + y * y)


def row_min(a: np.ndarray) -> np.ndarray:
    """a.min(axis=1) of a (T, H) array: the same minimum ufunc, taken column after column (numpy reduces a
    short last axis row by row, ~10x slower for a few people)."""
    if a.ndim != 2 or not 0 < a.shape[1] <= 32:
        return a.min(axis=1)
    out = a[:, 0].copy()
    for k in range(1, a.shape[1]):
        np.minimum(out, a[:, k], out=out)
    return out


def row_any(a: np.ndarray) -> np.ndarray:
    """a.any(axis=1) of a (T, H) bool array, column after column (see row_min)."""
    if a.ndim != 2 or not 0 < a.shape[1] <= 32 or a.dtype != bool:
        return np.asarray(a.any(axis=1))
    out = a[:, 0].copy()
    for k in range(1, a.shape[1]):
        out |= a[:, k]
    return out


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


def in_contact(gaps: np.ndarray) -> np.ndarray:
    """Boolean mask, same shape as `gaps`: which (step, human) pairs are in contact (gap <= CONTACT_MARGIN)."""
    return np.asarray(gaps) <= CONTACT_MARGIN


def overlapping(gaps: np.ndarray) -> np.ndarray:
    """Boolean mask: which (step, human) discs interpenetrate by more than OVERLAP_TOLERANCE (physics, not
    contact: see the module docstring)."""
    return np.asarray(gaps) < -OVERLAP_TOLERANCE


@dataclass(frozen=True)
class ContactSummary:
    """Everything a report says about contacts between the robot and people, computed once."""

    collision_steps: int  # steps on which the robot is in contact with at least one human
    collision_seconds: float
    first_collision_time: float | None
    first_collision_human: str | None
    worst_overlap: float  # m, >= 0 (0 when no discs overlapped)
    min_gap: float | None  # m, closest surface gap over the run (None without humans)
    min_gap_time: float | None
    min_gap_human: str | None
    steps_per_human: dict[str, int]  # contact steps per human
    intimate_seconds: float = 0.0  # s with the closest gap under INTIMATE_SPACE

    @property
    def collided(self) -> bool:
        return self.collision_steps > 0

    def describe(self) -> str:
        """One line for summaries: the closest gap, the time in intimate space and, if any, the contacts."""
        if self.min_gap is None:
            return "no humans"
        text = f"closest gap {self.min_gap:.2f} m to {self.min_gap_human} at t={self.min_gap_time:.1f} s"
        if self.intimate_seconds > 0:
            text += f"; {self.intimate_seconds:.1f} s within someone's intimate space (gap < {INTIMATE_SPACE:g} m)"
        if self.collided:
            text += (f"; {count(self.collision_steps, 'step')} in contact (gap <= {CONTACT_MARGIN:g} m, "
                     f"{self.collision_seconds:.1f} s), first with {self.first_collision_human} at "
                     f"t={self.first_collision_time:.1f} s")
            if self.worst_overlap > 0:
                text += f", worst overlap {self.worst_overlap:.2f} m"
        return text


def collision_steps(gaps: np.ndarray) -> int:
    """How many steps of (T, H) `gaps` have a contact."""
    return int(np.count_nonzero(row_any(in_contact(gaps))))


def summarize(trace: Trace, gaps: np.ndarray | None = None) -> ContactSummary:
    """Contacts of a whole trace (every step). `gaps`: trace_gaps(trace), when the caller has it already."""
    h = trace.humans.shape[1] if trace.humans.ndim == 3 else 0
    if trace.steps == 0 or h == 0:
        return ContactSummary(0, 0.0, None, None, 0.0, None, None, None, {})
    gaps = trace_gaps(trace) if gaps is None else gaps
    hits = in_contact(gaps)
    per_step = row_any(hits)
    steps = int(per_step.sum())
    closest = row_min(gaps)
    k, j = np.unravel_index(int(np.argmin(gaps)), gaps.shape)
    first_t = first_h = None
    if steps:
        f = int(np.argmax(per_step))
        first_t = float(trace.t[f])
        first_h = trace.human_names[int(np.argmin(gaps[f]))]
    dt = float(trace.dt)
    return ContactSummary(
        collision_steps=steps, collision_seconds=round(steps * dt, 6), first_collision_time=first_t,
        first_collision_human=first_h, worst_overlap=float(max(0.0, -gaps.min())),
        min_gap=float(gaps[k, j]), min_gap_time=float(trace.t[k]), min_gap_human=trace.human_names[j],
        steps_per_human=dict(zip(trace.human_names, np.count_nonzero(hits, axis=0).tolist(), strict=True)),
        intimate_seconds=round(int(np.count_nonzero(closest < INTIMATE_SPACE)) * dt, 6))


def people_gaps(trace: Trace) -> tuple[np.ndarray, list[tuple[int, int]]]:
    """(T, P) person-person surface gaps of a trace, one column per pair (i < j) listed in the second value:
    the same gap as the robot's (centre distance minus both radii), so `in_contact` is THE contact of two
    people too (bodies.CONTACT_MARGIN)."""
    h = trace.humans.shape[1] if trace.humans.ndim == 3 else 0
    pairs = [(i, j) for i in range(h) for j in range(i + 1, h)]
    if not pairs:
        return np.zeros((trace.steps, 0)), pairs
    xy, radii = trace.humans[:, :, :2], np.asarray(trace.human_radii, dtype=float)
    a, b = np.array([p[0] for p in pairs]), np.array([p[1] for p in pairs])
    return lengths(xy[:, a] - xy[:, b]) - (radii[a] + radii[b])[None, :], pairs
