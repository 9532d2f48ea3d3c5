"""Someone walking the robot's way passes it (robot.polite): the default robot makes the pass short and wide.
A walker overtaking it in a corridor with room finds it already on its side (it moves aside for someone close
behind walking its way, not only for someone already catching up); where the corridor is too narrow for that,
it stops for a walker beside it within intimate space and lets them ahead, instead of the two walking abreast
at a hand's breadth (the campaign's warehouse pedestrian-overtaking: 45 s abreast at 0.10 m)."""

from __future__ import annotations

import numpy as np

from socnavgen.bodies import INTIMATE_SPACE
from socnavgen.sim import empty_room
from socnavgen.sim.robot.api import ScriptedPolicy
from tests.sim.simhelpers import REGULAR, human, make_sim, tree_xml

WALK = tree_xml(REGULAR)


def _corridor(width: float):  # noqa: ANN202
    return empty_room(24.0, 10.0, walls=[(0.0, 0.0, 24.0, 5.0 - width / 2), (0.0, 5.0 + width / 2, 24.0, 10.0)])


def _overtaken(width: float, person_y: float, robot_y: float = 5.0, behind: float = 1.7):  # noqa: ANN202
    """A walker (1.2 m/s) starting `behind` m behind the robot (0.6 m/s), both going east along a corridor."""
    person = human(start=(2.5 - behind, person_y), goals=[(23.0, person_y)], max_vel=1.2)
    return make_sim([person], [WALK], [(2.5, robot_y), (21.0, robot_y)], ScriptedPolicy(), world=_corridor(width),
                    timeout=60).run()


def _gap(trace) -> np.ndarray:  # noqa: ANN001
    return np.hypot(*(trace.humans[:, 0, :2] - trace.robot[:, :2]).T) - trace.robot_radius - trace.human_radii[0]


def _report(trace) -> tuple[float, float, float]:  # noqa: ANN001
    gap = _gap(trace)
    close = float((gap < INTIMATE_SPACE).sum() * trace.dt)
    ahead = np.flatnonzero(trace.humans[:, 0, 0] > trace.robot[:, 0] + 1.0)
    print(trace.end_reason, "intimate s", close, "min gap", gap.min(), "ahead at", trace.t[ahead[0]] if len(ahead) else None)
    return close, float(gap.min()), float(trace.t[ahead[0]]) if len(ahead) else np.inf


def test_a_walker_held_behind_the_robot_in_a_corridor_with_room_is_made_room_for_and_passes():
    # 2.6 m: room beside the robot (0.7 m) for a person (0.8 m) and most of their passing gap. Before, the walker
    # caught up, then walked 0.53 m behind the robot for the whole corridor (held behind, never seen catching up)
    trace = _overtaken(2.6, 5.0, behind=4.0)
    close, least, ahead = _report(trace)
    assert trace.end_reason == "robot_goal"
    assert ahead < 15.0  # they got past it
    assert close <= 1.5, close
    assert least >= 0.3, least


def test_a_walker_beside_the_robot_in_a_narrow_corridor_is_let_ahead_not_walked_abreast():
    # 1.9 m: a person fits past the robot against the wall only at ~0.2-0.3 m; the walker starts beside-behind it
    trace = _overtaken(1.9, 5.4, robot_y=4.5, behind=1.0)
    close, least, ahead = _report(trace)
    assert trace.end_reason == "robot_goal"
    assert ahead < 8.0  # let ahead at once
    assert close <= 4.0, close
    assert least >= 0.15, least


def test_a_walker_who_cannot_get_by_is_not_stopped_for():
    # 1.6 m: no room past the robot even standing; it does not stop for them (they follow it)
    trace = _overtaken(1.6, 5.0, behind=4.0)
    close, least, ahead = _report(trace)
    assert trace.end_reason == "robot_goal" and trace.t[-1] < 35.0
    assert close == 0.0
