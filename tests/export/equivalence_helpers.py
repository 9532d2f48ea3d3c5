"""Simulate a run from its socrates trees and from their hunav2 translation, verify both against the
run's own expectations (derived from the socrates trees), and compare the outcomes."""

from __future__ import annotations

import re
import shutil
from pathlib import Path

from socnavgen.bt.expand import load_instance
from socnavgen.bt.library import HUNAV2, LIBRARY
from socnavgen.export.hunav2 import translate_tree
from socnavgen.export.models import ExportScene
from socnavgen.run import RunFolder
from socnavgen.sim.scenario import simulate_run
from socnavgen.sim.trace import Trace
from socnavgen.verify.runner import verify_trace


def stands_for(tree_xml: str) -> dict[str, str]:
    """2.x node -> the library node of this tree it translates (the 2.x node recording that action)."""
    out: dict[str, str] = {}
    for node in load_instance(tree_xml, "t").root.walk():
        tr = HUNAV2.get(node.name)
        if tr is None or tr.template is None or node.name not in LIBRARY:
            continue
        templates = [tr.template] + [t for c in tr.by_value.values() for t in c.values()]
        for template in templates:
            names = re.findall(r"<(\w+)", template)
            out.setdefault(names[-1] if names[0] == "Sequence" else names[0], node.name)
    return out


def relabel(trace: Trace, per_human: list[dict[str, str]]) -> Trace:
    """The hunav2 trace with each 2.x node's actions and successes recorded under the library node it
    stands for, so the socrates expectations ("human1 executes FollowRobot") apply to it."""
    names = trace.node_names
    action, succeeded = trace.action.copy(), trace.succeeded.copy()
    for h, mapping in enumerate(per_human):
        for native, ours in mapping.items():
            a, b = names.index(native), names.index(ours)
            action[trace.action[:, h] == a, h] = b
            fired = (trace.succeeded[:, h] >> a) & 1
            succeeded[:, h] |= fired << b
    trace.action, trace.succeeded = action, succeeded
    return trace


def hunav2_twin(run_dir: Path, scene: ExportScene, out: Path) -> Path | None:
    """A copy of the run whose behaviors are the hunav2 translations (goal queue from paths.json, as in
    the original), or None if a tree is refused."""
    texts = {}
    for human in scene.humans:
        text, problems = translate_tree(human, None)
        if problems:
            return None
        texts[human.name] = text
    shutil.copytree(run_dir, out)
    for name, text in texts.items():
        (RunFolder(out).behaviors_dir / f"{name}.xml").write_text(text)
    return out


def outcomes(run_dir: Path, scene: ExportScene, work: Path) -> tuple[dict, dict] | None:
    """(socrates outcome, hunav2 outcome): finding name -> passed, plus 'passed' overall."""
    twin = hunav2_twin(run_dir, scene, work)
    if twin is None:
        return None
    original = simulate_run(run_dir, save=False)
    translated = simulate_run(twin, save=False)
    translated = relabel(translated, [stands_for(h.tree_xml) for h in scene.humans])
    results = []
    for trace in (original, translated):
        report = verify_trace(run_dir, trace)
        results.append({"passed": report.passed, **{f.name: f.passed for f in report.findings}})
    return results[0], results[1]
