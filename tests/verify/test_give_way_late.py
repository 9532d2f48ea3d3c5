"""A gives_way that fails although the person did step aside says why that step did not count: the first moment
the person stood in the robot's way without stepping out of it within S s (home_10 of round 13 read "stepped
aside at t=14.7 s" next to FAIL: she was back in its way at 19.2 s for 5.3 s)."""

from __future__ import annotations

import numpy as np

from socnavgen.run.spec import Criterion, ScenarioSpec
from socnavgen.verify.criteria import compile_criterion
from socnavgen.verify.evidence import evidence
from socnavgen.verify.models import VerifySettings
from socnavgen.verify.signals import Signals
from socnavgen.verify.stl import monitor

from .verify_builders import build_trace


def _trace(ys: list[tuple[float, float]]):  # noqa: ANN202
    """The robot drives +x at 1 m/s from x = 0 on y = 3, stands at x = 3 from 3 s to 20 s, then drives on at
    0.5 m/s; human1 stands at x = 5 with y following the (t, y) keys (y 3: in its way; 4.2: aside)."""
    t = np.arange(0, 40.0 + 1e-9, 0.25)
    rx = np.where(t < 3.0, t, np.where(t < 20.0, 3.0, np.minimum(3.0 + 0.5 * (t - 20.0), 14.0)))
    hy = np.interp(t, [k[0] for k in ys], [k[1] for k in ys])
    trace = build_trace(t, np.stack([rx, np.full_like(t, 3.0)], 1), np.stack([np.full_like(t, 5.0), hy], 1)[:, None],
                        dt=0.25, goal=(14.0, 3.0))
    trace.robot[:, 2] = 0.0
    trace.robot_waypoints = [(0.0, 3.0), (14.0, 3.0)]
    return trace


def _judged(ys: list[tuple[float, float]]) -> tuple[bool, str]:
    c = Criterion(id="c", kind="gives_way", human="human1", distance=2.5, seconds=5.0, text="t")
    cc = compile_criterion(c, ScenarioSpec(), VerifySettings(), 0.5)
    s = Signals(_trace(ys), goal_radius=0.5)
    return monitor(cc.formula, s).passed, evidence(cc, s)[0]


def test_a_step_aside_undone_by_coming_back_into_the_way_for_too_long_says_so() -> None:
    passed, text = _judged([(0.0, 3.0), (4.0, 3.0), (5.0, 4.2), (7.0, 4.2), (8.0, 3.0), (15.0, 3.0), (16.0, 4.2),
                            (40.0, 4.2)])
    assert not passed
    assert "but in its way at t=2.5 s (2.50 m): stepped aside at t=4." in text, text
    assert "but was back in its way at t=7." in text and "out of it for good only at t=15." in text, text
    assert "(more than 5 s): not giving way" in text, text


def test_a_step_aside_too_late_says_how_late() -> None:
    passed, text = _judged([(0.0, 3.0), (12.0, 3.0), (13.0, 4.2), (40.0, 4.2)])
    assert not passed and "but in its way at t=2.5 s (2.50 m): out of it only at t=12." in text, text


def test_a_step_aside_in_time_that_is_kept_passes_without_a_why() -> None:
    passed, text = _judged([(0.0, 3.0), (4.0, 3.0), (5.0, 4.2), (40.0, 4.2)])
    assert passed and "stepped aside at t=4." in text and "not giving way" not in text, text


def test_a_step_aside_too_short_says_where_it_stopped() -> None:
    """warehouse_07 of round 14: the worker stepped off at once, 0.46 m, to 0.77 m from the robot's route, inside
    the 0.85 m its body sweeps; the robot waited 24 s and went round him. The verdict read "stepped aside at t=66.2
    s, 35.7 s later", as if he had dawdled: it says the step was short, and where it ended."""
    passed, text = _judged([(0.0, 3.0), (4.0, 3.0), (5.0, 3.6), (40.0, 3.6)])
    assert not passed
    assert "moved 0.60 m off its route by t=5.0 s but stood 0.60 m from it, inside the 0.85 m its body" in text, text


def test_a_reaction_to_the_phrase_too_short_to_count_says_where_it_stopped() -> None:
    trace = _trace([(0.0, 3.0), (4.0, 3.0), (5.0, 3.6), (40.0, 3.6)])
    trace.robot_gesture[(trace.t >= 3.0) & (trace.t <= 6.0)] = 4  # EXCUSE ME
    c = Criterion(id="c", kind="reacts_after_phrase", human="human1", phrase="EXCUSE ME", reaction="give_way",
                  seconds=5.0, text="t")
    cc = compile_criterion(c, ScenarioSpec(), VerifySettings(), 0.5)
    s = Signals(trace, goal_radius=0.5)
    text = evidence(cc, s)[0]
    assert not monitor(cc.formula, s).passed
    assert "first showed give_way at t=24.0 s, not within 5 s of the phrase (it moved 0.60 m off the robot's " \
        "route by t=5.0 s, but to 0.60 m from it, inside the 0.85 m" in text, text
