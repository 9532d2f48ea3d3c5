"""What the round-13 players had to guess (issue 25, /work/suite/r13/player_*_notes.md), each answered by a fact the
prompt states from its home, and the fact checked against what the simulator and the verifier do: a let_pass wait
is not in the pacing ETA and its person is never held, a node someone stands on is reached from beside them (a
patient on the robot's goal was released at once: hospital_11), a follower's encounter may sit at the robot's start,
which member of a group stands on which side, let_pass may stand only a moment, cue distances are straight, and
people who never meet the robot stay in the prose."""

from __future__ import annotations

import math

import numpy as np

from socnavgen.proposal.facts import (
    cue_triggers_text,
    follower_turn_text,
    groups_text,
    pacing_text,
    people_text,
    robot_limits_text,
)
from socnavgen.run.spec import CueTrigger, RobotCue, RobotScript, ScenarioSpec
from tests.sim.simhelpers import REGULAR, Stay, human, make_sim, tree_xml

STAND = tree_xml('<Sequence><LookAtRobot agent_id="{id}"/></Sequence>')
WALK = tree_xml(REGULAR)


def test_a_let_pass_wait_is_not_in_the_pacing_eta_and_a_plain_wait_is():
    """Players B and C: 'whether a let_pass wait counts in the pacing ETA'. still_waits is what pacing adds."""
    from socnavgen.sim.robot.script import still_waits

    def left(cue: RobotCue) -> float:
        sim = make_sim([human(start=(10.0, 8.0), goals=[(10.0, 8.0)])], [STAND], [(2.0, 5.0), (18.0, 5.0)],
                       policy=Stay(), script=RobotScript(cues=[cue]))
        sim.step()
        return float(still_waits(sim.episode.script, sim.t))

    start = CueTrigger(when="start")
    assert left(RobotCue(trigger=start, wait=10.0)) > 9.0
    assert left(RobotCue(trigger=start, wait=10.0, let_pass="human1")) == 0.0  # `wait` is only its most
    text = pacing_text()
    assert "what is left of the `wait` of cues that fired: not a cue yet to fire, a let_pass" in text
    assert "Whom a let_pass cue stands for comes at their own speed" in text


def _first_goal_after_a_step(someone_on_it: bool) -> complex:
    node = complex(10.0, 5.0)
    people = [human("human1", start=(8.6, 5.0), goals=[(10.0, 5.0), (10.0, 1.0)])]
    trees = [WALK]
    if someone_on_it:
        people.append(human("human2", start=(10.0, 5.0), goals=[(10.0, 5.0)]))
        trees.append(STAND)
    sim = make_sim(people, trees, [(2.0, 9.0), (18.0, 9.0)], policy=Stay())
    assert sim.goals_of(0)[0] == node
    sim.step()
    return sim.goals_of(0)[0]


def test_a_node_someone_stands_on_is_reached_from_beside_them():
    """Player C's patient started 1.5 m from her interaction point, where another patient stood: she was past it at
    once and never paced (hospital_11; the prompt had told her nothing, she guessed 'the robot's goal'). Unpaced she
    still reaches it from beside them at once; paced, she is held there until she walks (people.state.goal_reached,
    tests/sim/test_pacing.py), as the prompt says."""
    from socnavgen.sim.people.state import QUEUE_REACH

    assert _first_goal_after_a_step(someone_on_it=False) == complex(10.0, 5.0)  # nobody there: still to walk to
    assert _first_goal_after_a_step(someone_on_it=True) == complex(10.0, 1.0)  # reached beside human2 at once
    assert QUEUE_REACH > 1.4  # the start 1.4 m from the node above
    text = pacing_text()
    assert f"Someone starting within {QUEUE_REACH:.1f} m of their interaction point while another person stands on " \
           "it is paced there beside them (reached once they walk)" in text  # held: tests/sim/test_pacing.py
    assert "wherever they start (the robot's goal too)" in text
    assert "Someone starting within" not in pacing_text(False)  # detail: the small models' cut leaves it out


def test_a_follower_is_not_met_so_their_encounter_may_sit_at_the_robots_start():
    """Players A and B: 'whether an encounter may sit on the robot's start node (follow encounters)'."""
    from socnavgen.proposal.path_checks import _met
    from socnavgen.verify.derive import with_implied
    from socnavgen.verify.models import VerifySettings

    def spec(kind: str) -> ScenarioSpec:
        return ScenarioSpec.model_validate({
            "encounters": [{"id": "e1", "place": "ROOM", "humans": [
                {"human": "human1", "trigger": "robot_says", "phrase": "FOLLOW ME", "reaction": "follow",
                 "latch": True}]}],
            "criteria": [{"id": "c1", "kind": kind, "human": "human1", "encounter": "e1", "distance": 4.0}]})

    follows, meets = spec("follows_robot"), spec("meets")
    assert not _met(follows, follows.encounters[0], "human1") and _met(meets, meets.encounters[0], "human1")
    assert not [c for c, source in with_implied(follows, VerifySettings()) if c.kind == "meets"]
    text = follower_turn_text()
    assert "start a follower behind or beside the robot's start, not on its route ahead" in text
    assert "may meet it at its start node (stated by follows_robot, with no meets" in text


def test_which_member_of_a_group_stands_on_the_side_the_robot_comes_from():
    from socnavgen.bodies import PERSON_RADIUS
    from socnavgen.sim import empty_room, spawn_points

    node = 6 + 4j
    for n, west in ((2, 1), (3, None)):
        spots = spawn_points(empty_room(12.0, 8.0), [node] * n, [0] * n, PERSON_RADIUS, np.random.default_rng(0))
        assert int(np.argmax([s.real for s in spots])) == 0  # from the east: the first named
        if west is not None:
            assert int(np.argmin([s.real for s in spots])) == west
        else:  # three: nobody due west, two at +-120 degrees
            assert math.isclose(spots[1].real, spots[2].real)
    text = groups_text()
    assert "from the east, the first named; from the west, for two, the second" in text
    assert "(follow, follow_human) leaves the pull too" in text


def test_let_pass_may_stand_only_a_moment_so_a_needed_stop_is_a_plain_wait():
    """Players A and C: where the robot letting someone pass stands, and for how long."""
    from socnavgen.sim.robot.wait_spot import ASIDE, SPOT_REACH

    text = robot_limits_text()
    assert f"stepping up to {SPOT_REACH:g} m aside off her way where there is room" in text
    assert "a stop the story needs as such is a cue's plain `wait`" in text
    assert f"steps up to {ASIDE:g} m to its right" in text
    assert "plain `wait`" not in robot_limits_text(False)


def test_cue_distances_are_straight_and_people_who_never_meet_the_robot_stay_in_the_prose():
    """Player C: 'whether the human_within distance goes through walls'; player B: a nurse who never meets the
    robot, in the story but in no encounter (the pipeline refuses a human of human_behaviors in none)."""
    from socnavgen.proposal.spec_checks import spec_mistakes

    assert "(a cue trigger's `distance` is straight, walls or not)" in cue_triggers_text()
    assert "Only people who meet the robot are simulated" in people_text()
    assert "Only people who meet the robot are simulated" not in people_text(False)  # the small model's cut
    spec = ScenarioSpec.model_validate({"encounters": [{"id": "e1", "place": "ROOM", "humans": [
        {"human": "human1", "trigger": "robot_visible", "reaction": "look", "distance": 3.0}]}]})
    assert any("human2 of human_behaviors takes part in no encounter" in m
               for m in spec_mistakes(spec, ["human1", "human2"]))
