"""The prompts give the model what it needs to plan on THIS map (the place inventory, how the spec plays out,
the stl syntax, what an export target lacks), every number from where it is defined; and stage 1 refuses
what cannot work on the map or contradicts itself, while replies that can work pass."""

from __future__ import annotations

import copy
from pathlib import Path

import pytest

from socnavgen.location import load_location
from socnavgen.proposal.facts import STATED_BY
from socnavgen.proposal.replies import ScenarioReply
from socnavgen.proposal.scenario import scenario_checker, scenario_messages
from socnavgen.run import ScenarioRequest

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "locations"


@pytest.fixture(scope="module")
def home():
    return load_location(EXAMPLES / "home")


@pytest.fixture(scope="module")
def warehouse():
    return load_location(EXAMPLES / "warehouse")


def _request(location, **changes) -> ScenarioRequest:  # noqa: ANN001
    values = {"location": str(location.root), "context": "Assistant robot in a family home",
              "task": "Bring a cup of tea to the living room", "llm": "replay"}
    return ScenarioRequest(**{**values, **changes})


def _stage1_prompt(location, **changes) -> tuple[str, str]:  # noqa: ANN001
    messages = scenario_messages(_request(location, **changes), location)
    return messages[0].content, messages[-1].content


# ---- what the prompts say ---------------------------------------------------------------------------
def test_stage1_sees_the_place_inventory_of_the_map(home):
    _, user = _stage1_prompt(home)
    assert "PLACE INVENTORY" in user
    assert "- DINING AREA: a7 (at 4.7,0.5; dead end from 41" in user  # the dead-end dining node of the issue
    assert "NOTE: no DINING AREA node can hold an encounter on this map: a7 is a dead end reached only from 41" in user
    assert "2n (DOORWAY): 0.9 m wide, between 1f (BEDROOM) and i6 (HALLWAY)" in user
    assert "Blind turns (" in user and "Where a standing group of three fits" in user


def test_the_naive_baseline_gets_no_inventory(home):
    from socnavgen.proposal.naive import naive_messages

    assert "PLACE INVENTORY" not in naive_messages(_request(home), home)[0].content


def test_how_the_spec_plays_out_comes_from_its_sources(home):
    from socnavgen.bodies import GROUP_SPAWN_RADIUS
    from socnavgen.proposal.facts import STL_EXAMPLE
    from socnavgen.run.spec import Encounter, RobotCue
    from socnavgen.sim import ThrottleConfig
    from socnavgen.verify.signals import SIGNAL_KINDS
    from socnavgen.verify.stl import formula_problems

    system, _ = _stage1_prompt(home)
    pace = ThrottleConfig()
    assert f"slower than {pace.min_pace:g} m/s" in system and f"within {pace.release_distance:g} m" in system
    within = Encounter.model_fields["within"]
    assert f"\"within\" ({within.default:g} m unless set, at most 5 m)" in system
    assert RobotCue.model_fields["once"].default is True and "fires once" in system and "\"once\": false" in system
    assert f"circle of {GROUP_SPAWN_RADIUS:g} m" in system
    assert "\"latch\": true keeps a reaction going for good" in system  # any trigger latches (KeepRunning)
    assert "robot_far holds exactly when robot_near does not" in system and "\"lasts\" (s)" in system
    assert "human_farther (" in system  # the guide's cue for a follower who fell behind
    assert STL_EXAMPLE in system and all(k.shown in system for k in SIGNAL_KINDS if k.listed)
    assert not any(k.shown in system for k in SIGNAL_KINDS if not k.listed)  # the verifier's own (idle) is not told
    assert formula_problems(STL_EXAMPLE, ["human1"], ["e1"]) == []  # the example itself can be monitored


def test_stage1_states_how_far_a_follower_trails_where_criteria_are_written(home):
    """The follower's trail (sim/people/leaves.follow) sits at the follows_robot criterion of stage 1, and its
    physical-facts bullet is short enough to reach a player whole (a long one came back cut)."""
    from socnavgen.bodies import PERSON_MAX_SPEED
    from socnavgen.proposal.facts import follow_trail
    from socnavgen.proposal.prose_checks import close_follow_gap
    from socnavgen.sim.people.leaves import follow_trail as simulated_trail

    system, _ = _stage1_prompt(home)
    criterion = system[system.index("follows_robot: `human` stays within"):].split(";")[0]
    assert f"trails {simulated_trail(0.6, PERSON_MAX_SPEED):.1f} m behind the robot at 0.6 m/s" in criterion
    assert f"a `distance` of {follow_trail(0.6) + 2:.0f} m ({close_follow_gap(0.6, PERSON_MAX_SPEED):.1f} right behind)" \
        in criterion  # the prose check's ceiling, told before it refuses
    bullet = next(line for line in system.splitlines() if line.startswith("- A follower (FollowRobot"))
    assert len(bullet) <= 240 and bullet.endswith("other followers.")


def test_the_prompts_state_the_simulations_time_limit_from_its_home(home):
    """A slow round trip with a follower timed out and no prompt said when a run ends (a round-5 player)."""
    from socnavgen.proposal.facts import physical_facts_text
    from socnavgen.sim.engine.budget import RULE_TEXT

    system, _ = _stage1_prompt(home)
    assert f"at its time limit: {RULE_TEXT}" in system
    assert RULE_TEXT in physical_facts_text(scene_graph=True)  # stages 2 and 3 too


def test_pacing_is_stated_as_the_simulator_does_it(home):
    """Round-5 players: 'the person waits for the robot there' was optimistic when the robot stood for its own cues.
    Pacing now re-estimates the robot's arrival with the time it still stands (sim/people/pacing.py) and the prompt
    says so, with the release distance from ThrottleConfig."""
    from socnavgen.sim import ThrottleConfig

    pace = ThrottleConfig()
    system, _ = _stage1_prompt(home)
    assert "the person waits for the robot there" not in system
    assert "by the robot's ETA re-estimated as it goes (its route left at its speed, plus what is left of the " \
           "`wait` of cues that fired: not a cue yet to fire, a let_pass, a wait_until_clear, nor a wait it stands on its " \
           f"way within {pace.release_distance:g} m of the node along its route: they come during that wait)" in system
    assert f"nobody is held in the robot's way within {pace.release_distance:g} m of it, nor ahead on its way while " \
           "it stands for no known time" in system
    assert f"slower than {pace.min_pace:g} m/s" in system


def test_stage1_says_a_stop_shows_only_after_having_walked(home):
    """A player held a worker with MakeGesture 0 from the start and no wait_then_go showed: the tree held them
    still (tests/sim/test_nodes), but the verifier sees a stop only after a walk (verify/signals.reaction_evidence)."""
    from socnavgen.verify.thresholds import MOVED_DISTANCE, STOP_HOLD, STOP_SPEED

    system, _ = _stage1_prompt(home)
    assert f"a stop or wait_then_go is a person slower than {STOP_SPEED:g} m/s for {STOP_HOLD:g} s AFTER having " \
           f"walked {MOVED_DISTANCE:g} m from their start" in system and "shows none until they have walked" in system


def test_the_target_says_which_nodes_it_lacks(home):
    from socnavgen.bt.library import prompt_nodes

    system, _ = _stage1_prompt(home, target="hunav2")
    lacking = [n.name for n in prompt_nodes() if "hunav2" not in n.targets]
    assert lacking and f"hunav2 lacks the nodes {', '.join(lacking)}." in system
    assert "lacks the nodes" not in _stage1_prompt(home)[0]


def test_stage2_widths_are_the_inventorys_and_it_knows_where_people_may_start(home):
    import json

    from socnavgen.location.placement import start_rule_text
    from socnavgen.proposal.paths import paths_messages, scene_graph_text
    from socnavgen.run import ScenarioProposal

    links = json.loads(scene_graph_text(home))["links"]
    door = next(e for e in links if {e["source"], e["target"]} == {"2n", "1f"})
    assert door["width_m"] == home.inventory.width("2n", "1f") and door["narrow"] is True
    scenario = ScenarioProposal(scenario_description="The robot brings tea to the living room.", number_of_humans=1,
                                human_behaviors={"human1": "A resident walks to the kitchen."},
                                expected_robot_behavior="Pass politely.")
    prompt = paths_messages(home, scenario, images=False)[-1].content
    assert "PLACE INVENTORY" in prompt and "7. " + start_rule_text() in prompt
    assert "from the robot's start (1.8 m for a group" in start_rule_text()


# ---- stage 1 refuses what cannot work here, and passes what can ---------------------------------------
def _reply(place: str, criteria: list[dict] | None = None, part: dict | None = None, behavior: str = "",
           cues: list[dict] | None = None) -> ScenarioReply:
    """One resident at `place`; the criteria given (meets by default) and the one stating her reaction (stage 1
    asks it: spec_checks.unstated_reactions), unless given."""
    human = {"human": "human1", "trigger": "robot_near", "reaction": "give_way", "distance": 2.0, **(part or {})}
    criteria = criteria or [{"id": "c1", "kind": "meets", "human": "human1", "encounter": "e1"}]
    stating = STATED_BY.get(human["reaction"], ())
    if stating and not any(c["kind"] in stating for c in criteria):
        criteria = [*criteria, {"id": "c9", "kind": stating[0], "human": "human1", "encounter": "e1",
                                "text": f"the resident does {human['reaction']}"}]
    return ScenarioReply.model_validate({
        "scenario_description": "The robot carries tea through the home and meets a resident on the way.",
        "number_of_humans": 1,
        "human_behaviors": {"human1": behavior or "A resident walks across the room and steps aside for the robot."},
        "expected_robot_behavior": "Slow down near the resident and pass at a polite distance.",
        "spec": {"script": {"route": "through the home", "cues": cues or []},
                 "encounters": [{"id": "e1", "place": place, "humans": [human]}],
                 "criteria": criteria}})


def test_an_encounter_in_the_dead_end_dining_area_is_refused(home):
    check = scenario_checker(home)
    refused = check(_reply("DINING AREA"))
    assert any("encounter e1 happens at a DINING AREA" in m and "a7" in m for m in refused), refused
    assert check(_reply("LIVING ROOM")) == []
    assert check(_reply("BEDROOM")) == []  # dead ends with room to turn beside someone can work


def test_hidden_until_needs_a_blind_place_and_a_distance_it_can_hold(warehouse):
    check = scenario_checker(warehouse)

    def hidden(place: str, distance: float) -> list[str]:
        return check(_reply(place, criteria=[
            {"id": "c1", "kind": "meets", "human": "human1", "encounter": "e1"},
            {"id": "c2", "kind": "hidden_until", "human": "human1", "encounter": "e1", "distance": distance}]))

    assert any("needs a blind turn, but no ENTRANCE node" in m for m in hidden("ENTRANCE", 3.0))
    too_close = hidden("BLIND CORNER", 1.0)
    assert any("first see each other 3.2 m apart or more; set its distance to at least 4 (+0.5 m margin)" in m
               for m in too_close), too_close
    assert any("set its distance to at least 4" in m for m in hidden("BLIND CORNER", 3.0))  # under the worst way
    assert hidden("BLIND CORNER", 3.5) == [] and hidden("BLIND CORNER", 4.0) == []  # refused only below 3.2 m


def test_a_says_criterion_for_someone_who_never_speaks_is_refused(home):
    """The issue's reply: a `says` criterion for a person who never speaks, its text "placeholder"."""
    check = scenario_checker(home)
    mistakes = check(_reply("LIVING ROOM", criteria=[
        {"id": "c1", "kind": "meets", "human": "human1", "encounter": "e1"},
        {"id": "c2", "kind": "says", "human": "human1", "phrase": "WAIT", "text": "placeholder"}]))
    assert any("criterion c2 asks human1 to say WAIT, but the behavior of human1 never mentions it" in m
               for m in mistakes), mistakes
    assert any("criterion c2: text contains the placeholder 'placeholder'" in m for m in mistakes)
    speaks = _reply("LIVING ROOM", part={"reaction": "say", "says": "WAIT"},
                    behavior="A resident sees the robot coming and says WAIT to it.",
                    criteria=[{"id": "c1", "kind": "meets", "human": "human1", "encounter": "e1"},
                              {"id": "c2", "kind": "says", "human": "human1", "phrase": "WAIT",
                               "text": "the resident says WAIT"}])
    assert check(speaks) == []
    silent_prose = copy.deepcopy(speaks)
    silent_prose.human_behaviors["human1"] = "A resident walks across the room without a word."
    assert any("never mentions it" in m for m in check(silent_prose))
    mute = _reply("LIVING ROOM", part={"reaction": "stop"},  # her text says WAIT; her encounter never has her speak
                  behavior="A resident sees the robot coming and says WAIT to it.",
                  criteria=[{"id": "c1", "kind": "meets", "human": "human1", "encounter": "e1"},
                            {"id": "c2", "kind": "says", "human": "human1", "phrase": "WAIT",
                             "text": "the resident says WAIT"}])
    assert any("criterion c2 asks human1 to say WAIT, but no encounter has human1 speak" in m
               for m in check(mute)), check(mute)


@pytest.mark.parametrize("kind, reaction, expected", [  # the verifier's rule S1 (verify/blame.py contradictions)
    ("follows_robot", "walk_past", "asks human1 for what its encounter does not have it do (its reaction: walk_past"),
    ("blocks_robot", "give_way", "asks human1 for what its encounter does not have it do (its reaction: give_way"),
    ("keeps_away", "follow", "asks human1 for what its encounter does not have it do (its reaction: follow"),
])
def test_criteria_that_contradict_the_persons_reaction_are_refused(home, kind, reaction, expected):
    check = scenario_checker(home)
    reply = _reply("LIVING ROOM", part={"reaction": reaction}, criteria=[
        {"id": "c1", "kind": "meets", "human": "human1", "encounter": "e1"},
        {"id": "c2", "kind": kind, "human": "human1", "distance": 1.5}])
    assert any(expected in m for m in check(reply)), check(reply)


def test_a_latch_needs_a_trigger_a_tree_can_remember(home):
    latched = _reply("LIVING ROOM", part={"reaction": "follow", "latch": True})
    assert scenario_checker(home)(latched) == []  # KeepRunningUntilFailure holds any reaction once triggered
    refused = scenario_checker(home, target="hunav2")(latched)  # 2.x re-checks every condition each tick
    assert any("latch is true, but a hunav2 tree cannot remember the trigger robot_near" in m for m in refused), refused
    check = scenario_checker(home)
    phrase = _reply("LIVING ROOM", part={"trigger": "robot_says", "phrase": "FOLLOW ME", "reaction": "follow",
                                         "latch": True},
                    cues=[{"trigger": {"when": "human_within", "human": "human1", "distance": 2.0},
                           "say": "FOLLOW ME"}])
    assert check(phrase) == []


def test_stl_formulas_are_checked_before_anything_is_simulated(home):
    check = scenario_checker(home)

    def stl(formula: str) -> list[str]:
        return check(_reply("LIVING ROOM", criteria=[
            {"id": "c1", "kind": "meets", "human": "human1", "encounter": "e1"},
            {"id": "c2", "kind": "stl", "formula": formula, "text": "the robot passes slowly"}]))

    assert any("criterion c2: unknown signal 'speed_robbot'" in m for m in stl("always (speed_robbot <= 0.6)"))
    assert stl("always (dist_human1 >= 0.8)") == []


def test_the_guide_cue_for_a_follower_who_fell_behind(home):
    check = scenario_checker(home)
    reply = _reply("LIVING ROOM", part={"trigger": "robot_says", "phrase": "FOLLOW ME", "reaction": "follow",
                                        "latch": True},
                   cues=[{"trigger": {"when": "start"}, "say": "FOLLOW ME"},
                         {"trigger": {"when": "human_farther", "human": "human1", "distance": 3.0},
                          "wait": 4.0, "once": False}])
    assert check(reply) == []


def test_stage2_grounds_a_hidden_until_encounter_only_where_it_is_blind_enough(warehouse):
    from socnavgen.proposal.path_checks import check_paths
    from socnavgen.proposal.replies import PathsReply
    from socnavgen.proposal.scenario import to_spec

    reply = _reply("BLIND CORNER", part={"reaction": "stop"}, criteria=[
        {"id": "c1", "kind": "meets", "human": "human1", "encounter": "e1"},
        {"id": "c2", "kind": "hidden_until", "human": "human1", "encounter": "e1", "distance": 4.0}])
    assert scenario_checker(warehouse)(reply) == []  # 54 is blind until 3.2 m (+0.5 m margin): the place can work
    spec = to_spec(reply)

    def ground(robot: list[str], human: list[str], node: str) -> list[str]:
        answer = PathsReply.model_validate({"trajectories": {"robot": robot, "human1": human},
                                            "group_ids": {"human1": -1}, "interaction_points": {"human1": node},
                                            "encounter_nodes": {"e1": node}})
        return check_paths(answer, warehouse.graph, ["human1"], spec, warehouse)

    at_f7 = ground(["co", "54", "f7", "6r"], ["hd", "6r", "f7"], "f7")  # f7 hides them only until 3.6 m
    assert at_f7 == []  # 3.6 m <= 4 m: it can hold (the prompt advises the margin)
    spec.criteria[1].distance = 3.4
    at_f7 = ground(["co", "54", "f7", "6r"], ["hd", "6r", "f7"], "f7")
    assert any("they see each other from 3.6 m" in m for m in at_f7), at_f7
    assert ground(["up", "co", "54", "f7"], ["6r", "f7", "54"], "54") == []
    same_way = ground(["up", "co", "54", "f7"], ["up", "co", "54"], "54")  # walking in behind the robot
    assert any("they see each other from afar" in m for m in same_way), same_way


def test_stage2_refuses_a_way_in_that_looks_into_the_blind_turn():
    """Hospital q9 hides the elevator car jb from a robot coming past 8z, not from one coming through the
    doorway cc (it looks into the car from 11 m: a round-5 player's hidden_until failed there)."""
    from socnavgen.proposal.path_checks import check_paths
    from socnavgen.proposal.replies import PathsReply
    from socnavgen.proposal.scenario import to_spec

    hospital = load_location(EXAMPLES / "hospital")
    reply = _reply("ELEVATOR LOBBY", part={"reaction": "stop", "trigger": "robot_visible"}, criteria=[
        {"id": "c1", "kind": "meets", "human": "human1", "encounter": "e1"},
        {"id": "c2", "kind": "hidden_until", "human": "human1", "encounter": "e1", "distance": 4.5}])
    spec = to_spec(reply)

    def ground(robot: list[str]) -> list[str]:
        answer = PathsReply.model_validate({"trajectories": {"robot": robot, "human1": ["jb", "q9"]},
                                            "group_ids": {"human1": -1}, "interaction_points": {"human1": "q9"},
                                            "encounter_nodes": {"e1": "q9"}})
        return [m for m in check_paths(answer, hospital.graph, ["human1"], spec, hospital) if "c2" in m]

    through_cc = ground(["1g", "cc", "8r", "q9"])
    assert any("coming into node q9 of encounter e1 the way they do, they see each other from afar" in m
               for m in through_cc), through_cc
    assert ground(["lc", "8z", "8r", "q9"]) == []


def test_every_cue_trigger_is_explained_from_the_models_docstring():
    from typing import get_args

    from socnavgen.proposal.facts import cue_triggers_text
    from socnavgen.run.spec import CueTrigger

    text = cue_triggers_text()
    for when in get_args(CueTrigger.model_fields["when"].annotation):
        assert f"{when} (" in text and f"{when} ()" not in text, when  # each with its meaning


def test_the_stage1_grammar_offers_only_places_that_can_work_here(home):
    from socnavgen.proposal.scenario import build_scenario_grammar, workable_places

    places = workable_places(home)
    assert "DINING AREA" not in places and {"LIVING ROOM", "BEDROOM", "DOORWAY"} <= set(places)
    grammar = build_scenario_grammar(node_types=places)
    reply = _reply("LIVING ROOM").model_dump(exclude={"spec"})
    spec = {"script": {"route": "through the home", "cues": []},
            "encounters": [{"id": "e1", "place": "DINING AREA", "humans": [
                {"human": "human1", "trigger": "robot_near", "reaction": "give_way"}]}],
            "criteria": [{"id": "c1", "kind": "meets", "human": "human1", "encounter": "e1"},
                         {"id": "c2", "kind": "gives_way", "human": "human1", "encounter": "e1"}]}
    import json

    assert not grammar.matches(json.dumps({**reply, "spec": spec}))
    spec["encounters"][0]["place"] = "LIVING ROOM"
    assert grammar.matches(json.dumps({**reply, "spec": spec}))
