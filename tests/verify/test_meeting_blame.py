"""Rule N3 for a meeting that fails only because one party stayed off its place (issue 25 part 3, home_08 of the
new-request suite: the wife cooking at the stove 2.1 m from the kitchen node of a `within` 1.5 m encounter; the
robot drove up to her, they did approach each other, and the repair said "start them farther apart", which cannot
help). The meeting still FAILS (the rule is strict: each party came toward the place or waited within `within` of
it); what changes is the repair, which names who stayed off the place and how far."""

from __future__ import annotations

import numpy as np

from socnavgen.run.spec import Criterion, Encounter, HumanPart, ScenarioSpec
from socnavgen.verify.blame import blame_criterion
from socnavgen.verify.criteria import compile_criterion
from socnavgen.verify.models import VerifySettings
from socnavgen.verify.signals import Signals
from socnavgen.verify.stl import monitor

from .verify_builders import build_trace

T = np.arange(0, 20.0 + 1e-9, 0.5)
PLACE = (8.0, 3.0)


def _verdict(human_start: tuple[float, float], robot_from: float) -> tuple[bool, tuple]:
    """The robot drives +x along y = 3 from x = robot_from to x = 8 (the place) by t = 10 s and stays; human1
    stands at human_start the whole run."""
    spec = ScenarioSpec(encounters=[Encounter(id="e1", place="KITCHEN", node="k", within=1.5, humans=[
        HumanPart(human="human1", trigger="robot_near", reaction="look", distance=3.0)])])
    c = Criterion(id="c1", kind="meets", human="human1", encounter="e1", distance=2.5, text="the robot reaches her")
    cc = compile_criterion(c, spec, VerifySettings(), 0.5)
    robot = np.stack([np.interp(T, [0, 10, 20], [robot_from, 8.0, 8.0]), np.full_like(T, 3.0)], 1)
    human = np.tile([list(human_start)], (len(T), 1))[:, None]
    s = Signals(build_trace(T, robot, human, goal=PLACE), places={"e1": PLACE})
    return monitor(cc.formula, s).passed, blame_criterion(cc, s, spec, None, 10.0)


def test_a_person_waiting_beyond_within_fails_and_the_repair_says_where_she_stood() -> None:
    passed, (blame, _, reason) = _verdict((8.0, 5.1), 1.0)  # 2.1 m from the place (within 1.5)
    assert not passed
    assert blame == "paths" and "human1 stayed 2.1 m from k" in reason and "set the encounter there" in reason


def test_a_person_waiting_within_the_place_meets() -> None:
    passed, _ = _verdict((8.0, 4.2), 1.0)  # 1.2 m from the place: waiting at it
    assert passed


def test_no_approach_at_all_still_says_start_them_apart() -> None:
    # the robot starts 1.5 m from the place, the person 2.1 m from it: within 2.5 m of each other from the start
    passed, (blame, _, reason) = _verdict((8.0, 5.1), 7.9)
    assert not passed
    assert blame == "paths" and "without approaching each other" in reason, reason
