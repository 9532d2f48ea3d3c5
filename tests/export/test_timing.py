"""The timing inside exported trees (export.timing): where a person waits, when it is released, and that the
encounter then happens at its place whatever the robot's speed - and does not without it."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from socnavgen import proxemics
from socnavgen.bodies import CLEAR_LEAD, PERSON_START_LAG
from socnavgen.export.as_target import run_as_target, target_twin, waypoint_robot
from socnavgen.export.scene import build_scene
from socnavgen.export.timing import (
    GOAL_REACHED,
    HOLD_BEFORE,
    RELEASE_MARGIN,
    ROBOT_SPEEDS,
    WALK_SPEED,
    _Line,
    held_up_from,
    hold_for,
    holds,
    with_waiting_goals,
)
from socnavgen.run import HumanPlan, PathPlan
from socnavgen.sim import simulate_run
from socnavgen.verify.runner import verify_trace
from tests.synthetic import walled_room, write_location

from .export_helpers import REGULAR_TREE, build_run

# A 30 x 20 m hall (0.1 m/px): the robot drives west -> east through X, the person walks south -> north
# through X, 10 m each side; a second crossing C on the robot's path far east.
NODES = {"w": (30, 100), "x": (150, 100), "e": (270, 100), "s": (150, 190), "n": (150, 10), "c": (220, 100)}
EDGES = [("w", "x"), ("x", "c"), ("c", "e"), ("s", "x"), ("x", "n")]


@pytest.fixture(scope="module")
def hall(tmp_path_factory) -> Path:  # noqa: ANN001
    return write_location(tmp_path_factory.mktemp("hall"), walled_room(200, 300, wall=2), NODES, EDGES,
                          resolution=0.1, origin=(0.0, 0.0), name="hall")


def crossing(root: Path, hall: Path, **human: object) -> Path:
    plan = PathPlan(robot=["w", "x", "c", "e"], humans=[
        HumanPlan(**{"name": "human1", "path": ["s", "x", "n"], "interaction_point": "x", **human})])
    return build_run(root, hall, plan, {"human1": REGULAR_TREE})


def test_the_person_waits_before_the_node_and_is_released_by_the_robots_distance(tmp_path: Path, hall: Path) -> None:
    scene, location = build_scene(crossing(tmp_path / "run", hall))
    hold = hold_for(scene.humans[0], scene)
    assert hold is not None and hold.node == "x"
    start, node = complex(scene.humans[0].start.x, scene.humans[0].start.y), complex(*location.node_world("x"))
    # no path node 2 m before x: a goal is added there (reached GOAL_REACHED early), the first on the person's way
    assert hold.goals_first == 1 and hold.wait_index == 0 and hold.wait_goal is not None
    goal = complex(hold.wait_goal.x, hold.wait_goal.y)
    assert abs(abs(node - goal) - (HOLD_BEFORE - GOAL_REACHED)) < 1e-6
    assert abs((goal - start) / abs(goal - start) - (node - start) / abs(node - start)) < 1e-6  # on the leg
    spot = complex(*hold.wait_at)
    assert abs(abs(node - spot) - HOLD_BEFORE) < 1e-3
    # released when the robot is as far before x (at its cruise speed) as the person's last 2 m take
    behind = scene.robot_speed * (HOLD_BEFORE / WALK_SPEED + PERSON_START_LAG)
    robot_at = node - behind  # the robot comes from the west along y = const
    assert abs(complex(*hold.robot_at) - robot_at) < 1e-3
    nominal = {factor: distance for factor, distance, _ in hold.faster}[1.0]  # a robot at its cruise speed
    assert nominal == pytest.approx(abs(robot_at - spot) + RELEASE_MARGIN, abs=0.01)
    # the latest release, for the slowest robot, lets it come as close as its half-length last stretch needs
    slow_at = node - behind * min(ROBOT_SPEEDS)
    assert hold.release_distance == pytest.approx(abs(slow_at - spot) + RELEASE_MARGIN, abs=0.01)
    assert [f for f, _, _ in hold.faster] == sorted(set(ROBOT_SPEEDS) - {min(ROBOT_SPEEDS)}, reverse=True)
    assert [d for _, d, _ in hold.faster] == sorted(d for _, d, _ in hold.faster)[::-1]  # faster: let go farther
    assert hold.early_by < 0.3 and hold.timeout > 20  # the margin lets it go a few centimetres early
    timed, found = with_waiting_goals(scene)
    assert [g.node for g in timed.humans[0].goals] == ["human1_wait", "x", "n"] and found == holds(scene)


def test_who_is_not_timed(tmp_path: Path, hall: Path) -> None:
    for k, human in enumerate([{"interaction_point": None}, {"group_id": 1}, {"path": ["s", "x"], "interaction_point": "s"}]):
        scene, _ = build_scene(crossing(tmp_path / f"r{k}", hall, **human))
        assert hold_for(scene.humans[0], scene) is None, human  # no meeting place; a group; a node the robot skips
    scene, _ = build_scene(crossing(tmp_path / "near", hall, path=["x", "n"]))  # starts at its meeting place
    hold = hold_for(scene.humans[0], scene)
    assert hold is not None and hold.goals_first == 0 and hold.wait_goal is None  # waits where it stands
    assert hold.wait_at == pytest.approx((scene.humans[0].start.x, scene.humans[0].start.y), abs=1e-3)
    # it waits on the robot's path: released before the robot would wait for it (proxemics.HELD_UP_DISTANCE)
    assert hold.release_distance == pytest.approx(proxemics.HELD_UP_DISTANCE + RELEASE_MARGIN, abs=0.06)


def test_a_person_waiting_in_the_robots_way_is_released_before_the_robot_is_held_up() -> None:
    east_then_north = _Line([0j, 10 + 0j, 10 + 10j])
    # on the path ahead: in the way from HELD_UP_DISTANCE on
    assert held_up_from(east_then_north, 8 + 0j, 20.0) == pytest.approx(proxemics.HELD_UP_DISTANCE, abs=0.06)
    # beside the path (1 m off, more than the corridor the bodies sweep): never in its way
    assert held_up_from(east_then_north, 5 + 1j, 20.0) is None
    # round the corner: in its way only once the robot has turned north, 2 m below it
    assert held_up_from(east_then_north, 10 + 2j, 20.0) == pytest.approx(2.0, abs=0.06)
    # the robot stops before it comes that close (`upto`): never held up
    assert held_up_from(east_then_north, 8 + 0j, 4.0) is None


@pytest.mark.parametrize("speed", [0.5, 1.0, 1.5])
def test_the_encounter_happens_at_its_place_at_any_robot_speed_and_not_without_the_timing(
        tmp_path: Path, hall: Path, speed: float) -> None:
    run = crossing(tmp_path / "run", hall)
    for target in ("socrates", "hunav2"):
        report = run_as_target(target_twin(run, target, tmp_path / target), speed)
        meet = next(f for f in report.findings if "meets human1" in f.name)
        assert meet.passed, (target, speed, meet.evidence)
        # at 1.5x the robot crosses x just ahead of the person, who walks into its side: contact (gap <= 5 cm)
        assert report.passed or (speed == 1.5 and [f.kind for f in report.failures] == ["no_collision"]), \
            (target, speed, [f.name for f in report.failures])
    # the run's own tree without our pacing: the person crosses x 15 s before the robot gets there
    untimed = simulate_run(run, robot=waypoint_robot("careful", 0.6 * speed), throttle=False, save=False)
    report = verify_trace(run, untimed)
    assert not report.passed and any("meets human1" in f.name for f in report.failures)


def test_the_person_sets_off_as_early_as_the_robots_own_speed_needs(tmp_path: Path, hall: Path) -> None:
    """A robot at half or 1.5x its cruise speed covers the person's last 2 m of walking in a shorter or longer
    stretch of its path: the release tells its speed from how long it took to come near (a clock from
    measure_distance), so the robot is as far from the node when the person sets off as that walk takes at ITS
    speed - a release by one distance let the person go 4 s early for a slow robot and late for a fast one."""
    run = crossing(tmp_path / "run", hall)
    scene, location = build_scene(run)
    node = np.array(location.node_world("x"))
    walk = HOLD_BEFORE / WALK_SPEED + PERSON_START_LAG
    left = {}
    for speed in (0.5, 1.0, 1.5):
        twin = target_twin(run, "hunav2", tmp_path / f"twin{speed:g}")
        trace = simulate_run(twin.run, robot=waypoint_robot("careful", scene.robot_speed * speed),
                             location=twin.location, throttle=False, save=False)
        waited = np.flatnonzero(trace.action[1:, 0] == -1)
        released = waited[-1] + 2
        left[speed] = float(np.hypot(*(trace.robot[released, :2] - node)))  # the robot comes straight along y
        ideal = scene.robot_speed * speed * walk
        assert abs(left[speed] - ideal) < 0.5, (speed, left[speed], ideal)
    assert left[1.5] - left[0.5] > 0.5 * scene.robot_speed * walk, left  # ideal: 1 x robot_speed x walk


def test_the_speed_is_told_only_where_the_robot_keeps_coming_closer(tmp_path: Path, hall: Path) -> None:
    """The robot's distance tells how far along its path it is only while it keeps coming closer to the spot: a
    robot that passes near the spot first (its path bending round it) or starts too near to be timed gets the one
    release by distance, for its cruise speed."""
    from socnavgen.export.models import WorldPoint

    scene, _ = build_scene(crossing(tmp_path / "run", hall))
    straight = hold_for(scene.humans[0], scene)
    assert straight is not None and len(straight.faster) == len(ROBOT_SPEEDS) - 1
    nominal = {factor: distance for factor, distance, _ in straight.faster}[1.0]
    robot = scene.robot
    detour = robot.model_copy(update={  # from 4 m south of the waiting spot, west to (3, 10), then east through x
        "start": WorldPoint(node="q", x=15.0, y=4.0, yaw=0.0), "path": ["q", *robot.path],
        "waypoints": [WorldPoint(node="w", x=3.0, y=10.0, yaw=0.0), *robot.waypoints]})
    near = robot.model_copy(update={"start": WorldPoint(node="q", x=13.8, y=10.0, yaw=0.0)})  # 1.2 m before x
    for variant in (detour, near):
        hold = hold_for(scene.humans[0], scene.model_copy(update={"robot": variant}))
        assert hold is not None and hold.faster == ()
        if variant is detour:  # the same approach to x as the straight path: the cruise speed's distance
            assert hold.release_distance == pytest.approx(nominal, abs=0.01)


def test_the_release_is_latched_and_happens_at_the_release_distance(tmp_path: Path, hall: Path) -> None:
    run = crossing(tmp_path / "run", hall)
    twin = target_twin(run, "socrates", tmp_path / "twin")
    scene, _ = build_scene(run)
    hold = hold_for(scene.humans[0], scene)
    assert hold is not None
    trace = simulate_run(twin.run, robot=waypoint_robot("careful", 0.3), location=twin.location, throttle=False,
                         save=False)
    person, robot = trace.humans[:, 0, :2], trace.robot[:, :2]
    gap = np.hypot(*(person - robot).T)
    idle = trace.action[:, 0] == -1  # the waiting step does nothing but write the blackboard
    waited = np.flatnonzero(idle[1:])  # (row 0 is the start)
    assert len(waited) > 100  # it stood (at 0.3 m/s the robot comes ~40 s late)
    released = waited[-1] + 2
    assert gap[released - 1] < hold.release_distance <= gap[released - 2] + 0.05
    assert not idle[released:].any()  # never held again, though the robot drives away from it
    spot = person[waited[len(waited) // 2] + 1]
    assert math.dist(spot, hold.wait_at) < 0.3  # it stood at its waiting spot
    assert np.hypot(*trace.humans[waited[5] + 1:released - 1, 0, 3:5].T).max() < 0.05  # standing still


def test_at_a_door_the_person_is_released_earlier_by_pacings_lead(tmp_path: Path, hall: Path) -> None:
    """The hall has no door (no lead); where the scene says the node is a door on the robot's way, the release
    point moves back along the robot's path by that lead (pacing.door_lead), so the person goes through first."""
    scene, _ = build_scene(crossing(tmp_path / "run", hall))
    assert scene.leads == {}
    plain = hold_for(scene.humans[0], scene)
    door = hold_for(scene.humans[0], scene.model_copy(update={"leads": {"x": CLEAR_LEAD}}))
    assert plain is not None and door is not None
    assert abs(abs(complex(*plain.robot_at) - complex(*door.robot_at)) - CLEAR_LEAD) < 1e-3  # along the straight leg
    assert door.release_distance > plain.release_distance


def test_the_bundled_homes_bedroom_door_is_a_door_on_the_robots_way(tmp_path: Path, repo_root: Path) -> None:
    """entering-room on the home: the robot comes along the hallway into the bedroom through its 0.9 m door 2n,
    where the person meets it: the scene carries pacing's lead there, and only there."""
    from socnavgen.cards.generate import write_card_run

    run = write_card_run("entering-room", repo_root / "examples" / "locations" / "home", tmp_path / "run")
    scene, _ = build_scene(run.root)
    assert scene.humans[0].interaction_point == "2n" and scene.leads == {"2n": CLEAR_LEAD}


def test_a_door_just_past_the_node_leads_a_person_who_comes_through_it(tmp_path: Path, repo_root: Path) -> None:
    """entering-elevator on the hospital: the person comes out of the elevator jb to the lobby q9 the robot goes
    through into it. q9 is no door, but the leg q9 -> jb goes through the elevator's door: the person is to be
    through it before the robot gets there (the lead), not face to face in it; a person meeting the robot at q9
    from elsewhere is not led."""
    from socnavgen.cards.generate import write_card_run

    run = write_card_run("entering-elevator", repo_root / "examples" / "locations" / "hospital", tmp_path / "run")
    scene, _ = build_scene(run.root)
    person = scene.humans[0]
    assert person.path[:2] == ["jb", "q9"] and scene.leads == {} and scene.doors_after == {"q9": "jb"}
    led = hold_for(person, scene)
    plain = hold_for(person, scene.model_copy(update={"doors_after": {}}))
    assert led is not None and plain is not None
    assert led.release_distance > plain.release_distance + 0.5  # set off while the robot is farther away
    elsewhere = person.model_copy(update={"path": ["8z", *person.path[1:]]})  # comes to q9 another way
    assert hold_for(elsewhere, scene).robot_at == plain.robot_at  # type: ignore[union-attr]


def test_a_robot_within_the_clocks_distance_from_its_start_is_timed_from_the_start(
        tmp_path: Path, repo_root: Path) -> None:
    """entering-elevator again: the robot starts 4.8 m from the waiting spot, turns away along the corridor (5.2 m)
    and comes back; it never leaves the clock's distance and comes steadily closer within the releases', so its
    speed is told from the start (the release for a half-speed robot was the cruise speed's: the person walked
    out 1.4 m early past it)."""
    from socnavgen.cards.generate import write_card_run

    run = write_card_run("entering-elevator", repo_root / "examples" / "locations" / "hospital", tmp_path / "run")
    scene, _ = build_scene(run.root)
    hold = hold_for(scene.humans[0], scene)
    assert hold is not None and len(hold.faster) == len(ROBOT_SPEEDS) - 1
    start = complex(scene.robot.start.x, scene.robot.start.y)
    assert abs(start - complex(*hold.wait_at)) < hold.measure_distance  # the clock runs from the start


def test_the_elevator_is_left_before_the_robot_enters_it(tmp_path: Path, repo_root: Path) -> None:
    """As the fork runs it (its trees' timing, a careful waypoint robot at its cruise speed): the person leaves
    the elevator before the robot gets to its door. Met face to face in the lobby before the door lead, they stood
    there for the rest of the run (the robot held up 10 s and more)."""
    from socnavgen.cards.generate import write_card_run

    run = write_card_run("entering-elevator", repo_root / "examples" / "locations" / "hospital", tmp_path / "run")
    twin = target_twin(run.root, "socrates", tmp_path / "twin")
    report = run_as_target(twin, 1.0)
    assert report.passed, [f.name for f in report.failures]


@pytest.mark.parametrize("trigger", ["at_encounter", "human_within"])
def test_a_person_the_robot_stands_for_is_released_by_the_time_it_stands(tmp_path: Path, hall: Path,
                                                                         trigger: str) -> None:
    """The robot's script stands it to let human1 cross x first (let_pass, at most 20 s), 4 m before x
    (at_encounter) or once she is within 4 m of it (human_within): the person, waiting 2 m before x, is released
    once the robot stands there - not once it comes closer, which it never does while it waits for them (both stood
    the cue's whole wait: hospital_18's doctor, home_11's resident, 2026-11-28)."""
    from socnavgen.export.as_target import SPEEDS, trace_as_target
    from socnavgen.run import RunFolder
    from socnavgen.run.spec import CueTrigger, Encounter, HumanPart, RobotCue, RobotScript, ScenarioSpec

    run = crossing(tmp_path / "run", hall)
    when = CueTrigger(when="at_encounter", encounter="e1", distance=4.0) if trigger == "at_encounter" else \
        CueTrigger(when="human_within", human="human1", distance=4.0)
    cue = RobotCue(trigger=when, let_pass="human1", wait=20.0)
    meet = Encounter(id="e1", place="NODE", node="x", humans=[HumanPart(human="human1")])
    RunFolder(run).write_spec(ScenarioSpec(script=RobotScript(cues=[cue]), encounters=[meet]))
    scene, location = build_scene(run)
    hold = hold_for(scene.humans[0], scene)
    assert hold is not None
    node, wait = complex(*location.node_world("x")), complex(*hold.wait_at)
    # the robot drives east along y to x: it stands 4 m before x, or 4 m from her waiting spot 2 m south of x
    stop = node - 4.0 if trigger == "at_encounter" else node - math.sqrt(4.0 ** 2 - abs(node - wait) ** 2)
    assert hold.release_distance >= abs(stop - wait) + RELEASE_MARGIN - 0.06
    twin = target_twin(run, "socrates", tmp_path / "twin")
    for speed in SPEEDS:
        trace = trace_as_target(twin, speed, "script")
        robot = trace.robot[:, 0] + 1j * trace.robot[:, 1]
        person = trace.humans[:, 0, 0] + 1j * trace.humans[:, 0, 1]
        crossed = np.flatnonzero(np.abs(person - node) < 0.5)
        assert crossed.size, speed
        k = int(crossed[0])  # she crosses x while the robot still stands back for her, early in its wait
        assert abs(robot[k] - node) > 2.5, speed
        stood = np.flatnonzero(np.abs(robot - stop) < 0.6)
        assert trace.t[k] - trace.t[stood[0]] < 10.0, (speed, trace.t[k], trace.t[stood[0]])
