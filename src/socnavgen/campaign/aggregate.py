"""The episode table -> what the report shows: per policy (the ranking), per location and per scenario estimates
with bootstrap CIs over the seeds, paired comparisons with a baseline, the cards' expected-behaviour checks per
policy, the time-to-collision distribution, and the failed episodes, worst first."""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import pyarrow as pa

from socnavgen.campaign.columns import contact_free
from socnavgen.campaign.stats import Estimate, Paired, bootstrap_mean, paired_difference
from socnavgen.sim.metric_definitions import better_direction

# The ranking (the README's table): success, contact-free success, time to goal over successes, path efficiency
# against the shortest walkable path, seconds in intimate space (all, and those the robot made by closing in), the
# card's expected behaviour
RANKING = ("reached_goal", "success", "time_to_goal", "walkable_path_efficiency", "intimate_space_seconds",
           "intimate_approach_seconds", "expected_behaviour")
# What else a reader compares: comfort, safety margins, the evaluator's classics
SECONDARY = ("timeout", "personal_space_seconds", "ttc_under_1s", "mean_jerk", "minimum_distance_to_people",
             "collisions", "path_irregularity", "static_obstacle_collisions")
KEY_METRICS = (*RANKING, *SECONDARY)
FALSE_WHEN_MISSING = ("success", "reached_goal")  # a crashed episode neither succeeded nor reached its goal


@dataclass
class Aggregates:
    policies: list[str]  # ranked: best first (contact-free success, then reached goal, then expected behaviour)
    scenarios: list[str]
    locations: list[str]
    metrics: list[str]  # shown, in order (the ranking first)
    per_policy: dict[str, dict[str, Estimate]]  # policy -> metric -> estimate
    per_location: dict[tuple[str, str], dict[str, Estimate]]  # (location, policy) -> metric -> estimate
    per_scenario: dict[tuple[str, str], dict[str, Estimate]]  # (scenario, policy) -> success / reached_goal
    scenario_location: dict[str, str]
    paired: dict[str, dict[str, Paired]]  # policy -> metric -> difference to the baseline
    baseline: str
    failed: dict[str, int]  # policy -> crashed / timed-out episodes
    verified: dict[str, Estimate]  # policy -> share of episodes the verifier passed
    checks: dict[tuple[str, str], Estimate] = field(default_factory=dict)  # (check, policy) -> pass rate
    ttc: dict[str, list[float]] = field(default_factory=dict)  # policy -> seconds per TTC bin, summed
    worst: list[dict[str, Any]] = field(default_factory=list)
    seeds: int = 0
    episodes: int = 0
    speeds: tuple[float, float] | None = None  # smallest and largest drawn walking speed (m/s), if drawn

    @property
    def ranking(self) -> list[str]:
        return [m for m in RANKING if m in self.metrics]


def _column(table: pa.Table, name: str) -> np.ndarray:
    values = table.column(name).to_pylist()
    return np.array([np.nan if v is None else float(v) for v in values], dtype=float)


def _data(table: pa.Table) -> dict[str, np.ndarray]:
    data = {m: _column(table, m) for m in KEY_METRICS if m in table.column_names}
    for m in FALSE_WHEN_MISSING:
        if m in data:
            data[m] = np.nan_to_num(data[m], nan=0.0)
    if "success" in data and "static_obstacle_collisions" in data:  # a table written before walls counted
        data["success"] = contact_free(data["success"], data["static_obstacle_collisions"]).astype(float)
        if "time_to_goal" in data:  # over contact-free successes only, as the rows written since give it
            data["time_to_goal"] = np.where(data["success"] > 0, data["time_to_goal"], np.nan)
    if "end_reason" in table.column_names:
        data["timeout"] = np.array([r == "timeout" for r in table.column("end_reason").to_pylist()], dtype=float)
    return data


def aggregate(table: pa.Table, *, resamples: int = 2000, baseline: str | None = None,
              worst: int = 10) -> Aggregates:
    data = _data(table)
    metrics = [m for m in KEY_METRICS if m in data]
    policy_col = np.array(table.column("policy").to_pylist(), dtype=object)
    scenario_col = np.array(table.column("scenario").to_pylist(), dtype=object)
    location_col = np.array(table.column("location").to_pylist(), dtype=object)
    seed_col = np.array(table.column("seed").to_pylist())
    status = np.array(table.column("status").to_pylist(), dtype=object)
    verified = _column(table, "verified") if "verified" in table.column_names else np.full(len(status), np.nan)
    policies = list(dict.fromkeys(policy_col))
    scenarios = sorted(set(scenario_col))
    locations = sorted(set(location_col))

    def est(mask: np.ndarray, m: str) -> Estimate:
        return bootstrap_mean(data[m][mask], resamples)

    per_policy = {p: {m: est(policy_col == p, m) for m in metrics} for p in policies}
    policies.sort(key=lambda p: tuple(-_mean(per_policy[p].get(m)) for m in ("success", "reached_goal",
                                                                             "expected_behaviour")))
    ranking = [m for m in RANKING if m in data]
    per_location = {(loc, p): {m: est((location_col == loc) & (policy_col == p), m) for m in ranking}
                    for loc in locations for p in policies}
    per_scenario: dict[tuple[str, str], dict[str, Estimate]] = {(s, p): {m: est((scenario_col == s) & (policy_col == p), m)
                             for m in ("success", "reached_goal") if m in data}
                    for s in scenarios for p in policies}
    baseline = baseline if baseline is not None and baseline in policies else str(policy_col[0])  # default: the campaign's first policy
    return Aggregates(
        policies=policies, scenarios=scenarios, locations=locations, metrics=metrics, per_policy=per_policy,
        per_location=per_location, per_scenario=per_scenario,
        scenario_location=dict(zip(scenario_col, location_col, strict=True)),
        paired=_paired(data, metrics, policies, baseline, policy_col, scenario_col, seed_col, resamples),
        baseline=baseline,
        failed={p: int(np.count_nonzero((policy_col == p) & (status != "ok"))) for p in policies},
        verified={p: bootstrap_mean(verified[policy_col == p], resamples) for p in policies},
        checks=_checks(table, policy_col, resamples), ttc=_ttc(table, policy_col),
        worst=worst_episodes(table, worst), seeds=len(set(seed_col.tolist())), episodes=table.num_rows,
        speeds=_speeds(table))


def _mean(e: Estimate | None) -> float:
    return e.mean if e is not None and e.n and np.isfinite(e.mean) else -np.inf


def _paired(data: dict[str, np.ndarray], metrics: list[str], policies: list[str], baseline: str,
            policy_col: np.ndarray, scenario_col: np.ndarray, seed_col: np.ndarray,
            resamples: int) -> dict[str, dict[str, Paired]]:
    """Each policy minus the baseline on the same (scenario, seed): the same people, the same spawn points."""
    base_index = {(s, k): i for i, (s, k, p) in enumerate(zip(scenario_col, seed_col, policy_col, strict=True))
                  if p == baseline}
    paired: dict[str, dict[str, Paired]] = {}
    for p in policies:
        if p == baseline:
            continue
        pairs = [(i, base_index[(s, k)]) for i, (s, k, q) in enumerate(zip(scenario_col, seed_col, policy_col,
                                                                               strict=True))
                 if q == p and (s, k) in base_index]
        if pairs:
            mine, theirs = np.array([a for a, _ in pairs]), np.array([b for _, b in pairs])
            paired[p] = {m: paired_difference(data[m][mine], data[m][theirs], better_direction(m), resamples)
                         for m in metrics}
    return paired


def _checks(table: pa.Table, policy_col: np.ndarray, resamples: int) -> dict[tuple[str, str], Estimate]:
    """(check, policy) -> share of the episodes where the check applied that passed it."""
    if "expected_checks" not in table.column_names:
        return {}
    outcomes: dict[tuple[str, str], list[float]] = {}
    for policy, text in zip(policy_col, table.column("expected_checks").to_pylist(), strict=True):
        for item in json.loads(text) if text else []:
            if item.get("passed") is not None:
                outcomes.setdefault((item["check"], policy), []).append(float(item["passed"]))
    return {key: bootstrap_mean(np.array(v), resamples) for key, v in sorted(outcomes.items())}


def _ttc(table: pa.Table, policy_col: np.ndarray) -> dict[str, list[float]]:
    """policy -> seconds per time-to-collision bin, summed over its episodes."""
    if "ttc_seconds" not in table.column_names:
        return {}
    out: dict[str, np.ndarray] = {}
    for policy, bins in zip(policy_col, table.column("ttc_seconds").to_pylist(), strict=True):
        if bins:
            out[policy] = out.get(policy, np.zeros(len(bins))) + np.asarray(bins, dtype=float)
    return {p: [float(v) for v in bins] for p, bins in out.items()}


def _speeds(table: pa.Table) -> tuple[float, float] | None:
    if "people_traits" not in table.column_names:
        return None
    speeds = [t["speed"] for text in table.column("people_traits").to_pylist() if text
              for t in json.loads(text).values()]
    return (min(speeds), max(speeds)) if speeds else None


def worst_episodes(table: pa.Table, k: int) -> list[dict[str, Any]]:
    """The failed episodes only (crashed, or not a contact-free success), worst first: crashes, then the most
    steps in contact with a person, then the closest approach; never padded with successes."""
    rows = table.select([c for c in ("episode", "scenario", "policy", "seed", "status", "success", "collisions",
                                     "minimum_distance_to_people", "failure_reason", "location", "card",
                                     "end_reason") if c in table.column_names]).to_pylist()
    failed = [r for r in rows if r["status"] != "ok" or not r.get("success")]

    def badness(r: dict[str, Any]) -> tuple:
        gap = r.get("minimum_distance_to_people")
        return (r["status"] == "ok", -(r.get("collisions") or 0), gap if gap is not None else 1e9, r["episode"])

    return sorted(failed, key=badness)[:k]
