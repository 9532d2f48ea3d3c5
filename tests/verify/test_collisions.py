"""One definition of gap and contact (sim/contact.py): `simulate`'s summary, metrics.json (collisions, success,
HuNavSim's collision sides) and verify show the same numbers for the same run."""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pytest

from socnavgen.cli.common import console
from socnavgen.cli.sim_cmd import _print_outputs
from socnavgen.location import load_location
from socnavgen.sim import contact, write_outputs
from socnavgen.sim.metrics import compute_metrics
from socnavgen.verify import VerifySettings, verify_trace

from .verify_builders import build_trace


def _pass_by(gap_at_closest: float, steps_still: int = 3):  # noqa: ANN202
    """Robot at (3, 3) standing; human1 walks along y = 3 toward it and stands with the given surface gap
    (centre distance = gap + 0.35 + 0.4) for `steps_still` steps, then walks back."""
    stop = 3.0 + gap_at_closest + 0.75
    xs = [7.0, 6.0, 5.0] + [stop] * steps_still + [6.0, 7.0]
    n = len(xs)
    return build_trace(np.arange(n) * 0.5, [(3.0, 3.0)] * n, [[(x, 3.0)] for x in xs], dt=0.5)


def test_gap_and_collision_definition() -> None:
    trace = _pass_by(-0.20)
    gaps = contact.trace_gaps(trace)
    assert gaps.min() == pytest.approx(-0.20)
    summary = contact.summarize(trace)
    assert summary.collision_steps == 3 and summary.collision_seconds == pytest.approx(1.5)
    assert summary.first_collision_time == pytest.approx(1.5) and summary.first_collision_human == "human1"
    assert summary.worst_overlap == pytest.approx(0.20) and summary.min_gap == pytest.approx(-0.20)
    # contact is a gap of 5 cm or less: touching, nearly touching, overlapping; 6 cm is not
    for gap, steps in ((-0.02, 3), (-0.005, 3), (0.0, 3), (0.03, 3), (0.06, 0)):
        assert contact.summarize(_pass_by(gap)).collision_steps == steps, gap
    assert contact.summarize(_pass_by(0.50)).describe() == "closest gap 0.50 m to human1 at t=1.5 s"
    # time within someone's intimate space (gap < 0.45 m), said beside the closest gap
    assert contact.summarize(_pass_by(0.30)).describe() == ("closest gap 0.30 m to human1 at t=1.5 s; 1.5 s within "
                                                            "someone's intimate space (gap < 0.45 m)")


def test_metrics_and_verify_agree_on_collisions(give_way_run: Path, tiny_location: Path) -> None:
    trace = _pass_by(-0.20, steps_still=5)
    metrics = compute_metrics(trace)
    report = verify_trace(give_way_run, trace)
    (finding,) = [f for f in report.findings if f.kind == "no_collision"]
    # the robot stood still and human1 walked into it: its tree is to fix (rule C3)
    assert not finding.passed and finding.required and (finding.blame, finding.blame_human) == ("behaviors", "human1")
    steps = int(re.search(r"(\d+) steps in contact", finding.evidence)[1])
    assert metrics["collisions"] == steps == contact.summarize(trace).collision_steps == 5
    assert metrics["minimum_distance_to_people"] == 0.0  # the evaluator clamps the gap at 0 ...
    assert finding.distance == pytest.approx(-0.20)  # ... the verifier shows the overlap itself
    assert finding.robustness == pytest.approx(-0.25)  # gap - the 5 cm contact margin
    warn = verify_trace(give_way_run, trace, settings=VerifySettings(collisions_fail=False))
    assert [f.name for f in warn.warnings] == [finding.name]


def test_simulate_summary_prints_the_same_numbers(tmp_path: Path, tiny_location: Path) -> None:
    trace = _pass_by(-0.20, steps_still=4)
    with console.capture() as cap:
        _print_outputs(trace, write_outputs(trace, load_location(tiny_location), tmp_path))
    printed = cap.get()
    written = json.loads((tmp_path / "metrics.json").read_text())
    assert f"collisions = {written['collisions']}" in printed and written["collisions"] == 4
    assert "closest gap -0.20 m to human1" in printed and "4 steps in contact" in printed


def test_a_clear_run_agrees_too(give_way_run: Path) -> None:
    trace = _pass_by(0.35)
    (finding,) = [f for f in verify_trace(give_way_run, trace).findings if f.kind == "no_collision"]
    assert finding.passed and finding.robustness == pytest.approx(0.30)
    assert "closest gap 0.35 m to human1" in finding.evidence
    assert compute_metrics(trace)["minimum_distance_to_people"] == pytest.approx(0.35)
    assert compute_metrics(trace)["collisions"] == 0
