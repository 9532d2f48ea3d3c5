"""The one "in the robot's way" predicate (socnavgen.proxemics): its geometry, and that the very same
functions run on floats, elementwise on numpy arrays and compiled by numba, with the same answers."""

from __future__ import annotations

import math

import numpy as np
import pytest

from socnavgen import proxemics
from socnavgen.bodies import PERSON_RADIUS, ROBOT_RADIUS

R, P = ROBOT_RADIUS, PERSON_RADIUS


def test_in_way_is_the_swept_corridor_ahead() -> None:
    half = R + P + proxemics.WAY_MARGIN_VERIFY  # 0.85 m beside the robot's line of travel
    # robot at the origin heading +x
    assert proxemics.in_way(0.0, 0.0, 1.0, 0.0, 2.0, 0.0, R, P, proxemics.WAY_MARGIN_VERIFY)
    assert proxemics.in_way(0.0, 0.0, 1.0, 0.0, 2.0, half - 0.01, R, P, proxemics.WAY_MARGIN_VERIFY)
    assert not proxemics.in_way(0.0, 0.0, 1.0, 0.0, 2.0, half + 0.01, R, P, proxemics.WAY_MARGIN_VERIFY)
    assert not proxemics.in_way(0.0, 0.0, 1.0, 0.0, -0.5, 0.0, R, P, proxemics.WAY_MARGIN_VERIFY)  # behind
    # heading +y: the same person (2, 0) is now beside the robot, one at (0.3, 2) is in its way
    assert not proxemics.in_way(0.0, 0.0, 0.0, 1.0, 2.0, 0.0, R, P, proxemics.WAY_MARGIN_VERIFY)
    assert proxemics.in_way(0.0, 0.0, 0.0, 1.0, 0.3, 2.0, R, P, proxemics.WAY_MARGIN_VERIFY)
    # the margins differ per use: 0.82 m beside the line is in the script's way, not in the driving robot's
    assert proxemics.in_way(0.0, 0.0, 1.0, 0.0, 1.0, 0.82, R, P, proxemics.WAY_MARGIN_SCRIPT)
    assert not proxemics.in_way(0.0, 0.0, 1.0, 0.0, 1.0, 0.82, R, P, proxemics.WAY_MARGIN_DRIVE)


def test_in_front_is_a_cone_around_the_heading() -> None:
    cone = proxemics.FRONT_CONE_SCRIPT
    for angle in np.linspace(-math.pi, math.pi, 73):
        x, y = 3 * math.cos(angle), 3 * math.sin(angle)
        expected = abs(math.atan2(y, x)) <= cone
        if abs(abs(angle) - cone) > 1e-9:
            assert bool(proxemics.in_front(0.0, 0.0, 1.0, 0.0, x, y, cone)) == expected, angle
    assert proxemics.in_front(1.0, 1.0, 1.0, 0.0, 1.0, 1.0, cone)  # on the robot's centre


def test_blocking_needs_the_distance_and_a_negative_cone_means_corridor_only() -> None:
    args = (R, P)
    # 1.5 m ahead, 1.2 m aside: outside the corridor (0.85 m) and the 0.6 rad cone (atan(1.2 / 1.5) = 0.675)
    assert not proxemics.blocking(0.0, 0.0, 1.0, 0.0, 1.5, 1.2, *args, 3.0, proxemics.WAY_MARGIN_SCRIPT, 0.6)
    assert proxemics.blocking(0.0, 0.0, 1.0, 0.0, 2.0, 1.0, *args, 3.0, proxemics.WAY_MARGIN_SCRIPT, 0.6)  # in the cone
    assert not proxemics.blocking(0.0, 0.0, 1.0, 0.0, 2.0, 1.0, *args, 3.0, proxemics.WAY_MARGIN_SCRIPT, -1.0)
    assert proxemics.blocking(0.0, 0.0, 1.0, 0.0, 2.0, 0.5, *args, 3.0, proxemics.WAY_MARGIN_SCRIPT, -1.0)
    assert not proxemics.blocking(0.0, 0.0, 1.0, 0.0, 3.5, 0.0, *args, 3.0, proxemics.WAY_MARGIN_SCRIPT, 0.6)


def _random_cases(n: int = 400) -> list[np.ndarray]:
    rng = np.random.default_rng(7)
    heading = rng.uniform(-math.pi, math.pi, n)
    robot = rng.uniform(-5, 5, (2, n))
    person = robot + rng.uniform(-3, 3, (2, n))
    return [robot[0], robot[1], np.cos(heading), np.sin(heading), person[0], person[1]]


@pytest.mark.parametrize("name", ["in_way", "in_front", "blocking"])
def test_floats_arrays_and_numba_agree(name: str) -> None:
    numba = pytest.importorskip("numba")
    fn = getattr(proxemics, name)
    extra = {"in_way": (R, P, proxemics.WAY_MARGIN_VERIFY), "in_front": (proxemics.FRONT_CONE_SCRIPT,),
             "blocking": (R, P, 2.5, proxemics.WAY_MARGIN_SCRIPT, proxemics.FRONT_CONE_SCRIPT)}[name]
    cases = _random_cases()
    vectorised = np.asarray(fn(*cases, *extra), dtype=bool)
    compiled = numba.njit(fn)  # each function alone: it calls nothing else of the module
    scalar = [bool(fn(*(float(c[k]) for c in cases), *extra)) for k in range(len(cases[0]))]
    jitted = [bool(compiled(*(float(c[k]) for c in cases), *extra)) for k in range(len(cases[0]))]
    assert vectorised.tolist() == scalar == jitted
    assert 0 < sum(scalar) < len(scalar)  # the cases exercise both answers

