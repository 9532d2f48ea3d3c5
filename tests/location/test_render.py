"""The rendered map: readable size, deterministic, a legend with every type."""

from __future__ import annotations

import numpy as np
import pytest
from PIL import Image

from socnavgen.location import load_location
from socnavgen.location.models import Node, SceneGraph
from socnavgen.location.render import (
    LEGEND_WIDTH,
    choose_scale,
    png_bytes,
    render_location,
    render_location_with_layout,
    render_with_layout,
    type_colours,
)
from tests.location.conftest import BUNDLED, EXAMPLES


@pytest.mark.parametrize(("w", "h"), [(250, 250), (480, 320), (600, 280), (280, 200), (1300, 900), (3200, 1000),
                                    (300, 1500), (40, 30)])
def test_choose_scale_fits_a_vision_model(w: int, h: int) -> None:
    scale = choose_scale(w, h)
    map_w, map_h = w * scale, h * scale
    assert max(map_w, map_h) == pytest.approx(1280) or map_w + LEGEND_WIDTH == pytest.approx(1600)
    assert 1000 <= max(map_w, map_h) <= 1600
    assert map_w + LEGEND_WIDTH <= 1600 + 1e-9 and map_h <= 1600


@pytest.mark.parametrize("name", BUNDLED)
def test_render_is_deterministic_and_sized(name: str) -> None:
    loc = load_location(EXAMPLES / name)
    first, second = png_bytes(render_location(loc)), png_bytes(render_location(loc))
    assert first == second
    image, layout = render_location_with_layout(loc)
    x0, y0, x1, y1 = layout.crop
    w, h = x1 - x0, y1 - y0
    scale = choose_scale(w, h)
    assert image.size[0] == round(w * scale) + LEGEND_WIDTH <= 1600
    assert 1000 <= max(round(w * scale), round(h * scale)) <= 1600


def test_nodes_drawn_in_their_type_colour() -> None:
    loc = load_location(EXAMPLES / "warehouse")
    rendered, layout = render_location_with_layout(loc)
    image = np.asarray(rendered.convert("RGB"))
    node_colour, _ = type_colours(loc.schema, loc.scene_graph)
    for node in loc.scene_graph.nodes:
        x0, y0, x1, y1 = (int(v) for v in layout.boxes[node.id])
        box = image[y0 + 3:y1 - 2, x0 + 3:x1 - 2].reshape(-1, 3)
        want = tuple(int(node_colour[node.type][i:i + 2], 16) for i in (1, 3, 5))
        assert (box == want).all(axis=1).any(), node.id


def test_picture_is_cropped_to_the_mapped_part() -> None:
    """The home map has a wide band of unknown grey around the building: the picture leaves it out."""
    loc = load_location(EXAMPLES / "home")
    _, layout = render_location_with_layout(loc)
    x0, y0, x1, y1 = layout.crop
    w, h = loc.image_size
    assert (x1 - x0) * (y1 - y0) < 0.9 * w * h
    unknown = load_location(EXAMPLES / "home").occupancy.unknown
    known_rows = np.nonzero((~unknown).any(axis=1))[0]
    assert y0 <= known_rows[0] and y1 >= known_rows[-1] + 1  # nothing mapped is cut off
    for node in loc.scene_graph.nodes:
        assert x0 <= node.pos[0] < x1 and y0 <= node.pos[1] < y1


def _assert_no_overlap(boxes: dict) -> None:
    items = sorted(boxes.items())
    for i, (a, ba) in enumerate(items):
        for b, bb in items[i + 1:]:
            assert not (ba[0] < bb[2] and bb[0] < ba[2] and ba[1] < bb[3] and bb[1] < ba[3]), (a, b)


@pytest.mark.parametrize("name", BUNDLED)
def test_labels_never_overlap_on_the_bundled_maps(name: str) -> None:
    _, layout = render_location_with_layout(load_location(EXAMPLES / name))
    _assert_no_overlap(layout.boxes)
    assert layout.thinned == []


def test_crowded_labels_are_moved_or_thinned_never_overlapped() -> None:
    loc = load_location(EXAMPLES / "warehouse")
    ids = [a + b for a in "abcdefgh" for b in "0123456789"]
    x, y = loc.scene_graph.nodes[0].pos
    crowd = SceneGraph(nodes=[Node(id=i, type=loc.schema.node_types[0], pos=(x + k % 9, y + k // 9))
                              for k, i in enumerate(ids)])
    _, layout = render_with_layout(loc.map_gray, crowd, loc.schema)
    _assert_no_overlap(layout.boxes)
    assert len(layout.boxes) + len(layout.thinned) == len(ids)
    assert layout.thinned and len(layout.boxes) >= 20  # some moved aside, the rest thinned
    moved = [i for i, b in layout.boxes.items() if abs((b[0] + b[2]) / 2 - layout.at(crowd.node(i).pos)[0]) > 1]
    assert moved


def test_legend_lists_every_type() -> None:
    loc = load_location(EXAMPLES / "hospital")
    node_colour, edge_colour = type_colours(loc.schema, loc.scene_graph)
    assert list(node_colour) == loc.schema.node_types
    assert list(edge_colour) == loc.schema.edge_types
    legend = np.asarray(render_location(loc).convert("RGB"))[:, -LEGEND_WIDTH:]
    for colour in (*node_colour.values(), *edge_colour.values()):
        rgb = tuple(int(colour[i:i + 2], 16) for i in (1, 3, 5))
        assert (legend.reshape(-1, 3) == rgb).all(axis=1).any(), colour


def test_type_outside_schema_is_loud() -> None:
    loc = load_location(EXAMPLES / "home")
    graph = loc.scene_graph.model_copy(deep=True)
    graph.nodes[0].type = "GARAGE"
    node_colour, _ = type_colours(loc.schema, graph)
    assert node_colour["GARAGE"] == "#FF00FF"


def test_written_scene_graph_png_matches_render() -> None:
    loc = load_location(EXAMPLES / "home")
    with Image.open(EXAMPLES / "home" / "scene_graph.png") as img:
        assert np.array_equal(np.asarray(img.convert("RGB")), np.asarray(render_location(loc)))


def test_a_label_keeps_clear_of_the_scale_bar() -> None:
    """A node in the lower-left corner (a building's door on the map's edge) is not hidden under the
    scale bar: its label moves aside and a dot marks the node; without a scale bar it stays on the node."""
    loc = load_location(EXAMPLES / "home")
    x0, y0, x1, y1 = render_location_with_layout(loc)[1].crop
    corner = SceneGraph(nodes=[Node(id="dr", type=loc.schema.node_types[0], pos=(x0 + 3, y1 - 3)),
                               Node(id="up", type=loc.schema.node_types[0], pos=(x0 + 3, y0 + 3))])

    def on_node(layout, node_id: str) -> bool:
        box, (cx, cy) = layout.boxes[node_id], layout.at(corner.node(node_id).pos)
        return abs((box[0] + box[2]) / 2 - cx) < 0.5 and abs((box[1] + box[3]) / 2 - cy) < 0.5

    _, layout = render_with_layout(loc.map_gray, corner, loc.schema, metres_per_pixel=0.05)
    assert layout.scale_bar is not None
    assert not any(a[0] < b[2] and b[0] < a[2] and a[1] < b[3] and b[1] < a[3]
                   for a in layout.boxes.values() for b in [layout.scale_bar])
    assert not on_node(layout, "dr") and on_node(layout, "up")
    _, bare = render_with_layout(loc.map_gray, corner, loc.schema)  # no transform: no bar
    assert bare.scale_bar is None and on_node(bare, "dr")
