"""The compiled episode (sim.compiled) against the Python reference (Simulation.step): the same trace, step for
step, on every scenario card of every bundled location with every built-in robot, on trees that use every
control node and leaf, on scripts and gesture rules; and the reference still runs (and raises its errors)
where the compiled run cannot."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from socnavgen.bt.library import regular_walker_xml
from socnavgen.cards.generate import fit_all, write_card_run
from socnavgen.location import load_location
from socnavgen.run.models import RobotGestureRule
from socnavgen.run.spec import CueTrigger, RobotCue, RobotScript
from socnavgen.sim import kernels
from socnavgen.sim.engine import SimConfig
from socnavgen.sim.gestures import RobotScriptRunner, ScriptedGestures
from socnavgen.sim.interaction import InteractionThrottle, ThrottleConfig
from socnavgen.sim.robot import BUILTIN, load_policy
from socnavgen.sim.scenario import load_simulation
from socnavgen.sim.world import empty_room
from tests.sim.simhelpers import REGULAR, Drive, human, make_sim, tree_xml

pytestmark = pytest.mark.skipif(not kernels.AVAILABLE, reason="numba not installed: there is no compiled run")
EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "locations"


def assert_same_run(compiled, reference) -> None:  # noqa: ANN001
    """Two traces of one simulation: the same steps, the same discrete events, the same motion to 1e-9 m."""
    assert compiled.meta["engine"] == "compiled", compiled.meta.get("compiled_skipped")
    assert reference.meta["engine"] == "python"
    assert (compiled.steps, compiled.end_reason) == (reference.steps, reference.end_reason)
    for name in ("action", "succeeded", "human_gesture", "robot_gesture", "behavior_state"):
        assert np.array_equal(getattr(compiled, name), getattr(reference, name)), name
    assert np.abs(compiled.robot - reference.robot).max(initial=0.0) < 1e-9
    assert np.abs(compiled.humans - reference.humans).max(initial=0.0) < 1e-9
    for key in ("script_cues_fired", "held_seconds", "throttle_skipped"):
        assert compiled.meta.get(key) == reference.meta.get(key), key


def both(build) -> tuple:  # noqa: ANN001
    """Run the simulation `build()` makes twice: compiled and step by step."""
    first = build()
    second = build()
    second.compiled = False
    return first.run(), second.run()


@pytest.mark.slow
@pytest.mark.parametrize("location_name", ["warehouse", "hospital", "home"])
def test_every_card_and_robot_gives_the_reference_trace(location_name: str, tmp_path: Path) -> None:
    location = load_location(EXAMPLES / location_name)
    fits = [f for f in fit_all(location) if f.fits]
    assert len(fits) >= 15
    compared = 0
    for k, fit in enumerate(fits):
        run = write_card_run(fit.card.name, EXAMPLES / location_name, tmp_path / fit.card.name)
        for robot in BUILTIN:
            seed = k % 3

            def build(robot=robot, seed=seed, run=run):  # noqa: ANN001, ANN202
                return load_simulation(run.root, load_policy(robot), SimConfig(timeout=60.0, seed=seed),
                                       ThrottleConfig(), location)

            assert_same_run(*both(build))
            compared += 1
    assert compared == 4 * len(fits)


CONTROL_TREES = {
    # halted by the robot coming near, the inner sequence starts again from UpdateGoal (a new goal each time)
    "reactive halts a running sequence": tree_xml(
        '<ReactiveFallback><ReactiveSequence><Inverter><IsRobotNearby agent_id="{id}" distance="3.0"/></Inverter>'
        '<Sequence><ForceSuccess><IsGoalReached agent_id="{id}"/></ForceSuccess><UpdateGoal agent_id="{id}"/>'
        '<KeepRunningUntilFailure><RegularNav agent_id="{id}" time_step="{dt}"/></KeepRunningUntilFailure>'
        '</Sequence></ReactiveSequence><LookAtRobot agent_id="{id}"/></ReactiveFallback>'),
    "fallback of timers and looks": tree_xml(
        '<ReactiveFallback><Sequence><TimeExpiredCondition seconds="2.0" ts="{dt}" only_once="true"/>'
        '<LookAtRobot agent_id="{id}"/></Sequence>'
        '<Fallback><ForceFailure><MakeGesture agent_id="{id}" message="2"/></ForceFailure>'
        '<RetryUntilSuccessful num_attempts="3"><IsRobotVisible agent_id="{id}" distance="4.0"/>'
        '</RetryUntilSuccessful>' + REGULAR + '</Fallback></ReactiveFallback>'),
    "repeat and blackboard copies": tree_xml(
        '<Sequence><SetBlackboard output_key="who" value="{id}"/><SetBlackboard output_key="again" value="{who}"/>'
        '<Repeat num_cycles="2"><UpdateGoal agent_id="{again}"/></Repeat>'
        '<Fallback><IsRobotBlocking agent_id="{who}" distance="2.5"/><RegularNav agent_id="{who}" time_step="{dt}"/>'
        '</Fallback></Sequence>'),
    "give way, follow, block": tree_xml(
        '<Fallback><Sequence><IsRobotNearby agent_id="{id}" distance="2.0"/><GiveWaytoRobot agent_id="{id}" '
        'time_step="{dt}"/></Sequence><Sequence><RobotSaid agent_id="{id}" message="2"/>'
        '<FollowRobot agent_id="{id}" time_step="{dt}"/></Sequence>'
        '<Sequence><RobotMoved agent_id="{id}"/><IsRobotNearby agent_id="{id}" distance="5.0"/>'
        '<BlockRobot agent_id="{id}" time_step="{dt}"/></Sequence>' + REGULAR + '</Fallback>'),
    "run away and follow a human": tree_xml(
        '<Fallback><Sequence><HumanSays agent_id="{id}" target_id="0" message="3"/>'
        '<FollowHuman agent_id="{id}" target_id="0" time_step="{dt}"/></Sequence>'
        '<Sequence><RobotSays agent_id="{id}" message="4"/><RunAwayFromRobot agent_id="{id}" time_step="{dt}"/>'
        '</Sequence>' + REGULAR + '</Fallback>'),
    "hunav 2.x nodes": tree_xml(
        '<Fallback><Sequence><IsRobotClose agent_id="{id}" threshold="2.5"/>'
        '<AvoidRobot agent_id="{id}" time_step="{dt}" safe_distance="2.0" runaway_vel="0.8" duration="3.0"/>'
        '</Sequence><Sequence><IsRobotClose agent_id="{id}" threshold="5.0"/><SaySomething agent_id="{id}" '
        'message="WAIT"/><CuriousNav agent_id="{id}" time_step="{dt}" beh_duration="1" only_once="false" '
        'agent_vel="1.0" stop_distance="1.5"/></Sequence><Sequence><IsRobotClose agent_id="{id}" threshold="8.0"/>'
        '<ThreateningNav agent_id="{id}" time_step="{dt}" beh_duration="1" only_once="false" goal_dist="1.2"/>'
        '</Sequence><FollowAgent agent_id="{id}" target_agent_id="1" time_step="{dt}" closest_dist="1.0" '
        'max_vel="1.2" duration="0"/></Fallback>', fmt=4),
}


@pytest.mark.parametrize("name", sorted(CONTROL_TREES))
@pytest.mark.parametrize("robot", sorted(BUILTIN))
def test_control_nodes_and_leaves_give_the_reference_trace(name: str, robot: str) -> None:
    """Three people with the same tree meet a built-in robot crossing a room with a wall in it."""
    world = empty_room(14.0, 8.0, walls=[(6.0, 0.0, 6.4, 2.5)])
    people = [human("human1", start=(11.0, 4.2), goals=[(2.0, 4.0), (2.0, 6.5), (12.0, 6.5), (12.0, 2.0)] * 3),
              human("human2", start=(9.0, 3.0), goals=[(1.5, 2.0)]),
              human("human3", start=(4.0, 6.0), goals=[(12.0, 6.0), (12.0, 2.0)], cyclic=True)]
    gestures = ScriptedGestures([RobotGestureRule(gesture=4, when="blocked", distance=2.5, duration=1.0),
                                 RobotGestureRule(gesture=2, when="near_human", distance=3.0, duration=2.0)], {})

    def build():  # noqa: ANN202
        return make_sim(people, [CONTROL_TREES[name]] * 3, [(1.0, 4.0), (7.0, 4.5), (13.0, 4.0)],
                        policy=load_policy(robot), world=world, gestures=gestures, timeout=40.0)

    assert_same_run(*both(build))


@pytest.mark.parametrize("rule", ["eta", "socrates"])
def test_script_cues_and_pacing_give_the_reference_trace(rule: str) -> None:
    """The default robot's script (say, wait, wait until clear, change speed) and the interaction throttle."""
    script = RobotScript(speed=0.5, cues=[
        RobotCue(trigger=CueTrigger(when="start"), say="EXCUSE ME", hold=1.0),
        RobotCue(trigger=CueTrigger(when="blocked", distance=2.5), say="WAIT", wait_until_clear=True),
        RobotCue(trigger=CueTrigger(when="human_within", human="human2", distance=3.0), wait=1.5, speed=0.4),
        RobotCue(trigger=CueTrigger(when="after", seconds=12.0), speed=0.7),
        RobotCue(trigger=CueTrigger(when="at_encounter", encounter="e1", distance=2.0), say="PROCEED", once=False),
        RobotCue(trigger=CueTrigger(when="human_says", phrase="WAIT"), say="ACKNOWLEDGED")])
    people = [human("human1", start=(16.0, 5.0), goals=[(10.0, 5.0), (2.0, 5.0)]),
              human("human2", start=(10.0, 8.0), goals=[(10.0, 2.0)])]
    stubborn = tree_xml('<Fallback><Sequence><IsRobotNearby agent_id="{id}" distance="2.0"/>'
                        '<MakeGesture agent_id="{id}" message="1"/><LookAtRobot agent_id="{id}"/></Sequence>'
                        + REGULAR + '</Fallback>')

    def build():  # noqa: ANN202
        throttle = InteractionThrottle(ThrottleConfig(rule=rule, robot_speed=0.5), ["r0", "r1", "r2"],
                                       [2 + 5j, 10 + 5j, 18 + 5j], [(0, ["h0", "r1", "r0"], "r1", -1),
                                                                   (1, ["h1", "r1"], "r1", -1)])
        runner = RobotScriptRunner(script, {"e1": 10 + 5j})
        return make_sim(people, [stubborn, regular_walker_xml()], [(2.0, 5.0), (10.0, 5.0), (18.0, 5.0)],
                        policy=load_policy("scripted"), throttle=throttle, script=runner, timeout=60.0)

    compiled, reference = both(build)
    assert_same_run(compiled, reference)
    assert len(compiled.meta["script_cues_fired"]) >= 3  # the script really played


def test_a_policy_of_the_user_runs_step_by_step() -> None:
    sim = make_sim([human()], [tree_xml(REGULAR)], [(1.0, 5.0), (19.0, 5.0)], policy=Drive(0.5), timeout=5.0)
    trace = sim.run()
    assert trace.meta["engine"] == "python"
    assert "Drive has no compiled twin" in trace.meta["compiled_skipped"]


def test_a_tree_that_fails_while_running_raises_the_reference_error() -> None:
    """A port reading a key nobody writes: the compiled run gives up, the reference raises with the line."""
    bad = tree_xml('<Sequence><IsRobotNearby agent_id="{id}" distance="{far}"/>' + REGULAR + '</Sequence>')
    sim = make_sim([human()], [bad], [(1.0, 5.0), (19.0, 5.0)], policy=load_policy("waypoints"), timeout=5.0)
    with pytest.raises(Exception, match="far") as info:
        sim.run()
    assert "line" in str(info.value) or getattr(info.value, "line", None)
    assert sim.meta["compiled_skipped"] == "a behavior tree failed while running"


def test_a_blackboard_holding_text_runs_step_by_step() -> None:
    text = tree_xml('<Sequence><SetBlackboard output_key="d" value="2.5"/>'
                    '<Fallback><IsRobotNearby agent_id="{id}" distance="{d}"/>' + REGULAR + '</Fallback></Sequence>')
    sim = make_sim([human()], [text], [(1.0, 5.0), (19.0, 5.0)], policy=load_policy("waypoints"), timeout=5.0)
    trace = sim.run()
    assert trace.meta["engine"] == "python"
    assert "SetBlackboard of a literal" in trace.meta["compiled_skipped"]


ROOMS = {  # (width, height, walls, robot path): a room with walls, and a corridor too narrow to leave the path
    "room": (12.0, 8.0, [(5.0, 0.0, 5.4, 3.0), (8.0, 5.0, 8.4, 8.0)],
             [(1.0, 4.0), (4.0, 4.2), (6.5, 3.8), (7.0, 1.2), (11.0, 1.2)]),
    "corridor": (12.0, 2.2, [], [(0.8, 1.1), (6.0, 1.1), (11.2, 1.0)]),
}


@pytest.mark.parametrize("seed", range(3))
@pytest.mark.parametrize("room", sorted(ROOMS))
def test_the_side_step_is_the_reference_one(room: str, seed: int) -> None:
    """GiveWaytoRobot's plan (where to stand, from which arc position) for people scattered around a robot on
    a bent path in a room with walls, and in a corridor where no spot is far enough from the path (the
    fallback: the spot farthest from it, shorter walks preferred): the compiled plan equals
    nodes._plan_side_step every time."""
    from socnavgen.sim import nodes
    from socnavgen.sim.compiled.episode import _state
    from socnavgen.sim.compiled.geometry import world_tuple
    from socnavgen.sim.compiled.layout import HC_GW_TARGET, HF_GW_AT
    from socnavgen.sim.compiled.path import plan_side_step

    rng = np.random.default_rng(seed)
    width, height, walls, path = ROOMS[room]
    world = empty_room(width, height, walls=walls)
    people = [human(f"human{k + 1}", start=(float(rng.uniform(0.8, width - 0.8)),
                                            float(rng.uniform(0.7, height - 0.7)))) for k in range(12)]
    moved = 0
    for _ in range(25):  # robot positions along the first legs (a fresh simulation each: plans are per step)
        sim = make_sim(people, [tree_xml(REGULAR)] * 12, path, policy=load_policy("waypoints"), world=world)
        sim.robot_pos = complex(*path[0]) + complex(rng.uniform(0, 5), rng.uniform(-0.3, 0.3))
        spread = 0.5 if room == "room" else 0.15
        sim.crowd.pos[:] += rng.normal(0, spread, 12) + 1j * rng.normal(0, spread, 12)
        S, W = _state(sim), world_tuple(world)
        for i in range(12):
            want = nodes._plan_side_step(sim, i)
            plan_side_step(S, W, i)
            assert abs(S[7][HC_GW_TARGET][i] - want["target"]) < 1e-9
            assert S[6][HF_GW_AT][i] == pytest.approx(want["at"], abs=1e-9)
            moved += abs(want["target"] - sim.crowd.pos[i]) > 0.05
    assert moved >= 30  # many people really had to step aside


def test_sums_are_numpys_bit_for_bit() -> None:
    """The twins' sums (np.sum's pairwise summation spelled out) against np.sum itself, for every length up to
    two blocks and some longer, floats and complex numbers, magnitudes mixed so the order shows."""
    from socnavgen.sim.compiled.geometry import pairwise_sum, pairwise_sum_complex

    rng = np.random.default_rng(0)
    frames, left, left_im = np.zeros((64, 3), dtype=np.int64), np.zeros(64), np.zeros(64)
    sequential_differs = 0
    for n in [*range(0, 300), 1000, 4097]:
        a = rng.random(n) * rng.choice([1.0, 1e3, 1e-3], n)
        assert pairwise_sum(a, 0, n, frames, left) == np.sum(a), n
        assert pairwise_sum(np.concatenate([[7.0], a]), 1, n, frames, left) == np.sum(a), n  # from an offset
        sequential_differs += sum(a.tolist()) != np.sum(a)
        c = a + 1j * rng.random(n)[::-1]
        assert pairwise_sum_complex(c.real.copy(), c.imag.copy(), n, frames, left, left_im) == np.sum(c), n
    assert sequential_differs > 50  # a plain running sum would not pass: the order matters
