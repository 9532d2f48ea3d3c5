"""The one traversability rule: a person-sized disc or a short detour beside the line is fine, a
squeeze is a warning, a line through a rack or a wall is an error."""

from __future__ import annotations

import numpy as np
from scipy import ndimage

from socnavgen.location.traverse import edge_verdict

MPP = 0.05


def clearance(free: np.ndarray) -> np.ndarray:
    return ndimage.distance_transform_edt(free)


def hall() -> np.ndarray:
    free = np.zeros((200, 300), bool)
    free[20:180, 20:280] = True
    return free


def test_open_floor_is_ok_and_a_chair_is_stepped_around() -> None:
    free = hall()
    assert edge_verdict(clearance(free), (40, 100), (260, 100), MPP).level == "ok"
    free[95:105, 145:155] = False  # a 0.5 m chair on the line
    assert edge_verdict(clearance(free), (40, 100), (260, 100), MPP).level == "ok"


def test_clipping_a_wall_corner_by_one_pixel_is_ok() -> None:
    free = hall()
    free[20:100, 150:160] = False  # a wall stub from the north whose corner the line grazes
    c = clearance(free)
    assert edge_verdict(c, (40, 100), (260, 100), MPP).level == "ok"
    assert edge_verdict(c, (40, 90), (260, 90), MPP).level == "error"  # through the stub


def test_through_a_long_rack_is_an_error() -> None:
    free = hall()
    free[40:170, 148:152] = False  # a rack 6.5 m long across the line: no way round close beside
    assert edge_verdict(clearance(free), (40, 100), (260, 100), MPP).level == "error"


def test_a_gap_narrower_than_a_person_is_a_warning() -> None:
    free = hall()
    free[20:180, 148:152] = False
    free[96:105, 148:152] = True  # a 0.45 m slit: the line passes, a 0.8 m person does not
    assert edge_verdict(clearance(free), (40, 100), (260, 100), MPP).level == "warning"
