"""The evidence of an stl criterion is the moment that decides it (verify/witness.py), not each signal's minimum:
`always (dist < 2.5 implies speed > 0.3)` failing was shown as "speed_human1 min 0.00 m/s at t=0.0 s", when the
implication held vacuously (round 13, warehouse_10)."""

from __future__ import annotations

import numpy as np
import pytest

from socnavgen.run.spec import Criterion
from socnavgen.verify.criteria import Compiled
from socnavgen.verify.evidence import evidence
from socnavgen.verify.signals import Signals
from socnavgen.verify.stl import monitor

from .verify_builders import build_trace

IMPLIES = "always ((dist_human1 < 2.5) implies (speed_human1 > 0.3))"


def _signals(human: list[tuple[float, float]]) -> Signals:
    """The robot drives +x at 1 m/s from x = 0 for 10 s; human1 at the given (t, x) keys on y = 0 (dt 0.5)."""
    t = np.arange(21) * 0.5
    hx = np.interp(t, [k[0] for k in human], [k[1] for k in human])
    return Signals(build_trace(t, np.stack([t, np.zeros_like(t)], 1), np.stack([hx, np.zeros_like(t)], 1)[:, None]))


def _evidence(formula: str, s: Signals) -> tuple[bool, str, float | None]:
    cc = Compiled(criterion=Criterion(id="c1", kind="stl", formula=formula), formula=formula)
    text, time, _ = evidence(cc, s)
    return monitor(formula, s).passed, text, time


def test_a_failing_implication_is_shown_where_its_left_side_held_and_its_right_side_did_not() -> None:
    """human1 stands at x = 8 (speed 0 from t = 0): the implication fails first at t = 6.0 s, 2.0 m apart."""
    passed, text, time = _evidence(IMPLIES, _signals([(0.0, 8.0), (10.0, 8.0)]))
    assert not passed
    assert time == pytest.approx(6.0) and "at t=6.0 s" in text, text
    assert "dist_human1 < 2.5 held (dist_human1 2.00 m)" in text, text
    assert "speed_human1 > 0.3 did not (speed_human1 0.00 m/s)" in text, text
    assert "t=0.0 s" not in text, text


def test_a_failing_implication_with_a_timed_consequence_is_shown_where_it_was_due() -> None:
    formula = "always ((dist_human1 < 2.5) implies (eventually[0:1] (speed_human1 > 0.3)))"
    passed, text, time = _evidence(formula, _signals([(0.0, 8.0), (10.0, 8.0)]))
    assert not passed and "dist_human1 < 2.5 held, so" in text and time is not None and time >= 6.0, text


def test_an_implication_that_holds_is_shown_at_its_tightest_moment() -> None:
    """human1 walks off at 2 m/s from t = 5, before the robot comes within 2.5 m: the implication holds."""
    passed, text, _ = _evidence(IMPLIES, _signals([(0.0, 8.0), (5.0, 8.0), (10.0, 18.0)]))
    assert passed and "tightest moment" in text, text


def test_an_eventually_is_shown_where_it_first_held_or_came_closest() -> None:
    formula = "eventually ((dist_human1 < 2.0) and (speed_robot > 0.5))"
    passed, text, time = _evidence(formula, _signals([(0.0, 8.0), (10.0, 8.0)]))
    assert passed and time == pytest.approx(6.5) and "first moment the `eventually` part held" in text, text
    far = "eventually (dist_human1 < 1.0)"
    passed, text, time = _evidence(far, _signals([(0.0, 8.0), (10.0, 18.0)]))  # 8 m ahead and walking away
    assert not passed and "nearest" in text and time == pytest.approx(0.0) and "dist_human1 8.00 m" in text, text


def test_an_until_is_shown_where_its_right_side_held_or_its_left_side_stopped() -> None:
    """Who goes first (stage 1's order example): the robot stays 3 m off human1 until it stands still."""
    standing = _signals([(0.0, 8.0), (10.0, 8.0)])  # the robot never stops: 3 m off fails first at t=5.5 s
    passed, text, time = _evidence("(dist_human1 > 3.0) until (speed_robot < 0.1)", standing)
    assert not passed and time == pytest.approx(5.0) and "dist_human1 > 3.0 stopped holding before" in text, text
    assert "dist_human1 3.00 m" in text, text
    passed, text, time = _evidence("(speed_robot > 0.5) until (dist_human1 < 4.0)", standing)
    assert passed and time == pytest.approx(4.5) and "the first moment dist_human1 < 4.0 held" in text, text


def test_a_formula_with_no_moment_to_walk_to_keeps_the_per_signal_view() -> None:
    """A past operator at the top (since) has no deciding step walked here: each signal's minimum is shown."""
    formula = "(dist_human1 > 3.0) since (speed_robot > 0.5)"
    _, text, _ = _evidence(formula, _signals([(0.0, 8.0), (10.0, 8.0)]))
    assert "dist_human1 min" in text, text
