"""Name, unit, meaning and better direction of every metric socnavgen computes: one table, read by the
`definitions` of every metrics.json (simulate, verify, campaigns), the campaign report (its column names,
glossary and paired comparisons) and `socnavgen campaign metrics`. The navigation metrics HuNavSim's evaluator
leaves as TODO carry their formulas from sim.metrics.NAVIGATION_METRICS; the social metrics (sim.social_metrics)
and the expected-behaviour score (sim.behaviour_checks) carry theirs from here."""

from __future__ import annotations

from typing import Any

# (unit, meaning, better): better = "higher" | "lower" | None (no preferred direction)
_EVALUATOR: dict[str, tuple[str, str, str | None]] = {
    "success": ("bool", "robot reached its goal (within the goal radius) without touching anyone (no contact); "
                "in a campaign, touching no wall either (static_obstacle_collisions 0: campaign.columns.contact_free)",
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

# (unit, meaning, better, formula) of the metrics of sim.social_metrics and sim.behaviour_checks
_SOCIAL: dict[str, tuple[str, str, str | None, str]] = {
    "reached_goal": ("bool", "the robot came within the goal radius (0.2 m) of its goal, touching people or not",
                     "higher", "min_t |p_t - goal| <= r_goal"),
    "time_to_goal": ("s", "time until the robot first reached its goal, in successful episodes only (None in the "
                     "others: failures and timeouts are counted by success and by the timeouts column)", "lower",
                     "min {t : |p_t - goal| <= r_goal}, when success"),
    "walkable_path_efficiency": (
        "1", "shortest walkable path along the robot's route divided by the path it drove (1 = as short as the "
        "map allows; None when the goal was not reached)", "higher",
        "min(1, L* / L), L* = sum over the route's legs (start, waypoints in order) of the shortest path a disc "
        "of the robot's radius can take on the map (geodesic field pulled taut), L = path driven until arrival"),
    "route_length_walkable": ("m", "length L* of the shortest walkable path along the robot's route", None,
                              "see walkable_path_efficiency"),
    "mean_jerk": ("m/s^3", "comfort: mean magnitude of the robot's jerk (lower = smoother)", "lower",
                  "mean_t |(a_{t+1} - a_t) / dt|, a_t = (v_{t+1} - v_t) / dt, v = the robot's velocity vector"),
    "intimate_space_seconds": ("s", "time the robot spent within a person's intimate space (gap < 0.45 m)",
                               "lower", "sum_t dt [min_i gap_i(t) < 0.45]"),
    "intimate_approach_seconds": (
        "s", "time the robot itself closed in on someone within their intimate space (gap < 0.45 m, its own "
        "velocity toward them > 0.05 m/s): the robot's share of intimate-space time, without people walking up to "
        "a robot that stands", "lower",
        "sum_t dt [exists i: gap_i(t) < 0.45 and v_robot(t) . u_i(t) > 0.05], u_i = unit vector robot -> person i"),
    "personal_space_seconds": ("s", "time the robot spent in a person's personal space (gap 0.45-1.2 m)", "lower",
                               "sum_t dt [0.45 <= min_i gap_i(t) < 1.2]"),
    "ttc_under_1s": ("s", "time with a robot-person contact less than 1 s ahead at constant velocities", "lower",
                     "sum_t dt [min_i TTC_i(t) < 1 s]"),
    "ttc_seconds": ("s per bin", "time-to-collision distribution: seconds with the smallest TTC in [0, 0.5), "
                    "[0.5, 1), [1, 2), [2, 3), [3, 5) and [5 s, never)", None,
                    "sum_t dt [TTC(t) in bin], TTC = smallest constant-velocity time to contact over people"),
    "expected_behaviour": ("1", "share of the card's checkable expected robot behaviours the robot showed (None "
                           "when the card states none that can be checked, or none applied)", "higher",
                           "mean over the card's checks that applied of [check passed] (sim/behaviour_checks.py)"),
}

# Read from other columns of a campaign's table by its report, not computed per trace
_DERIVED: dict[str, tuple[str, str, str | None, str]] = {
    "timeout": ("bool", "the episode ran out of simulated time before the robot reached its goal", "lower",
                "end_reason == 'timeout'"),
}

# Readable names for tables and figures (units are added where they are shown)
LABELS: dict[str, str] = {
    "success": "Contact-free success", "reached_goal": "Reached goal", "collisions": "Contact steps",
    "min_time_to_collision": "Min time to collision", "time_to_goal": "Time to goal (successes)",
    "time_to_reach_goal": "Episode duration (HuNavSim)", "path_length": "Path length",
    "cumulative_heading_changes": "Heading changes", "avg_distance_to_closest_person": "Mean gap to closest",
    "minimum_distance_to_people": "Min gap to people", "maximum_distance_to_people": "Max distance to people",
    "intimate_space_intrusions": "Intimate-space share", "personal_space_intrusions": "Personal-space share",
    "social_space_intrusions": "Social-space share", "group_intimate_space_intrusions": "Group intimate share",
    "group_personal_space_intrusions": "Group personal share", "group_social_space_intrusions": "Group social share",
    "completed": "Completed (HuNavSim)", "minimum_distance_to_target": "Min distance to goal",
    "final_distance_to_target": "Final distance to goal", "robot_on_person_collision": "Robot-on-person contacts",
    "person_on_robot_collision": "Person-on-robot contacts", "time_not_moving": "Time not moving",
    "avg_robot_linear_speed": "Mean speed", "avg_robot_angular_speed": "Mean turn rate",
    "avg_acceleration": "Mean acceleration", "avg_overacceleration": "Mean jerk (HuNavSim)",
    "avg_pedestrian_velocity": "Mean pedestrian speed", "avg_closest_pedestrian_velocity": "Closest ped. speed",
    "social_force_on_agents": "Social force on people", "social_force_on_robot": "Social force on robot",
    "social_work": "Social work", "obstacle_force_on_agents": "Obstacle force on people",
    "obstacle_force_on_robot": "Obstacle force on robot", "samples": "Samples",
    "path_irregularity": "Path irregularity", "path_efficiency": "Path efficiency (straight line)",
    "static_obstacle_collisions": "Wall contacts", "min_obstacle_clearance": "Min wall clearance",
    "walkable_path_efficiency": "Path efficiency", "route_length_walkable": "Shortest walkable route",
    "mean_jerk": "Jerk", "intimate_space_seconds": "Intimate-space time",
    "intimate_approach_seconds": "Closing in (intimate)", "personal_space_seconds": "Personal-space time",
    "ttc_under_1s": "Time with TTC < 1 s", "ttc_seconds": "TTC distribution", "expected_behaviour": "Expected behaviour",
    "timeout": "Timeouts",
}


def metric_definitions(metrics: list[str] | tuple[str, ...] | None = None) -> dict[str, dict[str, Any]]:
    """{metric: {label, unit, meaning, better[, formula]}} for the chosen metric columns (default: all)."""
    out: dict[str, dict[str, Any]] = {}
    for name in metrics or all_metric_names():
        out[name] = {"label": label(name), **_definition(name)}
    return out


def _definition(name: str) -> dict[str, Any]:
    from socnavgen.sim.metrics import NAVIGATION_METRICS

    if name in NAVIGATION_METRICS:
        return {**NAVIGATION_METRICS[name], "better": _BETTER_NAVIGATION.get(name)}
    if name in _SOCIAL or name in _DERIVED:
        unit, meaning, better, formula = _SOCIAL.get(name) or _DERIVED[name]
        return {"unit": unit, "meaning": meaning, "better": better, "formula": formula}
    unit, meaning, better = _EVALUATOR.get(name, ("", "", None))
    return {"unit": unit, "meaning": meaning, "better": better}


def all_metric_names() -> tuple[str, ...]:
    """Every metric column, in the order tables list them."""
    from socnavgen.sim.metrics import EVALUATOR_METRICS, NAVIGATION_METRICS, OWN_METRICS

    return (*OWN_METRICS, *_SOCIAL, *NAVIGATION_METRICS, *EVALUATOR_METRICS)


def label(name: str, unit: bool = False) -> str:
    """The metric's readable name (with its unit in brackets when asked and it has one)."""
    text = LABELS.get(name, name.replace("_", " ").capitalize())
    if unit:
        u = _definition(name)["unit"]
        if u and u not in ("1", "bool"):
            text += f" ({u})"
    return text


def better_direction(name: str) -> str | None:
    return _definition(name)["better"]
