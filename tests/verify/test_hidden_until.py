"""`hidden_until`: the two do not see each other until they are close, on the approach that brings them there.
Seeing the robot is noticing it (keeps_away's notion: in sight within max(5, D + 2) m), so a robot in sight at the
far end of a warehouse at the start, 50 s before it comes round the rack, is not the one that appears suddenly
(warehouse_07 of the new-request suite: in sight 9-13 m apart for 13 s, then hidden until 3.0 m)."""

from __future__ import annotations

import numpy as np

from socnavgen.run.spec import Criterion, ScenarioSpec
from socnavgen.sim.world import empty_room
from socnavgen.verify.criteria import compile_criterion
from socnavgen.verify.evidence import evidence
from socnavgen.verify.models import VerifySettings
from socnavgen.verify.signals import Signals
from socnavgen.verify.stl import monitor

from .verify_builders import build_trace


def _run(visible: np.ndarray) -> tuple[Signals, np.ndarray]:
    """The robot drives +x at 0.5 m/s from x = 1 toward human1 standing at x = 11.5 (10.5 m apart at t = 0, 1.5 m
    at 18 s); `visible(t)`: when they see each other (a rack between them otherwise). dt 0.5 s, 0..20 s."""
    t = np.arange(41) * 0.5
    rx = np.minimum(1.0 + 0.5 * t, 10.0)
    trace = build_trace(t, np.stack([rx, np.full_like(t, 10.0)], 1),
                        np.stack([np.full_like(t, 11.5), np.full_like(t, 10.0)], 1)[:, None], goal=(15.0, 10.0))
    s = Signals(trace, world=empty_room(), places={})
    s._los = visible(t)[:, None].astype(bool)  # the rack: what the map's walls would hide
    return s, t


def _hidden(s: Signals, distance: float = 3.0) -> float:
    c = Criterion(id="c1", kind="hidden_until", human="human1", distance=distance)
    return monitor(compile_criterion(c, ScenarioSpec(criteria=[c]), VerifySettings(), 0.5).formula, s).robustness


def test_a_robot_seen_far_off_long_before_the_approach_still_appears_suddenly() -> None:
    # in sight 10.5-9 m apart for the first 3 s, then hidden until 2.5 m (16 s): hidden until close
    s, _ = _run(lambda t: (t < 3.0) | (t >= 16.0))
    assert _hidden(s) > 0
    c = Criterion(id="c1", kind="hidden_until", human="human1", distance=3.0)
    cc = compile_criterion(c, ScenarioSpec(criteria=[c]), VerifySettings(), 0.5)
    assert "first in sight within 5 m at t=16.0 s, 2.50 m apart" in evidence(cc, s)[0]


def test_a_robot_seen_within_noticing_range_before_it_is_close_fails() -> None:
    # in sight from 12 s on, 4.5 m apart: noticed before it came within 3 m
    s, _ = _run(lambda t: t >= 12.0)
    assert _hidden(s) < 0
    # seen all the way: fails whatever the start
    assert _hidden(_run(lambda t: t >= 0.0)[0]) < 0
    # a larger distance widens the noticing range with it (D + 2): a glimpse 6.0-5.5 m apart (9-10 s), then hidden
    # until 2.5 m, is unnoticed for D = 3 (5 m) and too early for D = 4.5 (6.5 m)
    s, _ = _run(lambda t: ((t >= 9.0) & (t < 10.0)) | (t >= 16.0))
    assert _hidden(s, distance=3.0) > 0 and _hidden(s, distance=4.5) < 0


def test_never_seen_and_never_close_is_no_sudden_appearance() -> None:
    s, t = _run(lambda t: t < 0.0)
    assert _hidden(s) > 0  # never in sight, and they came within 3 m after an approach
    s.trace.robot[:, 0] = 1.0  # the robot never moves: never close, never an approach
    assert _hidden(Signals(s.trace, world=empty_room(), places={})) < 0
