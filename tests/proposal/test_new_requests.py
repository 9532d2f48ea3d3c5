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
# session) on that session's code. People touching EACH OTHER is judged since s8 (`people_apart`): home_03, home_07,
# hospital_04, hospital_05, warehouse_05 and warehouse_07 fail it (their people's discs touch in the frames) and agree
# with their eyes; hospital_01 and warehouse_08 fail it too while their eyes, which saw the touching, accepted it.
# warehouse_02 agrees since e2's window no longer opens before e1's latched part began (verify/windows.py; seen in
# the frames: stop ~2 m behind the picker at 13.5 s, EXCUSE ME at 15 s, the picker walks out and steps aside at
# 17.5 s, the robot passes at 23.6 s and reaches p0 at 33.8 s while she walks back).
# Left: the robot passing people at 0.10-0.17 m (no contact by the 5 cm rule, brushing to the eyes: the eyes call
# 0.10 m "close but not touching" in home_06 and 0.17 m "brushing" in home_02, so no gap threshold agrees with both),
# and events of the text that no criterion of the model's spec states (then no verifier can see them missing).
_BUMP = "two people's bodies touch each other (gap 0.00 m)"
DISAGREE: dict[str, str] = {
    "home_02_resident_with_cane_in_doorway": "lenient PASS: the robot waits right next to the door and the resident "
    "brushes it coming out (~23 s, gap 0.17 m), against the text's 'clear way' and 'safe distance'",
    "home_04_grandchild_shows_drawing": "lenient PASS: the robot stands stuck in the doorway ~11 s until the child "
    "leaves the drawing spot, then takes the spot itself; the child never faces it at the drawing",
    "hospital_01_elevator_door_standoff": f"strict FAIL (people_apart): every event of the text happens, but {_BUMP}: "
    "the two visitors (one group) walk shoulder to shoulder with their discs touching at 1.4 s and 15-22 s (seen in "
    "the frames, 2026-11-26 s8); the eyes noted the overlap and judged the run as matching - the same bump that "
    "counts against home_03 and warehouse_05 (wt-people: group members keep apart)",
    "hospital_06_night_wandering_patient": "lenient PASS: after FOLLOW ME the robot drives up to ~0.4 m of the confused "
    "patient, who has to give way, where the text has it stop at a respectful distance and wait",
    "warehouse_04_pallet_jack_backing_out": "lenient PASS: the worker never backs out across the cross aisle in front "
    "of the robot and the robot never stops; it drives past the worker still standing at the aisle end",
    "warehouse_08_group_at_staging_pallet": f"strict FAIL (people_apart): the events happen as written, but {_BUMP} "
    "for a moment: the two packers standing together at the pallet touch (gap 0.04-0.05 m, 0.1 s at 38.4 s, as they "
    "start to give way; their discs touch in the frames at 37.5-38.4 s), which the eyes did not count",
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
