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
