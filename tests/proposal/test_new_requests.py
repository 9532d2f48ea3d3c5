"""The new-request suite (tests/fixtures/new_requests/): 54 requests written by sessions that never read the
code (18 per bundled location, half without a rough scenario: 24 of round 11, 12 of round 13, 6 of round 15, 6 of round
20, 6 of round 22), answered by separate
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
# prompts), round 13 (the seventh session's), round 14 re-recordings (the eighth session's), round 15 (six new
# requests) and round 16 re-recordings (six requests whose recordings the ninth session's checks refused or ended),
# replayed on the ninth session's code; the eyes of rounds 15-16 and of hospital_07 / hospital_10 are round 15's
# (sessions that read no code and saw no verdict), the others round 14's; home_03 and warehouse_12 were re-answered
# live in round 18 and judged, with hospital_04 and hospital_10 (whose runs the tenth session's group circle
# changed), in round 16 of the eyes; home_09 and warehouse_13 re-answered live in round 19 (their recordings ended under
# the tenth session's simulator) and judged in round 17 of the eyes; six new requests of round 20 answered live on the
# tenth session's final code and judged in round 18; home_05, home_10, hospital_04 and hospital_06 re-answered live in
# round 21 on the eleventh session's code (their recordings ended: a walker held at the start is a required `walks`
# failure, an order held at t = 0 fails, people who gave way stay aside) and judged in round 19; six new requests of
# round 22 answered live on the eleventh session's final code and judged in round 20 (home_18 and hospital_17 judged
# again on the twelfth session's replay, round 22 of the eyes, with home_08, home_13, home_16 and hospital_11, which
# verify at their first answers since); home_10, hospital_04, warehouse_04 and warehouse_14 re-answered live in round
# 23 on the twelfth session's place checks and judged in round 21; warehouse_17 re-answered live in round 24 on the
# twelfth session's final code (judged in round 23) and home_18 in round 25 on the thirteenth session's handover code
# (judged in round 24). Four lenient passes (a robot's wait spot and a worker's stop place no criterion states; a
# file of students and a pass the spec does not state; a robot passing a child at 0.3 m where the text says at a
# distance; a resident who leaves her mat as the robot passes, no criterion seeing her stay) and three strict fails
# (a step aside too short for the robot, called a weak point by eye; a pair that gave way together while the robot
# idled; a robot backing beside a patient it passes, judged by eye on an earlier run where it did not).
DISAGREE: dict[str, str] = {
    "hospital_10_meal_tray_family_in_doorway": "strict FAIL: the robot stops ~2.3 m short and says EXCUSE ME, the "
    "family shuffles aside and the robot threads through a ~0.9 m gap into the room without touching anyone (eyes: "
    "yes); the verifier fails the first visitor's give-way, she moved 0.43 m off the robot's route within 6 s, still "
    "inside the 0.85 m its body sweeps, and the robot waited till 20.5 s (the eyes saw the same short step and "
    "called it a weak point)",
    "home_05_serving_drinks_at_party": "strict FAIL (re-answered live in round 21, eyes: yes): the pair at vh "
    "step aside by themselves at ~3-7 s before the robot reaches them, the robot stops ~2 m short of the pair at 41, "
    "says EXCUSE ME, they step aside and it passes without contact; the verifier fails the first guest's step out "
    "of the way (in the robot's way within 3.5 m from 5.2 s, aside only at 27 s: the pair gave way together, the "
    "robot idled at vh ~17 s with its way clear) and 'never stuck' (10.6 s back and forth at vh, 0.57 m from her); "
    "the eyes saw the idling and called it a flaw, not a failure",
    "warehouse_04_pallet_jack_backing_out": "lenient PASS (re-answered live in round 23 on the place checks): the "
    "robot lets the worker go first and drives on only after he passed (closest ~1 m), but his ~5 s stop happens "
    "inside the middle aisle, not across the cross aisle, and the robot does not wait on its side ~3 m before sh: "
    "it pulls ~1.3 m into the mouth of the next rack aisle and is still moving while he stands (the spec bounds "
    "the robot's distance from sh, not where it stands, nor where the worker stops)",
    "hospital_17_lead_students_to_nurse_station": "lenient PASS (round 22): the patient stands ~1 m west of zs "
    "from ~20 to 28 s while the robot swerves, the robot turns into the nurse station ahead of him instead of "
    "passing him in the corridor, the students crowd round him (a touch at ~40 s by eye) instead of passing in file, "
    "and they end ~2 m north of the robot, not round it (no criterion for the file, the pass or the gathering)",
    "home_16_hide_and_seek_laundry": "lenient PASS (verified at its first answers since the twelfth session's "
    "walkable approach; the thirteenth session's replay looked at by the lead, who reads the code): the robot stops "
    "in the zv doorway at ~3 s while both children run by and drives on at ~11 s (before: ~20 s, then a loop away "
    "from its goal), but the seeker stands beside the hider right by its way to iq: it creeps beside her ~14-25 s "
    "and passes ~0.3 m from her as she steps back (5 s within intimate space), reaching lu at 31.5 s (the text has "
    "it pass the children at a distance; no criterion bounds how close it passes them)",
    "hospital_11_disinfecting_west_corridor": "FAIL where the recorded eyes (round 20, on the twelfth session's "
    "run) said yes - the run changed and the lead, who reads the code, saw a new robot flaw in it: the robot pulls "
    "over for the first patient and goes on as before, but as the second patient passes it at ck (~61 s, ~1 m) it "
    "backs ~1.7 m east beside her at up to 0.35 m/s before driving on west (the twelfth session's robot went on west "
    "throughout); the verifier fails 'the robot drives slowly whenever it is within 2 m of the second patient' "
    "(0.35 m/s at 0.99 m, the bound < 0.35); the recording has no answer for the paths stage the loop then asks",
    "home_18_towel_to_living_room_exercise": "lenient PASS (re-answered live in round 25, eyes round 24): the robot "
    "stops inside the bathroom ~2 m from the mat and says EXCUSE ME, the resident comes ~1.2 m in front of it for "
    "~4 s and walks back to the mat, the robot waits till she is back; but then it stalls in the doorway ~0.9 m from "
    "her while she exercises and she leaves her mat ~1.2 m until it has gone by (the text: she stays on the mat while "
    "the robot drives past, not interrupted; the criterion that sees her back at the mat is satisfied before the "
    "robot passes, none sees her stay while it passes)",
}

# Fixtures whose recorded answers never pass a stage (a stage check refuses them, or the recording ends where the
# pipeline now asks what the live run was never asked), each with why: the replay stops at that stage.
REFUSED: dict[str, str] = {
    "warehouse_17_first_aid_kit_to_staging": "scenario: re-answered live in round 24 (its round-22 answers were "
    "refused by the twelfth session's place checks) before the thirteenth session's check of who goes back after "
    "coming to the robot (place_checks.back_mistakes): every answer has the colleague 'walk back to the injured "
    "worker at vj' with no criterion on where he ends up (eyes round 23, on the live run that verified: he never "
    "came within ~2 m of the robot and never went back, standing ~3 m from the group to the end)",
}


def test_the_suite_is_there_and_judged():
    names = [p.stem for p in PATHS]
    assert len(names) == 54
    for location in ("home", "hospital", "warehouse"):
        mine = [p for p in PATHS if p.stem.startswith(location)]
        assert len(mine) == 18
        rough = [fixture_request(p, ROOT).rough for p in mine]
        assert sum(r is None for r in rough) == 9  # half of them without a rough scenario
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
