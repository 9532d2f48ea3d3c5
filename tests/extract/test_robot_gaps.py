"""`location extract` routes the robot only where its body passes: an edge through a gap narrower than the
robot (bodies.ROBOT_PASSAGE_WIDTH, wall to wall) is not kept, so routes go round it; a gap the robot fits
through keeps its edge. The gaps are measured to the pixel (a 7-pixel gap is 0.7 m, not 0.8 m)."""

from __future__ import annotations

import networkx as nx
import numpy as np
import pytest

from socnavgen.bodies import ROBOT_PASSAGE_WIDTH, ROBOT_RADIUS
from socnavgen.location.extract import ExtractOptions, extract_scene_graph
from socnavgen.location.occupancy import occupancy_from_image
from socnavgen.location.traverse import robot_fits_along
from tests.extract.synthetic_maps import RES, blank, carve

WALL = (190, 200)  # columns of the wall between the two rooms (0.5 m thick)
GAP_ROWS = 150  # the gap's first row, half-way up the wall
DOOR = (300, 332)  # rows of the wide (1.6 m) opening near the wall's south end


def two_rooms(gap_m: float) -> np.ndarray:
    """Two 9.5 m x 17 m rooms side by side, joined by a gap `gap_m` wide half-way along the wall between them
    and by a 1.6 m opening 7.5 m south of it: the way round the gap is ~15 m longer than through it."""
    img = blank(380, 400)
    carve(img, 20, 360, 10, WALL[0])
    carve(img, 20, 360, WALL[1], 390)
    carve(img, GAP_ROWS, GAP_ROWS + round(gap_m / RES), *WALL)
    carve(img, *DOOR, *WALL)
    return img


def crossings(gap_m: float, **opts: float) -> list[tuple[float, float]]:
    """Rows (y at the wall's middle) where the extracted graph's edges cross the wall; the graph must be one
    connected part with both rooms in it."""
    graph, _ = extract_scene_graph(occupancy_from_image(two_rooms(gap_m)), RES, ExtractOptions(seed=1, **opts))
    pos = {n.id: n.pos for n in graph.nodes}
    g = nx.Graph([(e.source, e.target) for e in graph.links])
    assert nx.is_connected(g)
    assert min(p[0] for p in pos.values()) < WALL[0] and max(p[0] for p in pos.values()) > WALL[1]
    mid = sum(WALL) / 2
    out = []
    for e in graph.links:
        (xa, ya), (xb, yb) = pos[e.source], pos[e.target]
        if min(xa, xb) <= mid <= max(xa, xb) and xa != xb:
            out.append((ya + (yb - ya) * (mid - xa) / (xb - xa), abs(xb - xa)))
    return out


def through_gap(rows: list[tuple[float, float]], gap_m: float) -> bool:
    lo, hi = GAP_ROWS - 10, GAP_ROWS + round(gap_m / RES) + 10
    return any(lo <= y <= hi for y, _ in rows)


@pytest.mark.parametrize("gap_m", [0.55, 0.7])
def test_a_gap_narrower_than_the_robot_carries_no_edge_and_routes_go_round(gap_m: float) -> None:
    assert gap_m < ROBOT_PASSAGE_WIDTH
    rows = crossings(gap_m)
    assert not through_gap(rows, gap_m), f"an edge still leads through the {gap_m} m gap: {rows}"
    assert any(DOOR[0] - 10 <= y <= DOOR[1] + 10 for y, _ in rows)  # the way round, through the wide opening
    # a person squeezes through it: without the robot's width the extractor keeps the edge (the gap is real)
    assert through_gap(crossings(gap_m, robot_width_m=0.0), gap_m)


def test_a_gap_the_robot_fits_through_keeps_its_edge() -> None:
    gap_m = 0.9
    assert gap_m >= ROBOT_PASSAGE_WIDTH
    assert through_gap(crossings(gap_m), gap_m)


@pytest.mark.parametrize("mpp", [0.1, 0.05])
def test_gap_widths_are_measured_to_the_pixel(mpp: float) -> None:
    """A corridor n pixels wide is n x mpp wall to wall: the robot needs ROBOT_PASSAGE_WIDTH, so one pixel less
    is refused and exactly that much passes, at either resolution (pixel-centre clearance calls a 7- and an
    8-pixel corridor both 0.8 m at 0.1 m a pixel)."""
    need = round(ROBOT_PASSAGE_WIDTH / mpp)
    assert need * mpp > 2 * ROBOT_RADIUS
    for width, fits in ((need - 1, False), (need, True), (need + 1, True)):
        blocked = np.ones((40, 80), bool)
        blocked[20 - width // 2:20 - width // 2 + width, 5:75] = False
        assert robot_fits_along(blocked, (25.0, 20.0), (55.0, 20.0), mpp) is fits, (width, mpp)
