"""Runs the evaluation: Table I (scenario proposals) and Tables II-III (paths and trees, ours vs
naive). Every run is an ordinary run folder under OUT/runs/, so an interrupted evaluation resumes and
each result can be inspected, exported or simulated like any other run."""

from __future__ import annotations

import contextlib
import re
from collections.abc import Callable
from dataclasses import dataclass
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

from pydantic import BaseModel, Field

from socnavgen import __version__
from socnavgen.errors import StageFailed
from socnavgen.evaluation.outcome import RunOutcome, read_outcome
from socnavgen.evaluation.suite import EvalSuite
from socnavgen.location import load_location
from socnavgen.run import Manifest, RunFolder, ScenarioRequest
from socnavgen.safeio import atomic_write_json


class EvalSettings(BaseModel):
    llm: str
    out: Path
    runs: int = Field(default=5, ge=1, description="runs per scene and method (Tables II-III)")
    proposals: int = Field(default=5, ge=1, description="proposals per context, with and without rough (Table I)")
    tables: list[str] = Field(default_factory=lambda: ["I", "III"])
    methods: list[str] = Field(default_factory=lambda: ["ours", "naive"])
    verify: bool = True
    use_cache: bool = True
    temperature: float = 0.7
    max_requeries: int = 3
    max_restarts: int = 2
    max_parallel: int = 4


@dataclass
class Job:
    table: str
    scene: str
    method: str
    rough: bool
    index: int
    folder: Path
    request: ScenarioRequest


def _slug(text: str) -> str:
    return re.sub(r"[^a-z0-9]+", "_", text.lower()).strip("_")


def plan_jobs(suite: EvalSuite, settings: EvalSettings, location: str) -> list[Job]:
    """Every run the evaluation needs, in a stable order (so resuming finds the same folders)."""
    common: dict[str, Any] = dict(location=location, llm=settings.llm, temperature=settings.temperature,
                  max_requeries=settings.max_requeries, max_restarts=settings.max_restarts)
    jobs: list[Job] = []
    runs = settings.out / "runs"
    if "I" in settings.tables:
        for scene in suite.proposal_scenes:
            for with_rough in (False, True):
                for i in range(settings.proposals):
                    folder = runs / "table1" / _slug(scene.name) / ("rough" if with_rough else "no_rough") / f"{i:02d}"
                    request = ScenarioRequest(context=scene.context, task=scene.task,
                                              rough=scene.rough if with_rough else None, seed=i, **common)
                    jobs.append(Job("I", scene.name, "proposal", with_rough, i, folder, request))
    if "III" in settings.tables:
        for path_scene in suite.path_scenes:
            for method in settings.methods:
                for i in range(settings.runs):
                    folder = runs / "table3" / _slug(path_scene.name) / method / f"{i:02d}"
                    request = ScenarioRequest(context=suite.path_context, task=suite.path_task,
                                              rough=path_scene.rough, naive=method == "naive", seed=i, **common)
                    jobs.append(Job("III", path_scene.name, method, True, i, folder, request))
    return jobs


def _outcome(job: Job) -> RunOutcome:
    return read_outcome(job.folder, table=job.table, scene=job.scene, method=job.method,  # type: ignore[arg-type]
                        rough=job.rough, index=job.index)


def _propose_only(job: Job, llm) -> None:  # noqa: ANN001 - an LLM
    """Table I measures stage 1 alone: one checked proposal per run folder."""
    from socnavgen.proposal.conversation import Policy, Recorder
    from socnavgen.proposal.scenario import propose_scenarios, to_proposal, to_spec

    run = RunFolder(job.folder)
    run.root.mkdir(parents=True, exist_ok=True)
    run.write_request(job.request)
    manifest = Manifest(socnavgen_version=__version__, created=datetime.now(UTC).isoformat(timespec="seconds"),
                        llm=job.request.llm, model=getattr(llm, "model", None))
    recorder = Recorder(run, manifest)
    policy = Policy(job.request.max_requeries, job.request.max_restarts, job.request.temperature)
    try:
        outcomes = propose_scenarios(job.request, load_location(job.request.location), llm, recorder, policy)
        run.write_scenario(to_proposal(outcomes[0].value))
        spec = to_spec(outcomes[0].value)
        if spec is not None:
            run.write_spec(spec)
        recorder.set_status("scenario", None, "done")
        manifest.status = "done"
    except StageFailed as exc:
        recorder.set_status("scenario", None, "failed")
        manifest.status, manifest.message = "failed", exc.message
    recorder.save()


def _verify(job: Job) -> None:
    from socnavgen.verify import verify_run

    try:
        verify_run(job.folder)
    except Exception as exc:  # a scenario that cannot be simulated does not verify; record why
        atomic_write_json(job.folder / "sim" / "verify.json", {"passed": False, "error": str(exc)})


def run_job(job: Job, settings: EvalSettings) -> RunOutcome:
    """Run one job unless its folder already holds a finished run; return what it achieved."""
    from socnavgen.llm.factory import make_llm
    from socnavgen.proposal.pipeline import generate

    done = _outcome(job)
    if done.finished and (not settings.verify or not done.valid or done.verified is not None):
        return done
    if not done.finished:
        job.folder.mkdir(parents=True, exist_ok=True)
        llm = make_llm(settings.llm, transcript=job.folder / "transcript.jsonl", use_cache=settings.use_cache,
                       max_parallel=settings.max_parallel)
        if job.table == "I":
            _propose_only(job, llm)
        else:
            with contextlib.suppress(StageFailed):  # an invalid run is a result, kept in its manifest
                generate(job.request, llm, job.folder)
    outcome = _outcome(job)
    if job.table == "III" and settings.verify and outcome.valid and outcome.verified is None:
        _verify(job)
        outcome = _outcome(job)
    return outcome


def run_eval(suite: EvalSuite, settings: EvalSettings, location: str,
             on_result: Callable[[Job, RunOutcome], None] | None = None) -> list[RunOutcome]:
    """All jobs in order; an LLM error that retrying cannot fix (bad key, no server) stops everything."""
    results = []
    for job in plan_jobs(suite, settings, location):
        outcome = run_job(job, settings)  # LLMError propagates: nothing else would work either
        results.append(outcome)
        if on_result:
            on_result(job, outcome)
    return results
