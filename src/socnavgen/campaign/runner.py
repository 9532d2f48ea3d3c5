"""`campaign run`: the campaign file -> scenarios x policies x seeds -> the episode table, resumable."""

from __future__ import annotations

import json
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from socnavgen.campaign.episode import Episode, EpisodeSettings
from socnavgen.campaign.executors import EXECUTORS, batches
from socnavgen.campaign.scenarios import Suite, build_suite
from socnavgen.campaign.spec import CampaignSpec
from socnavgen.campaign.store import EpisodeStore
from socnavgen.errors import InputFileError
from socnavgen.safeio import atomic_write_json, atomic_write_text

SCENARIOS_FILE = "scenarios.json"
METRICS_FILE = "metrics.json"
CAMPAIGN_FILE = "campaign.json"


@dataclass
class CampaignResult:
    out: Path
    total: int  # episodes in the campaign
    skipped_done: int  # already in the table (resumed)
    ran: int
    failed: int
    suite: Suite


def plan_episodes(spec: CampaignSpec, suite: Suite) -> list[Episode]:
    """Every scenario x policy x seed, ordered by location then scenario (workers keep their map)."""
    ordered = sorted(suite.scenarios, key=lambda s: (s.location_dir, s.id))
    return [Episode(s, p.name, p.robot, seed) for s in ordered for p in spec.policies for seed in spec.seeds]


def check_policies(spec: CampaignSpec) -> None:
    """Load every policy once before any episode: a typo in the campaign file is one clear error, not a
    table full of failed episodes (a policy that crashes *during* an episode fails only that episode)."""
    from socnavgen.sim import load_policy

    for policy in spec.policies:
        try:
            load_policy(policy.robot)
        except InputFileError as exc:
            raise InputFileError(f"policy {policy.name}: {exc.message}", hint=exc.hint) from exc


def settings_of(spec: CampaignSpec) -> EpisodeSettings:
    sim = spec.simulation
    return EpisodeSettings(dt=sim.dt, timeout=sim.timeout, throttle=sim.throttle, wall_timeout=sim.wall_timeout,
                           verify=spec.verify, metrics=tuple(spec.metrics) if spec.metrics else None)


def write_definitions(out: Path, metrics: list[str] | None) -> None:
    """metrics.json: every metric column with its unit and formula (the report shows the same)."""
    from socnavgen.sim.metric_definitions import metric_definitions

    atomic_write_json(out / METRICS_FILE, metric_definitions(metrics))


def run_campaign(spec: CampaignSpec, out: Path, *, executor: str = "local", workers: int | None = None,
                 address: str | None = None, batch_size: int = 4,
                 progress: Callable[[int, int], None] | None = None) -> CampaignResult:
    """Run every episode not yet in OUT's table; `progress(done, total)` after each batch."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    previous = out / CAMPAIGN_FILE
    current = spec.model_dump_json(indent=2, exclude={"base_dir"})
    if previous.is_file() and json.loads(previous.read_text()) != json.loads(current):
        raise InputFileError("this folder holds a different campaign", file=previous,
                             hint="resume with the same campaign file, or choose another -o folder")
    check_policies(spec)
    suite = build_suite(spec, out)
    atomic_write_text(previous, current + "\n")
    atomic_write_json(out / SCENARIOS_FILE, {"scenarios": [s.to_dict() for s in suite.scenarios],
                                             "skipped": suite.skipped})
    write_definitions(out, spec.metrics)
    store = EpisodeStore(out, spec.metrics)
    episodes = plan_episodes(spec, suite)
    done = store.done_keys()
    todo = [ep for ep in episodes if ep.key not in done]
    total, finished, failed = len(episodes), len(episodes) - len(todo), 0
    if progress:
        progress(finished, total)
    if todo:
        if executor not in EXECUTORS:
            raise InputFileError(f"unknown executor {executor!r}", hint=f"use one of {', '.join(EXECUTORS)}")
        runner = EXECUTORS[executor](workers=workers, address=address)
        try:
            for rows in runner.run(batches(todo, batch_size), settings_of(spec)):
                for row in rows:
                    store.add(row)
                    failed += row["status"] != "ok"
                finished += len(rows)
                if progress:
                    progress(finished, total)
        finally:
            store.flush()
            runner.close()
    store.consolidate()
    return CampaignResult(out, total, len(episodes) - len(todo), len(todo), failed, suite)
