"""The capable-model fixtures (tests/fixtures/replay/: the paper's scenes A, B, C with Table II's rough
scenarios verbatim, and a hospital evacuation without rough scenario) replayed through the real pipeline: every
stage valid at its first answer, the spec grounded, every tree meeting its encounter; then simulated, verified, and
the verdict compared with what a person saw in the GIF frames (the `eyes:` block).

Round 38 (2026-11-28) re-answered all four requests live on the day's prompts (sessions playing a capable model
through queue_openai.py, who read no code; `generate --verify`): the recordings of 2026-11-23/24 answered older
prompts, and since the strict verifier (contact at 5 cm, meetings after an approach, reactions after their cause)
none of them verified. A `_verify` fixture is the whole exchange; its plain twin replays the same exchange's first
answers without the loop. hospital_evacuation_v2_verify is a second live answer to the evacuation by another
session."""

from __future__ import annotations

from pathlib import Path

import pytest

from socnavgen.evaluation.fixtures import fixture_paths, fixture_request, replay_fixture
from socnavgen.proposal.tree_needs import tree_need_mistakes
from socnavgen.run import RunFolder

FIXTURES = Path(__file__).resolve().parents[1] / "fixtures" / "replay"
ROOT = Path(__file__).resolve().parents[2]
NAMES = ["hospital_evacuation", "hospital_evacuation_v2_verify", "hospital_evacuation_verify", "paper_scene_a",
         "paper_scene_a_verify", "paper_scene_b", "paper_scene_b_verify", "paper_scene_c"]


def test_the_fixtures_are_there():
    assert [p.stem for p in fixture_paths(FIXTURES)] == NAMES
    rough = {p.stem: fixture_request(p, ROOT).rough for p in fixture_paths(FIXTURES)}
    assert rough["hospital_evacuation"] is None
    assert rough["paper_scene_b"].startswith("Robot turns at a blind corner and encounters a human.")


@pytest.fixture(scope="module")
def replayed(tmp_path_factory) -> dict[str, tuple[object, Path]]:
    out = tmp_path_factory.mktemp("fixtures")
    return {p.stem: (replay_fixture(p, out / p.stem, root=ROOT), out / p.stem) for p in fixture_paths(FIXTURES)}


@pytest.mark.parametrize("name", NAMES)
def test_every_stage_is_valid(replayed, name):
    row, folder = replayed[name]
    assert (row.verify_rounds >= 1) == name.endswith("_verify")  # the loop replays only where it was recorded
    assert row.scenario_valid and row.paths_valid and row.trees_valid
    # every first answer was valid but the v2 evacuation's scenario: a prose check re-asked it once ("human2 behind
    # the visitor" with no criterion stating the order)
    assert row.first_attempt or name == "hospital_evacuation_v2_verify"
    run = RunFolder(folder)
    spec = run.read_spec()
    assert spec is not None and spec.encounters and all(e.node for e in spec.encounters)
    scenario = run.read_scenario()
    assert set(spec.humans()) == set(scenario.human_behaviors)
    for human, xml in run.behaviors().items():
        assert tree_need_mistakes(xml, human, spec) == []


# Verdicts on the day's code. Scene A's first answers fail (the live run's first design): the worker stands at the
# aisle's far end from t = 0 while the robot starts at the other end and drives AWAY, so it never comes within the
# keeps_away distance and no stop follows an approach; the model moved the scene in its second round (the robot
# drives south through the aisle and turns east, the worker walks in and stops as it comes out): the _verify fixture.
# A strict xfail turns red the day one passes.
FAILS = {"paper_scene_a"}


@pytest.mark.parametrize("name", [pytest.param(n, marks=pytest.mark.xfail(
    strict=True, reason="fails verification today (see FAILS)"))
    if n in FAILS else n for n in NAMES])
def test_simulated_and_verified(replayed, name):
    row, _ = replayed[name]
    assert row.verified is True, row.failing
    assert row.min_robustness is not None and row.min_robustness >= 0


# Where the eyes and the verifier differ, with what was seen (round 38's judge, frames of the live run's final answers).
DISAGREE = {
    "hospital_evacuation_v2_verify": "lenient PASS: both FOLLOW ME moments happen and the robot leads both followers "
    "through the double doors to 8r, but the hurrying nurse (walk_past, checked only by meets), told to walk briskly "
    "past without having to stop, faces the group head-on, stands ~2 m from the robot at ~34-35 s and creeps ~36-37 s, "
    "then squeezes past along the north wall ~0.1 m from the visitor (~40 s) and the patient (~41 s)",
}


@pytest.mark.parametrize("name", [pytest.param(n, marks=pytest.mark.xfail(strict=True, reason=DISAGREE[n]))
                                  if n in DISAGREE else n for n in NAMES])
def test_the_verifier_and_the_eyes_agree(replayed, name):
    row, _ = replayed[name]
    if row.eyes_match is None:  # only scene A's first answers, which were never the live run's final ones
        assert name in FAILS and row.verified is False, "every fixture whose answers verify has been looked at"
        return
    assert row.verified == row.eyes_match, (row.failing, row.eyes)
