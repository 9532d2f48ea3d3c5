"""Proof in our simulator that exported scenarios happen as the targets run them (issue 27): every card on
every bundled location and every replay fixture, simulated from the socrates and hunav2 exports with our pacing
off and a waypoint robot (export.as_target), verifies whenever the run verifies in our own simulator (the
scripted robot, our pacing, its own trees) - at least 95 % of the cards, the fixtures but the named misses.

Kept fast: each card runs at ONE robot speed, 0.5x, 1x and 1.5x in turn (so each speed covers a third of the
cards); the fixtures at all three. The full matrix (every card at every speed, and the robot's own reference)
is `python benchmarks/export_targets_bench.py` (docs/export.md has its table)."""

from __future__ import annotations

from pathlib import Path

import pytest

from socnavgen.export.as_target import SPEEDS, TIMED_TARGETS, run_as_target, target_twin
from socnavgen.sim.scenario import simulate_run
from socnavgen.verify.runner import verify_trace

# (target, fixture, speed) -> why it does not verify as the target runs it; the test fails if another misses
# or if one of these starts to verify (then remove it here).
KNOWN_MISSES = {
    ("socrates", "paper_scene_b_verify", 0.5): "the waypoint robot turns the blind corner into the worker who "
                                               "stops there and never gets past (also with our own pacing at 1x)",
    ("socrates", "paper_scene_b_verify", 1.0): "as at 0.5x",
    ("socrates", "paper_scene_b_verify", 1.5): "as at 0.5x",
    ("hunav2", "paper_scene_b_verify", 0.5): "as for socrates",
    ("hunav2", "paper_scene_b_verify", 1.0): "as for socrates",
    ("hunav2", "paper_scene_b_verify", 1.5): "as for socrates",
    ("socrates", "hospital_evacuation_v2_verify", 1.5): "a robot at 0.75 m/s outruns the patient who follows it "
                                                        "(also with our own pacing)",
    ("hunav2", "hospital_evacuation_v2_verify", 1.5): "as for socrates",
}


@pytest.fixture(scope="module")
def outcomes(bundled_runs, tmp_path_factory) -> list[tuple[str, str, str, float, bool, str]]:  # noqa: ANN001
    """(kind, label, target, speed, verified, why not) of every run that verifies in our simulator."""
    work = Path(tmp_path_factory.mktemp("as_target"))
    rows = []
    for k, (kind, label, run) in enumerate(bundled_runs):
        if not verify_trace(run, simulate_run(run, save=False)).passed:
            continue
        speeds = SPEEDS if kind == "fixtures" else (SPEEDS[k % len(SPEEDS)],)
        for target in TIMED_TARGETS:
            twin = target_twin(run, target, work / target / label.replace("/", "__"))
            for speed in speeds:
                if twin.refused:
                    rows.append((kind, label, target, speed, False, "refused: " + twin.refused))
                    continue
                report = run_as_target(twin, speed)
                rows.append((kind, label, target, speed, report.passed, "; ".join(f.name for f in report.failures)))
    return rows


@pytest.mark.parametrize("target", TIMED_TARGETS)
def test_cards_happen_as_the_target_runs_them(outcomes, target: str) -> None:  # noqa: ANN001
    rows = [r for r in outcomes if r[0] == "cards" and r[2] == target]
    assert len(rows) >= 60 and {r[3] for r in rows} == set(SPEEDS)  # nearly every card verifies in our simulator
    missed = [f"{label} at {speed:g}x: {why}" for _, label, _, speed, ok, why in rows if not ok]
    assert len(missed) <= 0.05 * len(rows), missed


def test_fixtures_happen_as_the_targets_run_them(outcomes) -> None:  # noqa: ANN001
    rows = [r for r in outcomes if r[0] == "fixtures"]
    assert {r[1] for r in rows} >= {"paper_scene_a", "paper_scene_c", "hospital_evacuation_v2_verify"}
    missed = {(target, label, speed): why for _, label, target, speed, ok, why in rows if not ok}
    assert set(missed) == set(KNOWN_MISSES), {k: v for k, v in missed.items() if k not in KNOWN_MISSES}
