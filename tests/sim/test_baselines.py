"""The ORCA and DWA robots (sim/robot/orca.py, dwa.py) on the classic cases in the simulator - head-on in a
corridor, crossing, overtaking a slow walker, a doorway off the straight line, a person standing on the route -
each reaching its goal without contact; the same scenes with the people-ignoring `straight` robot touch
someone (the scenes do test avoidance); and ORCA's geometry and linear program on cases worked by hand."""

from __future__ import annotations

import math

import numpy as np
import pytest

from socnavgen.errors import InputFileError
from socnavgen.sim import empty_room, load_policy, robot_from
from socnavgen.sim.contact import trace_gaps
from socnavgen.sim.robot.dwa import DWAPolicy, _arcs
from socnavgen.sim.robot.orca import ORCAPolicy, half_plane, least_violation, solve
from tests.sim.simhelpers import REGULAR, human, make_sim, tree_xml

WALK, STAND = tree_xml(REGULAR), tree_xml('<LookAtRobot agent_id="{id}"/>')
CORRIDOR = [(3.0, 0.0, 17.0, 3.8), (3.0, 6.2, 17.0, 10.0)]  # 2.4 m wide: room for a robot and a person side by side
SCENES = {
    "head_on": (CORRIDOR, human(start=(16.0, 5.0), goals=[(2.0, 5.0)]), WALK, [(2.0, 5.0), (18.0, 5.0)]),
    "crossing": ([], human(start=(10.0, 1.5), goals=[(10.0, 11.0)], start_delay=7.0), WALK, [(3.0, 5.0), (17.0, 5.0)]),
    "overtaking": (CORRIDOR, human(start=(5.0, 5.0), goals=[(19.0, 5.0)], max_vel=0.25), WALK, [(2.0, 5.0), (18.0, 5.0)]),
    # a wall across the room with a 1 m door off the straight line; someone comes through it the other way
    "doorway": ([(9.8, 0.0, 10.2, 6.0), (9.8, 7.0, 10.2, 10.0)], human(start=(16.0, 6.5), goals=[(4.0, 6.5)],
                                                                      start_delay=6.0), WALK, [(3.0, 3.0), (17.0, 3.0)]),
    "standing": ([], human(start=(10.0, 5.0), goals=[(10.0, 5.0)]), STAND, [(2.0, 5.0), (18.0, 5.0)]),
}


def _run(scene: str, robot: str):  # noqa: ANN202
    walls, person, tree, route = SCENES[scene]
    return make_sim([person], [tree], route, load_policy(robot), world=empty_room(20.0, 10.0, walls=walls),
                    timeout=60).run()


@pytest.mark.parametrize("robot", ["orca", "dwa"])
@pytest.mark.parametrize("scene", list(SCENES))
def test_baseline_reaches_its_goal_without_contact(scene: str, robot: str) -> None:
    trace = _run(scene, robot)
    gaps = trace_gaps(trace)
    assert trace.end_reason == "robot_goal", (scene, robot, trace.robot[-1, :2])
    assert gaps.min() > 0.05, (scene, robot, gaps.min())
    assert gaps.min() < 1.0  # they did meet: the scene tests avoidance


@pytest.mark.parametrize("robot", ["orca", "dwa"])
def test_baseline_drives_a_passage_barely_wider_than_the_robot(robot: str) -> None:
    """The SocRATES small warehouse as `location extract` draws it has 0.8 m passages for the 0.7 m robot: ORCA
    kept its whole safety margin (0.05 m) from both walls at once and stood at the mouth (narrow-hallway)."""
    walls = [(3.0, 0.0, 17.0, 4.55), (3.0, 5.45, 17.0, 10.0)]  # 0.8 m of free cells (a 0.4 m clearance on its axis)
    trace = make_sim([], [], [(2.0, 5.0), (18.0, 5.0)], load_policy(robot), world=empty_room(20.0, 10.0, walls=walls),
                     timeout=60).run()
    assert trace.end_reason == "robot_goal", (robot, trace.robot[-1, :2])


@pytest.mark.parametrize("scene", ["head_on", "overtaking", "standing"])
def test_a_robot_ignoring_people_touches_someone_in_the_same_scenes(scene: str) -> None:
    assert trace_gaps(_run(scene, "straight")).min() < 0.05


def test_velocity_obstacle_half_plane_excludes_the_way_into_a_neighbour_and_permits_the_way_out() -> None:
    """A neighbour 2 m ahead, we at 1 m/s toward it (tau 2 s: we would touch within the horizon)."""
    u, direction = half_plane(2 + 0j, 1 + 0j, 0.6, 2.0, 0.05)
    point = 1 + 0.5 * u  # reciprocal: half of u
    inside = lambda v: direction.real * (v - point).imag - direction.imag * (v - point).real >= 0  # noqa: E731
    assert abs(u) > 0 and not inside(1 + 0j) and inside(-1 + 0j)
    # a neighbour far behind and moving away puts no constraint on moving forward
    u_far, d_far = half_plane(-10 + 0j, 0.5 + 0j, 0.6, 2.0, 0.05)
    assert d_far.real * ((1 + 0j) - (0.5 + u_far)).imag - d_far.imag * ((1 + 0j) - (0.5 + u_far)).real >= 0


def test_linear_program_keeps_every_half_plane_and_the_speed_limit() -> None:
    """v_y <= 0.2 (line through 0.2i running toward -x: permitted to its left, i.e. below) and v_x <= 0.5."""
    lines = [(0.2j, -1 + 0j), (0.5 + 0j, 0 + 1j)]
    kept, v = solve(lines, 1.0, 1 + 1j)
    assert kept == 2 and v.imag <= 0.2 + 1e-9 and v.real <= 0.5 + 1e-9 and abs(v) <= 1.0 + 1e-9
    assert v == pytest.approx(0.5 + 0.2j)  # the corner nearest the preferred velocity
    kept, v = solve([(-0.5j, -1 + 0j), (0.5j, 1 + 0j)], 1.0, 0j)  # v_y <= -0.5 and v_y >= 0.5: nothing
    assert kept < 2


def test_dwa_arcs_follow_the_unicycle() -> None:
    """The closed-form arc equals small steps of x' = v cos(yaw), y' = v sin(yaw), yaw' = omega."""
    times = np.array([1.0, 2.0])
    arcs = _arcs(1 + 1j, 0.3, np.array([0.5, 0.5]), np.array([0.8, 0.0]), times)
    p, yaw, h = 1 + 1j, 0.3, 1e-4
    for _ in range(int(2.0 / h)):
        p += 0.5 * h * complex(math.cos(yaw + 0.4 * h), math.sin(yaw + 0.4 * h))
        yaw += 0.8 * h
    assert abs(arcs[0, 1] - p) < 1e-6
    assert abs(arcs[1, 1] - (1 + 1j + 1.0 * complex(math.cos(0.3), math.sin(0.3)))) < 1e-9


def test_baselines_take_parameters_and_refuse_unknown_ones() -> None:
    policy, body = robot_from("orca", {"tau": 2.0, "max_speed": 0.4, "kinematics": "holonomic"})
    assert isinstance(policy, ORCAPolicy) and policy.tau == 2.0 and body.kinematics == "holonomic"
    assert isinstance(robot_from("dwa", {"alpha": 1.5})[0], DWAPolicy)
    with pytest.raises(InputFileError, match="no parameter 'speed'"):
        robot_from("dwa", {"speed": 1.0})
    with pytest.raises(InputFileError, match="a number of 0 or more"):
        robot_from("orca", {"tau": -1.0})


def test_route_passes_a_waypoint_someone_stands_on_only_when_near_it() -> None:
    """The Python baselines' route (robot.route) skips an intermediate waypoint a person stands on once within
    2 m of it, as the built-in robots do; nobody on it, or far from it, it keeps the waypoint."""
    from socnavgen.sim.robot.route import Route

    sim = make_sim([human(start=(10.0, 5.0), goals=[(10.0, 5.0)])], [STAND], [(2.0, 5.0), (10.0, 5.0), (18.0, 5.0)],
                   load_policy("orca"), world=empty_room(20.0, 10.0))
    route = Route(sim.obs)
    here, people, radii = 9.0 + 5.0j, np.array([10.0 + 5.0j]), np.array([0.25])
    assert route.target(5.0 + 5.0j, people, radii) == (10.0 + 5.0j, False)  # 5 m away: still its waypoint
    assert route.target(here, np.zeros(0, complex), np.zeros(0)) == (10.0 + 5.0j, False)  # nobody on it
    assert route.target(here, people, radii) == (18.0 + 5.0j, True)


def test_a_campaign_keys_the_baselines_by_their_source(monkeypatch) -> None:  # noqa: ANN001
    """Editing orca.py or dwa.py re-runs their episodes: the resume key digests their module, not "builtin"."""
    from socnavgen.campaign import fingerprint
    from socnavgen.campaign.episode import EpisodeSettings
    from socnavgen.campaign.scenarios import Suite
    from socnavgen.campaign.spec import parse_campaign

    spec = parse_campaign("name: t\nscenarios: [{runs: [r]}]\npolicies: [orca, dwa, sfm]\nseeds: 1\n")
    suite = Suite(scenarios=[], skipped=[])
    before = fingerprint.inputs_of(spec, suite, EpisodeSettings()).policies
    seen = []
    monkeypatch.setattr(fingerprint, "policy_digest", lambda robot: seen.append(robot) or f"edited {robot}")
    after = fingerprint.inputs_of(spec, suite, EpisodeSettings()).policies
    assert seen == ["socnavgen.sim.robot.orca:ORCAPolicy", "socnavgen.sim.robot.dwa:DWAPolicy", "sfm"]
    assert before["orca"] != after["orca"] and before["dwa"] != after["dwa"]


def test_route_makes_way_after_standing_face_to_face_and_not_otherwise() -> None:
    """Held for `patience` s by someone within 0.8 m (each waiting for the other in a doorway), the route
    leads back 2 m along the robot's own trail for a while; alone, or moving on, it never does."""
    from socnavgen.sim.robot.route import BACK_OFF, MAKE_WAY, PATIENCE, Route

    sim = make_sim([], [], [(2.0, 5.0), (18.0, 5.0)], load_policy("orca"), world=empty_room(20.0, 10.0))
    person, radii = np.array([9.5 + 5.0j]), np.array([0.25])
    for nearby in (False, True):
        route, t = Route(sim.obs), 0.0
        for x in np.arange(2.0, 8.8, 0.1):  # drives up to 8.8
            t += 0.1 / 0.6
            assert route.target(complex(x, 5.0), person, radii, t)[0].real > x
        here, first, target = 8.8 + 5.0j, t, 18.0 + 5.0j
        while t < first + PATIENCE + 1.0 and target.real > here.real:
            t += 0.05
            target, last = route.target(here, person if nearby else np.zeros(0, complex), radii, t)
        if nearby:
            assert t >= first + PATIENCE - 0.5  # it waited
            assert not last and abs(target - here) >= BACK_OFF - 0.3 and target.real < here.real
            assert route.target(here, person, radii, t + MAKE_WAY - 0.1)[0] == target
            assert route.target(here, np.zeros(0, complex), radii, t + MAKE_WAY + 0.1)[0].real > here.real
        else:
            assert target.real > here.real


def test_orca_matches_rvo2_on_random_crowds() -> None:
    """Our ORCA's half-planes and linear programs give the velocity RVO2 (the authors' C++ library, through
    the `pyrvo` bindings of the bench extra) gives, within its float32 precision, on random crowds of 1-5
    neighbours - those where the half-planes leave nothing (the 3-D program) included."""
    pyrvo = pytest.importorskip("pyrvo")
    rng = np.random.default_rng(1)
    dt, tau, vmax, radius = 0.05, 2.0, 1.0, 0.3
    infeasible = 0
    for _ in range(150):
        n = int(rng.integers(1, 6))
        pos = [complex(*rng.uniform(-3, 3, 2)) for _ in range(n + 1)]
        vel = [complex(*rng.uniform(-0.7, 0.7, 2)) for _ in range(n + 1)]
        pref = complex(*rng.uniform(-1, 1, 2))
        sim = pyrvo.RVOSimulator(dt, 10.0, 10, tau, tau, radius, vmax)
        for k in range(n + 1):
            sim.add_agent((pos[k].real, pos[k].imag))
            sim.set_agent_velocity(k, (vel[k].real, vel[k].imag))
            wish = pref if k == 0 else vel[k]
            sim.set_agent_pref_velocity(k, (wish.real, wish.imag))
        sim.do_step()
        theirs = complex(*sim.get_agent_velocity(0).to_tuple())
        lines = []
        for k in sorted(range(1, n + 1), key=lambda k: abs(pos[k] - pos[0])):
            u, d = half_plane(pos[k] - pos[0], vel[0] - vel[k], 2 * radius, tau, dt)
            lines.append((vel[0] + 0.5 * u, d))
        kept, ours = solve(lines, vmax, pref)
        if kept < len(lines):
            infeasible += 1
            ours = least_violation(lines, 0, kept, vmax, ours)
        assert abs(ours - theirs) < 1e-3, (pos, vel, pref, ours, theirs)
    assert infeasible > 0  # the crowded case was exercised
