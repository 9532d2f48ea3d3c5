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
# they agree, and the pin must go). Empty means they agree on every fixture. Round 11 answers (six sessions playing a
# capable model on the fifth session's prompts of 2026-11-26), replayed on that session's final code and judged from
# GIF frames by three sessions that read no code and saw no verdict (round 11 of the eyes).
# Causes left: a robot that lets someone go first (let_pass) while that person waits for IT (people do not step
# round a robot standing on their way: home_06, home_07; the robot then goes first when she stands aside:
# warehouse_01), a person cutting between the robot and the patient it guides (hospital_07); a visitor who
# never stepped aside nor boarded (hospital_01, the eyes were generous); and two specs that ask more than the eyes did
# (hospital_05, warehouse_04).
DISAGREE: dict[str, str] = {
    "home_06_neighbour_lets_herself_in": "lenient PASS: PROCEED and her surprised pause happen (~6 s), but the robot "
    "waits in the middle of the living room on her way (let_pass): she is held up ~9 s less than 0.5 m from it and "
    "gets past only when it drives off (~19 s); no criterion of the spec states her going first. Since s11 (people "
    "walk round a robot standing on a point of their way) the replay verifies at its first answer, another run: "
    "frames show the robot stopping ~1.5 m west of vh where the room narrows (no room either side of it), the "
    "neighbour's pause after z2 (~5-7 s), her standing ~0.5 m east of it ~11-18 s, the robot moving aside south-east "
    "(~16-18 s) and her going round its north side (~18-21 s, 0.11 m as it moves) and on west; the round-11 run "
    "(robot parked on 41) replayed on s11 code: she goes round its north side at 0.2 m at ~11-12 s without stopping "
    "and is at ai by 16 s: to be judged again",
    "home_07_laundry_in_morning_rush": "lenient PASS: the first yield works (the robot waits in the bedroom doorway "
    "for the son); at the second the daughter comes within ~0.3 m of the waiting robot, retreats and waits while the "
    "robot goes first: 'lets her cross first' reversed. Since s11 (a walker between two goals does not make room) "
    "the same run's frames show her walking on from 41 past the waiting robot (~23-24 s, closest 0.29 m) through zv "
    "into the bathroom (~25 s) and the robot driving on only then (25.5 s): to be judged again",
    "hospital_07_assisted_rehab_walk": "lenient PASS: the nurse steps aside but walks on at ~25 s before the patient "
    "has passed, cutting between the robot and the patient ~0.1 m from her; the run ends with the patient in the "
    "doorway, not back in her room. Since s11 (a giver-way lets the robot's follower by) the frames show the nurse "
    "standing aside by the zs door until the patient has come by (~30.5 s) and walking west behind her "
    "(nurse-patient closest 0.20 m, was 0.10 m); the run's end not looked at again",
    "warehouse_01_blind_corner_cart": "lenient PASS: the worker stops and the robot pulls into the corner pocket, but "
    "at ~38 s the robot drives north while the worker still stands beside it, and he walks on only after it left: the "
    "order of the text reversed (the let_pass limit ran out with him standing aside). Since s11 (people walk round "
    "a robot standing on a point of their way) the replay's frames show him stopping (LookAtRobot ~31-35 s), the "
    "robot tucking into the pocket (~33-36 s), him setting off at ~36 s round its north-west side (~0.5 m) and west "
    "along the corridor to 54 while the robot leaves the pocket north (~38 s): to be judged again",
    "hospital_01_elevator_door_standoff": "strict FAIL: the eyes saw the pair block the robot, step aside to two "
    "sides after EXCUSE ME (~5 s), the robot pass without contact and the visitors board after it left. The trace "
    "(frames 0-30 s) shows human1 stepping aside, but human2 walked from the robot's route to a spot 1.2 m off it "
    "before the robot came out (0-4 s) and stood there still from 5 s on: the robot turned away from her, she never "
    "stepped aside after the phrase (reacts_after_phrase, gives_way: never; the old reading 'aside from t=1.5 s' "
    "was her walk off the route 5 m ahead round the bend, fixed in verify aside); and at the end she stands at the "
    "car door 1.6 m from lc behind human1 (x 14.5, the door at 15.0): not in the elevator. The scene's fault",
    "hospital_05_elevator_at_visiting_hour": "strict FAIL: the eyes saw the robot stop ~2 m before 1g for the visitor "
    "with the cane and back aside to let the couple out of the elevator before boarding; the spec's stl 'the robot "
    "does not drive up to the elevator door until the first visitor has left the lobby' measures its text: the "
    "robot came within 1 m of q9 at 35.5 s with the couple past it but still in the lobby (human2 1.9 m short of the "
    "double doors cc, through them at ~38 s, frames 33-38 s). The criterion asks more than the scenario's prose "
    "('lets them come out and pass it before it drives to q9') and than the eyes judged; the loop sends it to stage "
    "1 (U1 then spec), where the recording has no answer",
    "warehouse_08_group_at_staging_pallet": "lenient PASS: the replay now ends at the FIRST answer (its group "
    "parting and give-ways are judged right since the verifier's parting and let-through measures, session 11); the "
    "eyes judged round 3's run. Frames of the first answer: the robot stops ~0.5 s about 2 m before the packers, "
    "says EXCUSE ME and drives on at 0.3-0.45 m/s while they still step aside, passes packer 3 at a 0.45 m gap "
    "(~31 s) and packer 2 at 0.33 m (~40.5 s), and the packers gather again round vj (~48 s): it does not wait "
    "until the way is clear, which the prose asks and no criterion of the spec states",
    "warehouse_04_pallet_jack_backing_out": "strict FAIL: the eyes (round 11) saw the worker back out and block the "
    "aisle ~16-29 s, the robot wait and go on after the worker left. Since s11 the robot holds in front of the worker "
    "walking out to block it (blocks_robot passes); frames of the s11 replay: it stops ~1.3 m west of sh as she "
    "backs out (16 s) and stands, not veering, while she blocks it on the route ~0.75 m ahead (~17-22 s); she steps "
    "back into the aisle mouth (~22 s), it drives on east beneath her (23-27 s, closest gap 0.70 m in the run) and "
    "she walks west only after (~29 s): the stl 'the robot does not drive on east before the worker ... walked off "
    "west past it' fails, rightly for that run (she waits for the robot on her way instead of walking past it: "
    "people side)",
    "warehouse_03_fire_alarm_evacuation": "strict PASS since s11 (was a FAIL with the eyes): the eyes (round 11) saw "
    "the robot and four workers deadlocked in a clump from ~25 s to the timeout. On s11 code (the robot never makes "
    "way for its own followers, slows for one falling behind) the frames show FOLLOW ME at ~7 s, the robot going down "
    "to vj among the three (~16-22 s), then a line along the south cross aisle - robot, workers 2, 3, 1, worker 4 "
    "following worker 1 (~26-48 s) - and the robot at the loading door with the four behind it at 56 s: the eyes' "
    "verdict is of the old run; to be judged again",
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
