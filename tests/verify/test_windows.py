"""An encounter's reaction is judged in that encounter's window (verify/windows.py, issue 25): a picker met at
the south end of an aisle (e1), who then walks ahead of the robot through the whole aisle, and is met again at
its north end (e2, give way), is timed from the north-end meeting. Before, the clock of e2's gives_way started
at the e1 meeting ("in the robot's way first at t = 10 s; stepped aside at t = 37.8 s") and could never pass.
A picker who does not step aside at the north end, or a second meeting that never happens, still fails."""

from __future__ import annotations

from functools import partial

import numpy as np

from socnavgen.run.spec import Criterion, Encounter, HumanPart, ScenarioSpec
from socnavgen.verify.blame import blame_criterion
from socnavgen.verify.criteria import compile_criterion
from socnavgen.verify.evidence import evidence
from socnavgen.verify.models import VerifySettings
from socnavgen.verify.signals import Signals
from socnavgen.verify.stl import monitor
from socnavgen.verify.windows import encounter_window, opening_steps

from .verify_builders import build_trace

DT = 0.25
T = np.arange(0, 45.0 + 1e-9, DT)
SOUTH, NORTH = (4.0, 3.0), (12.0, 3.0)


def _aisle(steps_aside_at: float | None, robot_follows: bool = True, looks_back_from: float = 20.5) -> object:
    """human1 stands at SOUTH until 6 s, then walks ahead (+x, 0.5 m/s) to NORTH (there at 22 s) and steps aside
    (+y, 0.6 m/s) from `steps_aside_at` (None: stays in the way). The robot drives +x at 0.5 m/s, stops 1.8 m
    behind the person and follows 1.8 m behind, then drives on to x = 20 once the person is aside
    (`robot_follows` False: it stays at the south end). She faces the robot from `looks_back_from` on."""
    hx = np.clip(4.0 + 0.5 * (T - 6.0), 4.0, 12.0)
    hy = np.full_like(T, 3.0)
    if steps_aside_at is not None:
        hy = 3.0 + np.clip(0.6 * (T - steps_aside_at), 0.0, 1.2)
    rx = np.zeros_like(T)
    x = 0.0
    for k in range(len(T)):
        ahead = hx[k] - 1.8 if (robot_follows or hx[k] < 5.0) else min(x, 2.2)
        clear = hy[k] >= 4.1 and robot_follows
        x = min(x + 0.5 * DT, 20.0) if clear else min(x + 0.5 * DT, max(ahead, x))
        rx[k] = x
    trace = build_trace(T, np.stack([rx, np.full_like(T, 3.0)], 1),
                        np.stack([hx, hy], 1)[:, None], dt=DT, goal=(20.0, 3.0),
                        robot_gesture=np.where((T >= 5.0) & (T <= 6.0), 4, 0))
    trace.robot[:, 2] = 0.0  # facing +x, also while standing
    trace.humans[looks_back_from <= T, 0, 2] = np.pi  # at the north end she turns round and sees the robot in her
    # way (her give-way's cause: robot_blocking is judged in her view cone, and a reaction needs its cause first)
    trace.robot_waypoints = [(0.0, 3.0), (20.0, 3.0)]
    return trace


SPEC = ScenarioSpec(
    encounters=[Encounter(id="e1", place="AISLE END", node="qs", order=1, within=1.5, humans=[
        HumanPart(human="human1", trigger="robot_says", phrase="EXCUSE ME", reaction="walk_past", latch=True)]),
        Encounter(id="e2", place="INTERSECTION", node="zg", order=2, within=1.5, humans=[
            HumanPart(human="human1", trigger="robot_blocking", distance=2.5, reaction="give_way")])],
    criteria=[Criterion(id="c3", kind="gives_way", human="human1", encounter="e2", distance=2.5, seconds=5.0,
                        text="at the north end the picker steps aside")])


def _signals(trace: object, spec: ScenarioSpec = SPEC) -> Signals:
    settings = VerifySettings()
    return Signals(trace, places={"e1": SOUTH, "e2": NORTH}, goal_radius=0.5,
                   windows=partial(encounter_window, spec=spec, settings=settings))


def _gives_way(trace: object, spec: ScenarioSpec = SPEC) -> tuple[bool, str, Signals]:
    s = _signals(trace, spec)
    cc = compile_criterion(spec.criteria[0], spec, VerifySettings(), 0.5)
    return monitor(cc.formula, s).passed, evidence(cc, s)[0], s


def test_the_second_encounter_is_timed_from_its_own_meeting() -> None:
    passed, text, s = _gives_way(_aisle(steps_aside_at=22.5))
    assert passed, text
    assert "judged in e2's window" in text
    opens = opening_steps(s, SPEC, "human1", VerifySettings())
    assert opens[0] == 0 and 20.0 <= s.t[opens[1]] <= 22.5  # e2 opens as the two come together at the north end
    # without windows (the old formula) the same trace fails: in the way since the e1 meeting, all through the aisle
    old = "(eventually ((dist_human1 <= 2.5) and (inway_human1 > 0.5))) and (always (((dist_human1 <= 2.5) and " \
          "(inway_human1 > 0.5)) implies (eventually[0:5] (aside_human1 > 0.5))))"
    assert not monitor(old, s).passed


def test_no_step_aside_at_the_second_meeting_still_fails() -> None:
    for late in (None, 30.0):
        passed, text, _ = _gives_way(_aisle(steps_aside_at=late))
        assert not passed, text
        assert "judged in e2's window" in text


def test_a_second_meeting_that_never_happens_has_an_empty_window_and_fails_on_the_paths() -> None:
    trace = _aisle(steps_aside_at=22.5, robot_follows=False)
    passed, text, s = _gives_way(trace)
    assert not passed
    assert not (s.get("during_human1_e2") > 0.5).any()
    assert "never together at e2's place" in text
    cc = compile_criterion(SPEC.criteria[0], SPEC, VerifySettings(), 0.5)
    blame, _, reason = blame_criterion(cc, s, SPEC, None, 10.0)
    assert blame == "paths" and "never together at zg" in reason, reason


def test_a_person_met_once_is_judged_over_the_whole_run() -> None:
    one = ScenarioSpec(encounters=[SPEC.encounters[1].model_copy(update={"order": 1})], criteria=SPEC.criteria)
    cc = compile_criterion(one.criteria[0], one, VerifySettings(), 0.5)
    assert cc.window is None and "during_" not in cc.formula
    # she looks back at the robot all the way (it blocks her from the start): in its way all through the aisle, 16 s
    # before stepping aside
    passed, text, _ = _gives_way(_aisle(steps_aside_at=22.5, looks_back_from=0.0), one)
    assert not passed and "window" not in text


def _door(aside_from: float) -> object:
    """hospital_01: human1 stands at SOUTH in front of the robot (e1: block); the robot, 1.6 m short, says EXCUSE
    ME from 6 s; human1 steps aside (+y) from `aside_from`. e2's place (NORTH) is never visited."""
    hy = 3.0 + np.clip(0.6 * (T - aside_from), 0.0, 1.2)
    rx = np.interp(T, [0.0, 4.8, 12.0, 45.0], [0.0, 2.4, 2.4, 12.0])
    trace = build_trace(T, np.stack([rx, np.full_like(T, 3.0)], 1), np.stack([np.full_like(T, 4.0), hy], 1)[:, None],
                        dt=DT, goal=(12.0, 3.0), robot_gesture=np.where((T >= 6.0) & (T <= 8.0), 4, 0))
    trace.robot[:, 2] = 0.0
    trace.humans[:, :, 2] = np.pi
    trace.robot_waypoints = [(0.0, 3.0), (12.0, 3.0)]
    return trace


def test_a_later_part_triggered_by_the_phrase_opens_its_window_at_the_phrase() -> None:
    """"e1 block the robot, e2 give way once it says EXCUSE ME" (the prompt's own example) is one meeting: the
    simulated person switches to e2's part as soon as its trigger holds, so e2's window opens at the phrase."""
    spec = ScenarioSpec(
        encounters=[Encounter(id="e1", place="ELEVATOR", node="a", order=1, within=1.5, humans=[
            HumanPart(human="human1", trigger="robot_near", distance=3.0, reaction="block")]),
            Encounter(id="e2", place="CORRIDOR", node="b", order=2, within=1.5, humans=[
                HumanPart(human="human1", trigger="robot_says", phrase="EXCUSE ME", reaction="give_way")])],
        criteria=[Criterion(id="c", kind="reacts_after_phrase", human="human1", encounter="e2", phrase="EXCUSE ME",
                            reaction="give_way", seconds=5.0, text="steps aside after EXCUSE ME")])
    cc = compile_criterion(spec.criteria[0], spec, VerifySettings(), 0.5)
    assert cc.window == "during_human1_e2"
    s = _signals(_door(6.5), spec)
    assert s.t[int(np.flatnonzero(s.get("during_human1_e2") > 0.5)[0])] == 6.0
    assert monitor(cc.formula, s).passed, evidence(cc, s)[0]
    early = _signals(_door(3.0), spec)  # out of its way at 4.4 s, before the robot spoke: no reaction to it
    assert not monitor(cc.formula, early).passed


def test_a_later_trigger_before_a_latched_part_began_opens_no_window() -> None:
    """warehouse_02: e1 (latched, after EXCUSE ME) holds e2's branch inside its latch (proposal/tree_needs.py), so
    e2's trigger (the robot within 4 m) holding BEFORE the robot said EXCUSE ME (5 s) is no switch: e2's window
    opens at the phrase, and e1's reaction to it is judged in e1's window. Without the latch it opens before it."""
    near = SPEC.model_copy(update={"encounters": [SPEC.encounters[0], SPEC.encounters[1].model_copy(update={
        "humans": [HumanPart(human="human1", trigger="robot_near", distance=4.0, reaction="give_way")]})]})
    s = _signals(_aisle(steps_aside_at=22.5), near)
    assert s.get("dist_human1")[0] <= 4.0  # e2's trigger holds from the start
    assert s.t[opening_steps(s, near, "human1", VerifySettings())[1]] == 5.0
    loose = near.model_copy(update={"encounters": [near.encounters[0].model_copy(update={"humans": [
        near.encounters[0].humans[0].model_copy(update={"latch": False})]}), near.encounters[1]]})
    s = _signals(_aisle(steps_aside_at=22.5), loose)
    assert s.t[opening_steps(s, loose, "human1", VerifySettings())[1]] < 5.0


def test_held_within_looks_back_or_ahead_by_its_steps_only():
    """One window helper for "said within S s before" and "out of the way within S s after"."""
    import numpy as np

    from socnavgen.verify.windows import held_within

    flags = np.array([0, 0, 1, 0, 0, 0, 0, 0], dtype=bool)
    assert held_within(flags, 2).tolist() == [False, False, True, True, True, False, False, False]
    assert held_within(flags, 2, ahead=True).tolist() == [True, True, True, False, False, False, False, False]
    assert held_within(flags, 0).tolist() == flags.tolist()
