"""`campaign run`: the campaign file -> scenarios x policies x seeds -> the episode table, resumable."""

from __future__ import annotations

import json
import shutil
from collections import Counter
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from pathlib import Path

from socnavgen.campaign.episode import Episode, EpisodeSettings, warm_up_compiled
from socnavgen.campaign.executors import EXECUTORS, batches, run_work
from socnavgen.campaign.fingerprint import inputs_of, what_changed, write_inputs
from socnavgen.campaign.scenarios import Suite, build_suite
from socnavgen.campaign.spec import CampaignSpec
from socnavgen.campaign.store import PARTS, EpisodeStore
from socnavgen.errors import InputFileError
from socnavgen.locks import held
from socnavgen.safeio import atomic_write_json, atomic_write_text

SCENARIOS_FILE = "scenarios.json"
METRICS_FILE = "metrics.json"
CAMPAIGN_FILE = "campaign.json"
LOCK_FILE = ".socnavgen-lock"


@dataclass
class CampaignResult:
    out: Path
    total: int  # episodes in the campaign
    skipped_done: int  # already in the table (resumed)
    ran: int
    failed: int
    suite: Suite
    rerun: dict[str, int] = field(default_factory=dict)  # why rows on disk were not kept -> how many episodes
    problems: list[str] = field(default_factory=list)  # unreadable part files set aside


def plan_episodes(spec: CampaignSpec, suite: Suite) -> list[Episode]:
    """Every scenario x policy x seed, ordered by location then scenario (workers keep their map)."""
    ordered = sorted(suite.scenarios, key=lambda s: (s.location_dir, s.id))
    return [Episode(s, p.name, p.robot, seed, params=tuple(sorted(p.params.items())))
            for s in ordered for p in spec.policies for seed in spec.seeds]


def check_policies(spec: CampaignSpec) -> None:
    """Load every policy once before any episode: a typo in the campaign file is one clear error, not a
    table full of failed episodes (a policy that crashes *during* an episode fails only that episode)."""
    from socnavgen.sim import robot_from

    for policy in spec.policies:
        try:
            robot_from(policy.robot, policy.params)
        except InputFileError as exc:
            raise InputFileError(f"policy {policy.name}: {exc.message}", hint=exc.hint) from exc


def settings_of(spec: CampaignSpec) -> EpisodeSettings:
    sim = spec.simulation
    timeout = None if sim.timeout == "route" else sim.timeout  # None: each scenario's route decides
    return EpisodeSettings(dt=sim.dt, timeout=timeout, throttle=sim.throttle, wall_timeout=sim.wall_timeout,
                           verify=spec.verify, metrics=tuple(spec.metrics) if spec.metrics else None,
                           vary_people=sim.vary_people, trajectory_hz=spec.trajectories)


def write_definitions(out: Path, metrics: list[str] | None) -> None:
    """metrics.json: every metric column with its unit and formula (the report shows the same)."""
    from socnavgen.sim.metric_definitions import metric_definitions

    atomic_write_json(out / METRICS_FILE, metric_definitions(metrics))


def run_campaign(spec: CampaignSpec, out: Path, *, executor: str = "local", workers: int | None = None,
                 address: str | None = None, batch_size: int = 4,
                 progress: Callable[[int, int], None] | None = None) -> CampaignResult:
    """Run every episode whose row (for the same inputs) is not yet in OUT; `progress(done, total)` after each
    batch. One `campaign run` per folder at a time; a start that fails leaves no folder it created."""
    out = Path(out)
    if executor not in EXECUTORS:
        raise InputFileError(f"unknown executor {executor!r}", hint=f"use one of {', '.join(EXECUTORS)}")
    _same_campaign(spec, out / CAMPAIGN_FILE)
    check_policies(spec)
    created = not out.exists()
    out.mkdir(parents=True, exist_ok=True)
    try:
        with held(out / LOCK_FILE, f"campaign folder {out}",
                  "wait for the other `campaign run` on it to finish, or choose another -o folder"):
            return _run_locked(spec, out, executor, workers, address, batch_size, progress)
    except BaseException:
        if created and not any((out / PARTS).glob("part-*")):  # nothing but what this start wrote
            shutil.rmtree(out, ignore_errors=True)
        raise


def _same_campaign(spec: CampaignSpec, previous: Path) -> None:
    """A folder holds one campaign (by name); its file may change: the episodes it affects run again."""
    if not previous.is_file():
        return
    try:
        name = json.loads(previous.read_text()).get("name")
    except (ValueError, OSError, AttributeError):
        name = None
    if name is not None and name != spec.name:
        raise InputFileError(f"this folder holds another campaign ({name!r}, not {spec.name!r})", file=previous,
                             hint="choose another -o folder (or give the campaign its earlier name)")


def _run_locked(spec: CampaignSpec, out: Path, executor: str, workers: int | None, address: str | None,
                batch_size: int, progress: Callable[[int, int], None] | None) -> CampaignResult:
    suite = build_suite(spec, out)
    settings = settings_of(spec)
    inputs = inputs_of(spec, suite, settings)
    atomic_write_text(out / CAMPAIGN_FILE, spec.model_dump_json(indent=2, exclude={"base_dir"}) + "\n")
    atomic_write_json(out / SCENARIOS_FILE, {"scenarios": [s.to_dict() for s in suite.scenarios],
                                             "skipped": suite.skipped})
    write_inputs(out, inputs)
    write_definitions(out, spec.metrics)
    store = EpisodeStore(out, spec.metrics)
    episodes = [replace(ep, inputs=inputs.of(ep)) for ep in plan_episodes(spec, suite)]
    stored, older = store.done()
    todo = [ep for ep in episodes if (ep.key, ep.inputs) not in stored]
    changed = Counter(what_changed(older[ep.key], ep.inputs or "", ep.scenario.id, ep.policy)
                      for ep in todo if ep.key in older)
    total, finished, failed = len(episodes), len(episodes) - len(todo), 0
    if progress:
        progress(finished, total)
    if todo:
        store.unfinish()
        warm_up_compiled()  # once here: forked workers inherit it, others load it from numba's cache
        runner = EXECUTORS[executor](workers=workers, address=address)
        try:
            for rows in run_work(runner, batches(todo, batch_size), settings):
                for row in rows:
                    store.add(row)
                    failed += row["status"] != "ok"
                finished += len(rows)
                if progress:
                    progress(finished, total)
        finally:
            store.flush()
            runner.close()
    store.consolidate({ep.key: ep.inputs or "" for ep in episodes})
    return CampaignResult(out, total, len(episodes) - len(todo), len(todo), failed, suite,
                          rerun=dict(changed), problems=store.problems)
