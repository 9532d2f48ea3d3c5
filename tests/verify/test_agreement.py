"""One definition of contact (sim/contact.py) for every count: on every row of a campaign and on many traces,
`collisions`, HuNavSim's `robot_on_person_collision` / `person_on_robot_collision`, `success` and the verifier
agree. HuNavSim's collision sides classify the same (step, person) contact pairs `collisions` counts (its bearing
test may leave a pair unattributed: both still, or the same speed)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pyarrow.parquet as pq
import pytest

from socnavgen.campaign.runner import run_campaign
from socnavgen.campaign.spec import parse_campaign
from socnavgen.run.spec import ScenarioSpec
from socnavgen.sim import contact
from socnavgen.sim.metrics import compute_metrics
from socnavgen.verify import verify_trace
from tests.campaign.conftest import campaign_yaml

from .corpus import base_plan, make_corner_location, write_case_run
from .verify_builders import build_trace


def agree(collisions: int, robot_hits: int, person_hits: int, success: bool, no_contact: bool | None,
          verified: bool | None) -> list[str]:
    """What must hold between the counts of one episode (empty: they agree)."""
    wrong = []
    if no_contact is not None and no_contact != (collisions == 0):
        wrong.append(f"no_collision {no_contact} but {collisions} contact steps")
    if (robot_hits + person_hits > 0) and collisions == 0:
        wrong.append(f"HuNavSim counts {robot_hits}+{person_hits} collisions, collisions 0")
    if success and collisions:
        wrong.append("success with a contact")
    if verified and not success:
        wrong.append("verified without success")
    return wrong


def test_every_row_of_a_small_campaign_agrees(tmp_path: Path) -> None:
    text = campaign_yaml(["blind-corner", "pedestrian-obstruction", "narrow-doorway", "crowd-navigation"],
                         ["scripted", "{name: bad, robot: straight}"], 1)
    run_campaign(parse_campaign(text), tmp_path / "c", executor="inline")
    rows = pq.read_table(tmp_path / "c" / "episodes.parquet").to_pylist()
    assert len(rows) == 8 and all(r["status"] == "ok" for r in rows)
    problems = []
    for r in rows:
        verdicts = json.loads(r["verdicts"])
        # judged (a run that ended before anything could happen has no robustness and no contact verdict)
        (no_contact,) = [v["passed"] if v.get("robustness") is not None else None for v in verdicts
                         if v["kind"] == "no_collision"]
        wrong = agree(r["collisions"], r["robot_on_person_collision"], r["person_on_robot_collision"], r["success"],
                      no_contact, r["verified"])
        problems += [f"{r['episode']}: {w}" for w in wrong]
    assert not problems, problems
    assert any(r["collisions"] > 0 for r in rows)  # the rude robot touches people: the check is not vacuous


@pytest.fixture(scope="module")
def corner_run(tmp_path_factory: pytest.TempPathFactory) -> Path:
    root = tmp_path_factory.mktemp("agree")
    plan = base_plan().model_copy(update={"humans": base_plan().humans[:1]})
    return write_case_run(root / "run", make_corner_location(root / "corner"), ScenarioSpec(), plan)


def test_many_traces_agree_near_the_contact_margin(corner_run: Path) -> None:
    """120 robot-person passes whose closest gap straddles the 5 cm margin (overlaps, touching, 2-8 cm), the
    robot or the person moving: every count agrees with the verifier's no_collision."""
    rng = np.random.default_rng(25)
    t = np.arange(81) * 0.1
    seen = set()
    for k in range(120):
        closest = rng.uniform(-0.05, 0.1)
        offset = 0.75 + closest
        robot_moves = bool(k % 2)
        rx = 1.0 + 0.5 * t if robot_moves else 2.6 + 0.1 * t
        hx = np.full_like(t, 3.0) if robot_moves else 5.0 - 0.3 * t
        robot = np.stack([rx, np.full_like(t, 1.5)], 1)
        human = np.stack([hx, 1.5 + np.full_like(t, offset) * (1.0 if k % 3 else -1.0)], 1)[:, None]
        trace = build_trace(t, robot, human, dt=0.1, goal=tuple(robot[-1]), end_reason="robot_goal")
        trace.robot_waypoints = [tuple(robot[0]), tuple(robot[-1])]
        metrics = compute_metrics(trace)
        report = verify_trace(corner_run, trace)
        (finding,) = [f for f in report.findings if f.kind == "no_collision"]
        assert finding.robustness is not None
        no_contact = finding.passed
        wrong = agree(metrics["collisions"], metrics["robot_on_person_collision"], metrics["person_on_robot_collision"],
                      metrics["success"], no_contact, report.passed)
        assert not wrong, (k, closest, wrong)
        assert metrics["collisions"] == contact.summarize(trace).collision_steps
        seen.add(metrics["collisions"] > 0)
    assert seen == {True, False}
