"""A handover as a person sees it (issue 25, round 22: warehouse_17's colleague coming for the first-aid kit, home_18's
physiotherapist taking the towel): someone walks up to the standing robot, stands about 1.3 m in front of it facing
it, then walks back. stops_near_robot (the criterion a `follow` handover is stated by: proposal/facts.STATED_BY) sees
it; standing 2.3 m off to the side (where the old side step left them) or turned away is no handover."""

from __future__ import annotations

import math

import numpy as np

from socnavgen.proposal.facts import STATED_BY
from socnavgen.run.spec import Criterion, ScenarioSpec
from socnavgen.verify.criteria import compile_criterion
from socnavgen.verify.models import VerifySettings
from socnavgen.verify.signals import Signals
from socnavgen.verify.stl import monitor

from .verify_builders import build_trace

DT = 0.05
T = np.round(np.arange(0, 16.0 + 1e-9, DT), 6)
ROBOT = 5.0 + 0j  # stands there the whole time, heading +x (it came from the west)


def _handover(stand: complex, face: float | None = None) -> Signals:
    """human1 walks from (12, 0) to `stand` (4-8 s), stands there 4 s (facing the robot, or `face` rad), walks back."""
    start = 12.0 + 0j
    where = np.interp(T, [0.0, 4.0, 8.0, 12.0, 16.0], [0.0, 0.0, 1.0, 1.0, 0.0])
    human = start + (stand - start) * where
    robot = np.stack([np.full(len(T), ROBOT.real), np.full(len(T), ROBOT.imag)], 1)
    trace = build_trace(T, robot, np.stack([human.real, human.imag], 1)[:, None, :], dt=DT)
    standing = (T >= 8.0) & (T <= 12.0)
    to_robot = ROBOT - stand
    trace.humans[standing, 0, 2] = math.atan2(to_robot.imag, to_robot.real) if face is None else face
    trace.robot[:, 2] = 0.0
    return Signals(trace)


def _stops_near_robot(s: Signals) -> float:
    spec = ScenarioSpec(criteria=[Criterion(id="c1", kind="stops_near_robot", human="human1")])
    return monitor(compile_criterion(spec.criteria[0], spec, VerifySettings(), 0.5, DT).formula, s).robustness


def test_a_handover_is_stated_by_stops_near_robot_and_seen_by_it():
    assert "stops_near_robot" in STATED_BY["follow"]
    assert _stops_near_robot(_handover(6.3 + 0j)) > 0  # came up to 1.3 m in front, stood facing it


def test_standing_off_to_the_side_or_turned_away_is_no_handover():
    assert _stops_near_robot(_handover(6.3 + 2.0j)) < 0  # 2.3 m off to the side: too far
    assert _stops_near_robot(_handover(5.3 + 1.3j, face=math.pi / 2)) < 0  # beside it, turned away


def _blocks_robot(s: Signals) -> float:
    spec = ScenarioSpec(criteria=[Criterion(id="c1", kind="blocks_robot", human="human1")])
    return monitor(compile_criterion(spec.criteria[0], spec, VerifySettings(), 0.5, DT).formula, s).robustness


def test_a_blocker_standing_at_her_point_in_front_of_the_robot_blocks_it():
    """BlockRobot stands at its point 1.5 m ahead of the robot, still within BLOCK_HOLD of it: 1.53 m is a block
    (home_18's physiotherapist failed the old 1.5 m); 2.3 m off to the side is none."""
    from socnavgen.sim.people.leaves import BLOCK_AHEAD

    assert _blocks_robot(_handover(ROBOT + BLOCK_AHEAD + 0.03)) > 0
    assert _blocks_robot(_handover(6.3 + 2.0j)) < 0
