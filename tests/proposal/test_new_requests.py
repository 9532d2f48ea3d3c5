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
DISAGREE: dict[str, str] = {
    "hospital_02_guide_visitor_to_room": "lenient PASS: the nurse walks into another room and brushes the visitor "
    "(people touching each other is judged nowhere), the visitor is still in the doorway when the run ends",
    "hospital_06_night_wandering_patient": "lenient PASS (wt-robot, frames at 56-130 s): with the time limit that "
    "follows the route (293 s) the robot completes its round trip at 130.7 s with the patient following 2-3 m behind, "
    "but it still drives up to her spot at 8z and makes her step aside where the text wants it to keep its distance "
    "and turn at 8r; no criterion says so",
    "hospital_05_elevator_at_visiting_hour": "strict FAIL: the model's own hidden_until criterion cannot hold on this "
    "map (the robot sees into the elevator car through the double doors); what the text describes happens",
    "hospital_08_shift_handover_cluster": "lenient PASS: the nurses close up again while the robot is in the gap and it "
    "gets past by backing out and detouring; the criteria (give way after EXCUSE ME, goal, no contact) hold",
    "warehouse_01_blind_corner_cart": "lenient PASS: the robot drives on to a 0.17 m gap of the stopped worker (no "
    "contact by the 5 cm rule, but it looks touching), and the meeting moved to corner 54 while the prose says f7",
    "warehouse_04_pallet_jack_backing_out": "lenient PASS: the worker comes out of the aisle with the robot 9 m away "
    "and walks up to it (pacing releases a person in the robot's way 3 m ahead), not a sudden emergence",
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
    assert row.scenario_valid and row.paths_valid and row.trees_valid
    assert row.eyes_match is not None
    assert row.verified == row.eyes_match, (row.failing, row.eyes)
