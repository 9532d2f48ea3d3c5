"""A `let_pass` cue: "the robot lets her go first" (issue 25, round 10 of the new-request suite: five of 24 first
answers asked the robot to stay back until someone had gone by, with wait_until_clear, which waits only while
someone is in its way, so the robot went first). The robot stands where the cue fired until that person has gone
by (came near, out of its way, moving off), at most `wait` s (script.LET_PASS_PATIENCE without one)."""

from __future__ import annotations

import pytest

from socnavgen.bodies import PERSON_RADIUS, ROBOT_RADIUS
from socnavgen.run.spec import CueTrigger, RobotCue, RobotScript, ScenarioSpec
from socnavgen.sim.people.routing import project
from socnavgen.sim.robot.api import ScriptedPolicy
from socnavgen.sim.robot.script import LET_PASS_PATIENCE, LET_PASS_STILL
from socnavgen.sim.robot.wait_spot import CLEAR_OF_WAY
from tests.sim.simhelpers import REGULAR, human, make_sim, tree_xml

ROUTE = [(2.0, 5.0), (18.0, 5.0)]


def _cue(**kw) -> RobotScript:  # noqa: ANN003
    return RobotScript(cues=[RobotCue(trigger=CueTrigger(when="human_within", human="human1", distance=4.0), **kw)])


def _drive(script: RobotScript, person: dict, tree: str, seconds: float) -> list[tuple[float, complex, complex]]:
    sim = make_sim([human(**person)], [tree], ROUTE, policy=ScriptedPolicy(), script=script)
    rows = []
    while sim.t < seconds:
        sim.step()
        rows.append((sim.t, complex(sim.robot.pos), complex(sim.people.pos[0])))
    return rows


ONCOMING = {"start": (17.0, 5.0), "goals": [(1.0, 5.0)]}  # walks the robot's route the other way


def test_the_robot_stands_until_the_person_coming_the_other_way_has_gone_by():
    rows = _drive(_cue(let_pass="human1"), ONCOMING, tree_xml(REGULAR), 40.0)
    fired = next(k for k, (_, r, p) in enumerate(rows) if abs(r - p) <= 4.0)
    passed = next(k for k, (_, r, p) in enumerate(rows) if p.real < r.real - 1.0)  # she is behind it
    stood = [r for _, r, _ in rows[fired + 10:passed]]  # it may step aside, off her way, but not drive on
    assert max(abs(r.real - stood[0].real) for r in stood) < 0.3, "the robot drove on before she had gone by"
    assert rows[-1][1].real > 17.0  # then it drove on to its goal


@pytest.mark.parametrize("person", [ONCOMING,  # on its route, the other way
                                    # out of a door north of its route, through a point by the robot, then west
                                    {"start": (9.0, 9.0), "goals": [(4.3, 5.2), (1.0, 5.0)]}])
def test_the_robot_letting_someone_pass_waits_beside_their_way_not_on_it(person: dict):
    """home_06 of the new-request suite: the robot let the neighbour come through first, but stood on the open
    floor right on her line; she stalled half a metre in front of it, then squeezed past at 0.15 m. It now waits
    beside her way (wait_spot.CLEAR_OF_WAY between the bodies, the room allowing) and she walks on past it."""
    script = RobotScript(cues=[RobotCue(trigger=CueTrigger(when="start"), let_pass="human1")])
    sim = make_sim([human(**person)], [tree_xml(REGULAR)], [(4.0, 5.0), (18.0, 5.0)], policy=ScriptedPolicy(),
                   script=script)
    rows = []
    while sim.t < 45.0:
        sim.step()
        rows.append((sim.t, complex(sim.robot.pos), complex(sim.people.pos[0])))
    touch = PERSON_RADIUS + ROBOT_RADIUS
    passed = next(k for k, (_, r, p) in enumerate(rows) if p.real < r.real - 1.0)  # she is past it
    a, b = complex(*(person["goals"][-2] if len(person["goals"]) > 1 else person["start"])), complex(*person["goals"][-1])
    beside = max(project(r, a, b)[1] for _, r, p in rows[passed - 20:passed])  # off her line west
    assert beside >= touch + CLEAR_OF_WAY - 0.1, f"it waited {beside:.2f} m off her way"
    gap = min(abs(r - p) - touch for _, r, p in rows[:passed + 40])
    assert gap >= CLEAR_OF_WAY - 0.15, f"she passed it at {gap:.2f} m"
    stalled = sum(b[0] - a[0] for a, b in zip(rows[:passed], rows[1:passed + 1], strict=True)
                  if abs(b[2] - a[2]) < 0.1 * (b[0] - a[0]))
    assert stalled < 1.0, f"she stood {stalled:.1f} s before passing it"  # she walked on past it
    assert rows[-1][1].real > 17.0  # then it drove on to its goal


STANDING = tree_xml('<Sequence><LookAtRobot agent_id="{id}"/></Sequence>')


@pytest.mark.parametrize(("wait", "limit"), [(0.0, LET_PASS_PATIENCE), (6.0, 6.0)])
def test_someone_who_never_goes_by_holds_the_robot_at_most_its_limit(wait: float, limit: float):
    # she stands beside its route 3 m ahead: near, out of its way, never moving off (her walk not done: she
    # would go on west, but only looks at the robot)
    rows = _drive(_cue(let_pass="human1", wait=wait), {"start": (9.0, 7.2), "goals": [(9.0, 7.2), (1.0, 7.2)]},
                  STANDING, limit + 12.0)
    fired = next(k for k, (_, r, p) in enumerate(rows) if abs(r - p) <= 4.0)
    t0, r0 = rows[fired][0], rows[fired + 20][1]  # where it stands, 1 s after the cue (braking from cruise)
    still = [t for t, r, _ in rows[fired:] if abs(r - r0) < 0.05]
    assert still[-1] - t0 == pytest.approx(limit, abs=0.6)
    assert rows[-1][1].real > r0.real + 1.0  # it drove on after the limit


def test_a_cue_letting_pass_someone_of_no_encounter_is_refused():
    with pytest.raises(ValueError, match="lets human2 pass, who takes part in no encounter"):
        ScenarioSpec.model_validate({
            "encounters": [{"id": "e1", "place": "HALL", "humans": [{"human": "human1", "reaction": "walk_past"}]}],
            "script": {"cues": [{"trigger": {"when": "start"}, "let_pass": "human2"}]}})


def test_a_paced_person_the_robot_lets_pass_goes_first():
    """Round 11 of the new-request suite: with pacing, the person let pass was held about 4 m off while the robot
    stood for them, until the cue's limit ran out and the robot went first. Pacing now lets them go first."""
    from socnavgen.sim import PacingPlan, ThrottleConfig

    # she crosses the robot's route at node n (10, 5) from the north; the robot stops 3 m before n
    crossing = human(start=(10.0, 9.0), goals=[(10.0, 7.0), (10.0, 5.0), (10.0, 1.0)])
    robot_points = [(2.0, 5.0), (6.0, 5.0), (10.0, 5.0), (18.0, 5.0)]
    script = RobotScript(cues=[RobotCue(trigger=CueTrigger(when="at_encounter", encounter="e1", distance=3.0),
                                        let_pass="human1")])

    def run(cue: RobotScript | None):  # noqa: ANN202
        pacing = PacingPlan(ThrottleConfig(), ["r0", "r1", "n", "r3"], [(0, ["h0", "h1", "n", "h3"], "n", -1)])
        sim = make_sim([crossing], [tree_xml(REGULAR)], robot_points, policy=ScriptedPolicy(), script=cue,
                       pacing=pacing, encounters={"e1": complex(10.0, 5.0)}, timeout=90)
        trace = sim.run()
        her_past = next(k for k in range(trace.steps) if trace.humans[k, 0, 1] < 3.5)  # across the route
        robot_at_node = next(k for k in range(trace.steps) if trace.robot[k, 0] > 9.0)
        return trace.t[her_past], trace.t[robot_at_node], trace.end_reason

    her, robot, end = run(script)
    assert her < robot, f"she crossed at {her:.1f} s, the robot reached the crossing at {robot:.1f} s"
    assert end == "robot_goal" and robot < 35.0  # well before the cue's 20 s limit would have sent it on
    her, robot, _ = run(None)  # without the cue, pacing brings them there together: the robot is not behind her
    assert her > robot - 1.0



def test_someone_who_stopped_at_the_end_of_their_walk_no_longer_holds_the_robot():
    """home_14 of the new-request suite: the robot let the homeowner go by first; she came up the hallway and
    stopped at the front door, her walk's end, off its way and never farther from it than the closest she came:
    she never "went by", and the robot stood until the run ended. Someone standing at the end of their walk out of
    its way is no longer coming (script.gone_by): it drives on long before the cue's limit."""
    # she comes the other way 2.2 m beside its route and stops near it (her walk's end is the closest she comes:
    # she never gets farther from it, so she never "went by")
    rows = _drive(_cue(let_pass="human1"), {"start": (12.0, 7.2), "goals": [(5.0, 7.2)]}, tree_xml(REGULAR), 40.0)
    fired = next(k for k, (_, r, p) in enumerate(rows) if abs(r - p) <= 4.0)
    arrived = next(k for k in range(fired, len(rows) - 10) if abs(rows[k + 10][2] - rows[k][2]) < 0.02)
    assert abs(rows[arrived][2] - (5.0 + 7.2j)) < 0.7 and abs(rows[arrived][2] - rows[arrived][1]) < 3.0  # came near
    moved = next(k for k in range(arrived, len(rows)) if rows[k][1].real > rows[arrived][1].real + 0.5)
    assert rows[moved][0] - rows[arrived][0] < 5.0, (
        f"the robot stood {rows[moved][0] - rows[arrived][0]:.1f} s after she stopped at the end of her walk")
    assert rows[moved][0] - rows[fired][0] < LET_PASS_PATIENCE - 5.0
    assert min(abs(r - p) for _, r, p in rows) > PERSON_RADIUS + ROBOT_RADIUS  # no contact


def test_someone_who_went_by_and_stopped_off_its_way_has_gone_by():
    """home_16 of the new-request suite: the seeker ran past the robot after the hider and stopped by her 2.7 m
    from it, never LET_PASS_AWAY farther than her closest; the robot stood its whole 15 s with its way clear. A
    person let pass who walked LET_PASS_WALKED and then stood LET_PASS_STILL s off its way has gone by."""
    hider = human("human1", start=(12.0, 2.5), goals=[(3.5, 2.5)])  # along the robot's route, 2.5 m south of it
    seeker = human("human2", start=(13.3, 2.5), goals=[(3.5, 2.5)])
    script = RobotScript(cues=[RobotCue(trigger=CueTrigger(when="human_within", human="human2", distance=4.0),
                                        let_pass="human2", wait=20.0)])
    trees = [tree_xml(REGULAR), tree_xml('<FollowHuman agent_id="{id}" target_id="0" time_step="{dt}"/>')]
    sim = make_sim([hider, seeker], trees, ROUTE, policy=ScriptedPolicy(), script=script)
    rows = []
    while sim.t < 30.0:
        sim.step()
        rows.append((sim.t, complex(sim.robot.pos), complex(sim.people.pos[1]), abs(sim.people.vel[1])))
    fired = next(t for t, r, p, _ in rows if abs(r - p) <= 4.0)
    stood = next(t for t, _, p, v in rows if t > fired + 2.0 and v < 0.05)  # the seeker stopped by the hider
    drove = next(t for t, r, _, _ in rows if t > fired and r.real > rows[0][1].real + 0.3 and
                 r.real > next(r2 for t2, r2, _, _ in rows if t2 >= fired).real + 0.5)
    assert drove < stood + LET_PASS_STILL + 3.0 < fired + 20.0, (fired, stood, drove)
