"""The verifier's shared geometry, computed once per trace and per component, against the formulas as first
written (np.linalg.norm of (T, H, 2) differences, a Python loop for run lengths): identical values, not
close ones (the same floating-point operations in the same order)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from socnavgen.proxemics import BLOCK_GAP_VERIFY, WAY_MARGIN_VERIFY
from socnavgen.sim import contact
from socnavgen.verify import signals as signals_module
from socnavgen.verify.signals import Signals

from .verify_builders import build_trace


def runlength_loop(flags: np.ndarray, dt: float) -> np.ndarray:
    """The run length as first written: one addition of dt per step of a run."""
    out = np.zeros(len(flags))
    acc = 0.0
    for k, flag in enumerate(flags):
        acc = acc + dt if flag else 0.0
        out[k] = acc
    return out


@pytest.mark.parametrize("dt", [0.05, 0.1, 1 / 3, 0.5, 1.0])
def test_runlength_equals_the_loop(dt: float) -> None:
    rng = np.random.default_rng(int(dt * 1000))
    for flags in (rng.uniform(size=3000) < 0.97, rng.uniform(size=500) < 0.5, np.ones(2000, bool),
                  np.zeros(10, bool), np.array([True]), np.array([], bool)):
        got, want = signals_module._runlength(flags, dt), runlength_loop(flags, dt)
        assert got.dtype == want.dtype and np.array_equal(got, want)
    assert signals_module._runlength(np.ones(2000, bool), 0.05)[-1] != 2000 * 0.05  # a running sum drifts from n * dt


def wandering(steps: int, humans: int, seed: int):  # noqa: ANN201 - a Trace
    rng = np.random.default_rng(seed)
    t = np.arange(steps) * 0.1
    robot = np.cumsum(rng.normal(0, 0.1, (steps, 2)), axis=0)
    people = robot[:, None, :] + rng.normal(0, 1.5, (1, humans, 2)) + np.cumsum(rng.normal(0, 0.1, (steps, humans, 2)),
                                                                                axis=0)
    return build_trace(t, robot, people, dt=0.1)


@pytest.mark.parametrize(("steps", "humans"), [(400, 5), (300, 0), (1, 1), (200, 12)])
def test_shared_geometry_equals_the_formulas(steps: int, humans: int) -> None:
    trace = wandering(steps, humans, seed=steps + humans)
    s = Signals(trace)
    pr, pa = trace.robot[:, :2], trace.humans[:, :, :2]
    distances = np.linalg.norm(pa - pr[:, None, :], axis=-1)
    assert np.array_equal(contact.centre_distances(pr, pa), distances)
    assert np.array_equal(s.distances(), distances)
    assert np.array_equal(s.gaps(), distances - (trace.robot_radius + trace.human_radii.reshape(1, -1)))
    assert np.array_equal(s.speed("robot"), np.linalg.norm(trace.robot[:, 3:5], axis=1))
    yaw = trace.robot[:, 2]
    blocked = np.zeros(steps, bool)
    for i, name in enumerate(trace.human_names):
        assert np.array_equal(s.speed(name), np.linalg.norm(trace.humans[:, i, 3:5], axis=1))
        rel = trace.humans[:, i, :2] - trace.robot[:, :2]
        along = rel[:, 0] * np.cos(yaw) + rel[:, 1] * np.sin(yaw)
        lateral = np.abs(-rel[:, 0] * np.sin(yaw) + rel[:, 1] * np.cos(yaw))
        in_way = (along > 0) & (lateral < trace.robot_radius + float(trace.human_radii[i]) + WAY_MARGIN_VERIFY)
        assert np.array_equal(s.in_way(i), in_way)
        blocked |= in_way & (distances[:, i] - trace.robot_radius - trace.human_radii[i] <= BLOCK_GAP_VERIFY)
    assert np.array_equal(s.blocked(), blocked)
    summary = s.contacts()
    assert summary == contact.summarize(trace)
    if humans and steps > 1:
        assert blocked.any() and not blocked.all()  # the comparison is not between two empty masks
        assert math.isfinite(summary.min_gap)


def test_stalled_and_deadlock_signals_match_the_loop() -> None:
    trace = wandering(300, 3, seed=7)
    trace.robot[100:180, 3:5] = 0.0  # the robot stands still for 8 s
    s = Signals(trace)
    still = np.linalg.norm(trace.robot[:, 3:5], axis=1) < signals_module.STILL_SPEED
    assert np.array_equal(s.get("stalled"), runlength_loop(still, 0.1))
    assert np.array_equal(s.get("deadlock"), runlength_loop(still & s.blocked(), 0.1))
    assert s.get("stalled").max() == pytest.approx(8.0)


def test_place_spread_and_moved_signals_equal_the_formulas() -> None:
    from socnavgen.verify.evaluate import _robot_human_distance

    trace = wandering(250, 4, seed=3)
    goal = (1.5, -0.5)
    s = Signals(trace, places={"e1": (0.3, 0.7), "goal": goal}, goal_radius=0.8)
    robot, humans = trace.robot[:, :2], trace.humans[:, :, :2]
    assert np.array_equal(s.get("robot_to_e1"), np.linalg.norm(robot - np.array([0.3, 0.7]), axis=1))
    assert np.array_equal(s.get("human2_to_goal"), np.linalg.norm(humans[:, 1] - np.array(goal), axis=1))
    mid = 0.5 * (robot + humans[:, 2])
    assert np.array_equal(s.get("mid_human3_to_e1"), np.linalg.norm(mid - np.array([0.3, 0.7]), axis=1))
    pairs = [np.linalg.norm(humans[:, a] - humans[:, b], axis=1) for a, b in ((0, 1), (0, 3), (1, 3))]
    assert np.array_equal(s.get("spread_human1_human2_human4"), np.max(np.stack(pairs, axis=1), axis=1))
    walked = np.linalg.norm(humans[:, 0] - humans[:1, 0], axis=1) >= signals_module.MOVED_DISTANCE
    assert np.array_equal(s.get("moved_human1"), np.maximum.accumulate(walked.astype(float)))
    assert 0 < s.get("moved_human1").sum() < len(trace.t)
    for i in range(4):
        assert np.array_equal(_robot_human_distance(trace, i), np.linalg.norm(robot - humans[:, i], axis=1))
