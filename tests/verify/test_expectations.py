"""Tree expectations, and the spec derived for runs without spec.json (same strict thresholds)."""

from __future__ import annotations

from socnavgen.location import load_location
from socnavgen.run.models import HumanPlan, PathPlan
from socnavgen.run.spec import Criterion, Encounter, HumanPart, ScenarioSpec
from socnavgen.verify.derive import derive_spec, with_implied
from socnavgen.verify.expectations import card_tree_expectations, tree_checks, tree_expectations
from socnavgen.verify.models import VerifySettings

from .verify_builders import GIVE_WAY_XML, REGULAR_XML


def test_give_way_tree_key_nodes_and_their_causes() -> None:
    exps = tree_expectations("human1", GIVE_WAY_XML)
    by_node = {e.node: e for e in exps}
    assert by_node["GiveWaytoRobot"].kind == "gives_way_while_passing"
    assert by_node["GiveWaytoRobot"].caused_by == [("IsRobotVisible", None), ("RobotSays", 4)]
    assert by_node["RobotSays"].message == 4 and by_node["RobotSays"].name == "human1: RobotSays(EXCUSE ME) succeeds"
    # MakeGesture(0) is not an interaction; IsRobotNearby sits under an Inverter (must FAIL): not expected
    assert set(by_node) == {"GiveWaytoRobot", "IsRobotVisible", "RobotSays"}


def test_regular_tree_has_no_key_nodes() -> None:
    assert tree_expectations("human1", REGULAR_XML) == []


def test_derived_spec_is_strict(tiny_location) -> None:
    loc = load_location(tiny_location)
    plan = PathPlan(robot=["a1", "b2", "c3"], humans=[
        HumanPlan(name="human1", path=["c3", "b2"], interaction_point="b2"),
        HumanPlan(name="human2", path=["d4", "b2"], group_id=1),
        HumanPlan(name="human3", path=["d4", "b2"], group_id=1)])
    card = [{"kind": "meets_human", "human": "human1", "within": 3.5}, {"kind": "robot_reaches_goal"}]
    spec, judged = derive_spec(plan, loc, card, VerifySettings())
    (enc,) = spec.encounters
    assert enc.node == "b2" and enc.within == 1.0 and enc.place == "CORRIDOR"
    meet = next(c for c, _ in judged if c.kind == "meets")
    assert meet.distance == 2.0  # the card's 3.5 m is capped at the strict 2 m
    assert dict((c.kind, src) for c, src in judged)["meets"] == "card"
    kinds = [c.kind for c, _ in judged]
    assert kinds == ["meets", "group_together", "robot_reaches_goal", "no_collision", "no_deadlock", "people_apart"]
    group = next(c for c, _ in judged if c.kind == "group_together")
    assert group.humans == ["human2", "human3"]


def test_card_tree_criteria() -> None:
    exps = card_tree_expectations([{"kind": "executes", "node": "GiveWaytoRobot"}, {"kind": "meets_human"},
                                   {"kind": "executes", "human": "human1", "node": "MakeGesture"}])
    assert [e.kind for e in exps] == ["gives_way_while_passing", "executes"]
    assert exps[0].human is None and all(e.source == "card" for e in exps)


def test_unreadable_tree_is_a_failing_check() -> None:
    plan = PathPlan(robot=["a1", "c3"], humans=[HumanPlan(name="human1", path=["c3", "a1"])])
    (exp,) = tree_checks(plan, {"human1": "<root><BehaviorTree ID='x'><Sequence></root>"})
    assert exp.node is None and "does not parse" in exp.detail


def test_implied_criteria() -> None:
    spec = ScenarioSpec(encounters=[
        Encounter(id="e1", place="CORNER", node="b2", humans=[HumanPart(human="human1", reaction="stop"),
                                                                HumanPart(human="human2", reaction="block")])],
        criteria=[Criterion(id="c1", kind="keeps_away", human="human2", distance=1.0)])
    judged = with_implied(spec, VerifySettings())
    ids = [(c.id, src) for c, src in judged]
    # human1 meets the robot at e1 (implied); human2 must keep away, so no implied meeting; the goal is always
    # judged; no_collision implied; the two people never touch each other (people_apart, whatever the robot does);
    # no_deadlock NOT implied because human2 is meant to block the robot
    assert ids == [("c1", "spec"), ("meet_human1_e1", "implied"), ("goal", "implied"), ("no_collision", "implied"),
                   ("people_apart", "implied")]
    rude = spec.model_copy(update={"script": spec.script.model_copy(update={"misbehave": True})})
    assert [c.id for c, _ in with_implied(rude, VerifySettings())] == ["c1", "meet_human1_e1", "goal", "people_apart"]
    assert "people_apart" not in [c.id for c, _ in with_implied(rude, VerifySettings(), people=1)]  # one person


def test_every_run_is_judged_on_its_goal_and_contact() -> None:
    """Whether or not the spec names them: a spec without encounters or criteria still has the robot reach its
    goal, touch nobody and not deadlock."""
    judged = with_implied(ScenarioSpec(), VerifySettings())
    assert [(c.kind, src) for c, src in judged] == [("robot_reaches_goal", "implied"), ("no_collision", "implied"),
                                                    ("no_deadlock", "implied")]
    named = ScenarioSpec(criteria=[Criterion(id="c1", kind="robot_reaches_goal", distance=0.3)])
    assert [c.id for c, _ in with_implied(named, VerifySettings())] == ["c1", "no_collision", "no_deadlock"]


def test_each_encounter_of_a_human_is_its_own_meeting() -> None:
    """A human in two encounters gets two meetings, the later one chained after the earlier (two encounters
    never share one piece of evidence); a follower's encounter is shown by its following, not a meeting."""
    from socnavgen.verify.criteria import compile_criterion

    spec = ScenarioSpec(encounters=[
        Encounter(id="e1", place="CORNER", node="b2", order=1, humans=[HumanPart(human="human1")]),
        Encounter(id="e2", place="DOOR", node="d4", order=2, humans=[HumanPart(human="human1", reaction="stop")]),
        Encounter(id="e3", place="DOOR", node="a1", humans=[HumanPart(human="human2", reaction="follow")])],
        criteria=[Criterion(id="c1", kind="follows_robot", human="human2")])
    judged = {c.id: c for c, _ in with_implied(spec, VerifySettings())}
    assert {"meet_human1_e1", "meet_human1_e2"} <= set(judged) and not any("human2" in k for k in judged)
    first = compile_criterion(judged["meet_human1_e1"], spec, VerifySettings(), 0.2)
    second = compile_criterion(judged["meet_human1_e2"], spec, VerifySettings(), 0.2)
    assert first.previous is None and second.previous.id == "e1"
    assert "once ((dist_human1 > 2) and (once" in second.formula and "mid_human1_to_e1" in second.formula


def test_implied_order_and_scripted_waits() -> None:
    from socnavgen.run.spec import CueTrigger, RobotCue, RobotScript

    spec = ScenarioSpec(
        script=RobotScript(cues=[RobotCue(trigger=CueTrigger(when="blocked"), wait=30.0)]),
        encounters=[Encounter(id="e2", place="DOOR", node="d4", order=2, humans=[HumanPart(human="human2")]),
                    Encounter(id="e1", place="CORNER", node="b2", order=1, humans=[HumanPart(human="human1")])])
    judged = {c.id: c for c, _ in with_implied(spec, VerifySettings())}
    order = judged["order_e1_e2"]
    assert order.kind == "stl" and order.formula.startswith("(not ((dist_human2 <= 2)")
    assert order.formula.endswith("until ((dist_human1 <= 2) and (mid_human1_to_e1 <= 1))")
    assert judged["no_deadlock"].seconds == 35.0  # a scripted 30 s wait (+5 s) is no deadlock


def test_a_groups_encounter_happens_when_the_robot_meets_any_of_them() -> None:
    """The implied order of a group's encounter waits for the first member the robot meets, not for member 0 (who
    may stand behind the others), and a later group's encounter must not happen early through any member."""
    spec = ScenarioSpec(encounters=[
        Encounter(id="e1", place="LOBBY", node="b2", order=1,
                  humans=[HumanPart(human="human1"), HumanPart(human="human2")]),
        Encounter(id="e2", place="DOOR", node="d4", order=2,
                  humans=[HumanPart(human="human3"), HumanPart(human="human4")])])
    order = {c.id: c for c, _ in with_implied(spec, VerifySettings())}["order_e1_e2"]
    early, late = order.formula.split(" until ")
    assert "dist_human3" in early and "dist_human4" in early and " or " in early
    assert "dist_human1" in late and "dist_human2" in late and " or " in late
    assert "human1, human2" in order.text
