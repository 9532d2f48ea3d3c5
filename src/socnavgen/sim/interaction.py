"""Interaction-point throttling, after SocRATES's scenario manager (reference §11).

A solo human walking toward its interaction node (or spawned on it) is held in place while the robot
is still far from that node on its own path, so the two meet there. Only RegularNav honours the hold,
exactly like `pause_nav` in the fork. Two release rules:
* `socrates`: the fork's rule - release once the robot's current waypoint is the interaction node (the
  robot counts a waypoint as passed within 1.5 m). With a long last leg and a fast human the encounter
  then happens well before the node.
* `eta` (default): pace the human all the way to the node from the robot's ETA there (its remaining path
  at the script's cruise speed): walk at the speed that arrives together with the robot (slow down),
  stand while that speed would be a crawl (hold, or start later), and wait at the node itself if still
  early; full speed once the robot is close to the node. So both arrive together and meet AT the node.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any


@dataclass
class ThrottleConfig:
    enabled: bool = True
    waypoint_radius: float = 1.5  # robot counts a waypoint as passed within this distance
    release_distance: float = 2.0  # m: never hold a human this close to the robot (it would stand in its way)
    rule: str = "eta"  # "eta" or "socrates"
    robot_speed: float = 0.6  # m/s, nominal robot speed for the eta rule (the script's cruise speed)
    min_pace: float = 0.3  # m/s: a human who would walk slower than this stands instead (holds)
    robot_near: float = 0.5  # m: once the robot is this close to the node (along its path), full speed


@dataclass
class _Held:
    agent: int
    goals: list[str]  # node ids of the human's goal list (path without the spawn node)
    spawn: str
    node: str  # interaction node
    robot_index: int  # index of the node in the robot's goal list


class InteractionThrottle:
    def __init__(self, config: ThrottleConfig, robot_nodes: list[str], robot_goal_points: list[complex],
                 humans: list[tuple[int, list[str], str | None, int]]) -> None:
        """humans: (agent id, path node ids, interaction node or None, group id)."""
        self.config = config
        self.robot_goals = robot_nodes[1:]
        self.robot_points = robot_goal_points[1:]
        self.k = 0
        self.cumulative = [0.0]  # path length along the robot's goals from the first one
        for a, b in zip(self.robot_points, self.robot_points[1:], strict=False):
            self.cumulative.append(self.cumulative[-1] + abs(b - a))
        self.held: list[_Held] = []
        self.skipped: list[str] = []
        self.paused_steps: dict[int, int] = {}
        for agent, path, node, group in humans:
            if node is None or group != -1 or not path:
                continue
            if node not in self.robot_goals:
                self.skipped.append(f"agent {agent}: interaction node {node} is not on the robot's path after its start")
                continue
            goals = path[1:] if len(path) > 1 else [path[0]]
            self.held.append(_Held(agent, goals, path[0], node, self.robot_goals.index(node)))
        # agent -> index of its interaction node among its goals (-1: not among them); read every step
        self.node_at = {h.agent: h.goals.index(h.node) if h.node in h.goals else -1 for h in self.held}
        self.points: dict[int, list[complex]] = {}  # agent -> world points of its goals (set on first update)

    def update(self, sim: Any) -> None:
        """Advance the robot's waypoint index and set crowd.paused (and crowd.pace) for this step."""
        if not self.config.enabled or not self.held:
            return
        rp = sim.robot_pos
        while self.k < len(self.robot_points) - 1 and abs(self.robot_points[self.k] - rp) <= self.config.waypoint_radius:
            self.k += 1
        if self.config.rule == "socrates":
            self._socrates(sim)
            return
        crowd = sim.crowd
        for h in self.held:
            i = h.agent
            q = crowd.queues[i]
            pause, pace = False, float(crowd.max_vel[i])
            idx = len(h.goals) - len(q)  # index in h.goals of the goal the human walks to now
            node_at = self.node_at[i]
            robot_left = self._robot_left(rp, h)
            if (crowd.behavior_state[i] == 0 and q.goals and idx >= 0 and (idx <= node_at or h.spawn == h.node)
                    and robot_left > self.config.robot_near and sim.robot_dist[i] > self.config.release_distance):
                points = self.points.get(i)
                if points is None:
                    points = self.points[i] = [complex(*g) for g in crowd.specs[i].goals]
                node_point = self.robot_points[h.robot_index]
                if h.spawn == h.node or idx > node_at:
                    human_left = abs(node_point - crowd.pos[i])
                else:
                    human_left = abs(points[idx] - crowd.pos[i]) + sum(
                        abs(points[j + 1] - points[j]) for j in range(idx, node_at))
                eta = robot_left / max(self.config.robot_speed, 1e-3)
                want = human_left / max(eta, 1e-3)
                if want < self.config.min_pace:
                    pause = True
                else:
                    pace = min(pace, want)
            crowd.paused[i] = pause
            crowd.pace[i] = pace
            if pause:
                self.paused_steps[i] = self.paused_steps.get(i, 0) + 1

    def _robot_left(self, rp: complex, h: _Held) -> float:
        """The robot's remaining path length to h's interaction node (0 once past it)."""
        if self.k > h.robot_index:
            return 0.0
        return abs(self.robot_points[self.k] - rp) + self.cumulative[h.robot_index] - self.cumulative[self.k]

    def _socrates(self, sim: Any) -> None:
        """The fork's rule: hold on the leg before the node until the robot's current waypoint is the node."""
        crowd = sim.crowd
        for h in self.held:
            i = h.agent
            q = crowd.queues[i]
            if not q.goals or (len(q) == 1 and abs(q.goals[0] - crowd.pos[i]) <= q.radius):
                continue  # SocRATES sends no entry: the previous value stays
            idx = len(h.goals) - len(q)
            next_node = h.goals[idx] if 0 <= idx < len(h.goals) else None
            pause = (crowd.behavior_state[i] == 0
                     and sim.robot_dist[i] > self.config.release_distance
                     and (next_node == h.node or h.spawn == h.node)
                     and self.k < h.robot_index
                     and self.robot_goals[self.k] != h.node)
            crowd.paused[i] = pause
            if pause:
                self.paused_steps[i] = self.paused_steps.get(i, 0) + 1
