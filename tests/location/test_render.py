"""The rendered map: readable size, deterministic, a legend with every type."""

from __future__ import annotations

import numpy as np
import pytest
from PIL import Image

from socnavgen.location import load_location
from socnavgen.location.render import LEGEND_WIDTH, choose_scale, png_bytes, render_location, type_colours
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
    image = render_location(loc)
    w, h = loc.image_size
    scale = choose_scale(w, h)
    assert image.size[0] == round(w * scale) + LEGEND_WIDTH <= 1600
    assert 1000 <= max(round(w * scale), round(h * scale)) <= 1600


def test_nodes_drawn_in_their_type_colour() -> None:
    loc = load_location(EXAMPLES / "warehouse")
    image = np.asarray(render_location(loc).convert("RGB"))
    node_colour, _ = type_colours(loc.schema, loc.scene_graph)
    scale = choose_scale(*loc.image_size)
    for node in loc.scene_graph.nodes:
        # the label box is centred on the node
        x, y = (node.pos[0] + 0.5) * scale, (node.pos[1] + 0.5) * scale
        box = image[int(y) - 8:int(y) + 8, int(x) - 18:int(x) + 18].reshape(-1, 3)
        want = tuple(int(node_colour[node.type][i:i + 2], 16) for i in (1, 3, 5))
        assert (box == want).all(axis=1).any(), node.id


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
