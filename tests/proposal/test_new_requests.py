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
# prompts), round 13 answers (the seventh session's) and round 14 re-recordings (the eighth session's: eight requests
# whose recordings ended under the current pipeline, answered again live), replayed on the eighth session's code and
# judged from GIF frames by six sessions that read no code and saw no verdict (round 14 of the eyes). Four lenient
# passes (a spec that says less than the prose: where a person comes from, a wait at a distance; two people passing
# 0.19 m apart that the eyes saw as touching) and one strict fail the eyes accepted. warehouse_03 (the fourth worker
# came round another way) and home_09 (a child left in the hallway) agree since verify/way_in.py and way_end.py;
# home_09's order of followers is also refused at stage 1 now (REFUSED) until it is answered again live.
DISAGREE: dict[str, str] = {
    "hospital_06_night_wandering_patient": "lenient PASS: the patient stands at 8z until the robot calls her at ~40 s; "
    "she never wanders toward the south elevator, so the interception the text is about does not happen "
    "(verify/way_in.py's `walks` sees it, a warning while WALKS_REQUIRED is off: required, home_05's recording ends)",
    "hospital_07_assisted_rehab_walk": "lenient PASS: the nurse steps aside into the opening the pair is heading for "
    "and walks on past the patient at ~30-31 s (people_apart measured 0.19 m between the bodies: the eyes saw the "
    "discs overlap), and the patient ends in the doorway, not inside her room",
    "hospital_10_meal_tray_family_in_doorway": "lenient PASS: the robot does not wait at the counter 2-2.5 m back "
    "until the way is clear; it moves into the family still standing round zs, passing at ~0.3 m, and the doorway "
    "visitor backs into the room (no criterion holds the robot back until they have stepped aside)",
    "warehouse_07_night_patrol_west_corridor": "strict FAIL the eyes accepted: the robot stopped at ~32 s 1.5 m from "
    "the worker at f7 and said EXCUSE ME (again at ~49 s); he stepped aside at ~66 s, 35 s after the phrase, while the "
    "text has him step aside when it says it (the judge saw the times and the second EXCUSE ME and called it a match)",
    "warehouse_12_carrying_toolbox_for_technician": "lenient PASS: the picker never walks up the aisle from yh; she "
    "stands at its north end ~30 s and waits in its mouth, so the robot holding back for someone coming through a "
    "blind aisle becomes a standoff she breaks (no criterion states that she comes up the aisle)",
}

# Fixtures whose recorded answers never pass a stage (a stage check refuses them, or the recording ends where the
# pipeline now asks what the live run was never asked), each with why: the replay stops at that stage.
REFUSED: dict[str, str] = {
    "home_03_welcome_dinner_guests": "scenario: both recorded answers put the second guest behind Human 1 with a "
    "follows_robot only, which measures each follower from the robot (prose_checks.person_order_mistakes); the eyes "
    "saw the guests come down the hallway in the reverse order",
    "home_09_telepresence_grandma_kids_follow": "scenario: every recorded answer has Leo 'behind his sister' with a "
    "follows_robot only (person_order_mistakes): round 14's run passed with the two children in the reverse order",
    "warehouse_10_against_the_unloading_crew": "scenario: its first answer measures each worker filing behind another "
    "from the robot, its correction relates each pair only by a spread (the same whichever walks first): "
    "person_order_mistakes refuses both (the eyes saw the file in the text's order)",
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
