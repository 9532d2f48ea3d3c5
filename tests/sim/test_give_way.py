"""Where GiveWaytoRobot stands aside, checked against its rule by brute force on people scattered around a
robot on a bent path in a room with walls, and in a corridor where no spot is far enough from the path."""

from __future__ import annotations

import numpy as np
import pytest

from socnavgen.sim import empty_room, load_policy
from socnavgen.sim.people.give_way import GIVE_WAY_MARGIN, SIDE_STEP_MAX, plan_side_step
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


def reachable_spots(world, p: complex, radius: float) -> np.ndarray:  # noqa: ANN001
    """Every spot within SIDE_STEP_MAX of p a body walks to in a straight line (64 directions, every 5 cm)."""
    out = []
    for angle in np.linspace(0, 2 * np.pi, 64, endpoint=False):
        u = complex(np.cos(angle), np.sin(angle))
        room = world.free_along(p, u, SIDE_STEP_MAX, radius)
        out.extend(p + u * np.arange(0.05, room + 1e-9, 0.05))
    return np.array(out, dtype=complex)


@pytest.mark.parametrize("seed", range(3))
@pytest.mark.parametrize("room", sorted(ROOMS))
def test_the_side_step_leaves_the_robots_path_when_there_is_room(room: str, seed: int):
    """For each person near the robot's upcoming path: the spot is reached in a straight line clear of walls;
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
            if spot != p:
                walk = p + (spot - p) * np.linspace(0, 1, 40)[1:]
                assert world.clearance_at(walk).min() >= radius - 1e-9
            (there,), _ = to_path(np.array([spot]), upcoming)
            spots = reachable_spots(world, p, radius)
            room_left = to_path(spots, upcoming)[0].max(initial=0.0) if len(spots) else 0.0
            if room_left >= want + 0.3:  # clearly room: it must get out of the way
                roomy += 1
                assert there >= want - 1e-9
                a, b = upcoming[segment], upcoming[segment + 1]
                sideways = ((p - a) * (b - a).conjugate()).imag
                if abs(sideways) > 0.05 and ((spot - a) * (b - a).conjugate()).imag * sideways > 0:
                    same_side += 1
            else:
                cramped += 1
                assert there >= here - 1e-9
    assert planned >= 20
    assert same_side >= roomy // 2  # it mostly keeps to its own side
    if room == "corridor":
        assert cramped >= 10  # the corridor leaves no spot clear of the robot: the fallback is exercised
