"""An authored order claim (`a until b`: "the doctor goes through the door first") is witnessed by something that
happened during the run, never by where people start (issue 25, hospital_04: the doctor's spawn spot on the group's
circle was within 0.8 m of the door, so `(others far from the door) until (doctor near it)` held at t = 0 and the
"goes first" criterion passed before anyone moved)."""

from __future__ import annotations

import numpy as np

from socnavgen.run.spec import Criterion, ScenarioSpec
from socnavgen.verify.judge import judge_criterion
from socnavgen.verify.models import VerifySettings
from socnavgen.verify.signals import Signals

from .verify_builders import build_trace

T = np.arange(0, 10.0 + 1e-9, 0.5)
ORDER = "(dist_human2 > 1.0) until (dist_human1 < 1.0)"  # human1 comes within 1 m of the robot before human2


def _signals(human1_x: list[float], human2_x: list[float]) -> Signals:
    """The robot stands at the origin; human1 and human2 walk along y = 0 and y = 0.1 through (0, 5, 10 s) -> x."""
    keys = [0.0, 5.0, 10.0]
    h1 = np.stack([np.interp(T, keys, human1_x), np.zeros_like(T)], 1)
    h2 = np.stack([np.interp(T, keys, human2_x), np.full_like(T, 0.1)], 1)
    return Signals(build_trace(T, np.zeros((len(T), 2)), np.stack([h1, h2], 1)))


def _judge(formula: str, s: Signals, source: str = "spec"):  # noqa: ANN202 - a Finding
    c = Criterion(id="c1", kind="stl", formula=formula, text="human1 comes to the robot first")
    return judge_criterion(c, source, ScenarioSpec(criteria=[c]), None, s, VerifySettings(), 0.2)  # type: ignore[arg-type]


def test_an_order_already_true_where_people_start_fails():
    # human1 starts 0.5 m from the robot and walks away; human2 comes in later: "human1 first" held at t = 0
    found = _judge(ORDER, _signals([0.5, 6.0, 6.0], [8.0, 8.0, 0.5]))
    assert not found.passed, found.evidence
    assert "t=0" in found.evidence and "dist_human1 < 1.0" in found.evidence, found.evidence
    assert found.blame == "spec", found
    # in a conjunction at the top it is the same claim
    found = _judge(f"({ORDER}) and (always (dist_human1 > 0.1))", _signals([0.5, 6.0, 6.0], [8.0, 8.0, 0.5]))
    assert not found.passed, found.evidence


def test_an_order_that_happens_during_the_run_passes():
    # human1 walks up to the robot by 5 s while human2 is still 8 m off: the order is witnessed at ~4.6 s
    found = _judge(ORDER, _signals([6.0, 0.5, 0.5], [8.0, 8.0, 2.0]))
    assert found.passed, found.evidence
    assert found.time is not None and found.time > 4.0, found


def test_an_implied_order_of_encounters_may_start_met():
    # the implied "e1 before e2" of a guide who starts beside the person it guides (hospital_09): the meeting at
    # the start is the text's own first encounter, not a claim about who moves first
    found = _judge(ORDER, _signals([0.5, 6.0, 6.0], [8.0, 8.0, 0.5]), source="implied")
    assert found.passed, found.evidence


def test_a_kind_naming_a_whole_team_is_monitored_however_long_its_formula():
    """hospital_04 round 21: a `meets` naming the four staff compiled to 1001 characters, over the limit for an
    authored formula, and could not be checked at all. A kind's own formula grows with the people it names; an
    authored one of the same length is still refused."""
    from socnavgen.verify.stl import MAX_FORMULA_CHARS

    n = 20
    walk = [np.stack([np.interp(T, [0.0, 10.0], [6.0 + k, 0.6 + 0.1 * k]), np.full_like(T, 0.5 * k)], 1)
            for k in range(n)]
    s = Signals(build_trace(T, np.zeros((len(T), 2)), np.stack(walk, 1)))
    team = [f"human{k + 1}" for k in range(n)]
    c = Criterion(id="c1", kind="meets", humans=team, text="the team meets the robot")
    found = judge_criterion(c, "spec", ScenarioSpec(criteria=[c]), None, s, VerifySettings(), 0.2)  # type: ignore[arg-type]
    assert len(found.formula or "") > MAX_FORMULA_CHARS, found.formula
    assert found.passed, found.evidence
    far = Signals(build_trace(T, np.zeros((len(T), 2)), np.stack([w + 20.0 for w in walk], 1)))
    found = judge_criterion(c, "spec", ScenarioSpec(criteria=[c]), None, far, VerifySettings(), 0.2)  # type: ignore[arg-type]
    assert not found.passed and "cannot be monitored" not in found.evidence, found.evidence
    authored = Criterion(id="c2", kind="stl", formula=" or ".join(f"(dist_{h} < 1.0)" for h in team * 3),
                         text="the same claim written out")
    refused = judge_criterion(authored, "spec", ScenarioSpec(criteria=[authored]), None, s, VerifySettings(), 0.2)  # type: ignore[arg-type]
    assert not refused.passed and "characters (at most 1000)" in refused.evidence, refused.evidence
