"""Every card that fits a bundled location, generated, simulated with the DEFAULT robot (scripted) and
judged by the strict verifier on its spec.json: PASS, zero robot-human overlap, and each encounter within
1 m of its node. Cards that do not pass yet are listed in KNOWN_FAILING with the reason; the test fails
if one of them starts passing (so the list only shrinks) or if any other card fails."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from socnavgen.cards.generate import fit_all, write_card_run
from socnavgen.location import load_location
from socnavgen.sim import simulate_run
from socnavgen.sim.contact import overlapping, trace_distances, trace_gaps
from socnavgen.verify import verify_trace

MEET = 2.0  # m: centre distance that counts as meeting (the verifier's default)

# (location, card) -> why it does not pass yet (docs/cards.md, "Known failures"). Since contact is a gap of 5 cm
# or less (issue 25), the people the simulator puts back on the robot's surface after they walk into it (gap
# 0.005 m) and the scripted robot's 3 cm keep-clear touch people: simulator and card placement work, not the
# verifier's (do not loosen it to shrink this list).
KNOWN_FAILING: dict[tuple[str, str], str] = {
    ("warehouse", "pedestrian-obstruction"): "reacts_after_phrase give_way: seen in the GIF, the person stands still at "
                                             "the node the whole run; the robot drives round her before and after "
                                             "EXCUSE ME while her GiveWaytoRobot node runs (the body never moves; the "
                                             "verifier judges the body since issue 25)",
    # (hospital blind-corner plays out since s17: a meeting's approach counts from the walkable start, and the two
    # start in rooms side by side, 4.2 m apart through their walls; seen in the GIF: hidden from each other until
    # 3.8 m at ~3.8 s, she stops to look at the robot coming out of its door, they pass 0.5 m apart)
    # since people stop short of a goal the robot stands on or drives over (sim/people/avoid.py GOAL_GAP, 2026-11-26
    # s7) instead of sliding along its body at 0.1 m, a card loses its meeting to a robot and a person waiting
    # for each other (warehouse blind-corner plays out again since a goal the robot stands on gives a spot beside it,
    # s10: the worker stops short of the robot at the corner, they pass 0.25 m apart, each goes on its way):
    # (home exiting-room plays out since s11, people pass a robot standing on a point of their way: seen in the GIF,
    # the robot leaving the bedroom stops just inside it beside the door at ~3 s; the person coming down the hallway
    # walks through the door round it at ~4-5 s, 0.20 m off its body, and on to her goal; the robot then leaves;
    # before, both stood face to face in the door for 17 s until the robot backed into the room)
    ("hospital", "narrow-doorway"): "meets at cc: closest 1.35 m, 2.66 m from cc; the robot was nearest the node at "
                                    "t=16.0 s, the person at t=25.4 s (not yet looked at in the GIF)",
}


def _encounter_offsets(run, trace, location) -> list[float]:  # noqa: ANN001
    dist = trace_distances(trace)
    out = []
    for enc in run.read_spec().encounters:
        node = np.array(location.node_world(enc.node))
        k = trace.human_names.index(enc.humans[0].human)
        close = dist[:, k] <= MEET
        mid = (trace.robot[:, :2] + trace.humans[:, k, :2]) / 2
        out.append(float(np.linalg.norm(mid[close] - node, axis=1).min()) if close.any() else float("inf"))
    return out


@pytest.mark.slow
def test_every_card_plays_out_and_verifies_with_the_default_robot(bundled_location: Path, tmp_path: Path) -> None:
    location = load_location(bundled_location)
    fits = [f for f in fit_all(location) if f.fits]
    assert len(fits) >= 15
    unexpected, fixed = [], []
    for fit in fits:
        run = write_card_run(fit.card.name, bundled_location, tmp_path / fit.card.name)
        trace = simulate_run(run.root, location=location, save=False)
        report = verify_trace(run.root, trace, location=location)
        kinds = {f.kind for f in report.findings}
        assert {"robot_reaches_goal", "no_collision", "no_deadlock"} <= kinds  # judged on its spec
        overlap = bool(overlapping(trace_gaps(trace)).any())
        offsets = _encounter_offsets(run, trace, location)
        ok = report.passed and not overlap and all(o <= 1.0 for o in offsets)
        key = (bundled_location.name, fit.card.name)
        if key in KNOWN_FAILING:
            if ok:
                fixed.append(fit.card.name)
            continue
        if not ok:
            why = "; ".join(f"{f.name}: {f.evidence}" for f in report.findings if f.required and not f.passed)
            unexpected.append(f"{fit.card.name}: overlap={overlap} offsets={offsets} {why}")
    assert not unexpected, "cards that do not play out:\n" + "\n".join(unexpected)
    assert not fixed, f"now passing, remove from KNOWN_FAILING: {fixed}"


def test_card_spec_states_the_defining_condition(tmp_path: Path, repo_root: Path) -> None:
    """The blind corner's spec says it is blind; a group card says the group stays together; a card whose
    robot says EXCUSE ME has it as a cue, and the reaction must come after it."""
    warehouse = repo_root / "examples/locations/warehouse"
    blind = write_card_run("blind-corner", warehouse, tmp_path / "b").read_spec()
    assert any(c.kind == "hidden_until" and c.human == "human1" for c in blind.criteria)
    group = write_card_run("join-group", warehouse, tmp_path / "g").read_spec()
    together = [c for c in group.criteria if c.kind == "group_together"]
    assert together and len(together[0].humans) >= 2
    obstruction = write_card_run("pedestrian-obstruction", warehouse, tmp_path / "o").read_spec()
    assert [c.say for c in obstruction.script.cues] == ["EXCUSE ME"]
    assert obstruction.script.cues[0].trigger.when == "blocked"
    phrase = [c for c in obstruction.criteria if c.kind == "reacts_after_phrase"]
    assert phrase and phrase[0].phrase == "EXCUSE ME" and phrase[0].reaction == "give_way"


def test_robot_starts_later_when_its_person_cannot_be_there_in_time(tmp_path: Path, repo_root: Path) -> None:
    """Pacing both ways: people are slowed down by the throttle; a robot whose encounter node is its second
    node (leaving an elevator) waits at its start for the person coming from far away."""
    hospital = repo_root / "examples/locations/hospital"
    spec = write_card_run("exiting-elevator", hospital, tmp_path / "x").read_spec()
    waits = [c for c in spec.script.cues if c.trigger.when == "start" and c.wait > 0]
    assert waits and waits[0].wait >= 1.0
    near = write_card_run("pedestrian-obstruction", hospital, tmp_path / "o").read_spec()
    assert not [c for c in near.script.cues if c.trigger.when == "start"]  # the person is already there

