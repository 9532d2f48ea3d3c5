"""The episode table's columns and their Arrow types: one home, so every part file (and every executor)
writes the same schema and DuckDB / pandas read them as one table."""

from __future__ import annotations

from functools import cache
from typing import Any

import numpy as np
import pyarrow as pa

IDENTITY = [
    ("episode", pa.string()),  # scenario|policy|seed: the resume key
    ("scenario", pa.string()),
    ("location", pa.string()),
    ("card", pa.string()),
    ("source", pa.string()),
    ("humans", pa.int64()),
    ("policy", pa.string()),
    ("robot", pa.string()),
    ("seed", pa.int64()),
    ("inputs", pa.string()),  # digest of what decided the episode (campaign/fingerprint.py): resume needs it equal
    ("params", pa.string()),  # JSON of the policy's params (campaign file `params:` / `sweep:`)
    ("robot_body", pa.string()),  # JSON of the robot's kinematics and limits (sim.robot.body.RobotBody)
]
OUTCOME = [
    ("status", pa.string()),  # ok | failed
    ("failure_reason", pa.string()),  # why an episode failed (crash, timeout, collision, goal not reached)
    ("end_reason", pa.string()),  # robot_goal | timeout | all_done | error
    ("steps", pa.int64()),
    ("sim_seconds", pa.float64()),
    ("wall_seconds", pa.float64()),
    ("verified", pa.bool_()),  # every required verifier finding passed (null: not verified / crashed)
    ("verify_failed", pa.string()),  # names of the failed findings, "; "-separated
    ("verdicts", pa.string()),  # JSON list of {name, kind, passed, required, human[, robustness, blame]}
    ("expected_checks", pa.string()),  # JSON list of {check, value, passed} of the card's expected behaviour
    ("people_traits", pa.string()),  # JSON {human: {speed, personal_space, start_delay}}: this seed's people
    ("mean_person_speed", pa.float64()),  # m/s: their mean drawn walking speed
    ("trajectory", pa.string()),  # the episode's trajectories file, relative to the campaign folder
]
BOOL_METRICS = {"success", "completed", "reached_goal"}
LIST_METRICS = {"ttc_seconds"}  # seconds per time-to-collision bin (sim.social_metrics.TTC_EDGES)
INT_METRICS = {"collisions", "robot_on_person_collision", "person_on_robot_collision", "samples",
               "static_obstacle_collisions"}


@cache
def known_metric_names() -> tuple[str, ...]:
    from socnavgen.sim.metric_definitions import all_metric_names

    return all_metric_names()


def metric_type(name: str) -> pa.DataType:
    if name in BOOL_METRICS:
        return pa.bool_()
    if name in INT_METRICS:
        return pa.int64()
    if name in LIST_METRICS:
        return pa.list_(pa.float64())
    return pa.float64()


def schema(metrics: list[str] | tuple[str, ...] | None = None) -> pa.Schema:
    """The table schema for the chosen metrics (default: all). `success` is always kept."""
    chosen = list(metrics) if metrics is not None else list(known_metric_names())
    if "success" not in chosen:
        chosen.insert(0, "success")
    return pa.schema([*IDENTITY, *OUTCOME, *((m, metric_type(m)) for m in chosen)])


def contact_free(success: Any, wall_contacts: Any) -> Any:
    """A campaign's `success` ("contact-free success"): the goal reached touching nobody (sim.metrics' success) and
    no wall either (`static_obstacle_collisions` 0; None / NaN: not measured). A robot that scrapes along shelves
    to its goal has not navigated cleanly: on SocRATES's small warehouse 16-18 of 42 episodes per robot reached
    so and were counted as successes. Scalars or arrays (the row, and the report on older tables)."""
    walls = np.nan_to_num(np.asarray(wall_contacts, dtype=float), nan=0.0)
    return np.logical_and(np.asarray(success, dtype=bool), walls == 0)
