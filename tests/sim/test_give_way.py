"""Where GiveWaytoRobot stands aside, checked against its rule by brute force on people scattered around a
robot on a bent path in a room with walls, and in a corridor where no spot is far enough from the path."""

from __future__ import annotations

import numpy as np
import pytest

from socnavgen.sim import empty_room, load_policy
from socnavgen.sim.people.side_step import GIVE_WAY_MARGIN, SIDE_STEP_MAX, SPOT_ROOM, plan_side_step
from tests.sim.simhelpers import REGULAR, human, make_sim, tree_xml

ROOMS = {  # (width, height, walls, robot path): a room with walls, and a corridor too narrow to leave the path
    "room": (12.0, 8.0, [(5.0, 0.0, 5.4, 3.0), (8.0, 5.0, 8.4, 8.0)],
             [(1.0, 4.0), (4.0, 4.2), (6.5, 3.8), (7.0, 1.2), (11.0, 1.2)]),
    "corridor": (12.0, 2.2, [], [(0.8, 1.1), (6.0, 1.1), (11.2, 1.0)]),
}


def to_path(points: np.ndarray, path: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(distance to the polyline, index of the nearest segment) of each point."""
    a, b = path[:-1], path[1:]
    ab = b - a
    t = np.clip(((points[:, None] - a) * ab.conjugate()).real / np.maximum(np.abs(ab) ** 2, 1e-18), 0, 1)
    d = np.abs(points[:, None] - (a + ab * t))
    return d.min(axis=1), d.argmin(axis=1)


def reachable_spots(world, p: complex, radius: float, others: np.ndarray, robot: complex,  # noqa: ANN001
                    robot_radius: float) -> np.ndarray:
    """Every spot within SIDE_STEP_MAX of p a body walks to in a straight line (64 directions, every 5 cm) where
    no one else stands, with 0.3 m to spare (`others`: their centres, bodies of `radius`), and not through the
    robot's body (a spot behind the robot in the corridor is reached only through it)."""
    out = []
    reach = radius + robot_radius
    for angle in np.linspace(0, 2 * np.pi, 64, endpoint=False):
        u = complex(np.cos(angle), np.sin(angle))
        room = world.free_along(p, u, SIDE_STEP_MAX, radius)
        rel = (robot - p) * u.conjugate()
        if rel.real > 0 and abs(rel.imag) < reach:  # the walk meets the robot's body: it stops short of it
            room = min(room, max(0.0, rel.real - np.sqrt(reach**2 - rel.imag**2)))
        out.extend(p + u * np.arange(0.05, room + 1e-9, 0.05))
    spots = np.array(out, dtype=complex)
    if len(others) and len(spots):
        spots = spots[np.abs(spots[:, None] - others[None, :]).min(axis=1) >= 2 * radius + SPOT_ROOM + 0.3]
    return spots


@pytest.mark.parametrize("seed", range(3))
@pytest.mark.parametrize("room", sorted(ROOMS))
def test_the_side_step_leaves_the_robots_path_when_there_is_room(room: str, seed: int):
    """For each person near the robot's upcoming path: the spot is reached in a straight line clear of walls (from
    a start squeezed nearer a wall than their radius: never nearer one than they have been on the way);
    when there is clearly room somewhere within 3 m, the spot leaves 0.5 m between the bodies all along the
    path, on the person's own side when straight sideways is free; when there is no such room, it is at least
    as far from the path as the person already is (it never walks into a worse place)."""
    rng = np.random.default_rng(seed)
    width, height, walls, path = ROOMS[room]
    world = empty_room(width, height, walls=walls)
    waypoints = np.array([complex(*w) for w in path])
    planned = cramped = roomy = same_side = 0
    for _ in range(10):
        people = [human(f"human{k + 1}", start=(float(rng.uniform(0.8, width - 0.8)),
                                                float(rng.uniform(0.7, height - 0.7)))) for k in range(12)]
        sim = make_sim(people, [tree_xml(REGULAR)] * 12, path, policy=load_policy("waypoints"), world=world)
        robot = waypoints[0] + (waypoints[1] - waypoints[0]) * rng.uniform(0.05, 0.95)  # on its first leg
        sim.robot.pos = robot
        upcoming = np.concatenate([[robot], waypoints[1:]])
        for i in range(12):
            p = complex(sim.people[i].pos)
            plan_side_step(sim.state, i)
            spot, radius = complex(sim.people[i].aside), float(sim.people[i].radius)
            want = radius + sim.robot.radius + GIVE_WAY_MARGIN
            (here,), (segment,) = to_path(np.array([p]), upcoming)
            if here >= want:
                assert spot == p  # already out of the way: it stays
                continue
            planned += 1
            if spot != p:  # clear of walls: never nearer one than they have been (a squeezed start walks out first)
                clear = world.clearance_at(p + (spot - p) * np.linspace(0, 1, 40))
                assert (clear >= np.minimum(radius, np.maximum.accumulate(clear)) - 1e-9).all(), clear
                assert clear[-1] >= radius - 1e-9  # and their body has its room there
            (there,), _ = to_path(np.array([spot]), upcoming)
            others = np.array([complex(sim.people[j].pos) for j in range(12) if j != i])
            if spot != p:  # nobody stands there
                assert np.abs(others - spot).min() >= 2 * radius + SPOT_ROOM - 1e-9
            spots = reachable_spots(world, p, radius, others, robot, float(sim.robot.radius))
            room_left = to_path(spots, upcoming)[0].max(initial=0.0) if len(spots) else 0.0
            if room_left >= want + 0.3:  # clearly room: it must get out of the way
                roomy += 1
                assert there >= want - 1e-9
                a, b = upcoming[segment], upcoming[segment + 1]
                sideways = ((p - a) * (b - a).conjugate()).imag
                if ((spot - a) * (b - a).conjugate()).real <= 0:  # behind the robot (the corridor's only room,
                    roomy -= 1  # walked to round it, never through it): no side of its path to keep to
                elif abs(sideways) > 0.05 and ((spot - a) * (b - a).conjugate()).imag * sideways > 0:
                    same_side += 1
            else:
                cramped += 1
                assert there >= here - 1e-9
    assert planned >= 20
    assert same_side >= roomy // 2  # it mostly keeps to its own side
    if room == "corridor":
        assert cramped >= 10  # the corridor leaves no spot clear of the robot: the fallback is exercised


def test_a_group_giving_way_in_a_corridor_each_finds_a_spot_and_the_robot_passes():
    """Three people chatting in the middle of a 2.9 m corridor, on the robot's path, give way when it comes
    near: each steps to a spot of their own (the one in the middle does not walk into the spot of the one
    beside it and stand in the robot's way, as the hospital's handover nurses did for 52 s), and the robot,
    waiting until the way is clear, gets past without touching anyone."""
    from socnavgen.run.spec import CueTrigger, RobotCue, RobotScript

    gives_way = tree_xml('<Fallback><Sequence><IsRobotNearby agent_id="{id}" distance="3.0"/>'
                         '<GiveWaytoRobot agent_id="{id}" time_step="{dt}"/></Sequence>'
                         '<LookAtRobot agent_id="{id}"/></Fallback>')
    group = [human("human1", start=(7.7, 1.45), goals=[(7.7, 1.45)], group_id=0),
             human("human2", start=(6.8, 1.96), goals=[(6.8, 1.96)], group_id=0),
             human("human3", start=(6.8, 0.93), goals=[(6.8, 0.93)], group_id=0)]
    script = RobotScript(cues=[RobotCue(trigger=CueTrigger(when="blocked", distance=2.5), say="EXCUSE ME", hold=2.0,
                                        wait_until_clear=True)])
    sim = make_sim(group, [gives_way] * 3, [(1.0, 1.45), (13.0, 1.45)], policy=load_policy("scripted"),
                   world=empty_room(14.0, 2.9), script=script, timeout=60)
    trace = sim.run()
    assert trace.end_reason == "robot_goal" and trace.t[-1] < 40.0
    spots = [complex(sim.people[i].aside) for i in range(3)]
    assert min(abs(a - b) for k, a in enumerate(spots) for b in spots[k + 1:]) >= 0.5 + SPOT_ROOM - 1e-9
    assert [text for _, text in sim.cues.fired][-1] != "still blocked: stop waiting, go around"
    from socnavgen.sim.contact import trace_gaps

    assert trace_gaps(trace).min() > 0.05  # nobody touched


def test_a_follower_on_the_last_leg_of_a_round_trip_follows_at_once():
    """FOLLOW ME at the start of a round trip whose last leg leads back past the follower (into their room):
    they are not in the robot's way now, so they follow it out instead of standing aside until it comes back
    (the rehab patient stayed 12 m behind for the whole walk)."""
    follows = tree_xml('<FollowRobot agent_id="{id}" time_step="{dt}"/>')
    route = [(4.0, 4.0), (12.0, 4.0), (4.0, 4.0), (4.0, 8.0)]
    sim = make_sim([human(start=(4.0, 5.4), goals=[(4.0, 5.4)])], [follows], route, policy=load_policy("scripted"),
                   world=empty_room(16.0, 10.0), timeout=60)
    trace = sim.run()
    at = {round(float(t), 2): k for k, t in enumerate(trace.t)}
    k = at[12.0]  # the robot is near the far end
    robot, person = trace.robot[k, :2], trace.humans[k, 0, :2]
    assert robot[0] > 9.0
    assert np.hypot(*(robot - person)) < 4.0  # following, not waiting at the start
    assert not trace.executed(0, "GiveWaytoRobot").any() or person[0] > 6.0


def test_a_person_who_gave_way_to_a_round_trip_walks_on_once_the_robot_is_past_them():
    """A person who steps aside for a robot that will come back past them at the end of its round trip (the rehab
    patient in his room: the robot's last leg leads into it) is in its way where the robot passes them FIRST: once
    it has gone by there they follow it, instead of waiting for its return (the patient stood 80 s in his room)."""
    tree = tree_xml('<Fallback><Sequence><IsRobotBlocking agent_id="{id}" distance="1.8"/>'
                    '<GiveWaytoRobot agent_id="{id}" time_step="{dt}"/></Sequence>'
                    '<FollowRobot agent_id="{id}" time_step="{dt}"/></Fallback>')
    route = [(4.0, 5.6), (4.0, 4.0), (13.0, 4.0), (4.0, 4.0), (4.0, 8.6)]  # out of the room, along, back into it
    sim = make_sim([human(start=(4.2, 7.4), goals=[(4.2, 7.4)])], [tree], route, policy=load_policy("scripted"),
                   world=empty_room(16.0, 10.0), timeout=40)
    trace = sim.run()
    assert trace.executed(0, "GiveWaytoRobot").any()  # the robot came at them first
    k = int(np.searchsorted(trace.t, 18.0))  # the robot near the far end of its way out
    robot, person = trace.robot[k, :2], trace.humans[k, 0, :2]
    assert robot[0] > 9.0
    assert person[1] < 6.0 and np.hypot(*(robot - person)) < 6.0  # out of the room, following



@pytest.mark.parametrize(("follower_x", "follows", "held"), [(10.2, True, True), (11.8, True, False),
                                                             (10.2, False, False)])
def test_someone_who_gave_way_waits_for_the_robots_follower_before_crossing_its_way(follower_x: float, follows: bool,
                                                                                  held: bool):
    """The robot (12, 5) leads a follower east along y = 5; a person stood aside at (11, 3.8), bound north-west across
    that way: while the follower is still to come (1.8 m behind the robot) their walk on would cut between the two,
    so they wait (follower_to_come); once the follower has gone by them, or when the one behind the robot is not
    following it, they walk on (the rehab nurse walked on 0.1 m in front of the patient the robot guided)."""
    from socnavgen.sim.people.give_way import follower_to_come
    from socnavgen.sim.people.state import ROUTE_GOAL, ROUTE_ROBOT

    people = [human("human1", start=(11.0, 3.8), goals=[(6.0, 5.2)]),
              human("human2", start=(follower_x, 5.0), goals=[(follower_x, 5.0)])]
    sim = make_sim(people, [tree_xml(REGULAR)] * 2, [(follower_x + 1.8, 5.0), (18.0, 5.0)])
    q = sim.state.people[1]
    q.behavior, q.route = (1, ROUTE_ROBOT) if follows else (0, ROUTE_GOAL)
    assert follower_to_come(sim.state, 0) is held
