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
# they agree, and the pin must go). Empty means they agree on every fixture. Round 7 answers, judged 2026-11-26 (third
# session) on that session's code; replayed on the code of s8 (people keep PERSON_KEEP_GAP from each other, the robot
# keeps ROBOT_SOCIAL_GAP, people_apart judged, arrival short of an occupied goal only with no nearer free spot).
# Causes left: events of the text that no criterion of the model's spec states (then no verifier can see them
# missing), and eyes that judged an earlier run of the same answers ("stale eyes").
DISAGREE: dict[str, str] = {
    "home_02_resident_with_cane_in_doorway": "lenient PASS: the robot waits right next to the door and the resident "
    "passes it coming out (gap 0.22 m since s8; the eyes saw 0.17 m as brushing), against the text's 'clear way'",
    "home_04_grandchild_shows_drawing": "lenient PASS: the robot stands stuck in the doorway ~11 s until the child "
    "leaves the drawing spot, then takes the spot itself; the child never faces it at the drawing",
    "hospital_04_telepresence_ward_round": "stale eyes (s8 wave 2: the robot now goes on to the nearer free spot "
    "instead of parking in the doorway). Frames: the four staff start in a compact cluster at i1 (no overlap, no "
    "jump), the robot comes up behind them (~10 s) and waits in the corridor while they file into the room, goes in "
    "last (in the doorway ~50-57 s) and stops at its goal ~1.5 m inside the door beside the team (62.8 s, 0.58 m "
    "from the nurse): by this look it matches its text",
    "home_07_laundry_in_morning_rush": "lenient PASS since wt-people s8-2 (people stand round a taken goal, keep "
    "0.2 m off a standing robot): frames of the replay: after ACKNOWLEDGED (~6 s) the robot still drives up the "
    "hallway instead of stopping in the bedroom doorway, the children pass it (~10-16 s) while it stands in the "
    "north-west corner; the robot and the mother stand face to face in the hallway doorway ~27-35 s (robot gap "
    "0.10 m); it drives close past the father at the interaction point (~48 s) and reaches the bedroom ~57 s. None "
    "of the three yields plays out as written, yet `verify` passes at the end of --verify",
    "hospital_06_night_wandering_patient": "lenient PASS: after FOLLOW ME the robot drives on to ~0.5 m of the "
    "confused patient, where the text has it stop at a respectful distance and wait",
    "warehouse_01_blind_corner_cart": "stale eyes, lenient PASS by a look at today's replay (wt-verify s8 wave 2): the "
    "worker coming down the north leg stops at the corner (LookAtRobot ~33-50 s); the robot neither pulls over nor backs "
    "off but edges round the stopped worker's east side at 0.25 m (38-44 s, 6 s in intimate space) and drives on north; "
    "the worker walks on south-west once it is past (~55 s). No criterion states the robot pulling over or backing off",
    "warehouse_04_pallet_jack_backing_out": "lenient PASS: the worker never backs out across the cross aisle in front "
    "of the robot and the robot never stops; it drives past the worker still standing at the aisle end",
    "warehouse_05_sweeping_at_shift_change": "stale eyes: on today's replay (wt-verify s8 wave 2 look) the three "
    "encounters happen (worker 1 stops in the aisle at ki ~16 s, PROCEED ~30 s and worker 2 walks out past the robot "
    "pulled aside at sh ~35 s, worker 3 passes it at sw ~57 s, gap >= 0.48 m), workers 2 and 3 meet at 9z ~43-47 s "
    "one behind the other without touching; worker 3 still idles at 9z ~50 s before setting off (pacing)",
    "warehouse_07_night_patrol_west_corridor": "stale eyes: on today's replay (88 s; wt-verify s8 wave 2 look) the robot "
    "says PROCEED at 41-44 s before hd, the worker waits (LookAtRobot) and goes down the westernmost aisle first "
    "(45-55 s); at ki the second worker says WAIT at 66.2 s, the robot ACKNOWLEDGED from the same step, waits in the "
    "aisle mouth and she passes west in front of it (70-75 s); closest gap 0.34 m, the workers never touch",
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
