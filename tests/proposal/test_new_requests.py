"""The new-request suite (tests/fixtures/new_requests/): 48 requests written by sessions that never read the
code (16 per bundled location, half without a rough scenario: 24 of round 11, 12 of round 13, 6 of round 15, 6 of round
20), answered by separate
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
# tenth session's final code and judged in round 18. One lenient pass (a robot's wait at a distance), one strict fail
# (a step aside too short for the robot, called a weak point by eye) and one recording that ends (home_05). Agreeing
# since the eleventh session: hospital_06 (its old first answer's patient held at the bench is a required `walks`
# failure, way_in.py; re-answered live in round 21: verified at its first answers, as written by eye in round 19) and
# hospital_04 (its "doctor goes first" held at t = 0, verify/witness.held_at_the_start: a spec failure whose re-ask
# ends the recording; its robot stopping 1.2 m short of the doorway someone stands in is still an arrival).
DISAGREE: dict[str, str] = {
    "hospital_10_meal_tray_family_in_doorway": "strict FAIL: the robot stops ~2.3 m short and says EXCUSE ME, the "
    "family shuffles aside and the robot threads through a ~0.9 m gap into the room without touching anyone (eyes: "
    "yes); the verifier fails the first visitor's give-way, she moved 0.43 m off the robot's route within 6 s, still "
    "inside the 0.85 m its body sweeps, and the robot waited till 20.5 s (the eyes saw the same short step and "
    "called it a weak point)",
    "home_05_serving_drinks_at_party": "recording ends (eyes: yes on the final run): the first answer's guest "
    "human3 stands in the bathroom h9 for 31 s (walked 0.23 m) until the robot comes into view, while her text has "
    "her come out on her way to the dining area; verify/way_in.py's `walks` decides where the spec states the walk "
    "(since the eleventh session), so the loop re-asks the paths in round 1, which the live run never was: "
    "re-record it live",
    "warehouse_04_pallet_jack_backing_out": "lenient PASS: the robot does not stop ~3 m short; it drives up to the "
    "aisle mouth at sh within ~2 m of the worker backing out, then dodges north between the racks, and the worker's "
    "stop to swing the jack happens inside the aisle end, not across the cross aisle (no criterion says where the "
    "robot stands or where the worker stops)",
}

# Fixtures whose recorded answers never pass a stage (a stage check refuses them, or the recording ends where the
# pipeline now asks what the live run was never asked), each with why: the replay stops at that stage.
REFUSED: dict[str, str] = {}


def test_the_suite_is_there_and_judged():
    names = [p.stem for p in PATHS]
    assert len(names) == 48
    for location in ("home", "hospital", "warehouse"):
        mine = [p for p in PATHS if p.stem.startswith(location)]
        assert len(mine) == 16
        rough = [fixture_request(p, ROOT).rough for p in mine]
        assert sum(r is None for r in rough) == 8  # half of them without a rough scenario
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
