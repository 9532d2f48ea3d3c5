"""Pixel <-> world: one implementation, checked against hand-computed values and by round trips."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from socnavgen.location import Transform, load_location

# A non-square map whose origin is NOT centred: W=40 x H=20 px, 0.5 m/px, origin (-3, 7).
W, H, S, OX, OY = 40, 20, 0.5, -3.0, 7.0


def test_hand_computed_pixel_centres_on_non_square_uncentred_map() -> None:
    t = Transform.from_nav2(S, [OX, OY, 0.0], H)
    # top-left pixel: x = ox + 0.5 s, y = oy + (H - 0.5) s
    assert t.pixel_to_world(0, 0) == pytest.approx((-2.75, 16.75))
    # bottom-right pixel: x = ox + (W - 0.5) s, y = oy + 0.5 s
    assert t.pixel_to_world(W - 1, H - 1) == pytest.approx((16.75, 7.25))
    # an interior pixel (px=10, py=4): x = -3 + 10.5*0.5 = 2.25, y = 7 + 15.5*0.5 = 14.75
    assert t.pixel_to_world(10, 4) == pytest.approx((2.25, 14.75))
    assert t.meters_per_pixel == pytest.approx(S)


def test_socrates_y_formula_is_wrong_on_uncentred_map_and_ours_is_right() -> None:
    """SocRATES uses y = -(s*py + oy): only right when oy = -H*s/2. Here it is off by -(2*oy + H*s)."""
    t = Transform.from_nav2(S, [OX, OY, 0.0], H)
    px, py = 10, 4
    socrates_y = -(S * py + OY)  # -9.0: below the map, which spans y in [7, 17]
    ours_y = t.pixel_to_world(px, py)[1]
    assert ours_y == pytest.approx(14.75)
    assert OY <= ours_y <= OY + H * S
    assert not OY <= socrates_y <= OY + H * S
    # the documented error, up to SocRATES using the pixel edge instead of its centre (s/2)
    assert socrates_y - ours_y == pytest.approx(-(2 * OY + H * S) + S / 2)


def test_socrates_formula_agrees_when_map_is_centred() -> None:
    """On a vertically centred map the two differ only by half a pixel (pixel edge vs centre)."""
    h, s = 250, 0.1
    t = Transform.from_nav2(s, [-12.5, -12.5, 0.0], h)
    for py in (0, 31, 101, 249):
        assert -(s * py - 12.5) - t.pixel_to_world(0, py)[1] == pytest.approx(s / 2)


def test_yaw_rotates_about_the_origin() -> None:
    t = Transform.from_nav2(S, [OX, OY, math.pi / 2], H)
    # local point of pixel (10, 4) is (5.25, 7.75); rotated by +90 deg -> (-7.75, 5.25), then shifted.
    assert t.pixel_to_world(10, 4) == pytest.approx((OX - 7.75, OY + 5.25))
    # a step right in the image (+x local) points along world +y when yaw = 90 deg
    assert t.world_heading((10, 4), (11, 4)) == pytest.approx(math.pi / 2)
    # a step up in the image (-py) points along local +y, i.e. world -x
    assert abs(t.world_heading((10, 4), (10, 3))) == pytest.approx(math.pi)


def test_explicit_matrix() -> None:
    m = [[0.0, 0.2, 1.0], [0.2, 0.0, -4.0], [0.0, 0.0, 1.0]]  # swaps axes, 0.2 m/px
    t = Transform(m)
    assert t.pixel_to_world(10, 30) == pytest.approx((7.0, -2.0))
    assert t.world_to_pixel(7.0, -2.0) == pytest.approx((10, 30))
    assert t.meters_per_pixel == pytest.approx(0.2)


@pytest.mark.parametrize("matrix", [
    [[1, 2, 0], [2, 4, 0], [0, 0, 1]],  # rank 1
    [[0, 0, 3], [0, 0, 4], [0, 0, 1]],  # all pixels to one point
])
def test_singular_matrix_rejected(matrix: list[list[float]]) -> None:
    with pytest.raises(ValueError, match="singular"):
        Transform(matrix)


def test_non_3x3_rejected() -> None:
    with pytest.raises(ValueError, match="3x3"):
        Transform([[1, 0], [0, 1]])


@settings(max_examples=200, deadline=None)
@given(
    res=st.floats(0.01, 1.0),
    ox=st.floats(-100, 100), oy=st.floats(-100, 100), yaw=st.floats(-math.pi, math.pi),
    height=st.integers(1, 4000),
    px=st.floats(-10, 4000), py=st.floats(-10, 4000),
)
def test_round_trip_pixel_world_pixel(res: float, ox: float, oy: float, yaw: float, height: int,
                                      px: float, py: float) -> None:
    t = Transform.from_nav2(res, [ox, oy, yaw], height)
    back = t.world_to_pixel(*t.pixel_to_world(px, py))
    assert back == pytest.approx((px, py), abs=1e-6)
    # vectorised versions agree with the scalar ones
    world = t.pixels_to_world(np.array([[px, py]]))
    assert world[0] == pytest.approx(t.pixel_to_world(px, py), abs=1e-9)
    assert t.worlds_to_pixel(world)[0] == pytest.approx((px, py), abs=1e-6)
    # the scale is the resolution whatever the yaw
    assert t.meters_per_pixel == pytest.approx(res)


def test_bundled_warehouse_is_non_square_and_uncentred(warehouse_dir) -> None:
    loc = load_location(warehouse_dir)
    w, h = loc.image_size
    res, (ox, oy, _yaw) = loc.nav2.resolution, loc.nav2.origin
    assert w != h
    assert ox != -w * res / 2 and oy != -h * res / 2
    node = loc.scene_graph.nodes[0]
    px, py = node.pos
    assert loc.node_world(node.id) == pytest.approx((ox + (px + 0.5) * res, oy + (h - py - 0.5) * res))
