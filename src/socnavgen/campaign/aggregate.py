"""The episode table -> per-policy and per-scenario aggregates with CIs, paired comparisons, worst episodes."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
import pyarrow as pa

from socnavgen.campaign.stats import Estimate, Paired, bootstrap_mean, paired_difference
from socnavgen.sim.metric_definitions import better_direction

KEY_METRICS = ("success", "collisions", "minimum_distance_to_people", "time_to_reach_goal", "path_efficiency",
               "path_irregularity", "static_obstacle_collisions", "intimate_space_intrusions")


@dataclass
class Aggregates:
    policies: list[str]
    scenarios: list[str]
    metrics: list[str]  # shown, in order
    per_policy: dict[str, dict[str, Estimate]]  # policy -> metric -> estimate
    per_scenario: dict[tuple[str, str], dict[str, Estimate]]  # (scenario, policy) -> metric -> estimate
    paired: dict[str, dict[str, Paired]]  # policy -> metric -> difference to the baseline
    baseline: str
    failed: dict[str, int]  # policy -> crashed / timed-out episodes
    verified: dict[str, Estimate]  # policy -> share of episodes the verifier passed
    worst: list[dict[str, Any]] = field(default_factory=list)
    episodes: int = 0


def _column(table: pa.Table, name: str) -> np.ndarray:
    values = table.column(name).to_pylist()
    return np.array([np.nan if v is None else float(v) for v in values], dtype=float)


def aggregate(table: pa.Table, *, resamples: int = 2000, baseline: str | None = None,
              worst: int = 10) -> Aggregates:
    policies = list(dict.fromkeys(table.column("policy").to_pylist()))
    scenarios = sorted(set(table.column("scenario").to_pylist()))
    metrics = [m for m in KEY_METRICS if m in table.column_names]
    data = {m: _column(table, m) for m in metrics}
    if "success" in data:  # a crashed episode is a failed one
        data["success"] = np.nan_to_num(data["success"], nan=0.0)
    policy_col = np.array(table.column("policy").to_pylist(), dtype=object)
    scenario_col = np.array(table.column("scenario").to_pylist(), dtype=object)
    seed_col = np.array(table.column("seed").to_pylist())
    status = np.array(table.column("status").to_pylist(), dtype=object)
    verified = _column(table, "verified") if "verified" in table.column_names else np.full(len(status), np.nan)
    baseline = baseline if baseline in policies else policies[0]
    if baseline is None:
        baseline = policies[0]

    per_policy = {p: {m: bootstrap_mean(data[m][policy_col == p], resamples) for m in metrics} for p in policies}
    per_scenario = {(s, p): {m: bootstrap_mean(data[m][(policy_col == p) & (scenario_col == s)], resamples)
                             for m in ("success",) if m in data}
                    for s in scenarios for p in policies}
    paired: dict[str, dict[str, Paired]] = {}
    base_index = {(s, k): i for i, (s, k, p) in enumerate(zip(scenario_col, seed_col, policy_col, strict=True))
                  if p == baseline}
    for p in policies:
        if p == baseline:
            continue
        pairs = [(i, base_index[(s, k)]) for i, (s, k, q) in enumerate(zip(scenario_col, seed_col, policy_col,
                                                                               strict=True))
                 if q == p and (s, k) in base_index]
        if not pairs:
            continue
        mine, theirs = np.array([a for a, _ in pairs]), np.array([b for _, b in pairs])
        paired[p] = {m: paired_difference(data[m][mine], data[m][theirs], better_direction(m), resamples)
                     for m in metrics}
    return Aggregates(policies=policies, scenarios=scenarios, metrics=metrics, per_policy=per_policy,
                      per_scenario=per_scenario, paired=paired, baseline=baseline,
                      failed={p: int(np.count_nonzero((policy_col == p) & (status != "ok"))) for p in policies},
                      verified={p: bootstrap_mean(verified[policy_col == p], resamples) for p in policies},
                      worst=worst_episodes(table, worst), episodes=table.num_rows)


def worst_episodes(table: pa.Table, k: int) -> list[dict[str, Any]]:
    """Crashes first, then failures with the most person contact and the closest approach."""
    rows = table.select([c for c in ("episode", "scenario", "policy", "seed", "status", "success", "collisions",
                                     "minimum_distance_to_people", "failure_reason", "location", "card")
                         if c in table.column_names]).to_pylist()

    def badness(r: dict[str, Any]) -> tuple:
        return (r["status"] == "ok", bool(r.get("success")), -(r.get("collisions") or 0),
                r.get("minimum_distance_to_people") if r.get("minimum_distance_to_people") is not None else 1e9,
                r["episode"])

    return sorted(rows, key=badness)[:k]
