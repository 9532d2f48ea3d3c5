"""Speeds as a person watching sees them (issue 25, warehouse_10 of the new-request suite): the mean speed over the
thresholds.PERCEIVED_SECONDS around each step (verify/perceived.py).

warehouse_10: the lead worker of a file bends round the robot and his speed dips to 0.09 m/s for 0.25 s; the eyes
saw the file walk past without stopping, and the spec's "always (dist < 2 implies speed > 0.2)" failed on that one
slow step. The other side: a standstill of 1 s is a stop (it fails "keeps walking", and the stop criteria and the
stop reaction see it: they hold for perceived.seen_hold, the second less the window), a robot that stands still is
seen standing, a jolt of a standing person is no walking.
"""

from __future__ import annotations

import numpy as np
import pytest

from socnavgen.run.spec import Criterion, ScenarioSpec
from socnavgen.verify.criteria import compile_criterion
from socnavgen.verify.models import VerifySettings
from socnavgen.verify.perceived import perceived, seen_hold
from socnavgen.verify.signals import Signals
from socnavgen.verify.stl import monitor
from socnavgen.verify.thresholds import PERCEIVED_SECONDS, STOP_HOLD, WALK_SPEED

from .verify_builders import build_trace

DT = 0.05
T = np.round(np.arange(0, 12.0 + 1e-9, DT), 6)


def _walk(speeds: dict[tuple[float, float], float], base: float = 0.75) -> np.ndarray:
    """x(t) of someone walking +x at `base` m/s, at other speeds in the (from, to) spans given."""
    v = np.full(len(T), base)
    for (t0, t1), speed in speeds.items():
        v[np.greater_equal(T, t0 - 1e-9) & np.less(T, t1 - 1e-9)] = speed
    return np.concatenate([[0.0], np.cumsum(v[:-1] * DT)])


def _trace(human_x: np.ndarray, robot_x: np.ndarray | None = None) -> Signals:
    """human1 walks along y = 1 from x = 0; the robot stands (or drives) on y = 0 ahead of it, at x = 5."""
    robot_x = np.full(len(T), 5.0) if robot_x is None else robot_x
    robot = np.stack([robot_x, np.zeros(len(T))], 1)
    human = np.stack([human_x, np.ones(len(T))], 1)[:, None, :]
    return Signals(build_trace(T, robot, human, dt=DT))


def _velocity_speed(x: np.ndarray) -> np.ndarray:
    return np.abs(np.gradient(x, T))


def test_a_slow_step_is_no_stop_and_a_standstill_is_one() -> None:
    raw = np.full(200, 0.75)
    raw[100:105] = 0.09  # 0.25 s slow step (warehouse_10: 12.75-12.95 s)
    assert perceived(raw, DT).min() > 0.4
    still = np.full(200, 0.75)
    still[100:120] = 0.0  # 1 s standstill: seen standing (exactly 0) for its length less the window
    seen = perceived(still, DT)
    assert (seen == 0.0).sum() * DT == pytest.approx(1.0 - PERCEIVED_SECONDS)
    assert seen[:95] == pytest.approx(np.full(95, 0.75)) and seen[125:] == pytest.approx(np.full(75, 0.75))


def test_a_jolt_while_standing_is_no_walking() -> None:
    raw = np.zeros(200)
    raw[50:53] = 0.6  # 0.15 s jolt of a standing person
    raw[150:] = 0.8  # then walks off
    seen = perceived(raw, DT)
    assert seen[:140].max() < WALK_SPEED and seen[160:] == pytest.approx(np.full(40, 0.8))


def test_coarse_traces_are_read_as_they_are() -> None:
    raw = np.array([0.0, 0.5, 0.0, 0.7, 0.7])
    assert np.array_equal(perceived(raw, 0.5), raw)  # one step already spans PERCEIVED_SECONDS
    assert seen_hold(STOP_HOLD, 0.5) == STOP_HOLD and seen_hold(STOP_HOLD, DT) == pytest.approx(STOP_HOLD - 0.5)
    assert perceived(np.zeros(0), DT).shape == (0,)
    assert np.array_equal(perceived(np.zeros(3), DT), np.zeros(3))  # a trace shorter than the window


def _keeps_walking(s: Signals) -> float:
    return monitor("always ((dist_human1 < 3) implies (speed_human1 > 0.2))", s).robustness


def test_keeps_walking_holds_through_a_slow_step_while_bending_round() -> None:
    """The lead worker slows to 0.09 m/s for 0.25 s, 2 m from the robot: he kept walking."""
    x = _walk({(4.0, 4.25): 0.09})  # at x = 3, 2.2 m from the robot
    s = _trace(x)
    assert np.min(_velocity_speed(x)[(T > 3.5) & (T < 4.5)]) < 0.1  # the dip is there in the trace's velocity
    assert _keeps_walking(s) > 0


@pytest.mark.parametrize("seconds", [1.0, 0.6])
def test_keeps_walking_fails_on_a_real_stop(seconds: float) -> None:
    """... a standstill of a second (or of 0.6 s, just longer than a slow step) is a stop."""
    assert _keeps_walking(_trace(_walk({(4.0, 4.0 + seconds): 0.0}))) < 0


def _compiled(kind: str, **fields: object) -> str:
    spec = ScenarioSpec(criteria=[Criterion(id="c1", kind=kind, human="human1", **fields)])
    return compile_criterion(spec.criteria[0], spec, VerifySettings(), 0.5, DT).formula


def _stops(stop_at: float, seconds: float, *, dip: float = 0.0) -> float:
    """human1 walks toward the robot standing at x = 5 (1 m to the side) and stands `seconds` at `dip` m/s from
    `stop_at`, then walks on past it."""
    return monitor(_compiled("stops_near_robot", distance=2.0), _trace(_walk({(stop_at, stop_at + seconds): dip},
                                                                           base=0.6))).robustness


def test_stops_near_robot_sees_a_standstill_of_a_second_and_no_shorter() -> None:
    assert _stops(6.0, 1.0) > 0  # stands 1 s at x = 3.6, 1.7 m from the robot: seen standing 0.5 s
    assert _stops(6.0, 0.6) < 0  # 0.6 s is none
    assert _stops(6.0, 0.3) < 0
    assert _stops(6.0, 2.0, dip=0.09) > 0  # creeping at 0.09 m/s is standing (below STOP_SPEED)


def test_react_stop_needs_a_perceptible_standstill() -> None:
    s = _trace(_walk({(2.0, 2.25): 0.0, (4.0, 4.6): 0.0, (7.0, 8.0): 0.0}))
    stop = s.get("react_human1_stop") > 0.5
    assert stop.any() and not stop[T < 6.0].any()  # the 0.25 s and 0.6 s halts are no stop, the 1 s one is


def test_the_robot_standing_still_is_seen_and_a_stutter_is_not() -> None:
    robot_x = 0.2 * T
    robot_x[T >= 4.0] = robot_x[T >= 4.0][0]  # stands from t = 4 s to the end
    robot_x[(T > 2.0 - 1e-9) & (T < 2.15 + 1e-9)] = 0.4  # a 0.1 s hitch on the way (velocity 0 at 2.05, 2.1 s)
    s = _trace(np.zeros(len(T)), robot_x)
    still = s.get("robot_still") > 0.5
    assert still[(T > 4.3) & (T < 11.9)].all() and not still[T < 3.9].any()
    assert s.get("stalled")[-1] == pytest.approx(12.0 - 4.0, abs=PERCEIVED_SECONDS / 2)  # stood the last 8 s
    assert np.linalg.norm(s.trace.robot[(T > 2.0) & (T < 2.15), 3:5], axis=1).max() < 0.05  # the hitch is in the trace


def test_a_robot_pausing_half_a_second_is_seen_standing() -> None:
    """warehouse_08: the robot brakes from 0.4 m/s in 0.15 s, stands 0.45 s saying EXCUSE ME, and creeps on; the
    eyes saw it stop before the group. A rule that drops every change shorter than the window would not see it."""
    v = np.interp(T, [0.0, 3.0, 3.15, 3.6, 4.0, 12.0], [0.4, 0.4, 0.0, 0.0, 0.4, 0.4])
    s = _trace(np.zeros(len(T)), np.concatenate([[0.0], np.cumsum(v[:-1] * DT)]))
    still = s.get("robot_still") > 0.5
    assert still.any() and not still[(T < 2.8) | (T > 4.2)].any()
