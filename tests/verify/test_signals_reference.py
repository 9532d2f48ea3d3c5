"""The verifier's shared geometry, computed once per trace and per component, against the formulas as first
written (np.linalg.norm of (T, H, 2) differences, a Python loop for run lengths): identical values, not
close ones (the same floating-point operations in the same order)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from socnavgen.proxemics import HELD_UP_DISTANCE, WAY_MARGIN_VERIFY
from socnavgen.sim import contact
from socnavgen.verify import signals as signals_module
from socnavgen.verify.route import TIE
from socnavgen.verify.signals import Signals
from socnavgen.verify.thresholds import PERCEIVED_SECONDS

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
        got, want = signals_module.runlength(flags, dt), runlength_loop(flags, dt)
        assert got.dtype == want.dtype and np.array_equal(got, want)
    assert signals_module.runlength(np.ones(2000, bool), 0.05)[-1] != 2000 * 0.05  # a running sum drifts from n * dt


def perceived_loop(speed: np.ndarray, dt: float) -> np.ndarray:
    """verify/perceived.py's rule written out: the mean over the steps within PERCEIVED_SECONDS / 2 of each step
    (as many whole steps of dt as fit on each side), the window cut at the ends of the trace."""
    half = int(np.floor(PERCEIVED_SECONDS / dt / 2 + 1e-9))
    return np.array([np.mean(speed[max(k - half, 0):k + half + 1]) for k in range(len(speed))])


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
    assert np.allclose(s.speed("robot"), perceived_loop(np.linalg.norm(trace.robot[:, 3:5], axis=1), 0.1), rtol=0,
                       atol=1e-12)
    yaw = trace.robot[:, 2]
    blocked = np.zeros(steps, bool)
    for i, name in enumerate(trace.human_names):
        raw = np.linalg.norm(trace.humans[:, i, 3:5], axis=1)
        assert np.allclose(s.speed(name), perceived_loop(raw, 0.1), rtol=0, atol=1e-12)
        assert steps < 10 or not np.array_equal(s.speed(name), raw)  # the rule changes something
        rel = trace.humans[:, i, :2] - trace.robot[:, :2]
        along = rel[:, 0] * np.cos(yaw) + rel[:, 1] * np.sin(yaw)
        lateral = np.abs(-rel[:, 0] * np.sin(yaw) + rel[:, 1] * np.cos(yaw))
        in_way = (along > 0) & (lateral < trace.robot_radius + float(trace.human_radii[i]) + WAY_MARGIN_VERIFY)
        assert np.array_equal(s.in_way(i), in_way)
        blocked |= in_way & (distances[:, i] <= HELD_UP_DISTANCE)
    assert np.array_equal(s.blocked(), blocked)
    summary = s.contacts()
    assert summary == contact.summarize(trace)
    if humans and steps > 1:
        assert blocked.any() and not blocked.all()  # the comparison is not between two empty masks
        assert math.isfinite(summary.min_gap)


def progress_loop(xy: np.ndarray, waypoints: np.ndarray) -> np.ndarray:
    """Route progress by the rule written out: per step, the nearest point of each segment; among segments equally
    near (within route.TIE) the one whose progress is nearest the step before's (ties: the later), the first
    nearest at the start."""
    out: list[float] = []
    for p in xy:
        found = []  # (offset m, progress) per segment
        covered = 0.0
        for a, b in zip(waypoints[:-1], waypoints[1:], strict=True):
            d = b - a
            u = min(1.0, max(0.0, float((p - a) @ d) / float(d @ d)))
            found.append((float(np.sqrt(np.sum((p - (a + u * d)) ** 2))), covered + u * float(np.sqrt(d @ d))))
            covered += float(np.sqrt(d @ d))
        best = min(off for off, _ in found)
        tied = [at for off, at in found if off <= best + TIE]
        if out and len(tied) > 1:
            out.append(min(tied, key=lambda at: abs(at - out[-1]) - 1e-9 * at))
        else:
            out.append(next(at for off, at in found if off == best))
    return np.array(out)


def no_progress_loop(progress: np.ndarray, step: float) -> np.ndarray:
    """True on the steps without a new `step` metres of best progress since the last such step (the ratchet)."""
    out, ref, best = [], progress[0], -np.inf
    for value in progress:
        best = max(best, value)
        if best >= ref + step:
            ref = best
            out.append(False)
        else:
            out.append(True)
    return np.array(out)


def test_stalled_and_deadlock_signals_match_the_loop() -> None:
    trace = wandering(300, 3, seed=7)
    trace.robot[100:180, 3:5] = 0.0  # the robot stands still for 8 s
    trace.robot_waypoints = [tuple(trace.robot[k, :2] + 0.3) for k in (0, 60, 150, 299)]  # roughly where it wanders
    s = Signals(trace)
    still = perceived_loop(np.linalg.norm(trace.robot[:, 3:5], axis=1), 0.1) < signals_module.STILL_SPEED
    assert np.array_equal(s.get("stalled"), runlength_loop(still, 0.1))
    progress = progress_loop(trace.robot[:, :2], np.asarray(trace.robot_waypoints))
    assert np.allclose(s.route()[0], progress, rtol=0, atol=1e-12)
    stuck = no_progress_loop(progress, signals_module.PROGRESS_STEP)
    assert stuck.any() and not stuck.all()
    assert np.array_equal(s.get("deadlock"), runlength_loop(stuck & s.blocked(), 0.1))
    assert s.get("stalled").max() == pytest.approx(8.0 - 0.4)  # seen standing: less the window (2 steps each side)


def test_a_robot_jittering_in_place_is_deadlocked_and_one_driving_on_is_not() -> None:
    """Back and forth 0.2 m, 0.4 m/s, behind a person standing in its way: never still, no progress."""
    t = np.arange(200) * 0.1
    x = 2.0 + 0.1 * np.sin(t * 2.0)
    jitter = build_trace(t, np.stack([x, np.zeros_like(t)], 1), np.tile([[3.3, 0.0]], (200, 1))[:, None], dt=0.1,
                         goal=(9.0, 0.0))
    jitter.robot[:, 2] = np.where(np.cos(t * 2.0) >= 0, 0.0, np.pi)  # it turns as it reverses
    jitter.robot_waypoints = [(0.0, 0.0), (9.0, 0.0)]
    s = Signals(jitter, places={"goal": (9.0, 0.0)})
    assert s.get("stalled").max() < 1.0  # never standing still long: the old definition saw no deadlock
    assert s.get("deadlock").max() == pytest.approx(19.9, abs=0.15)  # no progress, held up all along
    driving = build_trace(t, np.stack([0.4 * t, np.zeros_like(t)], 1), np.tile([[9.5, 3.0]], (200, 1))[:, None],
                          dt=0.1, goal=(9.0, 0.0))
    driving.robot_waypoints = [(0.0, 0.0), (9.0, 0.0)]
    assert Signals(driving, places={"goal": (9.0, 0.0)}).get("deadlock").max() == 0.0


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
    from socnavgen.verify.passing import parted_for_robot  # not while they part to let the robot through

    pairs = [np.where(parted_for_robot(s, a, b), 0.0, np.linalg.norm(humans[:, a] - humans[:, b], axis=1))
             for a, b in ((0, 1), (0, 3), (1, 3))]
    assert np.array_equal(s.get("spread_human1_human2_human4"), np.max(np.stack(pairs, axis=1), axis=1))
    walked = np.linalg.norm(humans[:, 0] - humans[:1, 0], axis=1) >= signals_module.MOVED_DISTANCE
    assert np.array_equal(s.get("moved_human1"), np.maximum.accumulate(walked.astype(float)))
    assert 0 < s.get("moved_human1").sum() < len(trace.t)
    for i in range(4):
        assert np.array_equal(_robot_human_distance(trace, i), np.linalg.norm(robot - humans[:, i], axis=1))
