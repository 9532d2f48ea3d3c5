"""The new-request suite (tests/fixtures/new_requests/): 78 requests written by sessions that never read the
code (26 per bundled location, half without a rough scenario: 24 of round 11, 12 of round 13, 6 of round 15, 6 of round
20, 6 of round 22, 6 of round 27, 6 of round 29, 6 of round 30, 6 of round 32), answered by separate
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

# Where the verifier and the eyes disagree today, each with what was seen (a strict xfail: it turns red the day they
# agree, and the pin must go). Empty means they agree on every fixture. Round 11 answers (the fifth session's
# prompts), round 13 (the seventh session's), round 14 re-recordings (the eighth session's), round 15 (six new
# requests) and round 16 re-recordings (six requests whose recordings the ninth session's checks refused or ended),
# replayed on the ninth session's code; the eyes of rounds 15-16 and of hospital_07 / hospital_10 are round 15's
# (sessions that read no code and saw no verdict), the others round 14's; home_03 and warehouse_12 were re-answered
# live in round 18 and judged, with hospital_04 and hospital_10 (whose runs the tenth session's group circle changed),
# in round 16 of the eyes; home_09 and warehouse_13 re-answered live in round 19 (their recordings ended under the
# tenth session's simulator) and judged in round 17 of the eyes; six new requests of round 20 answered live on the
# tenth session's final code and judged in round 18; home_05, home_10, hospital_04 and hospital_06 re-answered live in
# round 21 on the eleventh session's code (their recordings ended: a walker held at the start is a required `walks`
# failure, an order held at t = 0 fails, people who gave way stay aside) and judged in round 19; six new requests of
# round 22 answered live on the eleventh session's final code and judged in round 20 (home_18 and hospital_17 judged
# again on the twelfth session's replay, round 22 of the eyes, with home_08, home_13, home_16 and hospital_11, which
# verify at their first answers since); home_10, hospital_04, warehouse_04 and warehouse_14 re-answered live in round
# 23 on the twelfth session's place checks and judged in round 21; warehouse_17 re-answered live in round 24 on the
# twelfth session's final code (judged in round 23) and home_18 in round 25 on the thirteenth session's handover code
# (judged in round 24); home_10, hospital_13, warehouse_14 and warehouse_17 re-answered live in round 26 on the
# thirteenth session's final code (their recordings ended unverified) and judged in round 25; six new requests of
# round 27 answered live on the fourteenth session's code (home_19 and warehouse_20 again in round 28 on its back
# check) and judged in round 27; the seven fixtures pinned before and five drawn at random (warehouse_01, home_02,
# warehouse_07, warehouse_11, hospital_11) judged again on the fourteenth session's replay in round 26, where all five
# drawn agreed and hospital_10, home_16 and warehouse_04 now agree (eyes no, yes, yes); six new requests of round 30
# answered live on the sixteenth session's starting code and judged in round 30, and the eighteen fixtures whose final
# run the sixteenth session's code changed by more than 0.6 m judged again in round 31 (home_22 and hospital_13 now
# agree); six new requests of round 32 answered live on the seventeenth session's starting code and judged in round
# 32 (all six verified live and judged as written), and the four fixtures whose final run that session's code moved by
# more than 0.6 m judged again in round 33; home_05, home_10, warehouse_17, warehouse_22 and warehouse_26, whose
# recordings no longer replayed to the end (the --verify loop asked a stage the live run never answered), re-answered
# live in round 34 on that session's final code and judged in round 34; hospital_04 and home_10, whose verdicts the
# twentieth session's people rules changed (a team files through a door, a resident no longer held in its mouth),
# judged again in round 38 on that session's final code (both as written); home_09 agrees since the twenty-first
# session's verify/way_end.py (eyes round 31: no - both children stood at the door of the roomy bedroom the robot led
# them into; a follower at a door passes only when no spot is left inside). Left: the lenient passes and strict fails
# below, each with what was seen.
DISAGREE: dict[str, str] = {
    "hospital_17_lead_students_to_nurse_station": "lenient PASS (round 22; eyes round 26: no): the patient waits "
    "facing the robot near zs ~8 s, then is boxed in by the bunched students ~15 s; the students never pass him one "
    "by one and only one of them ends with the robot at the nurse station (no criterion for the file, the pass or "
    "the gathering)",
    "home_24_water_past_children_chasing": "lenient PASS (a new request of round 30; eyes rounds 30 and 31: no): the "
    "robot waits ~2.8 m before 41 while the children run to the sofa corner, then sets off as they run back through "
    "the room towards it and creeps ~8 s past a child standing by the dining table with ~0.3 m between the bodies; "
    "its 'until' criterion held once both children were near ai (13.6 s) and no criterion bounds how close it "
    "passes ('keeping well clear')",
    "hospital_01_elevator_door_standoff": "lenient PASS (recorded in round 14; eyes round 31, on the sixteenth session's run: "
    "no): the visitors stop facing the robot at the elevator door, give way on EXCUSE ME - both to the same side - "
    "and the robot goes to the nurse station; the first visitor goes into the car, the second stops outside it at "
    "8z to the end (her walk ends by the queue rule beside the one inside); on the eighteenth session's final code the first goes to the back of the car (sim.people.spots.tight) and the second ends in its door (not re-judged); since the nineteenth session's lift helper (verify/way_end.py judges walkers into a room) she ends at x 15.25 (before: 15.04, in the door's mouth), half her body in the car's 0.4 m door, which way_end reads as inside (its centre past the door's narrowest point; frames at 23-35.8 s: she stands in the door)",
    "hospital_24_follow_nurse_to_west_room": "lenient PASS (a new request of round 30, failed live; eyes rounds 30-31 "
    "and round 33, on the seventeenth session's run: no): since that session the visitor starts in her doorway x5 "
    "(before: drawn into the corridor beside i1) and the run verifies, but the robot sits at i1 ~16 s (14-30 s) and "
    "the patient squeezes through between it and the visitor ~0.6-0.7 m from it instead of the robot passing her; in "
    "the room the robot drives round the nurse within ~1 m and ends beyond her, not behind her; no criterion sees "
    "who passes whom at i1 nor where the robot stops behind the nurse",
    "warehouse_22_parcel_run_past_safety_briefing": "lenient PASS (a new request of round 29, re-answered live in round "
    "34 on the seventeenth session's final code; eyes round 34: no): the robot stops ~2 m north of the briefing and "
    "says EXCUSE ME; one listener 'gives way' by walking north past its side ~0.1 m from it, the robot then crawls "
    "into the group's own spot at vj and stands ~0.05-0.1 m from another listener for ~5 s, and a worker passes it "
    "head-on at sh ~0.1 m clear; no contact by the 5 cm rule, and its spec loosened the group's spread to 5 m",
    "hospital_23_ward_round_group_oncoming": "lenient PASS (re-answered live in round 37 on the nineteenth session's "
    "starting code; eyes round 37: no): the doctor and two students walk east as a line along the corridor, never "
    "abreast; on EXCUSE ME the doctor (avoid) veers into the nurse-station opening ~1.2 m beyond the wall line and "
    "nearly stalls, the students trail after him, and the robot passes only once they came back out walking normally "
    "(1.3-1.9 m, no contact); no criterion sees the group abreast, nor the doctor walking on, and the player widened a "
    "student's reaction window to 9 s",
    "hospital_15_running_child_in_corridor": "lenient PASS (a new request of round 20; eyes round 31, on the sixteenth session's run: "
    "no, 'borderline'): the robot stops at the south wall, waits for the child (passing ~1.05 m from it) and then "
    "the parents and delivers to g3; the child brakes from ~1.8 to ~1 m/s passing the robot instead of running past "
    "without slowing, and the parents walk one behind the other",
}

# Fixtures whose recorded answers never pass a stage (a stage check refuses them, or the recording ends where the
# pipeline now asks what the live run was never asked), each with why: the replay stops at that stage.
REFUSED: dict[str, str] = {
    "home_18_towel_to_living_room_exercise": "scenario: re-answered live in round 25; the fourteenth session's back "
    "check refuses its answer: 'back on her mat' is stated only by an upper bound on her distance to 41, which held "
    "before she left it (eyes round 26, on the run it verified before: no - she leaves her mat as the robot comes "
    "through the doorway and returns only after it passed)",
}


def test_the_suite_is_there_and_judged():
    names = [p.stem for p in PATHS]
    assert len(names) == 90
    for location in ("home", "hospital", "warehouse"):
        mine = [p for p in PATHS if p.stem.startswith(location)]
        assert len(mine) == 30
        rough = [fixture_request(p, ROOT).rough for p in mine]
        assert sum(r is None for r in rough) == 15  # half of them without a rough scenario
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
