"""Groups stand and walk as people do: a crew setting off in single file from the circle it stood in walks off at
once (its leader is not boxed in by the one it leads), and members standing together stay where they stand unless
the robot or their tree moves them."""

from __future__ import annotations

import numpy as np

from socnavgen.bodies import PERSON_RADIUS
from socnavgen.sim import empty_room
from socnavgen.sim.people.leaves import FOLLOW_SLOWING, FOLLOW_STOP
from socnavgen.sim.people.neighbours import new_grid
from socnavgen.sim.people.spacing import keep_apart
from socnavgen.sim.people.spots import REACH, RING_STEP
from socnavgen.sim.people.state import PERSON
from socnavgen.sim.records import table

from .simhelpers import REGULAR, Drive, Stay, human, make_sim, tree_xml, xy


def follow_human(target: int) -> str:
    return tree_xml(f'<FollowHuman agent_id="{{id}}" target_id="{target}" time_step="{{dt}}"/>')


def test_a_walker_boxed_in_on_their_right_steps_round_the_one_ahead_on_the_left():
    """keep_apart on its own: a walker heading west is slowed against someone standing ahead on their right (north-
    west of them, body to body). With nobody else near they step round them on the right, as walkers do; with
    someone else standing on that side (behind them on the right, body to body: warehouse_10's crew in its circle)
    they step round on the left, on along their way - the right-hand step ran into the one behind, again and
    again, and the crew stood 40 s."""
    ahead_right, behind_right = complex(-0.32, 0.84), complex(0.57, 0.69)  # from the walker, gaps 0.1 m
    way = (-10.0 + 0.5j) / abs(-10.0 + 0.5j)  # the way they walk (toward their via)

    def step(others: list[complex]) -> complex:
        pos = [0j, *others]
        people = table(PERSON, len(pos), pos=pos, radius=PERSON_RADIUS, desired_speed=[0.8] + [0.0] * len(others),
                       goal=[-10.0 + 0.5j, *others], via=[-10.0 + 0.5j, *others],
                       walks=[True] + [False] * len(others), to_goal=[True] + [False] * len(others))
        return keep_apart(people, 0, -0.09 + 0.11j, way, 0.05, new_grid(len(pos)))

    away = -ahead_right / abs(ahead_right)
    alone, boxed = step([ahead_right]), step([ahead_right, behind_right])
    assert alone.real > 0.2, alone  # round them on the right (east of them: the walker's right-hand side)
    assert boxed.real < -0.2, boxed  # on along the way (west), round them on the left
    assert (boxed * away.conjugate()).real >= -1e-6, boxed  # and not into the one ahead ...
    assert (boxed * (-behind_right / abs(behind_right)).conjugate()).real >= -1e-6, boxed  # ... nor the one behind


def test_a_crew_setting_off_in_single_file_from_its_circle_walks_off_at_once():
    """Four members of a group stand in a circle 0.7 m from a wall (as the spawn puts them); the one on the wall side
    leads (RegularNav west), the others follow in a chain (FollowHuman). The leader is on their way within a few
    seconds and the whole file gets there (on main the leader stepped round the member ahead on his right into the
    one behind, the followers stood waiting for him, and the crew stood 40 s)."""
    offset = complex(-8.5, 4.45)  # warehouse_10's crew at vj, shifted into a 20 x 10 room (the wall at y = 0)
    starts = [complex(19.12, -3.02), complex(18.27, -2.87), complex(18.52, -3.72), complex(18.76, -2.16)]
    goal = (2.0, 1.5)
    people = [human(f"human{k + 1}", start=((s + offset).real, (s + offset).imag), goals=[goal], group_id=0)
              for k, s in enumerate(starts)]
    trees = [follow_human(3), follow_human(2), tree_xml(REGULAR), follow_human(1)]  # leader: human3
    trace = make_sim(people, trees, [(18.0, 8.5), (18.5, 8.5)], Stay(), world=empty_room(20.0, 10.0),
                     timeout=30).run()
    leader = trace.humans[:, 2, 0]
    assert leader[np.searchsorted(trace.t, 5.0)] < leader[0] - 2.0, leader[::20]  # walking within 5 s
    assert abs(complex(*trace.humans[-1, 2, :2]) - complex(*goal)) < 1.0  # the leader got there ...
    behind = trace.humans[-1, :, 0] - trace.humans[-1, 2, 0]
    assert np.all(behind < 3 * (FOLLOW_STOP + FOLLOW_SLOWING)), behind  # ... the file right behind him


def test_members_of_a_standing_group_whose_trees_only_look_stay_where_they_stand():
    """Three members of a group stand in a circle round a point (as the spawn puts them), their trees chatting or
    looking at the robot as it drives past beside them, out of their way: nobody moves them (no group force on
    members who stand, no spacing push, no making room), so each stays on their spot. (home_10's friends moved only
    when the robot stood waiting on its way through their circle: people.make_room.)"""
    look = tree_xml('<Fallback><Sequence><IsRobotVisible agent_id="{id}" distance="2.5"/>'
                    '<LookAtRobot agent_id="{id}"/></Sequence><MakeGesture agent_id="{id}" message="0"/></Fallback>')
    centre = complex(10.0, 4.0)
    starts = [centre + 0.6 * np.exp(2j * np.pi * k / 3) for k in range(3)]
    people = [human(f"human{k + 1}", start=(s.real, s.imag), goals=[(centre.real, centre.imag)], group_id=0)
              for k, s in enumerate(starts)]
    trace = make_sim(people, [look] * 3, [(2.0, 6.6), (18.0, 6.6)], Drive(0.5), world=empty_room(20.0, 10.0),
                     timeout=25).run()
    near = np.hypot(trace.humans[:, :, 0] - trace.robot[:, None, 0], trace.humans[:, :, 1] - trace.robot[:, None, 1])
    assert near.min() < 2.5  # the robot came by within sight (they looked)
    moved = np.hypot(trace.humans[:, :, 0] - trace.humans[0, None, :, 0], trace.humans[:, :, 1] - trace.humans[0, None, :, 1])
    assert moved.max() < 0.02, moved.max(axis=0)


def test_a_follower_whose_leader_stopped_for_good_comes_up_beside_them_off_the_robots_way():
    """Two people walk in single file (FollowHuman behind a RegularNav walker) to the leader's goal, which lies on the
    robot's way still to go, and the leader stands there for good (their walk is over). The follower comes up and
    stands beside the leader, off the robot's way, as two people who walked somewhere together do - not a trail's
    length behind them in file (warehouse_14: the follower stood 30 s in a 1.4 m passage the robot had to take,
    1.3 m behind the worker who had stopped at the loading door)."""
    leader_goal = (8.0, 5.0)
    people = [human("human1", start=(15.0, 5.0), goals=[leader_goal]),
              human("human2", start=(16.5, 5.0), goals=[(18.0, 5.0)])]
    trace = make_sim(people, [tree_xml(REGULAR), follow_human(0)], [(2.0, 5.0), (19.0, 5.0)], Stay(),
                     world=empty_room(20.0, 10.0), timeout=30).run()
    leader, follower = xy(trace, -1, 0), xy(trace, -1, 1)
    assert abs(leader - complex(*leader_goal)) < 0.8, leader  # the leader got there and stands
    assert abs(follower - leader) < 2 * RING_STEP + REACH, (follower, leader)  # beside them (a ring or two) ...
    assert abs(follower.imag - 5.0) > 2 * PERSON_RADIUS + 0.2, follower  # ... off the robot's way (y = 5) ...
    assert abs(follower - xy(trace, np.searchsorted(trace.t, trace.t[-1] - 3.0), 1)) < 0.1  # ... and stands there
