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
# they agree, and the pin must go). Empty means they agree on every fixture. Round 7 answers, replayed on the code of
# 2026-11-26's fourth session (people keep PERSON_KEEP_GAP from each other and stand round a shared goal, the robot
# keeps ROBOT_SOCIAL_GAP and goes on to the nearer free spot, people_apart judged, reactions stated by the spec) and
# judged from GIF frames by three sessions that read no code and saw no verdict (round 9 of the eyes).
# Causes left: the robot passing a person it could have waited for at 0.2-0.3 m (no contact, "a hair" to the eyes:
# warehouse_01, warehouse_07), two people standing 0.10 m apart (PERSON_KEEP_GAP, "pressed together" to the eyes:
# warehouse_05), events no criterion of the model's spec states (warehouse_04, home_04), and two strict fails where
# the spec asks more than the eyes did (home_01, hospital_05).
DISAGREE: dict[str, str] = {
    "home_01_child_blocks_vacuum": "strict FAIL: the eyes saw the child stand in the hallway opening in front of the "
    "stopped robot ~10.5-12.5 s, EXCUSE ME ~12.8-15 s, the child step back and follow to the dining area, the robot "
    "reach ai (~31 s); blocks_robot fails (the cue says EXCUSE ME when the child is 1.6 m ahead, she stands 1.5 m "
    "ahead: the block ends as it begins, the verifier's hint asks the spec for `lasts`)",
    "home_05_serving_drinks_at_party": "lenient PASS since the robot waits at its social gap instead of squeezing past "
    "(s10): frames of that code show the robot come up between the waiting pair (~36-40 s) and stand 0.30 m from "
    "human5 while human6 stands on its goal; human6 steps off south-west (~43-46 s) and the robot drives onto her spot "
    "(~48 s) with her beside it, as round 9's eyes saw; they wanted it to stop at a polite distance in front of the pair",
    "home_04_grandchild_shows_drawing": "lenient PASS: the child walks to the drawing spot and stands there; the robot "
    "creeps from i6 to the doorway (11-18 s), the child walks away ~1.2 m as it comes in and the robot drives onto "
    "the child's spot; the child never stops to wait for it on the way",
    "hospital_01_elevator_door_standoff": "strict FAIL since s10 (wt-people: a goal the robot stands on gives a spot "
    "beside it): the visitors, whose goal is the elevator the robot stands in, head for spots beside the door before "
    "EXCUSE ME (human2 'gives way' at 1.5 s, the phrase at 4.7 s); the eyes saw the old run's face-to-face standoff",
    "home_07_laundry_in_morning_rush": "lenient PASS since s10 (wt-people: standing gap, spots off the robot's way): "
    "the verifier now passes the final answers; the eyes judged the old run (not yet looked at in the new GIF)",
    "warehouse_01_blind_corner_cart": "lenient PASS: the worker stops at the corner (~33 s); the robot neither backs "
    "off to f7 nor pulls over but swerves round him, 'within a hair' at 42-45 s (gap ~0.25 m), and he walks on only "
    "after it passed; no criterion states the robot yielding",
    "warehouse_04_pallet_jack_backing_out": "lenient PASS: the worker never backs out across the cross aisle in front "
    "of the robot and the robot never stops; it drives past her still swinging the jack in the aisle mouth",
    "warehouse_05_sweeping_at_shift_change": "lenient PASS: the encounters at ki and sh happen, but worker 2 walks into "
    "worker 3 at the staging pallet and the two stand 'pressed together' ~45-53 s (0.10 m apart, PERSON_KEEP_GAP: "
    "no contact by the 5 cm rule) and worker 3 meets the robot at vj, not at sw",
    "hospital_06_night_wandering_patient": "strict FAIL of the replay, not of the run: the eyes saw the recorded end "
    "play as written; the recording's first tree correction brought the deadlock back with the same numbers (42.4 s "
    "from t=52.3 s, then t=52.0 s), so the loop now sends it to stage 1 (issue 25 part 3: a changed answer that "
    "changes nothing is not asked again), which the round-7 recording never answered (its third tree did it)",
    "warehouse_07_night_patrol_west_corridor": "lenient PASS: PROCEED at hd and the worker first down the aisle as "
    "written; at ki after WAIT/ACKNOWLEDGED the robot pulls out right beside the second worker ('a hand's breadth', "
    "~74-77 s) instead of following behind her",
}

# Fixtures whose recorded answers a stage check added since refuses, each with why; the recording has no answer
# that passes, so the replay stops at that stage (the eyes' judgement of the recorded end stays in the fixture).
REFUSED: dict[str, str] = {
    "home_03_welcome_dinner_guests": "scenario: the host stands to greet the guests (wait_then_go on robot_visible) "
    "but only meets was asked of her, so no verifier could see the greeting stop never happen (the eyes: the guests "
    "walk on past the host); stage 1 now asks the criterion that states the reaction (stops_near_robot)",
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
