"""Scripted robot speech (PathPlan.robot_gestures): e.g. say EXCUSE ME (4) while someone blocks the way.

Rules are checked in order every step; the first one whose condition held within its last `duration`
seconds sets the gesture (HuNavSim keeps the last /robot_gesture value, so a gesture persists while held).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from socnavgen.run.models import RobotGestureRule

FRONT_CONE = 0.6  # rad: "in front of the robot" for the `blocked` condition


class ScriptedGestures:
    def __init__(self, rules: list[RobotGestureRule], node_points: dict[str, complex]) -> None:
        self.rules = list(rules)
        self.node_points = node_points
        self.last_true = [-math.inf] * len(self.rules)

    def condition(self, rule: RobotGestureRule, sim: Any) -> bool:
        if rule.when == "always":
            return True
        if rule.when == "at_node":
            point = self.node_points.get(rule.node or "")
            return point is not None and abs(point - sim.robot_pos) <= 1.0
        if sim.crowd.n == 0:
            return False
        rel = sim.crowd.pos - sim.robot_pos
        near = np.abs(rel) <= rule.distance
        if rule.when == "near_human":
            return bool(near.any())
        # blocked: a person within `distance` ahead of the robot's direction of travel
        local = rel * sim.robot_direction().conjugate()
        ahead = (np.abs(np.angle(local)) <= FRONT_CONE) | ((local.real > 0) & (np.abs(local.imag) <
                                                                                sim.crowd.radius + sim.robot_radius))
        return bool((near & ahead).any())

    def gesture(self, sim: Any) -> int:
        for k, rule in enumerate(self.rules):
            if self.condition(rule, sim):
                self.last_true[k] = sim.t
            if sim.t - self.last_true[k] <= rule.duration:
                return rule.gesture
        return 0
