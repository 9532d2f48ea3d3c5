"""The new-request suite (tests/fixtures/new_requests/): 24 requests written by a session that never read the
code (8 per bundled location, half without a rough scenario), answered by a separate session playing a capable
model through the real prompts (`generate --verify` against queue_openai.py), recorded as replay fixtures. Each
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
# they agree, and the pin must go). Empty means they agree on every fixture.
# No longer pinned: hospital_08 (a step aside undone before the robot got past is no giving way:
# verify/passing.py); warehouse_01 agrees only because its replay stops: its first answers now deadlock 89 s in a
# standoff the spec sets up (blamed on the spec, which the recorded loop never re-asked), while its final answers
# still pass leniently (0.17 m from the stopped worker, the meeting moved to 54: the model's criteria).
DISAGREE: dict[str, str] = {
    "home_08_checking_on_couple_cooking": "lenient PASS: the robot stops 0.2 m from the wife (no contact, within its "
    "criteria) where the text wants it to keep about 2 m without crowding the couple; no criterion says 2 m",
    "hospital_02_guide_visitor_to_room": "lenient PASS: the nurse walks into another room and brushes the visitor "
    "(people touching each other is judged nowhere: on today's simulator people bump at >= 1 m/s in 12 verifying cards, "
    "so a check for it waits for the people to keep apart), the visitor is still in the doorway when the run ends",
    "warehouse_04_pallet_jack_backing_out": "lenient PASS: the worker comes out of the aisle with the robot 9 m away "
    "and walks up to it (pacing releases a person in the robot's way 3 m ahead), not a sudden emergence",
}

# Fixtures whose recorded answers a stage check added since refuses, each with why; the recording has no answer
# that passes, so the replay stops at that stage (the eyes' judgement of the recorded end stays in the fixture).
REFUSED: dict[str, str] = {
    "home_01_child_blocks_vacuum": "paths: the child's two encounters (block, then give way on EXCUSE ME) share node "
    "vh, which stage 2 refuses (one person's two meetings cannot be told apart at one node: proposal/facts.py "
    "TWO_ENCOUNTERS); one meeting is one encounter",
    "hospital_05_elevator_at_visiting_hour": "paths: every recorded route comes into the blind lobby q9 through the "
    "doorway cc, which looks into the elevator car from 11 m, so hidden_until (4 m) cannot hold; stage 2 now "
    "refuses that way in (the inventory names it); before, the verifier failed it after simulating (eyes: the rest "
    "happened as written)",
    "warehouse_01_blind_corner_cart": "scenario: hidden_until 3 m at a BLIND CORNER, whose blindest way in is now "
    "measured at 3.2 m on the worst approach (the player's own runs saw 3.08-3.44 m at f7); stage 1 asks for 4 m "
    "(+0.5 m margin). Its recorded end was a lenient PASS (eyes: no)",
}


def test_the_suite_is_there_and_judged():
    names = [p.stem for p in PATHS]
    assert len(names) == 24
    for location in ("home", "hospital", "warehouse"):
        mine = [p for p in PATHS if p.stem.startswith(location)]
        assert len(mine) == 8
        rough = [fixture_request(p, ROOT).rough for p in mine]
        assert sum(r is None for r in rough) == 4  # half of them without a rough scenario
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
