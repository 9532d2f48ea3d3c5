"""The spec language the model players missed, each as one field or trigger: validated, taught in the
prompts, checked in the trees (tree_needs), and for in-process models built by the tree grammar:
robot_far (a leader waits for a robot that falls behind), `lasts` (a reaction that ends), a latch on any
trigger (KeepRunningUntilFailure), a person's `speed` and `otherwise: stand`, and the later of a person's
encounters taking over. Trees that must fail are tested as much as trees that must pass."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from pydantic import ValidationError
from test_spec_checks import _sample

from socnavgen.bt.validate import validate_bt_text
from socnavgen.location import load_location
from socnavgen.proposal.behaviors import behavior_messages
from socnavgen.proposal.replies import ScenarioReply
from socnavgen.proposal.scenario import scenario_checker, scenario_messages
from socnavgen.proposal.tree_grammar import build_spec_tree_grammar
from socnavgen.proposal.tree_needs import needs_text, tree_need_mistakes
from socnavgen.run import HumanPlan, PathPlan, ScenarioProposal, ScenarioRequest
from socnavgen.run.spec import WAIT_THEN_GO_SECONDS, ScenarioSpec

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "locations"
WALK = ("<Sequence><SetBlackboard output_key='agentid' value='{id}'/><SetBlackboard output_key='timestep' "
        "value='{dt}'/><SubTree ID='RegularNavTree' id='agentid' dt='timestep'/></Sequence>")
LOOK = "<LookAtRobot agent_id='{id}'/>"
NEAR = "<IsRobotNearby agent_id='{id}' distance='4.0'/>"
VISIBLE = "<IsRobotVisible agent_id='{id}' distance='3.0'/>"
CLEAR = "<MakeGesture agent_id='{id}' message='0'/>"


def tree(body: str) -> str:
    return (f"<root main_tree_to_execute='M'><include path='BTRegularNav.xml'/><BehaviorTree ID='M'>{body}"
            f"</BehaviorTree></root>")


def spec(*parts: dict, people: dict | None = None, orders: tuple[int, ...] = ()) -> ScenarioSpec:
    encounters = [{"id": f"e{k + 1}", "place": "X", "order": orders[k] if orders else k + 1, "humans": [p]}
                  for k, p in enumerate(parts)]
    return ScenarioSpec.model_validate({"encounters": encounters, "people": people or {}})


def needs(xml: str, the_spec: ScenarioSpec) -> list[str]:
    assert validate_bt_text(xml, "t.xml", human_ids={0}, agent_id=0) == [], xml  # needs only of valid trees
    return tree_need_mistakes(xml, "human1", the_spec)


# ---- robot_far ------------------------------------------------------------------------------------
FAR = spec({"human": "human1", "trigger": "robot_far", "reaction": "stop", "distance": 4.0})


def test_robot_far_is_the_robot_near_condition_inverted():
    waits = tree(f"<Fallback><Sequence><Inverter>{NEAR}</Inverter>{LOOK}</Sequence>{WALK}</Fallback>")
    assert needs(waits, FAR) == []
    also = tree(f"<Fallback><Sequence>{NEAR}{WALK}</Sequence>{LOOK}</Fallback>")  # near: walk, else wait
    assert needs(also, FAR) == []
    wrong = tree(f"<Fallback><Sequence>{NEAR}{LOOK}</Sequence>{WALK}</Fallback>")  # waits while NEAR
    assert any("is not gated by an inverted " in m and "IsRobotNearby" in m for m in needs(wrong, FAR)), needs(wrong, FAR)
    text = needs_text("human1", FAR)
    assert "robot far (farther than 4 m) -> stop" in text and "detect it with an inverted IsRobot" in text


# ---- lasts, wait_then_go and the time trigger ------------------------------------------------------
def timer(seconds: str, inverted: bool = True) -> str:
    node = f"<TimeExpiredCondition seconds='{seconds}' ts='{{dt}}' only_once='true'/>"
    return f"<Inverter>{node}</Inverter>" if inverted else node


def test_a_reaction_that_lasts_has_its_timer():
    says = spec({"human": "human1", "trigger": "robot_blocking", "reaction": "say", "says": "WAIT", "lasts": 5})
    gesture = "<MakeGesture agent_id='{id}' message='1'/>"
    blocking = "<IsRobotBlocking agent_id='{id}' distance='2.0'/>"
    ok = tree(f"<Fallback><Sequence>{blocking}{timer('5')}{gesture}</Sequence><Sequence>{CLEAR}{WALK}</Sequence>"
              f"</Fallback>")
    assert needs(ok, says) == []
    kept_saying = tree(f"<Fallback><Sequence>{blocking}{timer('5')}{gesture}</Sequence>{WALK}</Fallback>")
    assert any("MakeGesture keeps showing WAIT" in m and "message='0'" in m for m in needs(kept_saying, says))
    assert "clear it: begin the branch that walks on with <MakeGesture agent_id='{id}' message='0'/>" in \
        needs_text("human1", says)
    for bad in (tree(f"<Fallback><Sequence>{blocking}{gesture}</Sequence>{WALK}</Fallback>"),
                tree(f"<Fallback><Sequence>{blocking}{timer('9')}{gesture}</Sequence>{WALK}</Fallback>"),
                tree(f"<Fallback><Sequence>{blocking}{timer('5', False)}{gesture}</Sequence>{WALK}</Fallback>")):
        assert any("the reaction lasts 5 s" in m for m in needs(bad, says)), bad
    waits = spec({"human": "human1", "trigger": "robot_near", "reaction": "wait_then_go", "distance": 4.0})
    three = f"{WAIT_THEN_GO_SECONDS:g}"
    assert needs(tree(f"<Fallback><Sequence>{NEAR}{timer(three)}{LOOK}</Sequence>{WALK}</Fallback>"), waits) == []
    assert needs(tree(f"<Fallback><Sequence>{NEAR}{LOOK}</Sequence>{WALK}</Fallback>"), waits)
    assert f"wait then go for {three} s, then walk on" in needs_text("human1", waits)


def test_seconds_belong_to_the_time_trigger_and_the_tree_carries_them():
    with pytest.raises(ValidationError, match="belongs to the trigger time"):
        spec({"human": "human1", "trigger": "robot_near", "reaction": "wait_then_go", "seconds": 4})
    later = spec({"human": "human1", "trigger": "time", "seconds": 20, "reaction": "walk_past"},
                 people={"human1": {"otherwise": "stand"}})
    stand = "<MakeGesture agent_id='{id}' message='0'/>"
    assert needs(tree(f"<Fallback><Sequence>{timer('20', False)}{WALK}</Sequence>{stand}</Fallback>"), later) == []
    wrong = tree(f"<Fallback><Sequence>{timer('2', False)}{WALK}</Sequence>{stand}</Fallback>")
    assert any("never checks TimeExpiredCondition(seconds='20')" in m for m in needs(wrong, later))
    assert "20 s after the start -> walk past" in needs_text("human1", later)


# ---- latch ----------------------------------------------------------------------------------------
SEEN = spec({"human": "human1", "trigger": "robot_visible", "reaction": "look", "distance": 3.0, "latch": True})


def test_a_latch_on_any_trigger_keeps_the_action_running():
    kept = tree(f"<Fallback><Sequence>{VISIBLE}<KeepRunningUntilFailure>{LOOK}</KeepRunningUntilFailure>"
                f"</Sequence>{WALK}</Fallback>")
    assert needs(kept, SEEN) == []
    plain = tree(f"<Fallback><Sequence>{VISIBLE}{LOOK}</Sequence>{WALK}</Fallback>")
    assert any("latched" in m and "KeepRunningUntilFailure" in m for m in needs(plain, SEEN))
    outside = tree(f"<Fallback><KeepRunningUntilFailure><Sequence>{VISIBLE}{LOOK}</Sequence>"
                   f"</KeepRunningUntilFailure>{WALK}</Fallback>")  # re-checks the condition: no latch
    assert any("latched" in m for m in needs(outside, SEEN))
    assert "<KeepRunningUntilFailure> right after the condition" in needs_text("human1", SEEN)


def test_the_latch_holds_in_the_simulator():
    """Seen once within 2 m, the person keeps the gesture after the robot drove away; without the latch not."""
    from tests.sim.simhelpers import INSTANT, Drive, human, make_sim, tree_xml

    near = '<IsRobotNearby agent_id="{id}" distance="2.0"/>'
    say, other = '<MakeGesture agent_id="{id}" message="1"/>', '<MakeGesture agent_id="{id}" message="2"/>'
    latched = f"<Fallback><Sequence>{near}<KeepRunningUntilFailure>{say}</KeepRunningUntilFailure></Sequence>" \
              f"{other}</Fallback>"
    plain = f"<Fallback><Sequence>{near}{say}</Sequence>{other}</Fallback>"
    for body, last in ((latched, 1), (plain, 2)):
        sim = make_sim([human(start=(2.0, 5.0))], [tree_xml(body)], [(3.0, 5.0), (19.0, 5.0)], Drive(1.0), body=INSTANT)
        sim.step()
        assert sim.people.gesture[0] == 1
        for _ in range(60):  # 6 s at 1 m/s: the robot is far away
            sim.step()
        assert abs(sim.robot.pos - complex(2.0, 5.0)) > 4.0 and sim.people.gesture[0] == last


SEEN_A_WHILE = spec({"human": "human1", "trigger": "robot_visible", "reaction": "look", "distance": 3.0,
                     "latch": True, "lasts": 4})


def test_a_latch_with_lasts_runs_its_seconds_then_walks_on_for_good():
    """latch + lasts: once triggered the reaction runs `lasts` s whatever the trigger does, then never again: the
    timer inside the latch (a timer before it is never ticked again once the latch runs)."""
    waits = spec({"human": "human1", "trigger": "robot_near", "reaction": "wait_then_go", "distance": 4.0,
                  "latch": True, "lasts": 5})
    assert waits.encounters[0].humans[0].lasting() == 5
    inside = tree(f"<Fallback><Sequence>{VISIBLE}<KeepRunningUntilFailure><Sequence>{timer('4')}{LOOK}</Sequence>"
                  f"</KeepRunningUntilFailure></Sequence>{WALK}</Fallback>")
    assert needs(inside, SEEN_A_WHILE) == []
    before = tree(f"<Fallback><Sequence>{VISIBLE}{timer('4')}<KeepRunningUntilFailure>{LOOK}"
                  f"</KeepRunningUntilFailure></Sequence>{WALK}</Fallback>")
    assert any("a timer outside the latch is never checked again" in m for m in needs(before, SEEN_A_WHILE))
    no_timer = tree(f"<Fallback><Sequence>{VISIBLE}<KeepRunningUntilFailure>{LOOK}</KeepRunningUntilFailure>"
                    f"</Sequence>{WALK}</Fallback>")
    assert any("the reaction lasts 4 s" in m for m in needs(no_timer, SEEN_A_WHILE))
    text = needs_text("human1", SEEN_A_WHILE)
    assert "once triggered it lasts 4 s whatever the trigger does (latch with lasts)" in text
    assert "<KeepRunningUntilFailure><Sequence><Inverter><TimeExpiredCondition seconds='4'" in text
    grammar = build_spec_tree_grammar("human1", SEEN_A_WHILE)
    assert grammar is not None
    acts = ["".join(getattr(sym, "text", "") for sym in alt) for alt in grammar.rules["act"]]
    assert acts and all(a.startswith("<KeepRunningUntilFailure><Sequence name='Timed'><Inverter><TimeExpiredCondition "
                                      "seconds='4'") for a in acts), acts


def test_a_standing_person_walks_on_inside_a_latch_that_lasts():
    """otherwise stand + latch + lasts: the tree's last branch stands, so walking on after the timed part goes
    inside the latch (a player followed the plain template and the person stood for good)."""
    stand = spec({"human": "human1", "trigger": "robot_visible", "reaction": "look", "distance": 3.0, "latch": True,
                  "lasts": 4}, people={"human1": {"otherwise": "stand"}})
    text = needs_text("human1", stand)
    assert "<KeepRunningUntilFailure><Fallback><Sequence><Inverter><TimeExpiredCondition seconds='4'" in text
    assert "they walk on inside the latch" in text
    walks_on = tree(f"<Fallback><Sequence>{VISIBLE}<KeepRunningUntilFailure><Fallback><Sequence>{timer('4')}{LOOK}"
                    f"</Sequence>{WALK}</Fallback></KeepRunningUntilFailure></Sequence>{CLEAR}</Fallback>")
    assert needs(walks_on, stand) == []
    assert "<KeepRunningUntilFailure><Sequence><Inverter>" in needs_text("human1", SEEN_A_WHILE)  # walkers: plain


def test_a_latch_with_lasts_holds_in_the_simulator():
    """Seen once within 2 m, the person keeps the gesture after the robot left for the 3 s it lasts, then the
    other one for good."""
    from tests.sim.simhelpers import INSTANT, Drive, human, make_sim, tree_xml

    near = '<IsRobotNearby agent_id="{id}" distance="2.0"/>'
    say, other = '<MakeGesture agent_id="{id}" message="1"/>', '<MakeGesture agent_id="{id}" message="2"/>'
    clock = '<Inverter><TimeExpiredCondition seconds="3" ts="{dt}" only_once="true"/></Inverter>'
    body = (f"<Fallback><Sequence>{near}<KeepRunningUntilFailure><Sequence>{clock}{say}</Sequence>"
            f"</KeepRunningUntilFailure></Sequence>{other}</Fallback>")
    sim = make_sim([human(start=(2.0, 5.0))], [tree_xml(body)], [(3.0, 5.0), (19.0, 5.0)], Drive(1.0), body=INSTANT)
    seen = []
    for _ in range(60):  # 6 s at 1 m/s
        sim.step()
        seen.append((round(sim.t, 2), abs(sim.robot.pos - complex(2.0, 5.0)), int(sim.people.gesture[0])))
    assert seen[0][2] == 1
    assert all(g == 1 for t, _, g in seen if t <= 2.8)  # latched: after the robot left 2 m (about t = 1 s)
    assert any(d > 2.0 for t, d, _ in seen if t <= 2.8)
    assert all(g == 2 for t, _, g in seen if t >= 3.3)  # its 3 s over: the other branch for good


def test_a_later_encounter_nests_inside_an_earlier_latched_part():
    """A latched part is never left (the Fallback resumes at its RUNNING child), so the prompt says to put the
    later encounter's branch inside the latch, and the tree check accepts that."""
    two = spec({"human": "human1", "trigger": "robot_visible", "reaction": "look", "distance": 3.0, "latch": True},
               {"human": "human1", "trigger": "robot_near", "reaction": "give_way", "distance": 4.0})
    text = needs_text("human1", two)
    assert "put the later encounter's branch INSIDE the latch" in text and "resume at the RUNNING child" in text
    give = "<GiveWaytoRobot agent_id='{id}' time_step='{dt}'/>"
    nested = tree(f"<Fallback><Sequence>{VISIBLE}<KeepRunningUntilFailure><Fallback><Sequence>{NEAR}{give}</Sequence>"
                  f"{LOOK}</Fallback></KeepRunningUntilFailure></Sequence>{WALK}</Fallback>")
    assert needs(nested, two) == []
    late_last = tree(f"<Fallback><Sequence>{VISIBLE}<KeepRunningUntilFailure><Fallback>{LOOK}<Sequence>{NEAR}{give}"
                     f"</Sequence></Fallback></KeepRunningUntilFailure></Sequence>{WALK}</Fallback>")
    assert any("must take over" in m for m in needs(late_last, two)), needs(late_last, two)


def test_a_target_that_rechecks_every_condition_cannot_latch():
    reply = {"scenario_description": "The robot crosses a hall and a visitor who saw it keeps looking at it.",
             "number_of_humans": 1, "human_behaviors": {"human1": "A visitor who sees the robot and keeps looking."},
             "expected_robot_behavior": "Pass the visitor politely at a distance.",
             "spec": {"encounters": [{"id": "e1", "place": "INTERSECTION", "humans": [
                 {"human": "human1", "trigger": "robot_visible", "reaction": "look", "distance": 3.0, "latch": True}]}],
                 "criteria": [{"id": "c1", "kind": "meets", "human": "human1", "encounter": "e1"}]}}
    warehouse = load_location(EXAMPLES / "warehouse")
    assert scenario_checker(warehouse)(ScenarioReply.model_validate(reply)) == []
    refused = scenario_checker(warehouse, target="hunav2")(ScenarioReply.model_validate(reply))
    assert any("latch is true, but a hunav2 tree cannot remember" in m for m in refused), refused


# ---- people: speed and otherwise stand -------------------------------------------------------------
def test_people_name_humans_of_the_spec_and_bound_their_speed():
    part = {"human": "human1", "trigger": "robot_says", "phrase": "PROCEED", "reaction": "walk_past"}
    assert spec(part, people={"human1": {"speed": 0.5}}).person("human1").speed == 0.5
    assert spec(part).person("human1").otherwise == "walk"
    with pytest.raises(ValidationError, match="people names human2, who takes part in no encounter"):
        spec(part, people={"human2": {"speed": 0.5}})
    with pytest.raises(ValidationError):
        spec(part, people={"human1": {"speed": 4.0}})


def test_a_person_who_stands_otherwise_has_a_standing_branch():
    waits = spec({"human": "human1", "trigger": "robot_says", "phrase": "PROCEED", "reaction": "walk_past"},
                 people={"human1": {"otherwise": "stand", "speed": 0.6}})
    said = "<RobotSays agent_id='{id}' message='2'/>"
    stands = tree(f"<Fallback><Sequence>{said}{WALK}</Sequence><MakeGesture agent_id='{{id}}' message='0'/></Fallback>")
    assert needs(stands, waits) == []
    walks = tree(f"<Fallback><Sequence>{said}{WALK}</Sequence>{WALK}</Fallback>")
    assert any("stands while none of its triggers holds" in m for m in needs(walks, waits))
    text = needs_text("human1", waits)
    assert "stands still (\"otherwise\": \"stand\")" in text and "walks at up to 0.6 m/s" in text


# ---- one person, two encounters: the later takes over ---------------------------------------------
BLOCK_THEN_YIELD = spec({"human": "human1", "trigger": "robot_visible", "reaction": "block", "distance": 3.0},
                        {"human": "human1", "trigger": "robot_says", "phrase": "EXCUSE ME", "reaction": "give_way",
                         "latch": True})


def test_the_later_encounter_takes_over():
    said = "<RobotSaid agent_id='{id}' message='4'/>"
    block = f"<Sequence>{VISIBLE}<BlockRobot agent_id='{{id}}' time_step='{{dt}}'/></Sequence>"
    give = f"<Sequence>{said}<GiveWaytoRobot agent_id='{{id}}' time_step='{{dt}}'/></Sequence>"
    assert needs(tree(f"<Fallback>{give}{block}{WALK}</Fallback>"), BLOCK_THEN_YIELD) == []
    late = needs(tree(f"<Fallback>{block}{give}{WALK}</Fallback>"), BLOCK_THEN_YIELD)
    assert any("encounter e2 comes after e1" in m and "put its branch before" in m for m in late), late
    unless = (f"<Sequence><Inverter>{said}</Inverter>{VISIBLE}<BlockRobot agent_id='{{id}}' time_step='{{dt}}'/>"
              f"</Sequence>")  # blocks only until EXCUSE ME: the order of the branches does not matter
    assert needs(tree(f"<Fallback>{unless}{give}{WALK}</Fallback>"), BLOCK_THEN_YIELD) == []
    assert "switches reactions" in needs_text("human1", BLOCK_THEN_YIELD)


def test_a_persons_encounters_come_in_their_order():
    swapped = spec({"human": "human1", "trigger": "robot_visible", "reaction": "look", "distance": 3.0},
                   {"human": "human1", "trigger": "robot_near", "reaction": "give_way", "distance": 2.0}, orders=(2, 1))
    assert [e.id for e, _ in swapped.parts_of("human1")] == ["e2", "e1"]


# ---- the grammar of in-process models builds all of it ----------------------------------------------
@pytest.mark.parametrize("part, people", [
    ({"human": "human1", "trigger": "robot_far", "reaction": "stop", "distance": 4.0}, None),
    ({"human": "human1", "trigger": "robot_near", "reaction": "wait_then_go"}, None),
    ({"human": "human1", "trigger": "robot_visible", "reaction": "look", "latch": True}, None),
    ({"human": "human1", "trigger": "robot_blocking", "reaction": "walk_past"}, {"human1": {"otherwise": "stand"}}),
    ({"human": "human1", "trigger": "robot_near", "reaction": "give_way", "lasts": 6}, None),
])
def test_the_tree_grammar_builds_trees_that_meet_the_new_fields(part, people):
    the_spec = spec(part, people=people)
    grammar = build_spec_tree_grammar("human1", the_spec)
    assert grammar is not None
    for text in _sample(grammar, 8):
        assert grammar.matches(text)
        assert needs(json.loads(text)["tree"], the_spec) == []


# ---- the prompts carry every field -----------------------------------------------------------------
def test_the_tree_prompt_says_every_field_of_the_spec():
    the_spec = ScenarioSpec.model_validate({
        "script": {"cues": [{"trigger": {"when": "blocked", "distance": 2.0}, "say": "ACKNOWLEDGED", "wait": 4.0,
                             "wait_until_clear": True},
                            {"trigger": {"when": "human_farther", "human": "human1", "distance": 3.0}, "wait": 2.0,
                             "once": False}]},
        "encounters": [{"id": "e1", "place": "X", "humans": [
            {"human": "human1", "trigger": "time", "seconds": 23, "reaction": "wait_then_go", "lasts": 4}]}]})
    text = needs_text("human1", the_spec)
    assert "23 s after the start -> wait then go for 4 s, then walk on" in text
    assert "seconds='4'" in text and "seconds='23'" in text
    assert "stands still 4 s and then until its way is clear" in text  # the cue's wait is not dropped
    assert "farther than 3 m (each time it becomes true again) it stands still 2 s" in text
    proposal = ScenarioProposal(scenario_description="d", number_of_humans=1, human_behaviors={"human1": "b"},
                                expected_robot_behavior="e")
    plan = PathPlan(robot=["a", "b"], humans=[HumanPlan(name="human1", path=["b"])])
    user = behavior_messages("human1", proposal, plan, the_spec)[-1].content
    assert text in user and "hunav2 lacks" in user and "KeepRunningUntilFailure" in user  # export targets, latch


def test_stage1_teaches_the_new_fields_and_what_the_robot_cannot_do():
    home = load_location(EXAMPLES / "home")
    request = ScenarioRequest(location=str(home.root), context="c", task="t", llm="replay")
    system = scenario_messages(request, home)[0].content
    from typing import get_args

    from socnavgen.run.spec import HumanTrigger, Reaction
    assert all(f"{t} (" in system or f"{t}," in system for t in get_args(HumanTrigger)), "a trigger is not taught"
    assert all(r in system for r in get_args(Reaction))
    assert "\"people\"" in system and "\"otherwise\"" in system and "\"lasts\"" in system
    assert "no cue makes it back off, pull over or follow someone" in system
    # what the default robot does by itself (sim/robot/polite.py make_way), with its numbers, and what to plan
    assert "makes way for someone who must get past it (after 2 s face to face, a gap of 0.8 m or less, it backs " \
           "off the way it came" in system
    assert "\"it follows someone\": they lead along its route" in system
    assert "It stops about 1.25 m (centres) from a person in its way; a wait_until_clear cue (after the cue's `wait`, " \
           "if it has one) holds it where the cue fired while anyone is in its way (ahead of it, on its route) within " \
           "3 m" in system  # a closer cue never fires then
    assert "nobody stands between nodes: an aisle that is an edge is met at an end node" in system
    assert "an encounter's node lies on the robot's path and on each of its humans' paths" in system
    assert "meets the robot twice, at two DIFFERENT nodes, and the two move apart (farther than the meeting " \
           "distance) in between" in system
    assert "takes over while its trigger holds (latch it, or the earlier part comes back" in system
    assert "where 1.6-2.3 m is free they pass only if the person keeps to one side" in system
    assert "(only with the reaction block)" in system  # blocks_robot needs block
    assert "A route may come back to its start after passing other nodes" in system
    assert "hunav2 lacks" in system and "robot_blocking" in system.split("hunav2 lacks")[1][:200]


# ---- until: a reaction that ends when the robot says a phrase ---------------------------------------
BLOCK_UNTIL = spec({"human": "human1", "trigger": "robot_visible", "reaction": "block", "distance": 3.0,
                    "until": "EXCUSE ME"})


def test_a_reaction_until_a_phrase_is_gated_by_the_remembered_phrase():
    """A child blocks the robot from first sight, stepping into its way, until it says EXCUSE ME (a round-6 player
    found no way to end a block on a phrase that kept the sidesteps): the block is gated by RobotSaid inverted."""
    said = "<Inverter><RobotSaid agent_id='{id}' message='4'/></Inverter>"
    block = "<BlockRobot agent_id='{id}' time_step='{dt}'/>"
    ok = tree(f"<Fallback><Sequence>{VISIBLE}{said}{block}</Sequence>{WALK}</Fallback>")
    assert needs(ok, BLOCK_UNTIL) == []
    forever = tree(f"<Fallback><Sequence>{VISIBLE}{block}</Sequence>{WALK}</Fallback>")
    assert any("ends once the robot said EXCUSE ME" in m and "RobotSaid" in m for m in needs(forever, BLOCK_UNTIL))
    while_said = tree(f"<Fallback><Sequence>{VISIBLE}<RobotSaid agent_id='{{id}}' message='4'/>{block}</Sequence>"
                      f"{WALK}</Fallback>")  # not inverted: blocks only AFTER the phrase
    assert needs(while_said, BLOCK_UNTIL) != []
    text = needs_text("human1", BLOCK_UNTIL)
    assert "block until the robot has said EXCUSE ME, then walk on" in text and "RobotSaid" in text


def test_a_latched_reaction_until_a_phrase_checks_it_inside_the_latch():
    latched = spec({"human": "human1", "trigger": "robot_visible", "reaction": "block", "distance": 3.0,
                    "until": "EXCUSE ME", "latch": True})
    said = "<Inverter><RobotSaid agent_id='{id}' message='4'/></Inverter>"
    block = "<BlockRobot agent_id='{id}' time_step='{dt}'/>"
    inside = tree(f"<Fallback><Sequence>{VISIBLE}<KeepRunningUntilFailure><Sequence>{said}{block}</Sequence>"
                  f"</KeepRunningUntilFailure></Sequence>{WALK}</Fallback>")
    assert needs(inside, latched) == []
    outside = tree(f"<Fallback><Sequence>{said}{VISIBLE}<KeepRunningUntilFailure>{block}</KeepRunningUntilFailure>"
                   f"</Sequence>{WALK}</Fallback>")  # once the latch runs the phrase is never checked again
    assert any("INSIDE <KeepRunningUntilFailure>" in m for m in needs(outside, latched)), needs(outside, latched)
    grammar = build_spec_tree_grammar("human1", latched)
    for text in _sample(grammar, 4):
        assert needs(json.loads(text)["tree"], latched) == []


def test_until_is_taught_in_stage_1_and_refused_without_its_phrase():
    from socnavgen.proposal.facts import UNTIL_FACT, people_text
    from socnavgen.proposal.spec_checks import spec_mistakes

    assert UNTIL_FACT in people_text() and '"until": "EXCUSE ME"' in UNTIL_FACT
    with pytest.raises(ValidationError):  # starts and ends on the same phrase
        spec({"human": "human1", "trigger": "robot_says", "phrase": "EXCUSE ME", "reaction": "block",
              "until": "EXCUSE ME"})
    unsaid = spec_mistakes(BLOCK_UNTIL, ["human1"])
    assert any("ends when the robot says EXCUSE ME (`until`), but no cue" in m for m in unsaid), unsaid
