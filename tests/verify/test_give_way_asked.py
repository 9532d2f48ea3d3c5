"""`gives_way`'s clock starts at the cause the spec names - the phrase that asks the person to move - not at the
first moment they stood in the robot's way (hospital_13 of round 15: a slow family walked ahead of the trailing robot,
in its way from 2 s; the robot said EXCUSE ME at 37 s and the verdict counted "56 s later" from 2 s). Still strict:
a person who never hears the phrase, or who steps aside later than S s after it, or who comes back into the way,
fails."""

from __future__ import annotations

from tests.verify.test_give_way_reach import _judge, _spec, _trace

# the robot stops 1.6 m short of the person at x = 8 (by 13 s); in its way within 2.5 m from ~9.5 s
SAID = 22.0


def test_a_person_in_the_way_long_before_the_phrase_who_steps_aside_when_asked_gave_way() -> None:
    passed, text, _ = _judge(_trace([(8.0, 0.0, SAID + 1.0, 1.5)], say_at=SAID), _spec(cue_distance=2.5))
    assert passed, text
    assert "first at t=22.0 s" in text, text  # the clock's start: the phrase, not ~9.5 s


def test_a_step_aside_more_than_s_after_the_phrase_still_fails() -> None:
    passed, text, _ = _judge(_trace([(8.0, 0.0, SAID + 6.0, 1.5)], say_at=SAID), _spec(cue_distance=2.5))
    assert not passed, text
    assert "but in its way at t=22.0 s" in text and "more than 5 s" in text, text


def test_never_asked_fails_and_says_so() -> None:
    """The phrase is never said (after the run): the person stepping aside by themselves at 23 s did not give way
    to anyone asking; the blame is not "never in the way" (they were, before being asked)."""
    passed, text, blame = _judge(_trace([(8.0, 0.0, SAID + 1.0, 1.5)], say_at=99.0), _spec(cue_distance=2.5))
    assert not passed, text
    assert "in its way only before human1 was asked to move" in text, text
    assert "nothing to give way to" not in blame, blame


def test_stepping_back_into_the_way_after_the_phrase_fails() -> None:
    # aside at 23 s (1.5 m), then back: another person in the way from 25 s is not needed; the same one returns
    trace = _trace([(8.0, 0.0, SAID + 1.0, 1.5)], say_at=SAID)
    back = trace.t >= SAID + 4.0
    trace.humans[back, 0, 1] = 0.0  # back on the robot's route for the rest of the run
    passed, text, _ = _judge(trace, _spec(cue_distance=2.5))
    assert not passed, text
