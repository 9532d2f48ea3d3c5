"""People who stand together keep a gap the eye does not read as touching (bodies.PERSON_STAND_GAP), a goal the
robot stands on is taken like one a person stands on (sim.people.spots), spots round a shared goal keep off the
robot's way, and a walker slowed by a crowd still steps round someone in their way (sim.people.spacing)."""

from __future__ import annotations

import cmath
import math
from pathlib import Path

import numpy as np

from socnavgen.bodies import PERSON_PASS_GAP, PERSON_RADIUS, PERSON_STAND_GAP
from socnavgen.location import load_location
from socnavgen.sim import World
from socnavgen.sim.people.neighbours import new_grid
from socnavgen.sim.people.spacing import SIDESTEP, keep_apart
from socnavgen.sim.people.state import PERSON
from socnavgen.sim.records import table

from .simhelpers import REGULAR, Stay, human, make_sim, tree_xml
from .test_people_spacing import pair_gaps
from .test_people_spots import robot_gaps

STAND = tree_xml('<Sequence><SetBlackboard output_key="agentid" value="{id}"/></Sequence>')
ROOT = Path(__file__).resolve().parents[2]
WALKING = 0.5  # m/s: someone this fast walks (a standing person's drift on the social force stays well under it)
SETTLE = 5.0  # s: people who walk 0.6 m to their places stand there by then
TOLERANCE = 0.05  # m: two walking side by side the walking gap apart stand where their walks ended (0.27 m)


def test_people_gathering_at_one_point_stand_the_standing_gap_apart():
    """Four people walk to one point in an open room: once they all stand round it, no two of them stand closer
    than PERSON_STAND_GAP (on main the spots and the queue kept 0.10 m, which read as 'pressed together')."""
    goal = (10.0, 5.0)
    people = [human(f"human{k + 1}", start=(3.0, 2.5 + 1.6 * k), goals=[goal]) for k in range(4)]
    trace = make_sim(people, [tree_xml(REGULAR)] * 4, [(18.0, 9.0), (18.5, 9.0)], Stay(), timeout=40).run()
    assert trace.end_reason == "all_done"
    assert pair_gaps(trace)[-1].min() >= PERSON_STAND_GAP - TOLERANCE, pair_gaps(trace)[-1]


def test_a_walker_whose_goal_someone_stands_on_stops_the_standing_gap_from_them():
    """Someone stands on the point another walks to: the walker stands beside them PERSON_STAND_GAP or more from
    their body (on main 0.10 m), and has arrived."""
    people = [human("human1", start=(3.0, 5.0), goals=[(12.0, 5.0)]), human("human2", start=(12.0, 5.0), goals=[])]
    trace = make_sim(people, [tree_xml(REGULAR), STAND], [(10.0, 9.0), (10.5, 9.0)], Stay(), timeout=20).run()
    assert trace.end_reason == "all_done"
    assert pair_gaps(trace)[-1].min() >= PERSON_STAND_GAP - TOLERANCE, pair_gaps(trace)[-1]
    assert abs(complex(*trace.humans[-1, 0, :2]) - (12.0 + 5.0j)) <= 2.0  # came up to them


def test_a_walker_whose_goal_the_robot_stands_on_stands_at_a_free_spot_beside_it():
    """The robot stands on a person's goal: the person walks up and stands at a free spot beside it, the passing
    gap off its body, and has arrived within a few seconds (on main they were held short of it, then squeezed on
    to the goal and stood against its body until the time limit)."""
    people = [human("human1", start=(3.0, 5.0), goals=[(12.0, 5.0)])]
    trace = make_sim(people, [tree_xml(REGULAR)], [(12.0, 5.0), (18.0, 5.0)], Stay(), timeout=30).run()
    assert trace.end_reason == "all_done"
    assert trace.t[-1] < 15.0, trace.t[-1]  # a 9 m walk, not the time limit
    assert robot_gaps(trace)[-1].min() >= PERSON_PASS_GAP - TOLERANCE, robot_gaps(trace)[-1]
    assert abs(complex(*trace.humans[-1, 0, :2]) - (12.0 + 5.0j)) <= 2.5  # beside it


def test_people_standing_round_a_shared_goal_keep_off_the_robots_way():
    """The robot's way runs 2 m north of a point four people walk to from the north: the first stands on the point,
    the others round it on the side away from the robot's way, the robot's passing gap off its body passing (on
    main the nearest spots, on the way, were taken: 1.1 m from it)."""
    goal = 10.0 + 5.0j
    people = [human(f"human{k + 1}", start=(7.0 + 2.0 * k, 9.5), goals=[(goal.real, goal.imag)]) for k in range(4)]
    route = [(2.0, 7.0), (18.0, 7.0)]
    trace = make_sim(people, [tree_xml(REGULAR)] * 4, route, Stay(), timeout=40).run()
    assert trace.end_reason == "all_done"
    end = trace.humans[-1, :, 1]
    clear = trace.human_radii + trace.robot_radius + PERSON_PASS_GAP  # the robot passes on y = 7 with its gap
    assert np.all(7.0 - end >= clear - TOLERANCE), end


def test_a_walker_slowed_to_a_crawl_steps_round_someone_in_the_way_at_a_walking_pace():
    """keep_apart on its own: a walker crawling (0.05 m/s) straight at someone standing in their way, their goal
    beyond them, steps round them at SIDESTEP of the speed they mean to walk (on main: of the crawl, 0.025 m/s, so
    a crowd slowed to a crawl never got round each other)."""
    people = table(PERSON, 2, pos=[5.0 + 5.0j, 5.9 + 5.0j], radius=PERSON_RADIUS, desired_speed=[1.3, 0.0],
                   goal=[12.0 + 5.0j, 5.9 + 5.0j], via=[12.0 + 5.0j, 5.9 + 5.0j], walks=[True, False],
                   to_goal=[True, False], vel=[0.05 + 0j, 0j])
    v = keep_apart(people, 0, 0.05 + 0j, 1.0 + 0j, 0.05, new_grid(2))
    assert abs(v.imag) >= SIDESTEP * 1.3 - 1e-6, v  # round them, at a walking pace
    assert v.real <= 1e-9, v  # not into them


def test_a_walker_coming_to_stand_keeps_the_standing_gap_and_one_walking_past_the_walking_gap():
    """keep_apart on its own: a walker 0.2 m from someone, stepping toward them, is held there when their walk
    ends beside them (they come to stand: PERSON_STAND_GAP), and may close in to PERSON_KEEP_GAP walking past."""
    def step(goal: complex) -> complex:
        people = table(PERSON, 2, pos=[5.0 + 5.0j, 6.0 + 5.0j], radius=PERSON_RADIUS, desired_speed=[1.0, 0.0],
                       goal=[goal, 6.0 + 5.0j], via=[goal, 6.0 + 5.0j], walks=[True, False], to_goal=[True, False])
        return keep_apart(people, 0, 1.0 + 1.0j, (goal - people[0].pos) / abs(goal - people[0].pos), 0.05, new_grid(2))

    arriving, passing = step(5.2 + 5.5j), step(12.0 + 9.0j)
    assert arriving.real <= 1e-9, arriving  # held at the 0.2 m it has (under the standing gap)
    assert passing.real > 0.5, passing  # closes in toward the walking gap


def test_a_walker_whose_walk_has_ended_only_drifts_and_never_steps_round_anyone():
    """keep_apart on its own: someone whose walk has ended (no way this step: they brake) drifting 0.1 m/s on the
    social force toward someone standing 0.3 m from them is held, not turned into a sidestep at a walking pace."""
    people = table(PERSON, 2, pos=[5.0 + 5.0j, 5.0 + 4.1j], radius=PERSON_RADIUS, desired_speed=[1.5, 0.0],
                   goal=[5.0 + 5.0j, 5.0 + 4.1j], via=[5.0 + 5.0j, 5.0 + 4.1j], walks=[True, False],
                   to_goal=[True, False], vel=[-0.07 - 0.07j, 0j])
    v = keep_apart(people, 0, -0.07 - 0.07j, 0j, 0.05, new_grid(2))
    assert abs(v) <= 0.1, v  # still a drift, not a 0.75 m/s step round them


def test_a_briefing_group_standing_by_a_wall_stays_standing():
    """Three people of one group gather at one point (warehouse_22's safety briefing at vj, on the bundled
    warehouse: they start round it 0.6 m from it) and stand there, the robot far off: nobody walks. Before, the
    social force's drift of one toward another within the standing gap was taken for being blocked on their way and
    turned into a sidestep at half their desired speed (0.75 m/s), which kept itself alive: the briefing's two
    listeners walked 5 m along the aisle side by side and back."""
    world = World.from_location(load_location(ROOT / "examples" / "locations" / "warehouse"))
    vj, apart = 18.525 - 3.025j, cmath.rect(0.6, math.pi / 3)  # round vj, 0.6 m from it, facing it
    starts = [vj + 0.6, vj - apart.conjugate(), vj - apart]
    people = [human(f"human{k + 1}", start=(p.real, p.imag), goals=[(vj.real, vj.imag)], group_id=0,
                    yaw=cmath.phase(vj - p)) for k, p in enumerate(starts)]
    trace = make_sim(people, [tree_xml(REGULAR)] * 3, [(6.0, -3.0), (5.0, -3.0)], Stay(), world=world,
                     timeout=30, idle_end=30.0).run()
    assert trace.t[-1] >= 29.0, trace.t[-1]
    settled = trace.t >= SETTLE  # their 0.6 m walks in have ended
    speeds = np.hypot(trace.humans[settled, :, 3], trace.humans[settled, :, 4])
    assert speeds.max() < WALKING, (speeds.max(), np.unravel_index(speeds.argmax(), speeds.shape))
