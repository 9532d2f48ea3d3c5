"""A stop for a greeting the text states needs a criterion that sees it (issue 25, proposal/stop_checks.py): home_03's
robot only slowed through its greeting stop and the host turned back before the guests came, and its criteria (the
host meets the robot and stops near it, the guests follow it) passed."""

from __future__ import annotations

import pytest
from gen_helpers import spec_for

from socnavgen.proposal.stop_checks import stop_mistakes
from socnavgen.run.spec import ScenarioSpec

GREETING = ("As the robot enters the living room, the host (Human 3) comes out of the kitchen, stops a couple of metres "
            "from the robot to welcome the guests, and the robot stands still for a few seconds so that the guests can "
            "greet the host.")
GUEST = {"human1": "A guest. Follows the robot, stops while it pauses for the greeting with the host, and follows on."}


def _spec(*criteria: dict) -> ScenarioSpec:
    spec = spec_for(3)
    spec["criteria"] += list(criteria)
    return ScenarioSpec.model_validate(spec)


def test_a_greeting_stop_with_no_criterion_that_sees_it_is_refused() -> None:
    mistakes = stop_mistakes(GREETING, GUEST, _spec())
    assert len(mistakes) == 3, mistakes
    robot, host, guest = (next(m for m in mistakes if key in m) for key in
                          ("the robot stop for a greeting", "human3 stop to greet", "human1 stop to greet"))
    assert '"kind": "robot_stops"' in robot and "('pauses'" in robot  # the guest's behavior says it first
    assert '"kind": "stop_together"' in host and '"humans": ["human3"' in host
    assert "('stops'" in guest


def test_criteria_that_see_the_stops_are_accepted() -> None:
    spec = _spec({"id": "c9", "kind": "robot_stops", "encounter": "e1", "seconds": 3},
                 {"id": "c10", "kind": "stop_together", "humans": ["human1", "human3"], "encounter": "e1"})
    assert stop_mistakes(GREETING, GUEST, spec) == []
    stl = _spec({"id": "c9", "kind": "stl", "formula": "eventually (always[0:2] (robot_still > 0.5))"},
                {"id": "c10", "kind": "stl", "formula": "eventually (always[0:1] ((speed_human1 < 0.1) and "
                 "(speed_human3 < 0.1) and (way_human1_human3 < 3)))"})
    assert [m for m in stop_mistakes(GREETING, GUEST, stl) if "human2" not in m] == []


def test_a_stop_together_that_leaves_the_person_out_does_not_see_them() -> None:
    spec = _spec({"id": "c9", "kind": "robot_stops", "encounter": "e1"},
                 {"id": "c10", "kind": "stop_together", "humans": ["human2", "human3"], "encounter": "e1"})
    mistakes = stop_mistakes(GREETING, GUEST, spec)
    assert len(mistakes) == 1 and "human1 stop to greet" in mistakes[0]


@pytest.mark.parametrize("text", [
    "The robot stops and waits until Human 1 has passed, then drives on.",  # no greeting: a wait (order checks)
    "Human 1 stops talking for a moment and looks at the robot.",  # talk is no greeting stop
    "Human 2 stops and greets the robot with a wave.",  # greeting the robot: stops_near_robot's
    "The host welcomes the guests at the door.",  # no stop
])
def test_stops_that_are_no_greeting_between_people_are_left_alone(text: str) -> None:
    assert stop_mistakes(text, {}, _spec()) == []
