"""One notion of "in the robot's way" for the robot and the verifier (issues 25 and 26; verify/held_up.py).

home_10 of the new-request suite, reduced: a room whose north wall has a 1 m doorway; the robot's route runs from
the room's middle diagonally to the doorway's centre, a leg that cuts through the door's east jamb, so the robot
(like any planning robot) drives west along the wall first and turns north into the door. A friend stands below
the door, off that leg but in the robot's way along the wall. The built-in robots stop for her along exactly that
way (sim.robot.policies.look_ahead toward the planner's carrot); the old verifier looked only along the robot's
body heading and the route's straight legs, called the way clear and blamed the simulator for idling.

Cases: waiting there shorter than the deadlock limit PASSES (someone stands in the doorway it must use; failed
before); waiting there too long FAILS as stuck behind her, not as idle with its way clear (failed before with
the wrong cause); the same wait with her standing off its way FAILS as idle (as before: the new way is no
licence to idle).
"""

from __future__ import annotations

import numpy as np

from socnavgen.run.spec import Criterion, ScenarioSpec
from socnavgen.sim import empty_room
from socnavgen.verify.blame import blame_criterion
from socnavgen.verify.criteria import compile_criterion
from socnavgen.verify.evidence import evidence
from socnavgen.verify.held_up import heading_to
from socnavgen.verify.models import VerifySettings
from socnavgen.verify.signals import Signals
from socnavgen.verify.stl import monitor
from socnavgen.verify.thresholds import DEADLOCK_SECONDS, IDLE_SECONDS

from .verify_builders import build_trace

DOOR = (1.95, 3.475)  # the doorway's centre, in the wall y 3.4 - 3.55 (open for x 1.45 - 2.45)
ROUTE = [(6.0, 2.3), (3.5, 2.3), DOOR, (1.95, 5.0)]
WORLD = empty_room(8.0, 6.0, walls=[(0.0, 3.4, 1.45, 3.55), (2.45, 3.4, 8.0, 3.55)])
WAITS_AT = (2.7, 3.0)  # against the wall east of the door, on the route's leg to it
BELOW_DOOR = (1.34, 2.4)  # the friend: 1.2 m off that leg, 0.15 m (gap) from the corner the robot must round
OFF_THE_WAY = (3.6, 1.0)  # behind the robot, nowhere near its way
SHORT = IDLE_SECONDS + 0.5  # s: longer than the idle limit, shorter than the deadlock limit (its slide to the door
# makes little progress along the leg: the clock runs on a second after the wait)
assert SHORT < DEADLOCK_SECONDS - 1.0


def _trace(person: tuple[float, float], stand: float) -> object:
    """The robot drives the route to WAITS_AT by t = 6 s, stands there `stand` s, then rounds the jamb into the
    door and on to the goal; `person` stands still the whole run."""
    t = np.arange(0.0, 6.0 + stand + 8.0 + 1e-9, 0.5)
    when = [0.0, 4.0, 6.0, 6.0 + stand, 6.0 + stand + 2.0, 6.0 + stand + 8.0]
    xs = [6.0, 3.5, WAITS_AT[0], WAITS_AT[0], 1.95, 1.95]
    ys = [2.3, 2.3, WAITS_AT[1], WAITS_AT[1], 3.05, 5.0]
    robot = np.stack([np.interp(t, when, xs), np.interp(t, when, ys)], 1)
    human = np.tile(np.asarray(person, dtype=float), (len(t), 1))[:, None]
    trace = build_trace(t, robot, human, goal=ROUTE[-1])
    standing = (t >= 6.0) & (t <= 6.0 + stand)
    trace.robot[standing, 2] = np.arctan2(WAITS_AT[1] - 2.3, WAITS_AT[0] - 3.5)  # still facing the way it came
    trace.robot_waypoints = list(ROUTE)
    trace.meta = {"script_cues_fired": []}
    return trace


def _judge(trace: object) -> tuple[bool, Signals, object]:
    cc = compile_criterion(Criterion(id="c", kind="no_deadlock", text="t"), ScenarioSpec(), VerifySettings(), 0.5)
    s = Signals(trace, world=WORLD, goal_radius=0.5)
    return monitor(cc.formula, s).passed, s, cc


def test_the_friend_is_off_every_straight_way_yet_in_the_planned_one() -> None:
    """The scene is the case: by the body's heading and the route's legs she is clear; along the wall she is not."""
    trace = _trace(BELOW_DOOR, SHORT)
    s = Signals(trace, goal_radius=0.5)  # no map: heading, leg and route ahead only (the old verifier's ways)
    k = int(np.searchsorted(trace.t, 8.0))
    assert not s.holding_up()[k, 0]
    assert Signals(trace, world=WORLD, goal_radius=0.5).holding_up()[k, 0]


def test_waiting_for_someone_standing_below_the_door_it_must_use_passes() -> None:
    passed, s, _ = _judge(_trace(BELOW_DOOR, SHORT))
    assert s.get("idle").max() < IDLE_SECONDS / 4  # a blip at the turns of the drive, never while it waits
    assert passed


def test_waiting_there_too_long_is_stuck_behind_her_not_idle() -> None:
    passed, s, cc = _judge(_trace(BELOW_DOOR, DEADLOCK_SECONDS + 6.0))
    assert not passed
    assert s.get("idle").max() < IDLE_SECONDS / 4 and s.get("deadlock").max() >= DEADLOCK_SECONDS
    text, _, _ = evidence(cc, s)
    assert "human1 in its way" in text and "way clear" not in text
    blame, _, _ = blame_criterion(cc, s, ScenarioSpec(), None, DEADLOCK_SECONDS)
    assert blame != "simulator"


def test_the_same_wait_with_her_off_its_way_is_idle() -> None:
    passed, s, cc = _judge(_trace(OFF_THE_WAY, SHORT))
    assert not passed
    assert s.get("idle").max() >= SHORT - 0.5
    text, _, _ = evidence(cc, s)
    assert "with its way clear" in text
    blame, _, _ = blame_criterion(cc, s, ScenarioSpec(), None, DEADLOCK_SECONDS)
    assert blame == "simulator"


def test_the_waypoint_it_heads_for_follows_its_progress() -> None:
    legs = np.cumsum([0.0, 2.5, np.hypot(3.5 - DOOR[0], 2.3 - DOOR[1])])
    assert list(heading_to(ROUTE, np.array([0.0, 2.0, 2.4, legs[2] - 0.5, legs[2] - 0.3, 99.0]))) == [1, 1, 2, 2, 3, 3]
