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
# they agree, and the pin must go). Empty means they agree on every fixture. Judged 2026-11-26 (round 6) on the
# final code of that day. Five lenient passes share one cause: people pass the robot at exactly 0.10 m (the gap
# their own steps keep, sim/people/avoid.py KEEP_GAP / MIN_PASS_GAP), which is no contact by the 5 cm rule but reads
# as touching in the GIF.
_TOUCH = "a gap of 0.10 m, which the eyes read as touching (no contact by the verifier's 5 cm rule)"
DISAGREE: dict[str, str] = {
    "home_02_resident_with_cane_in_doorway": "lenient PASS: the resident walks into the waiting robot's spot "
    f"instead of on to the west end; {_TOUCH} at 31.6 s and again as the robot squeezes to the door",
    "home_05_serving_drinks_at_party": f"lenient PASS: a guest walks back to her spot into the passing robot, {_TOUCH}",
    "home_07_laundry_in_morning_rush": f"lenient PASS: the daughter comes out as the robot reaches 41, {_TOUCH}",
    "hospital_02_guide_visitor_to_room": "lenient PASS: the robot stands on the nurse's crossing point and creeps "
    f"on, she squeezes behind it ({_TOUCH}); the visitor sets off before she has passed",
    "hospital_05_elevator_at_visiting_hour": "lenient PASS: the robot waits in the middle of the lobby in the exit "
    f"path, not beside the door; the couple squeeze past ({_TOUCH}) where the text wants a wide berth",
    "hospital_06_night_wandering_patient": "lenient PASS: after FOLLOW ME the robot drives up to the elevator where "
    "the patient stood and makes her step aside for ~20 s instead of turning round at the lobby centre",
    "warehouse_03_fire_alarm_evacuation": "strict FAIL, the verifier is right (wt-verify s7 looked at the frames): "
    "after FOLLOW ME the first worker (FollowRobot) stands still at 9z from 13 s to 37 s while the robot drives 5 m "
    "south, then runs to catch up (6.6 m walkable behind at 37 s); a follower who stands while the leader leaves is "
    "not following; the eyes call the late catch-up minor. Cause: the follower waiting (simulator), not the verifier",
    "warehouse_01_blind_corner_cart": "stale eyes, not a verifier bug: the eyes judged the robot before wt-robot s7 "
    "(standoff, timeout); since the robot slows near people and a waiting robot steps right of its way (robot.polite near_speed, wait_aside) it PASSES at the end "
    "of --verify, and frames at 34/37/40/43 s show the worker stopping at f7, the robot pulled into the corner pocket "
    "south of f7 (closest gap ~0.3 m), the worker walking on west past it, the robot going north to hd: re-judge by eye",
    "warehouse_04_pallet_jack_backing_out": "lenient PASS: the worker comes out with the robot ~8 m away, walks at it "
    "and stands in front of it looking at it; no backing out across the aisle at sh, which the text wants. No criterion "
    "passed vacuously (wt-verify s7): the --verify repair moved the meeting from sh to ki and no criterion states the "
    "text's event (out of the aisle at sh when the robot is ~3 m away, not looking at it): the spec stage's job",
}

# Fixtures whose recorded answers a stage check added since refuses, each with why; the recording has no answer
# that passes, so the replay stops at that stage (the eyes' judgement of the recorded end stays in the fixture).
REFUSED: dict[str, str] = {}


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
