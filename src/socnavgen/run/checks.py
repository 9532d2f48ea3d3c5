"""Checks of a stored PathPlan against a location's scene graph, shared by everything that reads
paths.json (cards, simulator, exporters): one wording of each mistake."""

from __future__ import annotations

from socnavgen.location.models import SceneGraph
from socnavgen.location.scene_graph import path_mistakes
from socnavgen.run.models import PathPlan


def plan_mistakes(plan: PathPlan, graph: SceneGraph, *, interaction_points: bool = True) -> list[str]:
    """Every way `plan` does not fit `graph`: unknown nodes, missing edges, empty paths, humans not named
    human1..humanN without gaps, and (unless `interaction_points` is False: a run can still be simulated
    and exported without its meeting place) interaction points that are not on both paths."""
    mistakes: list[str] = []
    if not plan.robot:
        mistakes.append("the robot path is empty")
    mistakes += path_mistakes(graph, "robot path", plan.robot)
    for h in plan.humans:
        if not h.path:
            mistakes.append(f"{h.name}'s path is empty")
        mistakes += path_mistakes(graph, f"{h.name}'s path", h.path)
        point = h.interaction_point
        if interaction_points and point is not None and (point not in h.path or point not in plan.robot):
            mistakes.append(f"the interaction point {point} of {h.name} is not on both its path and the robot's")
    ids = sorted(h.agent_id for h in plan.humans)
    if ids != list(range(len(ids))):
        mistakes.append("humans must be named human1..humanN without gaps (agent id = number - 1)")
    return mistakes
