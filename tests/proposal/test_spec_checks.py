"""Stage 1 against the spec: placeholders, template echoes and empty behaviors are named mistakes; the
spec is consistent with the humans, the location, the robot's script and the export target. Stage 2
grounds each encounter; stage 3 trees are checked against what their encounter parts need."""

from __future__ import annotations

import copy
import json
from typing import get_args

import pytest
from gen_helpers import STOP_TREE, paths_reply, scenario_reply, spec_for, tree_reply, write_script

from socnavgen.bt.library import LIBRARY, REACTION_NODES, TRIGGER_NODES
from socnavgen.bt.validate import validate_bt_text
from socnavgen.location import load_location
from socnavgen.proposal.facts import physical_facts_text
from socnavgen.proposal.path_checks import check_paths
from socnavgen.proposal.replies import PathsReply, ScenarioReply
from socnavgen.proposal.scenario import scenario_checker, scenario_messages
from socnavgen.proposal.tree_needs import tree_need_mistakes
from socnavgen.run import RunFolder
from socnavgen.run.spec import ScenarioSpec


@pytest.fixture
def check(mini_location):
    return scenario_checker(load_location(mini_location))


def _mistakes(check, **changes) -> list[str]:  # noqa: ANN001
    return check(ScenarioReply.model_validate(scenario_reply(**changes)))


def test_a_good_reply_passes(check):
    assert _mistakes(check) == []


@pytest.mark.parametrize("behavior, expected", [
    ("<task and behavior towards the robot of Human 1>},", "copies the answer template"),
    ("<what the worker does>", "contains the placeholder '<what the worker does>'"),
    ("...", "placeholder"),
    ("   ", "is empty"),
    ("Walks to the shelf and stops when the robot is near},", "JSON punctuation"),
    ("walks", "too short"),
])
def test_placeholders_echoes_and_empty_behaviors_are_named(check, behavior, expected):
    mistakes = _mistakes(check, n=1, human_behaviors={"human1": behavior})
    assert any("behavior of human1" in m and expected in m for m in mistakes), mistakes


def test_the_issue_reply_is_rejected_in_the_real_stage(tmp_path, mini_location):
    """The reply accepted before (a behavior reading literally the template) is re-asked with its mistake."""
    from gen_helpers import run_replay

    echo = scenario_reply(n=1, human_behaviors={"human1": "<task and behavior towards the robot of Human 1>},"},
                          spec=spec_for(1))
    good = scenario_reply(n=1, spec=spec_for(1))
    paths = paths_reply(trajectories={"robot": ["32", "ch", "11", "07"], "human1": ["07", "11", "ch"]},
                        interaction_points={"human1": "11"}, group_ids={"human1": -1})
    script = write_script(tmp_path / "s.yaml", {"scenario": [echo, good], "paths": [paths],
                                                "behaviors": {"human1": [tree_reply()]}})
    run, llm = run_replay(script, mini_location, tmp_path / "run")
    asks = [m for s, _k, m in llm.calls if s == "scenario"]
    assert len(asks) == 2 and "copies the answer template" in asks[1][-1].content
    assert "<" not in run.scenario.human_behaviors["human1"]


def _spec_mistakes(check, spec: dict, n: int = 2) -> list[str]:  # noqa: ANN001
    return _mistakes(check, n=n, spec=spec)


def test_spec_is_required_and_validated(check):
    assert any("spec is missing" in m for m in _mistakes(check, spec=None))
    bad = spec_for(2)
    bad["encounters"][0]["humans"][0]["trigger"] = "robot_sings"
    assert any(m.startswith("spec.encounters.0.humans.0.trigger") for m in _spec_mistakes(check, bad))


def test_humans_of_encounters_are_the_humans_of_the_scenario(check):
    spec = spec_for(1)  # human2 is in no encounter
    assert any("human2 of human_behaviors takes part in no encounter" in m for m in _spec_mistakes(check, spec))
    spec = spec_for(3)  # human3 is not a human of the scenario
    assert any("human3 is not one of the humans" in m for m in _spec_mistakes(check, spec))


def test_criteria_reference_existing_humans_and_encounters(check):
    spec = spec_for(2)
    spec["criteria"].append({"id": "c3", "kind": "meets", "human": "human7", "encounter": "e9"})
    mistakes = _spec_mistakes(check, spec)
    assert any("criterion c3: human7 is not a human" in m for m in mistakes)
    assert any("criterion c3: encounter e9 is not in spec.encounters" in m for m in mistakes)


def test_each_encounter_needs_a_criterion(check):
    spec = spec_for(2)
    spec["criteria"] = [{"id": "c1", "kind": "no_collision"}]
    assert any("encounter e1 has no acceptance criterion" in m for m in _spec_mistakes(check, spec))


def test_a_phrase_waited_for_must_be_said_by_the_robot(check):
    spec = spec_for(2)
    spec["encounters"][0]["humans"][0].update(trigger="robot_says", phrase="EXCUSE ME", reaction="give_way")
    spec["criteria"][2].update(kind="gives_way", text="human1 steps out of the robot's way")
    mistakes = _spec_mistakes(check, spec)
    assert any("no cue of spec.script.cues says EXCUSE ME" in m for m in mistakes)
    spec["script"]["cues"] = [{"trigger": {"when": "blocked"}, "say": "EXCUSE ME"}]
    assert _spec_mistakes(check, spec) == []


def test_a_reaction_of_the_text_needs_the_criterion_that_states_it(check):
    """home_03 (round 7): the host stands to greet the guests (wait_then_go on robot_visible), but only `meets`
    was asked, so nobody could see the greeting never happen. A reaction to the robot needs its kind."""
    spec = spec_for(2)
    spec["encounters"][0]["humans"][1].update(trigger="robot_visible", reaction="wait_then_go", lasts=5.0)
    del spec["criteria"][3]  # human2's stops_near_robot: only meets is left for them
    mistakes = _spec_mistakes(check, spec)
    assert mistakes == ["encounter e1: human2 reacts to the robot (wait_then_go on robot_visible), but no criterion "
                        "states it (meets only says they came near, so the verifier could not see it missing); add "
                        "a criterion of kind stops_near_robot for human2 with encounter e1, its text saying what "
                        "human2 does"], mistakes
    spec["encounters"][0]["humans"][1].update(trigger="robot_says", phrase="EXCUSE ME", reaction="give_way")
    spec["script"]["cues"] = [{"trigger": {"when": "blocked"}, "say": "EXCUSE ME"}]
    assert any("kind gives_way or keeps_away or reacts_after_phrase for human2" in m
               for m in _spec_mistakes(check, spec))
    for stated in ({"kind": "reacts_after_phrase", "human": "human2", "phrase": "EXCUSE ME", "reaction": "give_way"},
                   {"kind": "gives_way", "human": "human2", "encounter": "e1"},
                   {"kind": "stl", "formula": "eventually (aside_human2 > 0.5)"},
                   {"kind": "group_together", "humans": ["human1", "human2"]}):  # human1's stop is stated (c3)
        assert _spec_mistakes(check, {**spec, "criteria": [*spec["criteria"], {"id": "c9", **stated}]}) == [], stated
    # another person's criterion, an unrelated kind or a group of unstated members states nothing
    for unstated in ({"kind": "gives_way", "human": "human1"}, {"kind": "says", "human": "human2"},
                     {"kind": "stl", "formula": "eventually (dist_human12 < 1)"}):
        assert any("human2 reacts to the robot" in m for m in
                   _spec_mistakes(check, {**spec, "criteria": [*spec["criteria"], {"id": "c9", **unstated}]})), unstated
    # walking past or looking is no reaction a kind states; reacting to another human is not to the robot
    spec["encounters"][0]["humans"][1].update(trigger="robot_near", reaction="walk_past")
    assert _spec_mistakes(check, spec) == []


def test_the_kind_stage_one_asks_for_a_reaction_is_one_the_verifier_accepts_for_it():
    """Following the correction never leads into rule S1 (a kind asked of a reaction it contradicts)."""
    from socnavgen.proposal.facts import STATED_BY
    from socnavgen.run.spec import CriterionKind, Reaction
    from socnavgen.verify.blame import REACTIONS_OF

    for reaction, kinds in STATED_BY.items():
        assert reaction in get_args(Reaction)
        for kind in kinds:
            assert kind in get_args(CriterionKind)
            assert reaction in REACTIONS_OF.get(kind, {reaction}), (reaction, kind)


def test_criteria_the_verifier_would_blame_on_the_spec_are_refused(check):
    spec = spec_for(2)
    spec["criteria"][0]["distance"] = 0.5  # a "meeting" at 0.5 m centre to centre is a collision
    assert any("criterion c1 asks for a meeting closer than" in m for m in _spec_mistakes(check, spec))


def test_places_are_node_types_of_the_location(check):
    spec = spec_for(2)
    spec["encounters"][0]["place"] = "KITCHEN"
    assert any("place 'KITCHEN' is not a node type" in m for m in _spec_mistakes(check, spec))


def test_the_target_refuses_parts_it_cannot_run(mini_location):
    location = load_location(mini_location)
    spec = spec_for(2)  # robot_blocking -> IsRobotBlocking: socrates only
    reply = ScenarioReply.model_validate(scenario_reply(spec=spec))
    assert scenario_checker(location)(reply) == []
    mistakes = scenario_checker(location, target="hunav1")(reply)
    assert any("trigger robot_blocking cannot be detected by any node hunav1 runs" in m for m in mistakes)


def test_target_filters_the_offered_nodes(mini_location):
    from socnavgen.run import ScenarioRequest

    location = load_location(mini_location)
    request = ScenarioRequest(location=str(mini_location), context="c", task="t", target="hunav1")
    system = scenario_messages(request, location)[0].content
    assert "exported to hunav1" in system and "robot_blocking" not in system.split("exported to hunav1")[1]
    assert "Give way to the robot" not in system  # GiveWaytoRobot is socrates-only


# ---- the library's encounter-needs block --------------------------------------------------------
def test_every_mapped_node_is_in_the_library_or_announced():
    """Nodes of the mapping exist (RobotSaid is the simulator branch's latching node, used once it lands)."""
    for nodes in [*TRIGGER_NODES.values(), *REACTION_NODES.values()]:
        for name in nodes:
            assert name in LIBRARY or name == "RobotSaid", name


# ---- stage 2 grounding -----------------------------------------------------------------------------
def _path_mistakes(mini_location, **changes) -> list[str]:  # noqa: ANN001
    graph = load_location(mini_location).graph
    spec = ScenarioSpec.model_validate(spec_for(2))
    return check_paths(PathsReply.model_validate(paths_reply(**changes)), graph, ["human1", "human2"], spec)


def test_grounding_on_a_node_of_the_place_on_both_paths(mini_location):
    assert _path_mistakes(mini_location) == []
    assert "encounter_nodes: e1 has no node; give the BLIND CORNER node where encounter e1 happens" in \
        _path_mistakes(mini_location, encounter_nodes={})
    assert any("encounter e1 happens at a BLIND CORNER but node ch is a INTERSECTION" in m and "11" in m
               for m in _path_mistakes(mini_location, encounter_nodes={"e1": "ch"}))
    assert "encounter e1: node 'zz' is not in the scene graph" in _path_mistakes(mini_location,
                                                                                 encounter_nodes={"e1": "zz"})
    off = _path_mistakes(mini_location, trajectories={"robot": ["32", "ch", "d9"], "human1": ["07", "11", "ch"],
                                                      "human2": ["f7", "07", "11"]},
                         interaction_points={"human1": "ch", "human2": "07"})
    assert "the node 11 of encounter e1 is not on the robot's path" in off
    assert "the interaction point 07 of human2 differs from the node 11 of its encounter e1; use 11" in off
    assert any("'e5' is not an encounter" in m for m in _path_mistakes(mini_location,
                                                                       encounter_nodes={"e1": "11", "e5": "11"}))


def test_stage_two_writes_the_grounded_spec(tmp_path, mini_location):
    from gen_helpers import run_replay
    GOOD_TREES = {"human1": [tree_reply()], "human2": [tree_reply()]}  # noqa: N806

    script = write_script(tmp_path / "s.yaml", {"scenario": [scenario_reply()], "paths": [paths_reply()],
                                                "behaviors": GOOD_TREES})
    run, _ = run_replay(script, mini_location, tmp_path / "run")
    spec = RunFolder(tmp_path / "run").read_spec()
    assert spec.encounters[0].node == "11" and run.spec == spec
    assert {h.interaction_point for h in run.paths.humans} == {"11"}


def test_an_edited_spec_is_validated_again_on_resume(tmp_path, mini_location):
    from gen_helpers import run_replay
    GOOD_TREES = {"human1": [tree_reply()], "human2": [tree_reply()]}  # noqa: N806

    from socnavgen.errors import InputFileError

    script = write_script(tmp_path / "s.yaml", {"scenario": [scenario_reply()], "paths": [paths_reply()],
                                                "behaviors": GOOD_TREES})
    out = tmp_path / "run"
    run_replay(script, mini_location, out)
    data = json.loads(RunFolder(out).spec_path.read_text())
    data["encounters"][0]["humans"][0]["human"] = "human5"
    RunFolder(out).spec_path.write_text(json.dumps(data))
    result, _ = run_replay(script, mini_location, out)
    assert isinstance(result, InputFileError) and "human5" in result.message
    assert str(result.file) == str(RunFolder(out).spec_path)


# ---- stage 3 against the spec ----------------------------------------------------------------------
SAYS_SPEC = {"script": {"cues": [{"trigger": {"when": "blocked"}, "say": "EXCUSE ME"}]},
             "encounters": [{"id": "e1", "place": "BLIND CORNER", "humans": [
                 {"human": "human1", "trigger": "robot_says", "phrase": "EXCUSE ME", "reaction": "give_way"}]}],
             "criteria": [{"id": "c1", "kind": "meets", "human": "human1", "encounter": "e1"}]}
WALK = ("<Sequence><SetBlackboard output_key='agentid' value='{id}'/><SetBlackboard output_key='timestep' "
        "value='{dt}'/><SubTree ID='RegularNavTree' id='agentid' dt='timestep'/></Sequence>")
GATED = ("<root main_tree_to_execute='M'><include path='BTRegularNav.xml'/><BehaviorTree ID='M'><Fallback>"
         "<Sequence><RobotSays agent_id='{id}' message='4'/><GiveWaytoRobot agent_id='{id}' time_step='{dt}'/>"
         f"</Sequence>{WALK}</Fallback></BehaviorTree></root>")
# the reaction inside a SubTree of the file: gated by the caller's Sequence
CALLED = ("<root main_tree_to_execute='M'><include path='BTRegularNav.xml'/><BehaviorTree ID='M'><Fallback>"
          "<Sequence><RobotSays agent_id='{id}' message='4'/><SetBlackboard output_key='me' value='{id}'/>"
          "<SetBlackboard output_key='step' value='{dt}'/><SubTree ID='Yield' id='me' dt='step'/></Sequence>"
          f"{WALK}</Fallback></BehaviorTree><BehaviorTree ID='Yield'><GiveWaytoRobot agent_id='{{id}}' "
          "time_step='{dt}'/></BehaviorTree></root>")


@pytest.mark.parametrize("tree, expected", [
    (GATED, None),
    (GATED.replace("message='4'", "message='5'"), "never checks RobotSays(message='4')"),
    (GATED.replace("<RobotSays agent_id='{id}' message='4'/>",
                   "<Inverter><RobotSays agent_id='{id}' message='4'/></Inverter>"), "is not gated by"),
    (GATED.replace("GiveWaytoRobot", "LookAtRobot").replace(" time_step='{dt}'", ""), "has no GiveWaytoRobot"),
    # the negated condition in an earlier Fallback branch gates the later branch
    ("<root main_tree_to_execute='M'><include path='BTRegularNav.xml'/><BehaviorTree ID='M'><Fallback><Sequence>"
     f"<Inverter><RobotSays agent_id='{{id}}' message='4'/></Inverter>{WALK}</Sequence>"
     "<GiveWaytoRobot agent_id='{id}' time_step='{dt}'/></Fallback></BehaviorTree></root>", None),
    # reactive controls and the explicit form are read by their library semantics
    (GATED.replace("<Sequence><RobotSays", "<ReactiveSequence><RobotSays").replace(
        "time_step='{dt}'/></Sequence>", "time_step='{dt}'/></ReactiveSequence>"), None),
    (GATED.replace("<RobotSays agent_id='{id}' message='4'/>", "<Condition ID='RobotSays' agent_id='{id}' message='4'/>"),
     None),
    (GATED.replace("message='4'", "message=' 4'"), None),  # the port's int, however it is written
    (CALLED, None),
    (CALLED.replace("<RobotSays agent_id='{id}' message='4'/>", ""), "never checks RobotSays"),
    (GATED.replace("<Sequence><RobotSays", "<Fallback><RobotSays").replace(
        "time_step='{dt}'/></Sequence>", "time_step='{dt}'/></Fallback>"), "is not gated by"),
])
def test_trees_are_checked_against_their_encounter(tree, expected):
    assert validate_bt_text(tree, "t.xml") == []  # needs are checked on trees bt check accepts
    mistakes = tree_need_mistakes(tree, "human1", ScenarioSpec.model_validate(SAYS_SPEC))
    if expected is None:
        assert mistakes == []
    else:
        assert len(mistakes) == 1 and expected in mistakes[0], mistakes


def test_stage_three_requeries_a_tree_that_lacks_its_trigger(tmp_path, mini_location):
    from gen_helpers import run_replay

    walker = STOP_TREE.replace("<IsRobotBlocking agent_id='{id}' distance='0.5'/>",
                               "<IsRobotVisible agent_id='{id}' distance='0.5'/>")
    script = write_script(tmp_path / "s.yaml", {
        "scenario": [scenario_reply()], "paths": [paths_reply()],
        "behaviors": {"human1": [tree_reply()], "human2": [tree_reply(walker), tree_reply()]}})
    run, llm = run_replay(script, mini_location, tmp_path / "run")
    asks = [m for s, k, m in llm.calls if (s, k) == ("behaviors", "human2")]
    assert len(asks) == 2 and "never checks IsRobotBlocking" in asks[1][-1].content
    assert "IsRobotBlocking" in RunFolder(tmp_path / "run").read_behavior("human2")


# ---- physical facts ---------------------------------------------------------------------------------
def test_prompts_carry_the_simulators_numbers(mini_location):
    from socnavgen.bodies import PERSON_MAX_SPEED as HUMAN_MAX_VEL
    from socnavgen.bodies import PERSON_RADIUS as HUMAN_RADIUS
    from socnavgen.bodies import ROBOT_RADIUS
    from socnavgen.proposal.paths import scene_graph_text

    facts = physical_facts_text()
    assert f"{HUMAN_MAX_VEL:g} m/s" in facts and f"radius {HUMAN_RADIUS:g} m" in facts
    assert f"radius {ROBOT_RADIUS:g} m" in facts and "CENTRES" in facts
    location = load_location(mini_location)
    nodes = json.loads(scene_graph_text(location))["nodes"]
    node = next(n for n in nodes if n["id"] == "11")
    assert node["xy_m"] == [round(v, 1) for v in location.node_world("11")]


def test_prompt_examples_pass_the_checks():
    """The hand-written examples obey the rules the model is held to."""
    from socnavgen.proposal.templates import template_data

    for example in template_data("scenario_examples.json"):
        reply = ScenarioReply.model_validate(copy.deepcopy(example["reply"]))
        assert scenario_checker(None)(reply) == []


# ---- stage 3 grammar for in-process models ---------------------------------------------------------
@pytest.mark.parametrize("trigger, reaction", [("robot_blocking", "stop"), ("robot_visible", "give_way"),
                                               ("always", "walk_past"), ("robot_near", "follow")])
def test_spec_tree_grammar_admits_only_trees_that_meet_the_spec(trigger, reaction):
    from socnavgen.bt.validate import validate_bt_text
    from socnavgen.proposal.tree_grammar import build_spec_tree_grammar

    spec = ScenarioSpec.model_validate({"encounters": [{"id": "e1", "place": "X", "humans": [
        {"human": "human1", "trigger": trigger, "reaction": reaction}]}]})
    grammar = build_spec_tree_grammar("human1", spec)
    assert grammar is not None
    sentences = list(_sample(grammar, 12))
    assert sentences
    for text in sentences:
        assert grammar.matches(text)
        tree = json.loads(text)["tree"]
        assert validate_bt_text(tree, "t.xml", human_ids={0}, agent_id=0) == [], tree
        assert tree_need_mistakes(tree, "human1", spec) == [], tree
    wrong = sentences[0].replace("IsRobot", "IsRobo")
    assert trigger == "always" or not grammar.matches(wrong)


def _sample(grammar, limit):  # noqa: ANN001, ANN202 - every alternative once, numbers fixed
    from socnavgen.proposal.gbnf import Chars, Lit, Ref

    def expand(symbols, choice):  # noqa: ANN001, ANN202
        out = ""
        for sym in symbols:
            if isinstance(sym, Lit):
                out += sym.text
            elif isinstance(sym, Ref):
                alts = grammar.rules[sym.name]
                out += expand(alts[choice % len(alts)], choice)
            elif isinstance(sym, Chars):
                out += ("1" if "0-9" in sym.cls else "a") * max(1, sym.min)
        return out

    seen = set()
    for choice in range(limit):
        text = expand(grammar.rules["root"][0], choice)
        if text not in seen:
            seen.add(text)
            yield text
