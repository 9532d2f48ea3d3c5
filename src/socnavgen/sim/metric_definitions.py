"""Unit, meaning and better direction of every metric socnavgen computes: one table, read by the
`definitions` of every metrics.json (simulate, verify, campaigns), the campaign report's glossary and its
paired comparisons. The navigation metrics HuNavSim's evaluator leaves as TODO carry their formulas from
sim.metrics.NAVIGATION_METRICS."""

from __future__ import annotations

from typing import Any

# (unit, meaning, better): better = "higher" | "lower" | None (no preferred direction)
_EVALUATOR: dict[str, tuple[str, str, str | None]] = {
    "success": ("bool", "robot reached its goal (within the goal radius) without touching anyone (no contact)",
                "higher"),
    "collisions": ("steps", "steps with the robot in contact with a person (gap <= 0.05 m, sim/contact.py)", "lower"),
    "min_time_to_collision": ("s", "smallest constant-velocity time to robot-person contact", "higher"),
    "time_to_reach_goal": ("s", "duration of the recording (HuNavSim's definition)", "lower"),
    "path_length": ("m", "distance driven by the robot", None),
    "cumulative_heading_changes": ("rad", "sum of |yaw changes| of the robot", "lower"),
    "avg_distance_to_closest_person": ("m", "mean gap to the closest person", None),
    "minimum_distance_to_people": ("m", "smallest robot-person gap", "higher"),
    "maximum_distance_to_people": ("m", "largest centre distance minus the robot radius", None),
    "intimate_space_intrusions": ("%", "percent of samples with the closest gap < 0.45 m", "lower"),
    "personal_space_intrusions": ("%", "percent of samples with the closest gap in [0.45, 1.2) m", "lower"),
    "social_space_intrusions": ("%", "percent of samples with the closest gap in [1.2, 3.6) m", "lower"),
    "group_intimate_space_intrusions": ("%", "as intimate, to group centres", "lower"),
    "group_personal_space_intrusions": ("%", "as personal, to group centres", "lower"),
    "group_social_space_intrusions": ("%", "as social, to group centres", "lower"),
    "completed": ("bool", "final robot position within 0.2 m of a goal (HuNavSim)", "higher"),
    "minimum_distance_to_target": ("m", "closest the robot came to its goal", "lower"),
    "final_distance_to_target": ("m", "robot-goal distance at the end", "lower"),
    "robot_on_person_collision": ("count", "(sample, person) contacts the robot drove into (HuNavSim bearing "
                                  "test on the pairs sim/contact.py counts)", "lower"),
    "person_on_robot_collision": ("count", "(sample, person) contacts a person walked into (HuNavSim bearing "
                                  "test on the pairs sim/contact.py counts)", "lower"),
    "time_not_moving": ("s", "time with speed < 0.01 m/s and angular speed < 0.02 rad/s", "lower"),
    "avg_robot_linear_speed": ("m/s", "mean robot speed", None),
    "avg_robot_angular_speed": ("rad/s", "mean |angular speed|", "lower"),
    "avg_acceleration": ("m/s^2", "mean |linear acceleration|", "lower"),
    "avg_overacceleration": ("m/s^3", "mean |jerk| (HuNavSim's formula)", "lower"),
    "avg_pedestrian_velocity": ("m/s", "mean pedestrian speed", None),
    "avg_closest_pedestrian_velocity": ("m/s", "mean speed of the closest pedestrian", None),
    "social_force_on_agents": ("N (model units)", "sum of the robot's social force on people", "lower"),
    "social_force_on_robot": ("N (model units)", "sum of people's social force on the robot", "lower"),
    "social_work": ("N (model units)", "social + obstacle force magnitudes summed", "lower"),
    "obstacle_force_on_agents": ("N (model units)", "mean obstacle force on people, summed over time", None),
    "obstacle_force_on_robot": ("N (model units)", "obstacle force on the robot, summed over time", "lower"),
    "samples": ("count", "samples the evaluator metrics used", None),
}
_BETTER_NAVIGATION = {"path_irregularity": "lower", "path_efficiency": "higher",
                      "static_obstacle_collisions": "lower", "min_obstacle_clearance": "higher"}


def metric_definitions(metrics: list[str] | tuple[str, ...] | None = None) -> dict[str, dict[str, Any]]:
    """{metric: {unit, meaning, better[, formula]}} for the chosen metric columns (default: all)."""
    from socnavgen.sim.metrics import EVALUATOR_METRICS, NAVIGATION_METRICS, OWN_METRICS

    out: dict[str, dict[str, Any]] = {}
    for name in metrics or (*OWN_METRICS, *NAVIGATION_METRICS, *EVALUATOR_METRICS):
        if name in NAVIGATION_METRICS:
            out[name] = {**NAVIGATION_METRICS[name], "better": _BETTER_NAVIGATION.get(name)}
        else:
            unit, meaning, better = _EVALUATOR.get(name, ("", "", None))
            out[name] = {"unit": unit, "meaning": meaning, "better": better}
    return out


def better_direction(name: str) -> str | None:
    return _BETTER_NAVIGATION.get(name) or _EVALUATOR.get(name, ("", "", None))[2]
