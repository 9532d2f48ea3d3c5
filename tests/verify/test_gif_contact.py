"""The GIF shows contact by the one definition (sim.contact) instead of leaving it to the eye (round 14's hospital_07:
two people 0.19 m apart, 5 px at that scale, were seen as overlapping): every disc has a white rim, so bodies apart
show a gap, and an agent in contact at any step since the previous frame gets a magenta outline."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from PIL import Image

from socnavgen.bodies import CONTACT_MARGIN, PERSON_TOUCH_DISTANCE
from socnavgen.location import load_location
from socnavgen.sim.outputs.animate import CONTACT_COLOR, _Canvas, contact_marks, write_gif

from .verify_builders import build_trace

APART = PERSON_TOUCH_DISTANCE + 0.19  # centre to centre: hospital_07's nurse and patient at their closest
TOUCH = PERSON_TOUCH_DISTANCE + CONTACT_MARGIN / 2


def _two_people(touch_at: int | None, steps: int = 21) -> object:
    t = np.arange(steps) * 0.5
    robot = np.stack([np.full_like(t, 1.025), np.full_like(t, 2.975)], axis=1)  # far from both
    gap = np.full(steps, APART)
    if touch_at is not None:
        gap[touch_at] = TOUCH
    h1 = np.stack([np.full_like(t, 6.025), np.full_like(t, 3.475)], axis=1)
    h2 = np.stack([6.025 + gap, np.full_like(t, 3.475)], axis=1)
    return build_trace(t, robot, np.stack([h1, h2], axis=1))


def test_a_touch_between_two_frames_is_marked_on_the_next_frame():
    marks = contact_marks(_two_people(touch_at=5), np.arange(0, 21, 4))  # frames at steps 0 4 8 12 16 20
    assert marks.shape == (6, 3)
    assert marks[2, 0] and marks[2, 1] and not marks[2, 2]  # the frame at step 8 covers steps 5..8; not the robot
    assert marks.sum() == 2


def test_people_apart_are_not_marked():
    assert not contact_marks(_two_people(touch_at=None), np.arange(21)).any()


def _frame(tmp_path: Path, tiny_location: Path, touch_at: int | None) -> tuple[np.ndarray, object]:
    trace = _two_people(touch_at)
    loc = load_location(tiny_location)
    gif = Image.open(write_gif(trace, loc, tmp_path / "a.gif"))
    gif.seek(5)
    return np.asarray(gif.convert("RGB")).astype(int), _Canvas(trace, loc, None, 6.4, 100)


def test_a_gap_between_two_people_shows_white_and_a_touch_shows_magenta(tmp_path: Path, tiny_location: Path):
    frame, canvas = _frame(tmp_path, tiny_location, touch_at=None)
    mid = canvas.pixel(6.025 + APART / 2, 3.475)
    assert (frame[round(mid[1]), round(mid[0])] >= 245).all()  # the rims meet: white between the outlines
    magenta = np.all(np.abs(frame - np.array(CONTACT_COLOR)) <= 40, axis=-1)
    assert magenta.sum() == 0
    frame, _ = _frame(tmp_path, tiny_location, touch_at=5)
    magenta = np.all(np.abs(frame - np.array(CONTACT_COLOR)) <= 40, axis=-1)
    assert magenta.sum() > 30
