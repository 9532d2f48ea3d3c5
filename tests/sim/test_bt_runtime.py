"""The BT interpreter: dispatch from the library table, BT.CPP v3/v4 semantics, SubTree remapping,
strict building that lists every problem."""

from __future__ import annotations

import pytest

from socnavgen.bt.library import leaf_nodes
from socnavgen.errors import ValidationFailed
from socnavgen.sim.engine.errors import BTRuntimeError
from socnavgen.sim.engine.simulation import NODE_NAMES
from socnavgen.sim.people.leaves import LEAVES

from .simhelpers import REGULAR, human, make_sim, tree_xml


def test_every_library_leaf_has_a_function_and_nothing_else():
    names = {n.name for n in leaf_nodes()}
    assert names == set(LEAVES)
    assert [n.name for n in leaf_nodes()] == NODE_NAMES  # trace bit order follows the table
    assert len(NODE_NAMES) <= 63  # fits the int64 success bitmask


def test_every_control_and_decorator_of_the_library_runs():
    """What bt check accepts the simulator runs: each control's flow and each decorator's rule has its node
    kind in the interpreter."""
    from socnavgen.bt.library import LIBRARY
    from socnavgen.sim.people.trees import CONTROLS, DECORATORS

    controls = [s for s in LIBRARY.values() if s.kind == "control"]
    decorators = [s for s in LIBRARY.values() if s.kind == "decorator"]
    assert len(controls) >= 4 and len(decorators) >= 6
    assert all((s.flow, s.reactive) in CONTROLS for s in controls)
    assert all(s.rule in DECORATORS for s in decorators)


def gesture_after_one_step(body: str, fmt: int = 3, robot_at=(3.0, 5.0)) -> int:
    sim = make_sim([human(start=(2.0, 5.0))], [tree_xml(body, fmt)], [robot_at, (19.0, 5.0)])
    sim.step()
    return int(sim.people[0].gesture)


@pytest.mark.parametrize(("body", "expected"), [
    # Sequence stops at the first FAILURE
    ('<Sequence><IsRobotNearby agent_id="{id}" distance="0.5"/><MakeGesture agent_id="{id}" message="1"/></Sequence>', 0),
    ('<Sequence><IsRobotNearby agent_id="{id}" distance="2"/><MakeGesture agent_id="{id}" message="1"/></Sequence>', 1),
    # Fallback stops at the first SUCCESS
    ('<Fallback><MakeGesture agent_id="{id}" message="2"/><MakeGesture agent_id="{id}" message="1"/></Fallback>', 2),
    ('<Fallback><IsRobotNearby agent_id="{id}" distance="0.5"/><MakeGesture agent_id="{id}" message="3"/></Fallback>', 3),
    # Inverter, ForceSuccess, ForceFailure
    ('<Sequence><Inverter><IsRobotNearby agent_id="{id}" distance="0.5"/></Inverter>'
     '<MakeGesture agent_id="{id}" message="1"/></Sequence>', 1),
    ('<Sequence><ForceSuccess><IsRobotNearby agent_id="{id}" distance="0.5"/></ForceSuccess>'
     '<MakeGesture agent_id="{id}" message="2"/></Sequence>', 2),
    ('<Fallback><ForceFailure><MakeGesture agent_id="{id}" message="1"/></ForceFailure>'
     '<MakeGesture agent_id="{id}" message="3"/></Fallback>', 3),
    ('<ReactiveSequence><IsRobotNearby agent_id="{id}" distance="2"/><MakeGesture agent_id="{id}" message="2"/>'
     '</ReactiveSequence>', 2),
    ('<ReactiveFallback><IsRobotNearby agent_id="{id}" distance="0.5"/><MakeGesture agent_id="{id}" message="1"/>'
     '</ReactiveFallback>', 1),
    # explicit v3 form <Action ID=.../>
    ('<Action ID="MakeGesture" agent_id="{id}" message="3"/>', 3),
])
def test_control_flow(body, expected):
    assert gesture_after_one_step(body) == expected


SUBTREE_DOC = """<root main_tree_to_execute="Main"{fmt}>
  <BehaviorTree ID="Main">
    <Sequence>
      <SetBlackboard output_key="code" value="{code}"/>
      <SetBlackboard output_key="me" value="{{id}}"/>
      <SubTree ID="Say" agent_id="{me_ref}" msg="{code_ref}"/>
    </Sequence>
  </BehaviorTree>
  <BehaviorTree ID="Say">
    <Sequence>
      <SetBlackboard output_key="inside" value="1"/>
      <MakeGesture agent_id="{{agent_id}}" message="{{msg}}"/>
    </Sequence>
  </BehaviorTree>
</root>"""


@pytest.mark.parametrize(("fmt", "me_ref", "code_ref"), [(3, "me", "code"), (4, "{me}", "{code}")])
def test_subtree_remaps_ports_live_v3_and_v4(fmt, me_ref, code_ref):
    xml = SUBTREE_DOC.format(fmt=' BTCPP_format="4"' if fmt == 4 else "", code=2, me_ref=me_ref, code_ref=code_ref)
    sims = make_sim([human(), human("human2", start=(4.0, 5.0))], [xml, xml], [(10.0, 5.0), (19.0, 5.0)])
    sims.step()
    assert list(sims.people.gesture) == [2, 2]  # each tree's {id} reached MakeGesture through two remaps


def test_a_subtrees_own_keys_stay_in_its_blackboard():
    """The subtree writes `inside`; its caller reading `{inside}` afterwards would find it unset: blackboards
    of SubTrees are isolated unless remapped (the tree is refused before it runs, with the line)."""
    xml = SUBTREE_DOC.format(fmt="", code=2, me_ref="me", code_ref="code").replace(
        '<SubTree ID="Say" agent_id="me" msg="code"/>',
        '<SubTree ID="Say" agent_id="me" msg="code"/><MakeGesture agent_id="{id}" message="{inside}"/>')
    with pytest.raises(ValidationFailed, match=":6: MakeGesture message='{inside}': blackboard key 'inside' is "
                                               "never set"):
        make_sim([human()], [xml], [(10.0, 5.0), (19.0, 5.0)])


def test_v4_subtree_plain_value_is_a_literal():
    xml = SUBTREE_DOC.format(fmt=' BTCPP_format="4"', code=0, me_ref="{me}", code_ref="3")
    sim = make_sim([human()], [xml], [(10.0, 5.0), (19.0, 5.0)])
    sim.step()
    assert list(sim.people.gesture) == [3]


def test_reading_a_key_that_a_skipped_branch_would_have_written_stops_the_run_with_its_line():
    """`{x}` is written before it is read in document order (bt check accepts it), but the branch that writes
    it fails first: the read finds nothing and the run stops, naming the line."""
    body = ('<Fallback><Sequence><IsRobotNearby agent_id="{id}" distance="0.1"/>'
            '<SetBlackboard output_key="x" value="2"/></Sequence>\n<MakeGesture agent_id="{id}" message="{x}"/>'
            '</Fallback>')
    sim = make_sim([human()], [tree_xml(body)], [(10.0, 5.0), (19.0, 5.0)])
    with pytest.raises(BTRuntimeError) as err:
        sim.step()
    assert "reads blackboard key `x` that is not set" in err.value.message and err.value.line == 5


def test_building_lists_every_problem_with_lines():
    body = ('<Sequence><FlyAway agent_id="{id}"/>\n<IsRobotNearby agent_id="{id}"/>\n'
            '<RegularNav agent_id="{id}" time_step="{dt}" speed="3"/>\n'
            '<MakeGesture agent_id="{id}" message="loud"/></Sequence>')
    with pytest.raises(ValidationFailed) as err:
        make_sim([human()], [tree_xml(body)], [(10.0, 5.0), (19.0, 5.0)])
    text = err.value.message
    assert ":4: unknown node 'FlyAway'" in text
    assert ":5: IsRobotNearby is missing required port 'distance'" in text
    assert ":6: unknown port 'speed' on RegularNav" in text
    assert ":7: MakeGesture message='loud': message must be an integer" in text


def test_unknown_subtree_and_missing_include_are_reported():
    xml = '<root main_tree_to_execute="M"><BehaviorTree ID="M"><SubTree ID="Nope"/></BehaviorTree></root>'
    with pytest.raises(ValidationFailed, match="SubTree ID 'Nope' names no BehaviorTree"):
        make_sim([human()], [xml], [(10.0, 5.0), (19.0, 5.0)])
    xml = ('<root main_tree_to_execute="M"><BehaviorTree ID="M"><SubTree ID="RegularNavTree" id="agentid" '
           'dt="timestep"/></BehaviorTree></root>')
    with pytest.raises(ValidationFailed, match="needs <include path='BTRegularNav.xml'/>"):
        make_sim([human()], [xml], [(10.0, 5.0), (19.0, 5.0)])


def test_regular_nav_tree_from_the_library_include_walks_to_the_goal():
    sim = make_sim([human(start=(2.0, 2.0), goals=[(8.0, 2.0)])], [tree_xml(REGULAR)], [(2.0, 8.0), (3.0, 8.0)], timeout=15)
    trace = sim.run()
    assert abs(trace.humans[-1, 0, 0] - 8.0) < 0.7
    assert trace.executed(0, "RegularNav").any() and trace.fired(0, "IsGoalReached").any()


def test_repeat_decorator_ticks_its_child_n_times():
    # a failing child stops Repeat after one tick: the timer (1 s per tick, 2.5 s to go) fires on the 3rd step
    body = ('<Fallback><Repeat num_cycles="3"><TimeExpiredCondition seconds="2.5" ts="1" only_once="true"/>'
            '</Repeat><MakeGesture agent_id="{id}" message="0"/></Fallback>')
    sim = make_sim([human()], [tree_xml(body)], [(10.0, 5.0), (12.0, 5.0)], timeout=0.2)
    trace = sim.run()
    assert trace.fired(0, "TimeExpiredCondition").tolist() == [False, False, False, True, True]
    # with a succeeding child it runs 3 times within one tick
    body = '<Repeat num_cycles="3"><UpdateGoal agent_id="{id}"/></Repeat>'
    sim = make_sim([human(goals=[(5, 5), (6, 5), (7, 5), (8, 5)])], [tree_xml(body)], [(10.0, 5.0)])
    sim.step()
    assert [g.real for g in sim.goals_of(0)] == [8.0]
    retry = '<RetryUntilSuccessful num_attempts="3"><UpdateGoal agent_id="{id}"/></RetryUntilSuccessful>'
    sim = make_sim([human(goals=[(5, 5), (6, 5), (7, 5), (8, 5)])], [tree_xml(retry)], [(10.0, 5.0)])
    sim.step()
    assert [g.real for g in sim.goals_of(0)] == [6.0, 7.0, 8.0]  # it succeeded at once: one try


@pytest.mark.parametrize("name", ["LLMBT_0.xml", "LLMBT_1.xml", "LLMBT_2.xml", "BTCuriousNav.xml", "BTRegularNav.xml"])
def test_socrates_fork_trees_run(reference_dir, name):
    xml = (reference_dir / "data" / "socrates-hunav" / "behavior_trees" / name).read_text()
    sim = make_sim([human(start=(4.0, 5.0), goals=[(15.0, 5.0)])], [xml], [(2.0, 5.0), (3.0, 5.0)])
    for _ in range(20):
        sim.step()
        assert sim.people[0].action >= 0  # some action ran every tick


def test_stale_socrates_placeholder_tree_is_refused(reference_dir):
    xml = (reference_dir / "data" / "socrates-hunav" / "behavior_trees" / "LLMBT_3.xml").read_text()
    with pytest.raises(ValidationFailed, match="HasRobotMoved"):
        make_sim([human()], [xml], [(2.0, 5.0), (3.0, 5.0)])
