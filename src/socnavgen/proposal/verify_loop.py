"""`--verify`: simulate the generated run, and when the intended interaction did not happen, re-query
the stage the verifier blames (paths or behaviors) with its findings as the correction, up to the
restart budget. The verifier (socnavgen.verify) is optional: without it `--verify` says so."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from socnavgen.proposal.conversation import ProgressEvent, bullet_list
from socnavgen.proposal.templates import render
from socnavgen.run import PathPlan, ScenarioProposal

if TYPE_CHECKING:
    from socnavgen.proposal.pipeline import _Pipeline

STAGE = "verify"


def _describe(finding: Any) -> str:
    who = f" ({finding.human})" if getattr(finding, "human", None) else ""
    return f"{getattr(finding, 'name', 'check')}{who}: {getattr(finding, 'evidence', '')}".strip()


def verify_and_repair(pipeline: _Pipeline, scenario: ScenarioProposal, paths: PathPlan,
                      trees: dict[str, str]) -> tuple[ScenarioProposal, PathPlan, dict[str, str], Any]:
    from socnavgen.proposal.pipeline import verifier

    verify_run = verifier()
    run, recorder = pipeline.run, pipeline.recorder
    report: Any = None
    for round_ in range(pipeline.policy.max_restarts + 1):
        (run.sim_dir / "trace.npz").unlink(missing_ok=True)  # the trace of the previous answer is stale
        recorder.set_status(STAGE, None, "running")
        recorder.progress(ProgressEvent(STAGE, None, "attempt", round_ + 1))
        report = verify_run(run.root)
        recorder.update(STAGE, None, lambda r: setattr(r, "attempts", r.attempts + 1))
        # Warnings (e.g. a collision, which judges the robot, not the scenario) are not the model's to fix.
        failing = [f for f in report.findings if not f.passed and getattr(f, "required", True)]
        recorder.mistakes(STAGE, None, [_describe(f) for f in failing])
        if report.passed:
            recorder.set_status(STAGE, None, "done")
            recorder.progress(ProgressEvent(STAGE, None, "done"))
            return scenario, paths, trees, report
        if round_ == pipeline.policy.max_restarts:
            break
        recorder.progress(ProgressEvent(STAGE, None, "invalid", round_ + 1, message="; ".join(map(_describe, failing))))
        blamed_paths = [f for f in failing if getattr(f, "stage", None) == "paths"]
        if blamed_paths:
            text = render("verify_correction.md", findings=bullet_list([_describe(f) for f in blamed_paths]))
            paths = pipeline.paths(scenario, correction=text)
            continue
        corrections: dict[str, str] = {}
        for human in scenario.human_behaviors:
            mine = [f for f in failing if getattr(f, "human", None) in (human, None)]
            if mine:
                corrections[human] = render("verify_correction.md", findings=bullet_list([_describe(f) for f in mine]))
        trees = pipeline.behaviors(scenario, paths, corrections or None)
    recorder.set_status(STAGE, None, "failed")
    recorder.progress(ProgressEvent(STAGE, None, "failed", message="the verifier still finds problems"))
    return scenario, paths, trees, report
