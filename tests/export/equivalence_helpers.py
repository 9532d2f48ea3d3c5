"""Simulate a run from its socrates trees and from their hunav2 translation, verify both against the
run's own expectations (derived from the socrates trees), and compare the outcomes."""

from __future__ import annotations

import shutil
from pathlib import Path

from socnavgen.export.as_target import relabel, stands_for
from socnavgen.export.hunav2 import translate_person
from socnavgen.export.models import ExportScene
from socnavgen.run import RunFolder
from socnavgen.sim import simulate_run
from socnavgen.verify.runner import verify_trace


def hunav2_twin(run_dir: Path, scene: ExportScene, out: Path) -> Path | None:
    """A copy of the run whose behaviors are the hunav2 translations (goal queue from paths.json, as in
    the original; phrase conditions as the robot script's; no timing: our pacing stays on), or None if a tree
    is refused."""
    texts = {}
    for human in scene.humans:
        done = translate_person(human, None, scene)
        if done.problems:
            return None
        texts[human.name] = done.text
    shutil.copytree(run_dir, out)
    for name, text in texts.items():
        (RunFolder(out).behaviors_dir / f"{name}.xml").write_text(text)
    return out


PHRASE_NODES = ("RobotSays(", "RobotSaid(")


def _compared(finding) -> bool:  # noqa: ANN001 - verify.models.Finding
    """Every criterion; of the warnings, all but those about a phrase node: the 2.x tree has none (it became the
    robot script's condition), so "RobotSays(...) succeeds" or "... before its cause RobotSays held" cannot
    be said of it - what those conditions make the person do is judged by the criteria."""
    return finding.required or not any(p in finding.name or p in finding.evidence for p in PHRASE_NODES)


def outcomes(run_dir: Path, scene: ExportScene, work: Path) -> tuple[dict, dict] | None:
    """(socrates outcome, hunav2 outcome): finding name -> passed (see _compared), plus 'passed' overall."""
    twin = hunav2_twin(run_dir, scene, work)
    if twin is None:
        return None
    original = simulate_run(run_dir, save=False)
    translated = simulate_run(twin, save=False)
    translated = relabel(translated, [stands_for(h.tree_xml) for h in scene.humans])
    reports = [verify_trace(run_dir, trace) for trace in (original, translated)]
    dropped = {f.name for r in reports for f in r.findings if not _compared(f)}
    results = [{"passed": r.passed, **{f.name: f.passed for f in r.findings if f.name not in dropped}} for r in reports]
    return results[0], results[1]
