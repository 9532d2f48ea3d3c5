"""An idle robot fails `no_deadlock` (issue 25, verify/idle.py): standing, creeping or wandering with no progress
along its route for more than IDLE_SECONDS while its way is clear and no cue of its script asks it to stand. It
passes where a viewer sees why it waits: someone in its way, a timed `wait`, a `let_pass` whose person has not
gone by yet. home_16 of the new-request suite passed with its robot standing 9 s in a doorway after both
children had run by (its let_pass cue still counted) - a lenient pass."""

from __future__ import annotations

import numpy as np

from socnavgen.run.spec import Criterion, ScenarioSpec
from socnavgen.verify.blame import blame_criterion
from socnavgen.verify.criteria import compile_criterion
from socnavgen.verify.evidence import evidence
from socnavgen.verify.models import VerifySettings
from socnavgen.verify.signals import Signals
from socnavgen.verify.stl import monitor
from socnavgen.verify.thresholds import DEADLOCK_SECONDS, IDLE_SECONDS

from .verify_builders import build_trace

STAND = IDLE_SECONDS + 1.5  # s: longer than the idle limit, shorter than the deadlock limit
assert STAND < DEADLOCK_SECONDS
T = np.arange(0, 30.0 + 1e-9, 0.5)
FAR = (0.0, 12.0)  # nowhere near the robot's way


def _robot(creep: float = 0.0, stand: float = STAND) -> np.ndarray:
    """East along y = 3 from x = 0: at x = 3 by t = 5 s, standing (or creeping `creep` m/s) there `stand` s, then
    on to its goal (12, 3) by t = 26 s."""
    x = np.interp(T, [0.0, 5.0, 5.0 + stand, 26.0], [0.0, 3.0, 3.0 + creep * stand, 12.0])
    return np.stack([x, np.full_like(T, 3.0)], 1)


def _trace(person: np.ndarray | tuple[float, float] = FAR, log: list | None = None, creep: float = 0.0,
           stand: float = STAND) -> object:
    people = np.asarray(person, dtype=float)
    people = np.tile(people, (len(T), 1)) if people.ndim == 1 else people
    trace = build_trace(T, _robot(creep, stand), people[:, None], goal=(12.0, 3.0))
    trace.robot[:, 2] = 0.0  # facing +x, also while standing
    trace.robot_waypoints = [(0.0, 3.0), (12.0, 3.0)]
    trace.meta = {"script_cues_fired": log if log is not None else []}
    return trace


def _judge(trace: object) -> tuple[bool, Signals, object]:
    cc = compile_criterion(Criterion(id="c", kind="no_deadlock", text="t"), ScenarioSpec(), VerifySettings(), 0.5)
    s = Signals(trace, goal_radius=0.5)
    return monitor(cc.formula, s).passed, s, cc


def test_standing_with_its_way_clear_and_no_cue_fails_and_says_so() -> None:
    passed, s, cc = _judge(_trace())
    assert not passed
    assert s.get("idle").max() >= STAND - 0.5
    text, when, _ = evidence(cc, s)
    assert "stood still" in text and "with its way clear and no cue of its script asking it to wait" in text
    assert when is not None and abs(when - 5.0) <= 1.0
    blame, _, reason = blame_criterion(cc, s, ScenarioSpec(), None, DEADLOCK_SECONDS)
    assert blame == "simulator" and "its way clear" in reason and "from t=5" in reason


def test_creeping_is_no_progress() -> None:
    """5 mm/s: moving, yet getting nowhere along its route (the round-23 robot behind someone beyond its goal)."""
    passed, s, _ = _judge(_trace(creep=0.005))
    assert not passed and s.get("idle").max() >= STAND - 0.5


def test_a_person_in_its_way_is_a_cause() -> None:
    passed, s, _ = _judge(_trace(person=(5.0, 3.0)))  # standing 2 m ahead on its route while it waits ...
    assert passed and s.get("idle").max() <= 1.0 and s.get("deadlock").max() > 0
    # ... who then leaves: the trace's person stands there only while the robot does
    person = np.where((T < 5.0 + STAND)[:, None], [5.0, 3.0], [5.0, 9.0])
    passed, s, _ = _judge(_trace(person=person))
    assert passed, s.get("idle").max()


def test_a_timed_wait_cue_is_a_cause() -> None:
    assert _judge(_trace(log=[[5.0, f"at_encounter: wait {STAND:g} s"]]))[0]
    # a shorter wait covers only its own seconds
    assert not _judge(_trace(log=[[5.0, "at_encounter: wait 1 s"]]))[0]


LONG = 15.0  # s the robot stands letting someone pass (no deadlock: nobody stands in its way)


def _walks_by(stop: bool) -> np.ndarray:
    """human1 crosses the robot's way 1 m ahead of it as it stops (x = 4 at t = 5 s) and walks on south (or
    comes along y = 1, 2 m beside its way, and stops there 0.5 m past it at t = 7 s: never farther than closest)."""
    if stop:
        x = np.interp(T, [0.0, 7.0, 30.0], [13.0, 3.5, 3.5])
        return np.stack([x, np.full_like(T, 1.0)], 1)
    y = np.interp(T, [0.0, 5.0, 30.0], [10.5, 3.0, 3.0 - 37.5])
    return np.stack([np.full_like(T, 4.0), y], 1)


def test_letting_someone_pass_is_a_cause_until_they_have_gone_by() -> None:
    log = [[5.0, "at_encounter: wait 20 s, let human1 pass"], [5.0 + LONG, "human1 has gone by: drive on"]]
    # still coming while the robot stands: the robot lets them by
    coming = np.stack([np.full_like(T, 4.0), np.interp(T, [0.0, 5.0 + LONG, 30.0], [20.0, 5.0, 5.0])], 1)
    assert _judge(_trace(person=coming, log=log, stand=LONG))[0]
    # gone by at ~6 s (across its way and on) or stopped beside it at 7 s: it stands on for no visible cause
    for stop in (False, True):
        passed, s, _ = _judge(_trace(person=_walks_by(stop), log=log, stand=LONG))
        assert not passed, (stop, s.get("idle").max())
        assert LONG - 5.0 < s.get("idle").max() < LONG - 0.5  # the wait counted until they had gone by


def test_the_signal_is_the_verifiers_own_not_the_prompts() -> None:
    from socnavgen.proposal.facts import stl_text

    assert "deadlock (s)" in stl_text() and "idle (s)" not in stl_text()
