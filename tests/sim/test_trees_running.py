"""Behavior trees while they run: control nodes that remember or halt a running child, blackboards that hold
text, and a tree that cannot go on stopping the run with its file and line (whether stepped or run)."""

from __future__ import annotations

import re

import numpy as np
import pytest

from socnavgen.sim.engine.errors import BTRuntimeError

from .simhelpers import REGULAR, human, make_sim, tree_xml

GOALS = [(5.0, 5.0), (6.0, 5.0), (7.0, 5.0), (8.0, 5.0), (9.0, 5.0), (10.0, 5.0), (11.0, 5.0), (12.0, 5.0)]
ROBOT = [(18.0, 9.0), (19.0, 9.0)]


def run_tree(body: str, timeout: float = 5.0, people=None, **kw):  # noqa: ANN001, ANN003, ANN201
    people = people or [human(start=(2.0, 5.0), goals=GOALS)]
    return make_sim(people, [tree_xml(body, **kw)] * len(people), ROBOT, timeout=timeout).run()


WALK = '<Sequence><UpdateGoal agent_id="{id}"/><KeepRunningUntilFailure><RegularNav agent_id="{id}" ' \
       'time_step="{dt}"/></KeepRunningUntilFailure></Sequence>'
EVERY_SECOND = '<Inverter><TimeExpiredCondition seconds="1.0" ts="{dt}" only_once="false"/></Inverter>'


def test_a_sequence_resumes_its_running_child_and_a_reactive_parent_halts_it():
    """Sequence(UpdateGoal, KeepRunningUntilFailure(RegularNav)) keeps running RegularNav: UpdateGoal is ticked
    once. Under a ReactiveSequence whose first child fails once a second, the running Sequence is halted each
    time and starts again from UpdateGoal: a new goal every second."""
    plain = run_tree(f'<Sequence>{EVERY_SECOND}{WALK}</Sequence>')
    reactive = run_tree(f'<ReactiveSequence>{EVERY_SECOND}{WALK}</ReactiveSequence>')
    assert plain.fired(0, "UpdateGoal").sum() == 1
    assert plain.executed(0, "RegularNav")[2:].all()
    updates = np.flatnonzero(reactive.fired(0, "UpdateGoal"))
    assert len(updates) == 5  # at the start and after each of the four halts in 5 s
    assert set(np.diff(updates).tolist()) <= {20, 21}  # once a second (the timer adds dt per tick)


def test_a_fallback_remembers_its_running_child():
    """Fallback(ForceFailure(MakeGesture 2), KeepRunningUntilFailure(RegularNav)): the running second child is
    resumed, the first is not ticked again (its gesture stays shown, its success bit set once)."""
    trace = run_tree('<Fallback><ForceFailure><MakeGesture agent_id="{id}" message="2"/></ForceFailure>'
                     '<KeepRunningUntilFailure><RegularNav agent_id="{id}" time_step="{dt}"/>'
                     '</KeepRunningUntilFailure></Fallback>')
    assert trace.fired(0, "MakeGesture").sum() == 1 and (trace.human_gesture[1:, 0] == 2).all()
    reactive = run_tree('<ReactiveFallback><ForceFailure><MakeGesture agent_id="{id}" message="2"/></ForceFailure>'
                        '<KeepRunningUntilFailure><RegularNav agent_id="{id}" time_step="{dt}"/>'
                        '</KeepRunningUntilFailure></ReactiveFallback>')
    assert reactive.fired(0, "MakeGesture")[1:].all()  # a reactive parent ticks it again every step


def test_a_blackboard_entry_holding_text_is_read_as_the_ports_type():
    """SetBlackboard stores its literal as text (as BT.CPP does); IsRobotNearby reads it as a distance."""
    def nearby(distance: str, robot_at: float) -> bool:
        body = (f'<Sequence><SetBlackboard output_key="d" value="{distance}"/>'
                '<Fallback><Sequence><IsRobotNearby agent_id="{id}" distance="{d}"/>'
                '<MakeGesture agent_id="{id}" message="1"/></Sequence><MakeGesture agent_id="{id}" message="0"/>'
                '</Fallback></Sequence>')
        sim = make_sim([human(start=(2.0, 5.0))], [tree_xml(body)], [(2.0 + robot_at, 5.0), (19.0, 5.0)])
        sim.step()
        return sim.people[0].gesture == 1

    assert nearby("2.5", 2.0) and not nearby("2.5", 3.0) and nearby("3e0", 2.9)


def test_a_shared_blackboard_subtree_writes_into_its_callers_blackboard():
    xml = ('<root main_tree_to_execute="Main"><BehaviorTree ID="Main"><Sequence>'
           '<SubTree ID="Set" __shared_blackboard="true"/><MakeGesture agent_id="{id}" message="{code}"/>'
           '</Sequence></BehaviorTree><BehaviorTree ID="Set"><SetBlackboard output_key="code" value="3"/>'
           '</BehaviorTree></root>')
    sim = make_sim([human()], [xml], ROBOT)
    sim.step()
    assert sim.people[0].gesture == 3


@pytest.mark.parametrize(("body", "line", "message"), [
    ('<Fallback><Sequence><IsRobotNearby agent_id="{id}" distance="0.1"/><SetBlackboard output_key="x" value="2"/>'
     '</Sequence>\n<MakeGesture agent_id="{id}" message="{x}"/></Fallback>', 5,
     "MakeGesture: port `message` reads blackboard key `x` that is not set"),
    ('<Sequence>\n<HumanSays agent_id="{id}" target_id="4" message="1"/></Sequence>', 5,
     "port `target_id` = 4 is not a human id"),
    ('<Sequence>\n<FollowAgent agent_id="{id}" target_agent_id="3" time_step="{dt}" closest_dist="1" max_vel="1" '
     'duration="0"/></Sequence>', 5, "port `target_agent_id` = 3 is not a human id"),
    ('<Fallback><Sequence><IsRobotNearby agent_id="{id}" distance="0.1"/><SetBlackboard output_key="a" value="1"/>'
     '</Sequence>\n<SetBlackboard output_key="b" value="{a}"/></Fallback>', 5,
     "value reads blackboard key `a` that is not set"),
])
def test_a_tree_that_cannot_go_on_names_its_file_and_line(body: str, line: int, message: str):
    """What only running can tell (a branch that would have set a key was skipped, an id beyond the crowd)
    stops the run, stepped or not, with the tree's file and the node's line."""
    for stepping in (True, False):
        sim = make_sim([human()], [tree_xml(body, fmt=4 if "FollowAgent" in body else 3)], ROBOT, timeout=2.0)
        with pytest.raises(BTRuntimeError) as err:
            sim.step() if stepping else sim.run()
        assert message in err.value.message, err.value.message
        assert err.value.line == line and err.value.file == "tree of agent 0"


@pytest.mark.parametrize(("body", "message"), [
    ('<MakeGesture agent_id="{id}"\n message="{nothing}"/>', ":4: MakeGesture message='{nothing}': blackboard key "
     "'nothing' is never set"),
    ('<Sequence><SetBlackboard output_key="d" value="far"/>\n<IsRobotNearby agent_id="{id}" distance="{d}"/>'
     '</Sequence>', ":5: IsRobotNearby distance='{d}': {d} holds 'far', and distance must be a number"),
    ('<Sequence><SetBlackboard output_key="who" value="7"/>\n<MakeGesture agent_id="{who}" message="1"/>'
     '</Sequence>', ":5: MakeGesture agent_id='{who}': agent_id must be {id}"),
])
def test_what_the_tree_language_refuses_is_refused_before_the_run_with_its_line(body: str, message: str):
    """The simulator reads trees with bt check's parser: a tree it refuses never starts running."""
    from socnavgen.errors import ValidationFailed

    with pytest.raises(ValidationFailed, match=re.escape(message)):
        make_sim([human()], [tree_xml(body)], ROBOT)


def test_regular_walkers_and_the_walking_idiom_agree():
    """The RegularNavTree SubTree idiom walks exactly like RegularNav called directly (same goals, same steps)."""
    direct = run_tree('<Fallback><Sequence><Inverter><IsGoalReached agent_id="{id}"/></Inverter>'
                      '<RegularNav agent_id="{id}" time_step="{dt}"/></Sequence><UpdateGoal agent_id="{id}"/>'
                      '</Fallback>', timeout=8.0)
    idiom = run_tree(REGULAR, timeout=8.0)
    assert np.array_equal(direct.humans, idiom.humans)
