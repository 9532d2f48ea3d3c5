"""STL monitoring of named signals with rtamt: formulas from spec.json are checked (length, one expression,
known signals, syntax) and each criterion kind's formula is non-vacuous and has the right robustness."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from socnavgen.run.spec import Criterion, Encounter, HumanPart, ScenarioSpec
from socnavgen.sim.world import empty_room
from socnavgen.verify.criteria import compile_criterion
from socnavgen.verify.models import VerifySettings
from socnavgen.verify.signals import Signals
from socnavgen.verify.stl import MAX_FORMULA_CHARS, FormulaError, formula_problems, formula_signals, monitor

from .verify_builders import build_trace


def _approach(stop_at: float, human_x: float = 6.0, human_from: float | None = None) -> Signals:
    """Robot drives +x at 1 m/s from x = 1 and stops at x = 1 + stop_at; human1 stands at x = human_x facing
    -x (or walks there from x = human_from during the first 3 s). dt 0.5, 0..10 s, open 20 m room; place e1
    at x = 5."""
    t = np.arange(21) * 0.5
    rx = np.minimum(t, stop_at) + 1.0
    hx = np.full_like(t, human_x) if human_from is None else \
        np.where(t < 3.0, human_from + (human_x - human_from) * t / 3.0, human_x)
    trace = build_trace(t, np.stack([rx, np.full_like(t, 10.0)], 1), np.stack([hx, np.full_like(t, 10.0)], 1)[:, None],
                        goal=(15.0, 10.0))
    trace.humans[:, 0, 2] = np.pi  # facing the robot
    trace.robot[:, 2] = 0.0
    return Signals(trace, world=empty_room(), places={"e1": (5.0, 10.0)})


def test_formula_signals_ignore_operators_and_numbers() -> None:
    assert formula_signals("always[0:1.5e1] ((dist_human1 <= 2) and not (los_human1 > 0.5))") == \
        ["dist_human1", "los_human1"]


@pytest.mark.parametrize(("formula", "message"), [
    ("", "empty"),
    ("x" * (MAX_FORMULA_CHARS + 1), "at most 1000"),
    ("eventually (dist_human1 <= 2); import os", "one expression"),
    ("a = eventually (dist_human1 <= 2)", "one expression"),
    ("eventually (dist_human7 <= 2)", "human7 is not in this run"),
    ("eventually (speed_robbot > 0.3)", "unknown signal 'speed_robbot'"),
    ("eventually (robot_says_hello > 0.5)", "no phrase 'hello'"),
    ("eventually (exec_human1_dance > 0.5)", "no library action 'dance'"),
    ("eventually (mid_human1_to_e9 < 1)", "unknown place 'e9'"),
    ("eventually (dist_human1 <= ", "STL syntax: column"),
    ("12 > 3", "names no signal"),
    ("(" * 400 + "dist_human1 < 1" + ")" * 400, "nests 400 levels deep"),
    ("eventually " * 60 + "(dist_human1 < 1)", "nests 60 levels deep"),
])
def test_bad_formulas_are_refused_clearly(formula: str, message: str) -> None:
    (problem,) = formula_problems(formula, ["human1"], ["e1"])
    assert message in problem


def test_good_formula_passes_the_static_check() -> None:
    ok = "always ((dist_human1 <= 1.5 and ahead_human1 > 0.5) implies eventually[0:2] speed_human1 < 0.1)"
    assert formula_problems(ok, ["human1"], ["e1"]) == []


def test_robustness_is_in_the_signal_unit() -> None:
    s = _approach(stop_at=2.0, human_x=6.0)  # robot stops at x = 3, 3 m from the human
    assert monitor("eventually (dist_human1 <= 2)", s).robustness == pytest.approx(-1.0)
    assert monitor("eventually (dist_human1 <= 4)", s).robustness == pytest.approx(1.0)
    assert monitor("always (gap_human1 >= 0)", s).robustness == pytest.approx(2.25)  # 3 - 0.75
    assert monitor("eventually (robot_to_e1 <= 0.5)", s).robustness == pytest.approx(-1.5)
    with pytest.raises(FormulaError):
        monitor("eventually (nope > 1)", s)


def _criterion(s: Signals, **kw) -> float:  # noqa: ANN003
    c = Criterion(id="c1", **kw)
    spec = ScenarioSpec(encounters=[Encounter(id="e1", place="CORNER", node="n", humans=[
        HumanPart(human="human1", reaction="stop")])], criteria=[c])
    return monitor(compile_criterion(c, spec, VerifySettings(), 0.5).formula, s).robustness


def test_criteria_are_not_vacuous() -> None:
    far = _approach(stop_at=1.0)  # the robot stops 4 m from the standing human: it never comes near
    near = _approach(stop_at=4.0)  # the robot stops 1.0 m from the human
    # 'stops while the robot is near' needs the robot to come near (the cause), then the human still: walking
    # then stopping, or waiting still as the robot comes; never a robot that starts near a still human
    assert _criterion(far, kind="stops_near_robot", human="human1") < 0
    assert _criterion(near, kind="stops_near_robot", human="human1") > 0
    walked = _approach(stop_at=4.0, human_from=8.0)  # walks 8 -> 6 while the robot comes, then stands
    assert _criterion(walked, kind="stops_near_robot", human="human1") > 0
    assert _criterion(_approach(stop_at=0.0, human_x=2.2), kind="stops_near_robot", human="human1") < 0
    # 'gives way' needs the robot to come within the distance at all
    assert _criterion(far, kind="gives_way", human="human1") < 0
    # 'hidden until' needs them to come close (never seen, never met is no blind-corner encounter)
    assert _criterion(far, kind="hidden_until", human="human1", distance=3.0) < 0
    # 'keeps away' needs the human to have noticed the robot
    away = _approach(stop_at=0.0, human_x=7.0)  # 6 m apart: never within the 5 m notice range
    assert _criterion(away, kind="keeps_away", human="human1", distance=1.5) < 0
    assert _criterion(far, kind="keeps_away", human="human1", distance=1.5) > 0
    # meets: near the encounter place e1 (x = 5) and within 2 m
    assert _criterion(walked, kind="meets", human="human1", encounter="e1") > 0
    assert _criterion(far, kind="meets", human="human1", encounter="e1") < 0
    # ... after an approach: the same two standing 1.9 m apart from the start never met
    assert _criterion(_approach(stop_at=0.0, human_x=2.9), kind="meets", human="human1") < 0


def test_stops_near_robot_needs_them_in_front_of_one_another() -> None:
    # the robot comes up to 1 m of a still person: in front of each other when the person faces it, or stands in its
    # way with its back to it (a picker at a shelf the robot drove up behind: warehouse_02); never when the person
    # stands beside the robot's way, or behind it, facing away
    facing = _approach(stop_at=4.0)
    assert _criterion(facing, kind="stops_near_robot", human="human1") > 0
    back_in_way = _approach(stop_at=4.0)
    back_in_way.trace.humans[:, 0, 2] = 0.0  # faces +x, away from the robot coming up behind it
    assert _criterion(back_in_way, kind="stops_near_robot", human="human1") > 0
    beside = _approach(stop_at=4.0)
    beside.trace.humans[:, 0, 1] = 10.9  # 0.9 m off the robot's line, out of its swept corridor (0.85 m) ...
    beside.trace.humans[:, 0, 2] = 0.0  # ... and facing away: the robot is not in front of them
    assert _criterion(beside, kind="stops_near_robot", human="human1") < 0
    shelf = _approach(stop_at=6.0, human_x=5.5)  # the robot drives past a person 1 m off its line ...
    shelf.trace.humans[:, 0, 1] = 11.0
    shelf.trace.humans[:, 0, 2] = np.pi / 2  # ... who faces a shelf the other way, never towards it
    assert _criterion(shelf, kind="stops_near_robot", human="human1") < 0


def test_gives_way_robustness_follows_the_human() -> None:
    # the robot stops 1 m from the human, who stays in its way: fails; stepping 1.5 m aside at t = 4 s, within
    # 2 s of the robot coming within 2 m (t = 3 s): passes
    staying = _approach(stop_at=4.0)
    assert _criterion(staying, kind="gives_way", human="human1", seconds=2) < 0
    stepping = _approach(stop_at=4.0)
    stepping.trace.humans[8:, 0, 1] = 11.5  # steps 1.5 m aside at t = 4 s
    stepping._cache.clear()
    assert _criterion(stepping, kind="gives_way", human="human1", seconds=2) > 0


def _long_trace(steps: int = 2400) -> Signals:
    t = np.arange(steps) * 0.05
    trace = build_trace(t, np.stack([0.01 * t, np.zeros_like(t)], 1),
                        np.stack([6.0 - 0.04 * t, 0.5 * np.sin(t)], 1)[:, None], dt=0.05)
    return Signals(trace, world=empty_room())


def test_huge_bounds_cost_what_the_trace_costs() -> None:
    """Bounds are clipped to the trace: eventually[0:100000000] tried to allocate 14.9 GiB, [0:10000000] ran 255 s
    at 3.3 GB (issue 30); now both are the unbounded operator, in the memory of a few series."""
    import tracemalloc

    s = _long_trace()
    tracemalloc.start()
    try:
        for bound in ("100000000", "10000000"):
            assert monitor(f"eventually[0:{bound}] (dist_human1 < 2)", s).series.tolist() == \
                monitor("eventually (dist_human1 < 2)", s).series.tolist()
        assert monitor("always[50000000:90000000] (dist_human1 < 2)", s).series.tolist() == [np.inf] * 2400
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 16e6, peak


def test_a_long_bounded_until_is_exact_and_linear() -> None:
    """until[0:60] on a 2400-step trace (rtamt: cubic in the bound, over a minute): the same values as the
    definition, max over d in [a, b] of min(right[i+d], min(left[i..i+d-1])), computed here by brute force."""
    s = _long_trace()
    left, right = s.get("dist_human1") - 1.0, s.get("speed_human1") - 0.3
    for lo, hi in ((0, 60), (2, 7.5)):
        got = monitor(f"(dist_human1 > 1) until[{lo:g}:{hi:g}] (speed_human1 > 0.3)", s).series
        a, b = int(round(lo / 0.05)), int(round(hi / 0.05))
        want = np.full(2400, -np.inf)
        for i in range(0, 2400, 37):
            best = -np.inf
            for d in range(a, b + 1):
                if i + d >= 2400:
                    break
                best = max(best, min(right[i + d], left[i:i + d].min(initial=np.inf)))
            want[i] = best
        assert np.array_equal(got[::37], want[::37])


def test_stage_one_refuses_what_cannot_be_monitored() -> None:
    """formula_problems (stage 1's spec check calls it): intervals no episode can hold or
    the simulator's step cannot sample, reversed intervals, arithmetic that fails; a fine formula passes."""
    huge = formula_problems("eventually[0:10000000] (dist_human1 < 2)", ["human1"], [])
    assert len(huge) == 1 and "longer than any episode" in huge[0]
    assert "multiple of the simulation step" in formula_problems("eventually[0:0.03] (dist_human1 < 2)",
                                                                 ["human1"], [])[0]
    assert "a <= b" in formula_problems("eventually[1:0.5] (dist_human1 < 2)", ["human1"], [])[0]
    assert formula_problems("(dist_human1 > 1) until[0:60] (speed_human1 > 0.3)", ["human1"], []) == []
    assert formula_problems("eventually[0:0.5] (dist_human1 < 2)", ["human1"], []) == []


def test_the_stage_one_spec_check_refuses_an_unbounded_formula() -> None:
    """Issue 30: stage 1 accepted eventually[0:10000000]; its spec check asks formula_problems, which refuses it."""
    from socnavgen.location import load_location
    from socnavgen.proposal.spec_checks import spec_mistakes

    location = load_location(Path(__file__).resolve().parents[2] / "examples" / "locations" / "warehouse")
    corner = next(n.id for n in location.scene_graph.nodes if n.type == "BLIND CORNER")
    spec = ScenarioSpec(encounters=[Encounter(id="e1", place="BLIND CORNER", node=corner, humans=[
        HumanPart(human="human1", reaction="stop")])], criteria=[
        Criterion(id="c1", kind="meets", human="human1", encounter="e1"),
        Criterion(id="c2", kind="stl", formula="eventually[0:100000000] (dist_human1 < 2)")])
    mistakes = spec_mistakes(spec, ["human1"], list(location.schema.node_types), location=location)
    assert [m for m in mistakes if "criterion c2" in m and "longer than any episode" in m], mistakes
    fine = spec.model_copy(update={"criteria": [spec.criteria[0], Criterion(
        id="c2", kind="stl", formula="eventually[0:30] (dist_human1 < 2)")]})
    assert not [m for m in spec_mistakes(fine, ["human1"], list(location.schema.node_types), location=location)
                if "criterion c2" in m]


def test_a_formula_too_large_for_its_trace_is_refused() -> None:
    from socnavgen.verify import stl

    s = _long_trace()
    big = " and ".join(["(dist_human1 < 2)"] * 40)
    assert monitor(big, s).robustness is not None
    old = stl.MAX_STL_CELLS
    try:
        stl.MAX_STL_CELLS = 100_000
        with pytest.raises(FormulaError, match="too many to monitor"):
            monitor(big, s)
    finally:
        stl.MAX_STL_CELLS = old
