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
# capable model on the fifth session's prompts of 2026-11-26), replayed on the sixth session's code and judged from
# GIF frames by three sessions that read no code and saw no verdict (round 12 of the eyes).
# Causes left: a robot waiting for someone right on her line (she stalls before it, then squeezes past: home_06), a
# person walking back into the robot's side as it passes (0.10 m, "touching" to the eyes: hospital_08); a blocker
# hovering at ~0.1 m/s at her block point, which breaks the 1 s standoff (home_01); a visitor who never stepped aside
# (hospital_01: the eyes were generous twice); and two specs that ask more than the eyes did (hospital_05,
# warehouse_04).
DISAGREE: dict[str, str] = {
    "home_06_neighbour_lets_herself_in": "lenient PASS: the robot says PROCEED and waits, but on the open floor west "
    "of vh right on her line: she stands face to face ~0.4-0.5 m from it ~11-17 s until it sidles south-west, then "
    "squeezes past its north side at ~0.15 m (~20 s); no criterion of the spec states her calm walk past",
    "hospital_08_shift_handover_cluster": "lenient PASS: every event of the text happens, but at ~29 s the nurse "
    "walking back to the counter comes against the robot's side as it passes between the nurses (closest gap 0.10 m "
    "at 29.1 s: no contact for the verifier, outlines meeting for the eyes; the text excludes touching)",
    "home_01_child_blocks_vacuum": "strict FAIL: the eyes saw the child run up in front of the robot (~9-11 s, ~0.1 m), "
    "back off to ~0.5 m and stand blocking while it holds, shift with it when it turns to go round, and run off only "
    "after EXCUSE ME (~15 s); blocks_robot misses its 1 s standoff by 0.01: standing at her block point (~12.75-14.25 "
    "s) the child hovers at 0.04-0.11 m/s, and a sample above 0.1 m/s breaks the hold (a route-aware 'in the way' "
    "changes nothing here)",
    "hospital_01_elevator_door_standoff": "strict FAIL: the eyes (rounds 11 and 12) saw both visitors give way after "
    "EXCUSE ME and board after the robot left. The trace: human2 walked from the robot's route to a spot 1.2 m off "
    "it before the robot came out (0-4 s) and stood there from 5 s on, never stepping aside after the phrase; at the "
    "end she stands at the car door 1.6 m from lc, not in the car: the verifier is right, the eyes generous",
    "hospital_05_elevator_at_visiting_hour": "strict FAIL: the eyes saw the robot stop ~2.3 m before 1g for the "
    "visitor with the cane, back off in the lobby while the couple left the elevator and passed, then board; the "
    "spec's stl 'the robot does not drive up to the elevator door until the first visitor has left the lobby through "
    "the double doors' sees the robot 0.07 m from q9 at 37.1 s and the visitor 0.12 m from cc at 39.4 s: the "
    "criterion asks more than the prose and the eyes ('pass it before it drives to q9')",
    "warehouse_04_pallet_jack_backing_out": "strict FAIL: the eyes saw the worker back out and block ~15-22 s and the "
    "robot stop ~1.5 m short and wait; she cleared the way by stepping back into the aisle mouth and walked west only "
    "after the robot passed, which the eyes called minor and the spec's stl ('does not drive on east before the "
    "worker ... walked off west past it') does not (robot 0.02 m from sw at 32.8 s, she at ki at 32.7 s)",
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
