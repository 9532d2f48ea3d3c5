"""What the simulator refuses or bounds, whatever its caller or a policy asks: configurations that make no
sense, points that are not positions, crowds too big to simulate, gestures that are no gesture, and a robot
asked to move faster than it can or through a wall."""

from __future__ import annotations

import math

import numpy as np
import pytest

from socnavgen.bodies import ROBOT_MAX_SPEED
from socnavgen.errors import InputFileError, ValidationFailed
from socnavgen.limits import MAX_SIM_PEOPLE
from socnavgen.sim import RobotAction, RobotBody, SimConfig, empty_room
from tests.sim.simhelpers import REGULAR, Drive, human, make_sim, tree_xml


@pytest.mark.parametrize(("field", "value"), [
    ("robot_radius", math.nan), ("robot_radius", -0.3), ("robot_radius", 0.0), ("goal_tolerance", math.inf),
    ("goal_tolerance", math.nan), ("dt", 0.0), ("dt", math.inf), ("timeout", -1.0), ("timeout", 1e9),
    ("idle_end", math.nan), ("seed", 1.5),
])
def test_a_configuration_that_makes_no_sense_is_refused_by_name(field: str, value: float):
    with pytest.raises(ValidationFailed, match=f"SimConfig.{field}"):
        SimConfig(**{field: value})


def test_force_factors_must_be_numbers():
    from socnavgen.sim.people.physics import SFMParams

    with pytest.raises(ValidationFailed, match="SimConfig.sfm"):
        SimConfig(sfm=SFMParams(k_soc=math.nan))
    assert SimConfig(sfm=SFMParams(cutoff=math.inf)).sfm.cutoff == math.inf  # every pair: allowed


@pytest.mark.parametrize("where", ["robot", "start", "goal"])
def test_points_that_are_not_positions_are_refused(where: str):
    path = [(1.0, 5.0), (math.nan, 5.0)] if where == "robot" else [(1.0, 5.0), (19.0, 5.0)]
    person = human(start=(math.inf, 5.0)) if where == "start" else human(goals=[(3.0, 1e12)]) if where == "goal" \
        else human()
    with pytest.raises(ValidationFailed, match="not a finite world position"):
        make_sim([person], [tree_xml(REGULAR)], path)


def test_a_crowd_beyond_the_bound_is_refused_at_once():
    people = [human(f"human{k + 1}") for k in range(20_000)]
    with pytest.raises(ValidationFailed, match=f"20000 people: a simulation takes at most {MAX_SIM_PEOPLE}"):
        make_sim(people, [REGULAR] * len(people), [(1.0, 5.0), (19.0, 5.0)])


@pytest.mark.parametrize("gesture", [10**30, -7, 6, 2.0, True, "4"])
def test_a_policy_gesture_outside_the_robots_codes_stops_the_run_naming_the_policy(gesture: object):
    sim = make_sim([human()], [tree_xml(REGULAR)], [(1.0, 5.0), (19.0, 5.0)], Drive(0.3, gesture=gesture), timeout=2)
    with pytest.raises(InputFileError, match="the robot policy Drive returned gesture"):
        sim.run()


def test_a_policy_answer_that_is_not_an_action_stops_the_run():
    class Lazy:
        def act(self, obs):  # noqa: ANN001, ANN202
            return (0.3, 0.0)

    class Wordy:
        def act(self, obs):  # noqa: ANN001, ANN202
            return RobotAction("fast", 0.0)

    for policy, message in ((Lazy(), "returned tuple, not a RobotAction"), (Wordy(), "not two numbers")):
        with pytest.raises(InputFileError, match=message):
            make_sim([], [], [(1.0, 5.0), (19.0, 5.0)], policy, timeout=1).run()


class Teleport:
    """Asks to be at its goal within one step: (goal - position) / dt."""

    def act(self, obs):  # noqa: ANN001, ANN201
        v = (obs.waypoints_c[-1] - obs.position_c) / obs.dt
        return RobotAction(v.real, v.imag)


def test_a_robot_asked_to_jump_to_its_goal_moves_at_its_max_speed_and_never_through_a_wall():
    world = empty_room(20.0, 10.0, walls=[(9.8, 0.0, 10.0, 10.0)])  # a wall across the room, 0.2 m thick
    for dt in (0.05, 0.5):  # at 0.5 s a step of the capped robot is 1 m: it would land beyond the thin wall
        trace = make_sim([], [], [(4.0, 5.0), (16.0, 5.0)], Teleport(), world=world, timeout=20, dt=dt).run()
        speed = np.hypot(trace.robot[:, 3], trace.robot[:, 4])
        assert speed.max() <= ROBOT_MAX_SPEED + 1e-9
        assert trace.robot[:, 0].max() < 9.8  # it stopped at the wall, on its side
        assert trace.end_reason != "robot_goal"
    fast = RobotBody(kinematics="holonomic", max_speed=ROBOT_MAX_SPEED, max_accel=100.0, max_decel=100.0)
    free = make_sim([], [], [(4.0, 5.0), (16.0, 5.0)], Teleport(), timeout=20, body=fast).run()
    assert free.end_reason == "robot_goal" and 5.9 <= free.t[-1] <= 6.1  # 12 m at 2 m/s in an empty room
    body = RobotBody()  # the default differential drive: its own limits, speeding up at max_accel
    default = make_sim([], [], [(4.0, 5.0), (16.0, 5.0)], Teleport(), timeout=20).run()
    speed = np.hypot(default.robot[:, 3], default.robot[:, 4])
    assert speed.max() <= body.max_speed + 1e-9 and np.diff(speed).max() <= body.max_accel * default.dt + 1e-9
    ideal = 12.0 / body.max_speed + body.max_speed / (2 * body.max_accel)
    assert default.end_reason == "robot_goal" and ideal - 0.5 <= default.t[-1] <= ideal + 0.1
    assert default.meta["robot_body"] == body.meta()


def test_non_finite_velocities_stand_still():
    trace = make_sim([], [], [(4.0, 5.0), (16.0, 5.0)], Drive(math.nan, math.inf), timeout=1).run()
    assert np.isfinite(trace.robot).all() and (trace.robot[:, :2] == (4.0, 5.0)).all()
