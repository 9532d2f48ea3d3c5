"""The new-request suite (tests/fixtures/new_requests/): 36 requests written by sessions that never read the
code (12 per bundled location, half without a rough scenario: 24 of round 11, 12 of round 13), answered by separate
sessions playing a capable model through the real prompts (`generate --verify` against queue_openai.py), recorded as replay fixtures. Each
fixture carries what a person saw in the GIF frames of its final answers (`eyes`). Replayed here through the
real pipeline: every stage's first answer valid or corrected within its stage, and the verifier's verdict on the
end of the --verify loop the same as the person's (docs/measurements.md has the table and what was seen)."""

from __future__ import annotations

from pathlib import Path

import pytest

from socnavgen.evaluation.fixtures import fixture_paths, fixture_request, replay_fixture
from socnavgen.safeio import load_yaml_file

FIXTURES = Path(__file__).resolve().parents[1] / "fixtures" / "new_requests"
ROOT = Path(__file__).resolve().parents[2]
PATHS = fixture_paths(FIXTURES)

# Where the verifier and the eyes disagree today, each with what was seen (a strict xfail: it turns red the day
# they agree, and the pin must go). Empty means they agree on every fixture. Round 11 answers (the fifth session's
# prompts) and round 13 answers (the seventh session's prompts: four players' sessions, twelve new requests),
# replayed on the seventh session's code and judged from GIF frames by four sessions that read no code and saw no
# verdict (round 13 of the eyes). Causes left: a spec that asks more than the eyes did (hospital_05). (The
# lenient passes of specs and plans that said less than their prose, home_09, hospital_11 and warehouse_07, are
# refused by proposal/prose_checks.py: see REFUSED and tests/proposal/test_prose_checks.py.) warehouse_10 agrees
# since speeds are judged as a person sees them (verify/perceived.py: the lead worker's 0.25 s slow step to
# 0.09 m/s while bending round the robot is no stop).
DISAGREE: dict[str, str] = {
    "hospital_05_elevator_at_visiting_hour": "strict FAIL: the eyes saw the robot stop ~2 m before 1g for the visitor "
    "with the cane and let the couple out of the elevator and past it before boarding; the spec's stl 'the robot does "
    "not drive up to the elevator door until the first visitor has left the lobby through the double doors' asks more "
    "than the prose (the robot 0.99 m from q9 at 35.6 s, the visitor 1.95 m from cc; no speed in it); frames of the "
    "replay show the robot at q9 at ~36.5-37.2 s with both visitors still in the lobby at the double doors, through "
    "them at ~38 s (the eyes' 'only then, ~40 s' misread the time), and the new loop asks stage 1 where the live run "
    "was not asked (the recording ends there)",
}

# Fixtures whose recorded answers never pass a stage (a stage check refuses them, or the recording ends where the
# pipeline now asks what the live run was never asked), each with why: the replay stops at that stage.
REFUSED: dict[str, str] = {
    "home_09_telepresence_grandma_kids_follow": "scenario: the text has the older child right behind the robot and "
    "its follows_robot allows 4.5 m (the eyes: he stood 12 s by the table, 3.25 m away, and passed); stage 1 is asked "
    "for at most the close-follow gap (prose_checks), and the recording has no answer for it",
    "warehouse_07_night_patrol_west_corridor": "scenario: the text has the second worker walk on behind the robot "
    "and no criterion about her can see who goes first (the eyes: she walked ahead of it to the door); stage 1 is "
    "asked for one (prose_checks), and the recording has no answer for it",
    "hospital_10_meal_tray_family_in_doorway": "paths: live, stage 2 was asked 12 times to put the family's meeting "
    "3 m from the robot's start, a distance only stage 1's meets criterion decides (the run ended in error); the "
    "pipeline now sends that cause to stage 1 after stage 2's second answer, and the recording has no stage-1 answer "
    "for it",
}


def test_the_suite_is_there_and_judged():
    names = [p.stem for p in PATHS]
    assert len(names) == 36
    for location in ("home", "hospital", "warehouse"):
        mine = [p for p in PATHS if p.stem.startswith(location)]
        assert len(mine) == 12
        rough = [fixture_request(p, ROOT).rough for p in mine]
        assert sum(r is None for r in rough) == 6  # half of them without a rough scenario
    for path in PATHS:
        data = load_yaml_file(path)
        assert data.get("verify_loop") is True, path.stem
        eyes = data.get("eyes")
        assert isinstance(eyes, dict) and isinstance(eyes.get("matches"), bool) and len(eyes.get("seen", "")) > 40, \
            f"{path.stem}: no judgement by eye"


@pytest.mark.parametrize("path", [pytest.param(p, id=p.stem, marks=pytest.mark.xfail(
    strict=True, reason=DISAGREE[p.stem])) if p.stem in DISAGREE else pytest.param(p, id=p.stem) for p in PATHS])
def test_the_verifier_and_the_eyes_agree(path, tmp_path):
    row = replay_fixture(path, tmp_path / path.stem, root=ROOT)
    if path.stem in REFUSED:
        stage = REFUSED[path.stem].split(":")[0]
        assert not getattr(row, f"{stage}_valid") and row.verified is None and row.eyes_match is not None
        return
    assert row.scenario_valid and row.paths_valid and row.trees_valid
    assert row.eyes_match is not None
    assert row.verified == row.eyes_match, (row.failing, row.eyes)
