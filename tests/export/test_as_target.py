"""Proof in our simulator that exported scenarios happen as the targets run them (issue 27): every card on
every bundled location and every replay fixture that verifies in our own simulator (the scripted robot, our
pacing, its own trees) is simulated from the socrates and hunav2 exports with our pacing off and a waypoint
robot (export.as_target), and judged. The export's timing must do what our pacing does: a run the same robot
manages with our pacing and the run's own trees (the reference) verifies as the target runs it, but for the
named misses (KNOWN_LOST, each with why; the test fails if another is lost or one of them verifies again).

Kept fast: each card runs at ONE robot speed, 0.5x, 1x and 1.5x in turn (so each speed covers a third of the
cards); the fixtures at all three. The full matrix (every card at every speed, with the references) is
`python benchmarks/export_targets_bench.py` (docs/export.md has its table)."""

from __future__ import annotations

from pathlib import Path

import pytest

from socnavgen.export.as_target import (
    SPEEDS,
    TIMED_TARGETS,
    run_as_target,
    target_twin,
    timeout_for,
    waypoint_robot,
)
from socnavgen.export.scene import build_scene
from socnavgen.export.timing import start_wait
from socnavgen.run import load_run
from socnavgen.sim import simulate_run
from socnavgen.verify.runner import verify_trace

# (target, card, speed) -> why it misses as the target runs it although our pacing makes it with the same robot
# reacts_after_phrase measures the reaction from the moment the phrase STARTS (issue 25: no credit for a reaction
# to a phrase the robot has been repeating for 20 s); 2.x has no phrase input and no side step: the translated
# person (AvoidRobot on the script's geometric condition) backs away along the passage ahead of the robot and
# leaves its way 10-20 s after EXCUSE ME began (measured: warehouse narrow-hallway said 28.2 s, aside 49.9 s)
_PHRASE_LATE = ("hunav2 has no phrase input and no side step: the person backs away along the passage and leaves the "
                "robot's way 10-20 s after EXCUSE ME began, later than the criterion's window")
# Measured 2026-11-26 on the merged simulator (at one speed per card, socrates 4 and hunav2 5 misses of 59 rows): what
# is lost is hunav2's late give-way in the narrow hallways and one crossing. home/exiting-room (both targets, 1.5x: the waypoint robot
# used to edge into the person at the 0.9 m door) and hunav2 home/pedestrian-obstruction (0.5x) verify as the
# targets run them again; hospital/narrow-hallway runs at 1.5x and warehouse/narrow-hallway at 0.5x only (the speed
# a card runs at follows its place among the cards that fit), so their entries at 0.5x and 1.0x left
# Measured 2026-11-26 (third session) after people stop short of a goal the robot is on and let a robot driving
# across go by: warehouse intersection-no-gesture at 1.5x verifies as both targets run it again (it left the list);
# the crowd in the hospital's lobby and the followers in the home hallway lost to contact with the plain waypoint
# robot for one session; since people keep PERSON_KEEP_GAP from each other and stand round a shared goal (2026-11-26,
# fourth session) both verify as the targets run them again (they left the list)
KNOWN_LOST = {
    # socrates hospital/narrow-hallway at 1.5x verifies again since the release adapts to the robot's own speed
    # (2026-11-27, s13: a 1.5x robot lets the person go from farther; it used to give way too late after EXCUSE ME)
    ("hunav2", "hospital/narrow-hallway", 1.5): _PHRASE_LATE,
    # hunav2 warehouse/narrow-hallway at 0.5x verifies again since a walker held up face to face by the waiting robot
    # makes room (2026-11-27, s16, sim/people/make_room.py; told by the verdicts, not looked at in frames; it left
    # the list)
    # since people coming to stand keep PERSON_STAND_GAP and a goal the robot stands on is taken, and the robot waits
    # behind people (2026-11-26, s10): warehouse/narrow-hallway verifies as hunav2 runs it at 0.5x again
    # since people walk round a robot standing on a point of their way (s11): traced, not yet seen in a GIF of this
    # code - the robot stands on q9 ~1 m outside the elevator; her pass-through goal q9 is dropped, and in the door
    # her way round it (the tangent past its body) runs into the jambs, so she turns north and south by turns ~0.5 m
    # from it and the waiting robot stands over 10 s (keeping her side and a way round her body can walk fixed it, but
    # let people coming out of a door pass a robot beside its exit at 0.22 m: tests/sim/test_robot_margin.py)
    # hospital/entering-elevator at 0.5x (both targets) verifies again since the elevator's door, just past q9 on the
    # robot's next leg, gives her the door lead and the robot is timed from its start (2026-11-27, s15: she is out
    # of the elevator before the robot gets to its door; it left the list)
    # lost with the eighth session's people and robot (2026-11-27: followers queue 0.3 m apart, a follower falls in
    # once the robot is level, the default robot brakes within 1.5 m/s2), told by the verdicts, not yet looked at in
    # frames: the crowd pressing round the plain waypoint robot touches it (socrates 1x), and 2.x's give-way comes
    # after the criterion's window at 0.5x (hunav2)
    # (socrates home/robot-crowding 1x verified again in the fifteenth session: told by the verdicts, not traced)
    ("hunav2", "home/pedestrian-obstruction", 0.5): _PHRASE_LATE,
    # lost again with the sixteenth session's walkers (2026-11-28: a point on a person's way that another reached
    # first is walked through, not stood round): the hallway followers pressing round the plain waypoint robot touch
    # it and it stands over 10 s behind them; told by the verdicts, not looked at in frames (the card verifies with
    # our own robot and pacing: tests/cards)
    # socrates home/robot-crowding at 1x verifies again since a person who walks to its waiting spot asks the robot's
    # distance only there (2026-11-28, s24, timing.hold_root; seen: the three gather at their spots, two follow round
    # the careful robot as it creeps west through them, the third stands aside; it reaches its goal at 27 s untouched)
}


@pytest.fixture(scope="module")
def outcomes(bundled_runs, tmp_path_factory) -> list[tuple]:  # noqa: ANN001
    """(kind, label, target, speed, verified, reference verified, why not) of every run that verifies in our
    simulator; the reference is the same robot at the same speed with our pacing and the run's own trees."""
    work = Path(tmp_path_factory.mktemp("as_target"))
    rows = []
    for k, (kind, label, run) in enumerate(bundled_runs):
        if not verify_trace(run, simulate_run(run, save=False)).passed:
            continue
        scene, _ = build_scene(run)
        speeds = SPEEDS if kind == "fixtures" else (SPEEDS[k % len(SPEEDS)],)
        reference = {}
        for speed in speeds:
            robot = waypoint_robot("careful", scene.robot_speed * speed, start_wait(scene))
            trace = simulate_run(run, robot=robot, timeout=timeout_for(speed), save=False)
            reference[speed] = verify_trace(run, trace).passed
        for target in TIMED_TARGETS:
            twin = target_twin(run, target, work / target / label.replace("/", "__"))
            for speed in speeds:
                if twin.refused:
                    rows.append((kind, label, target, speed, False, reference[speed], "refused: " + twin.refused))
                    continue
                report = run_as_target(twin, speed)
                rows.append((kind, label, target, speed, report.passed, reference[speed],
                             "; ".join(f.name for f in report.failures)))
    return rows


@pytest.mark.parametrize("target", TIMED_TARGETS)
def test_cards_happen_as_the_target_runs_them(outcomes, target: str) -> None:  # noqa: ANN001
    rows = [r for r in outcomes if r[0] == "cards" and r[2] == target]
    assert len(rows) >= 25 and {r[3] for r in rows} == set(SPEEDS)  # the cards that verify in our simulator
    lost = {(target, label, speed): why for _, label, _, speed, ok, ref, why in rows if ref and not ok}
    known = {k: v for k, v in KNOWN_LOST.items() if k[0] == target}
    assert set(lost) == set(known), lost  # what our pacing manages, the exported timing manages
    missed = [f"{label} at {speed:g}x: {why}" for _, label, _, speed, ok, _, why in rows if not ok]
    # the same robot with our pacing misses some too (docs/export.md); measured 2026-11-26 at one speed per card:
    # hunav2 5 of 59 (its two late give-ways above among them), socrates 4
    assert len(missed) <= 0.125 * len(rows), missed


@pytest.mark.xfail(strict=True, reason="the replay fixtures re-answered in round 38 verify in our simulator (7 of 8), "
                   "and as the targets run them 8 of their 42 runs (2 targets x 3 speeds) are lost, e.g. hunav2 "
                   "hospital_evacuation at 0.5x: the visitor who joins the robot at the nurse station does not end "
                   "with it in the lobby (issue 27; benchmarks/export_targets_bench.py, docs/export.md)")
def test_fixtures_happen_as_the_targets_run_them(outcomes) -> None:  # noqa: ANN001
    rows = [r for r in outcomes if r[0] == "fixtures"]
    assert rows and {r[2] for r in rows} == set(TIMED_TARGETS)
    lost = [f"{target} {label} at {speed:g}x: {why}" for _, label, target, speed, ok, ref, why in rows if ref and not ok]
    assert lost == []


def test_the_check_can_fail(bundled_runs, tmp_path: Path) -> None:
    """The trees without their timing lose encounters our pacing makes: the same check on them fails."""
    cards = [(label, run) for kind, label, run in bundled_runs if kind == "cards" and "intersection" in label]
    lost = 0
    for label, run in cards:
        twin = target_twin(run, "socrates", tmp_path / label.replace("/", "__"), timing=False)
        lost += not run_as_target(twin, 1.0).passed
    assert lost > 0.05 * len(cards), (lost, len(cards))


def test_hunav1_runs_its_built_in_trees_untimed_and_refuses_the_rest(make_run, tmp_path: Path) -> None:  # noqa: ANN001
    """1.x loads only its built-in behaviors: a custom tree is refused (naming the human), a built-in one runs as
    it is - the run's own tree, without the timing (human1 meets the robot at its interaction node, so the
    socrates twin does time it)."""
    from .export_helpers import REGULAR_TREE

    refused = target_twin(make_run(), "hunav1", tmp_path / "custom")
    assert refused.run is None and "human1" in refused.refused and "built-in" in refused.refused
    run = make_run({"human1": REGULAR_TREE, "human2": REGULAR_TREE}, name="regular")
    twin = target_twin(run, "hunav1", tmp_path / "hunav1")
    assert not twin.refused and twin.run is not None
    for name in ("human1", "human2"):
        assert (twin.run.root / "behaviors" / f"{name}.xml").read_text() == (run / "behaviors" / f"{name}.xml").read_text()
    assert [h.path for h in twin.run.paths().humans] == [h.path for h in load_run(run).paths().humans]
    timed = target_twin(run, "socrates", tmp_path / "socrates")
    assert "socnavgen_robot_close" in (timed.run.root / "behaviors" / "human1.xml").read_text()
