"""A stop that lasts while the robot is near (a `stop` part on robot_near, no `lasts`): stops_near_robot also needs
the person not to walk off after their stand while the robot is still within the stop's distance (verify/stay.py).

home_10 of the new-request suite: two chatting friends whose text has them "stay where they are" while the robot
goes round them stood 1 s, then made room for the robot waiting in front of them (walked 1-1.5 m away), and the robot
drove through where the group stood; stops_near_robot passed on the 1 s stand. Here: the robot stands at x = 5 on
y = 0, human1 walks along y = 1 toward it and stands at x = 3.6 (1.7 m from it) from t = 6 s.
"""

from __future__ import annotations

import numpy as np

from socnavgen.run.spec import Criterion, Encounter, HumanPart, ScenarioSpec
from socnavgen.verify.criteria import compile_criterion
from socnavgen.verify.models import VerifySettings
from socnavgen.verify.signals import Signals
from socnavgen.verify.stay import stay_broken
from socnavgen.verify.stl import monitor

from .verify_builders import build_trace

DT = 0.05
T = np.round(np.arange(0, 20.0 + 1e-9, DT), 6)
STAND = (6.0, 3.6)  # from t = 6 s at x = 3.6


def _spec(lasts: float | None = None) -> ScenarioSpec:
    part = HumanPart(human="human1", trigger="robot_near", distance=2.5, reaction="stop", lasts=lasts)
    return ScenarioSpec(encounters=[Encounter(id="e1", place="CORRIDOR", humans=[part])],
                        criteria=[Criterion(id="c1", kind="stops_near_robot", human="human1", encounter="e1",
                                            distance=2.0)])


def _signals(walk_off: float | None, robot_leaves: float | None = None, making_room: bool = False) -> Signals:
    """human1 walks in at 0.6 m/s, stands at STAND, and walks back (-x) at 0.6 m/s from `walk_off`; the robot stands
    at x = 5 and, from `robot_leaves`, drives off +x at 1 m/s. `making_room`: the trace marks the walk as the
    simulator's making room (behavior_state 2)."""
    x = np.minimum(0.6 * T, STAND[1])
    if walk_off is not None:
        x = np.where(walk_off <= T, STAND[1] - 0.6 * (T - walk_off), x)
    robot_x = np.full(len(T), 5.0)
    if robot_leaves is not None:
        robot_x = np.where(robot_leaves <= T, 5.0 + (T - robot_leaves), robot_x)
    trace = build_trace(T, np.stack([robot_x, np.zeros(len(T))], 1),
                        np.stack([x, np.ones(len(T))], 1)[:, None, :], dt=DT)
    if making_room and walk_off is not None:
        trace.behavior_state[walk_off <= T, 0] = 2
    return Signals(trace)


def _robustness(s: Signals, lasts: float | None = None) -> float:
    spec = _spec(lasts)
    return monitor(compile_criterion(spec.criteria[0], spec, VerifySettings(), 0.5, DT).formula, s).robustness


def test_a_person_who_stays_while_the_robot_is_near_passes() -> None:
    assert _robustness(_signals(None)) > 0


def test_walking_off_while_the_robot_is_still_near_fails() -> None:
    """Stood 3 s, then walked away 2 m from the robot standing 1.7 m from them: no stay (passed before)."""
    assert _robustness(_signals(9.0)) < 0


def test_walking_on_once_the_robot_has_gone_passes() -> None:
    """The robot drives off at t = 9 s (beyond 2.5 m at ~t = 10 s); they walk on at t = 11 s: the stop lasted while
    it was near."""
    assert _robustness(_signals(11.0, robot_leaves=9.0)) > 0


def test_a_timed_stop_may_end_with_the_robot_near() -> None:
    """A stop with `lasts` ends after that long whatever the robot does: walking off after it is no broken stay."""
    assert _robustness(_signals(9.0), lasts=3.0) > 0


def test_blame_making_room_is_the_spec_and_a_tree_walk_the_tree() -> None:
    """Made room for the waiting robot (the simulator moved them, their tree still standing them): the robot found no
    way round someone who is to stay, which the spec decides; a walk of their own: their tree."""
    spec = _spec()
    cc = compile_criterion(spec.criteria[0], spec, VerifySettings(), 0.5, DT)
    room = stay_broken(cc, _signals(9.0, making_room=True))
    assert room is not None and room[0] == "spec" and "give way" in room[2]
    own = stay_broken(cc, _signals(9.0))
    assert own is not None and own[:2] == ("behaviors", "human1")
    assert stay_broken(cc, _signals(None)) is None
    assert stay_broken(cc, _signals(11.0, robot_leaves=9.0)) is None


def _spec_at(distance: float) -> ScenarioSpec:
    """The stop gated at the criterion's own distance (round 32's home_26: both 2.5 m)."""
    part = HumanPart(human="human1", trigger="robot_near", distance=distance, reaction="stop")
    return ScenarioSpec(encounters=[Encounter(id="e1", place="CORRIDOR", humans=[part])],
                        criteria=[Criterion(id="c1", kind="stops_near_robot", human="human1", encounter="e1",
                                            distance=distance)])


def test_setting_off_as_the_leaving_robot_crosses_the_stops_distance_passes() -> None:
    """The robot (1.7 m off) drives away from t = 9 s at 1 m/s and is 2.5 m off at t = 9.9 s; a person whose stop is
    gated at 2.5 m and sets off as it crosses (t = 9.8 s, 2.42 m: the tree's tick and the verifier's sample differ)
    has stayed while it was near; one who walks at t = 9.3 s (1.97 m) has not."""
    spec = _spec_at(2.5)

    def robustness(walk_off: float) -> float:
        return monitor(compile_criterion(spec.criteria[0], spec, VerifySettings(), 0.5, DT).formula,
                       _signals(walk_off, robot_leaves=9.0)).robustness

    assert robustness(9.8) > 0
    assert robustness(9.3) < 0
