"""Human agents: their state arrays (one row per agent, complex numbers for 2D vectors) and the goal
queue with HuNavSim's semantics (reference §7)."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from socnavgen.bodies import PERSON_GOAL_RADIUS, PERSON_GOAL_SLACK, PERSON_MAX_SPEED, PERSON_RADIUS


@dataclass
class HumanSpec:
    """Everything needed to create one simulated human (world coordinates)."""

    name: str
    start: tuple[float, float]
    goals: list[tuple[float, float]]
    yaw: float = 0.0
    group_id: int = -1
    radius: float = PERSON_RADIUS
    max_vel: float = PERSON_MAX_SPEED
    goal_radius: float = PERSON_GOAL_RADIUS
    cyclic: bool = False
    interaction_point: tuple[float, float] | None = None
    path_nodes: list[str] = field(default_factory=list)


class GoalQueue:
    """The manager's goal list of one agent: all goals share the agent's goal radius."""

    __slots__ = ("goals", "radius", "cyclic")

    def __init__(self, goals: list[complex], radius: float, cyclic: bool) -> None:
        self.goals = list(goals)
        self.radius = float(radius)
        self.cyclic = bool(cyclic)

    def __len__(self) -> int:
        return len(self.goals)

    @property
    def front(self) -> complex | None:
        return self.goals[0] if self.goals else None

    def update_goal(self) -> None:
        """UpdateGoal (fork rule): pop the front unless it is the only goal; re-append it if cyclic."""
        if not self.goals:
            return
        g = self.goals[0]
        if len(self.goals) != 1:
            self.goals.pop(0)
        if self.cyclic:
            self.goals.append(g)

    def consume(self) -> None:
        """SFM-step goal consumption: the front goal was reached inside its radius; pop it (append if cyclic)."""
        if self.goals:
            g = self.goals.pop(0)
            if self.cyclic:
                self.goals.append(g)

    def reached(self, pos: complex, slack: float = PERSON_GOAL_SLACK) -> bool:
        """IsGoalReached: non-empty and within radius + slack of the front goal."""
        return bool(self.goals) and abs(self.goals[0] - pos) <= self.radius + slack


class Crowd:
    """State of all humans. Vectors are complex (x + iy) so the force code needs fewer numpy calls."""

    def __init__(self, specs: list[HumanSpec]) -> None:
        n = len(specs)
        self.n = n
        self.specs = specs
        self.names = [s.name for s in specs]
        # packed rows (see sim.kernels): the named arrays are views, always updated in place
        self.cs = np.zeros((3, n), dtype=complex)
        self.fs = np.zeros((4, n))
        self.pos, self.vel, self.goal = self.cs[0], self.cs[1], self.cs[2]
        self.yaw, self.radius, self.goal_radius, self.omega = self.fs[0], self.fs[1], self.fs[2], self.fs[3]
        self.pos[:] = [complex(*s.start) for s in specs]
        self.yaw[:] = [s.yaw for s in specs]
        self.radius[:] = [s.radius for s in specs]
        self.goal_radius[:] = [s.goal_radius for s in specs]
        self.max_vel = np.array([s.max_vel for s in specs], dtype=float)
        self.group = np.array([s.group_id for s in specs], dtype=np.int64)
        self.queues = [GoalQueue([complex(*g) for g in s.goals], s.goal_radius, s.cyclic) for s in specs]
        self.has_goal = np.zeros(n, dtype=bool)
        for i in range(n):
            self.refresh_goal(i)
        # per-agent scalars the behavior trees read and write (Python lists: cheap scalar access)
        self.gesture = [0] * n
        self.behavior_state = [0] * n
        self.paused = [False] * n
        self.pace = self.max_vel.tolist()  # walking speed RegularNav asks for (the throttle slows walkers down)

    def refresh_goal(self, i: int) -> None:
        """Mirror the front of agent i's queue into the goal arrays after the queue changed."""
        front = self.queues[i].front
        self.has_goal[i] = front is not None
        self.goal[i] = front if front is not None else self.pos[i]

    def done(self, i: int, speed_eps: float = 0.05) -> bool:
        """Finished its walk: no goal left, or only its last goal and standing within reach of it."""
        q = self.queues[i]
        if q.cyclic and q.goals:
            return False
        if len(q) > 1:
            return False
        return (not q.goals or q.reached(self.pos[i])) and abs(self.vel[i]) < speed_eps
