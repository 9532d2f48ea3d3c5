"""Every geometry type, pose composition and model lookup, on small synthetic worlds whose obstacles
are known to the centimetre."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from socnavgen.location.world_import import WorldImportOptions, import_world
from socnavgen.location.world_raster import SliceOptions
from socnavgen.location.world_reader import read_world
from tests.world.conftest import occupied_world_box, static_model, world_file

FINE = WorldImportOptions(slice=SliceOptions(resolution=0.05, margin=1.0))
# a closed room of 8 m x 6 m so every world has walkable floor for the extraction
ROOM = "".join(static_model(f"wall{i}", pose, f"<box><size>{size}</size></box>") for i, (pose, size) in enumerate([
    ("0 -3 1 0 0 0", "8.2 0.2 2"), ("0 3 1 0 0 0", "8.2 0.2 2"), ("-4 0 1 0 0 0", "0.2 6.2 2"),
    ("4 0 1 0 0 0", "0.2 6.2 2")]))


def _box_of(tmp_path: Path, body: str, **kw: object) -> tuple[float, float, float, float]:
    """World box of what `body` adds inside the room (the room's walls are subtracted by bounds)."""
    opts = WorldImportOptions(slice=SliceOptions(resolution=0.05, margin=1.0, bounds=(-3.5, -2.5, 3.5, 2.5)), **kw)
    (tmp_path / "models").mkdir(parents=True, exist_ok=True)
    import_world(world_file(tmp_path / "src", ROOM + body), tmp_path / "loc", [tmp_path / "models"], opts)
    return occupied_world_box(tmp_path / "loc")


def _close(box: tuple[float, ...], expected: tuple[float, ...], tol: float = 0.06) -> None:
    assert np.allclose(box, expected, atol=tol), f"{np.round(box, 3)} != {expected}"


@pytest.mark.parametrize(("geometry", "pose", "expected"), [
    ("<box><size>1 2 1</size></box>", "1 0.5 0.5 0 0 0", (0.5, -0.5, 1.5, 1.5)),
    ("<box><size>1 2 1</size></box>", "1 0.5 0.5 0 0 1.5707963", (0.0, 0.0, 2.0, 1.0)),  # turned a quarter
    ("<cylinder><radius>0.5</radius><length>1</length></cylinder>", "-1 1 0.5 0 0 0", (-1.5, 0.5, -0.5, 1.5)),
    ("<sphere><radius>0.6</radius></sphere>", "0 0 0.6 0 0 0", (-0.6, -0.6, 0.6, 0.6)),
    ("<capsule><radius>0.3</radius><length>1</length></capsule>", "0 0 1 1.5707963 0 0", (-0.3, -0.8, 0.3, 0.8)),
    ("<ellipsoid><radii>1 0.5 0.5</radii></ellipsoid>", "0 0 0.5 0 0 0", (-1.0, -0.5, 1.0, 0.5)),
    # a vertical plane is a wall of no thickness: its size's 2nd side runs along y, its 1st up the wall
    ("<plane><normal>1 0 0</normal><size>3 1</size></plane>", "2 0 0.5 0 0 0", (1.95, -0.5, 2.05, 0.5)),
    ("<polyline><point>0 0</point><point>1 0</point><point>0 1</point><height>1</height></polyline>",
     "0 0 0 0 0 0", (0.0, 0.0, 1.0, 1.0)),
])
def test_each_primitive_lands_where_the_world_puts_it(geometry: str, pose: str, expected: tuple, tmp_path: Path) -> None:
    _close(_box_of(tmp_path, static_model("thing", pose, geometry)), expected)


def test_a_horizontal_plane_is_floor_and_a_low_box_is_walked_over(tmp_path: Path) -> None:
    body = (static_model("ground", "0 0 0 0 0 0", "<plane><normal>0 0 1</normal><size>100 100</size></plane>")
            + static_model("rug", "0 0 0.02 0 0 0", "<box><size>2 2 0.04</size></box>")
            + static_model("lamp", "0 0 2.5 0 0 0", "<box><size>1 1 0.2</size></box>")
            + static_model("post", "1 1 1 0 0 0", "<box><size>0.2 0.2 2</size></box>"))
    _close(_box_of(tmp_path, body), (0.9, 0.9, 1.1, 1.1))  # only the post


@pytest.mark.parametrize("fmt", ["stl", "obj", "dae"])
def test_mesh_files_scaled_and_placed(fmt: str, tmp_path: Path) -> None:
    import trimesh

    folder = tmp_path / "models" / "crate" / "meshes"
    folder.mkdir(parents=True)
    mesh = trimesh.creation.box(extents=[1, 1, 1])
    mesh.export(folder / f"crate.{fmt}")
    (folder.parent / "model.sdf").write_text(
        '<sdf version="1.6"><model name="crate"><static>1</static><link name="l"><collision name="c"><geometry>'
        f'<mesh><uri>model://crate/meshes/crate.{fmt}</uri><scale>2 1 1</scale></mesh></geometry></collision>'
        '</link></model></sdf>')
    body = "<include><uri>model://crate</uri><pose>1 1 0.5 0 0 0</pose></include>"
    _close(_box_of(tmp_path, body), (0.0, 0.5, 2.0, 1.5))


def test_nested_models_frames_and_relative_to_compose(tmp_path: Path) -> None:
    """world -> model (x+1) -> nested model (y+1, turned a quarter) -> link in a frame -> collision."""
    body = ('<model name="outer"><static>1</static><pose>1 0 0 0 0 0</pose>'
            '<model name="inner"><pose>0 1 0 0 0 1.5707963</pose>'
            '<frame name="f"><pose>1 0 0 0 0 0</pose></frame>'
            '<link name="l"><pose relative_to="f">0 0 0.5 0 0 0</pose>'
            '<collision name="c"><geometry><box><size>0.4 0.2 1</size></box></geometry></collision></link>'
            '</model></model>')
    # inner frame at (1, 1) yawed 90 deg; f is 1 m along its x -> world (1, 2); the box is turned too
    _close(_box_of(tmp_path, body), (0.9, 1.8, 1.1, 2.2))


def test_degrees_and_quaternion_poses(tmp_path: Path) -> None:
    box = "<box><size>1 0.2 1</size></box>"
    a = _box_of(tmp_path / "a", static_model("a", "", box).replace("<pose></pose>", '<pose degrees="true">0 0 0.5 0 0 90</pose>'))
    b = _box_of(tmp_path / "b", static_model("b", "", box).replace(
        "<pose></pose>", '<pose rotation_format="quat_xyzw">0 0 0.5 0 0 0.7071068 0.7071068</pose>'))
    _close(a, (-0.1, -0.5, 0.1, 0.5))
    _close(b, (-0.1, -0.5, 0.1, 0.5))


def test_models_found_through_gazebo_model_path_and_include_overrides(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    lib = tmp_path / "elsewhere" / "pillar"
    lib.mkdir(parents=True)
    (lib / "model.config").write_text('<model><name>p</name><sdf version="1.5">pillar.sdf</sdf></model>')
    (lib / "pillar.sdf").write_text('<sdf version="1.5"><model name="pillar"><pose>5 5 0 0 0 0</pose>'
                                    '<link name="l"><collision name="c"><pose>0 0 1 0 0 0</pose><geometry><box>'
                                    '<size>0.2 0.2 2</size></box></geometry></collision></link></model></sdf>')
    monkeypatch.setenv("GAZEBO_MODEL_PATH", str(tmp_path / "elsewhere"))
    body = ("<include><name>p1</name><uri>model://pillar</uri><pose>-1 0 0 0 0 0</pose></include>"
            "<include><name>p2</name><uri>model://pillar</uri><pose>1 0 0 0 0 0</pose><static>false</static></include>")
    _close(_box_of(tmp_path, body), (-1.1, -0.1, 1.1, 0.1))  # the include's pose replaces the model's (5, 5)
    world = read_world(tmp_path / "src" / "w.world")
    assert {m.name for m in world.models} >= {"p1", "p2"}
    assert {m.name: m.static for m in world.models}["p2"] is False  # non-static models are obstacles too


def test_saved_state_moves_models(tmp_path: Path) -> None:
    body = (static_model("crate", "0 0 0.5 0 0 0", "<box><size>0.4 0.4 1</size></box>")
            + '<state world_name="t"><model name="crate"><pose>2 1 0.5 0 0 0</pose></model></state>')
    _close(_box_of(tmp_path, body), (1.8, 0.8, 2.2, 1.2))


def test_a_closed_solid_is_an_outline_around_unknown(tmp_path: Path) -> None:
    import_world(world_file(tmp_path / "src", ROOM + static_model("shelf", "0 0 1 0 0 0", "<box><size>2 1 2</size></box>")),
                 tmp_path / "loc", [], FINE)
    from socnavgen.location import load_location

    loc = load_location(tmp_path / "loc")
    px, py = (round(v) for v in loc.transform.world_to_pixel(0.0, 0.0))
    assert loc.occupancy.unknown[py, px] and not loc.occupancy.occupied[py, px]  # the shelf's inside
    ex, ey = (round(v) for v in loc.transform.world_to_pixel(1.0, 0.0))
    assert loc.occupancy.occupied[ey, ex]  # its side
    fx, fy = (round(v) for v in loc.transform.world_to_pixel(2.0, 2.0))
    assert not loc.occupancy.blocked[fy, fx]  # the floor beside it


def test_map_yaml_is_what_map_server_reads(tmp_path: Path) -> None:
    import yaml
    from PIL import Image

    result = import_world(world_file(tmp_path / "src", ROOM), tmp_path / "loc", [], FINE)
    nav2 = yaml.safe_load((tmp_path / "loc" / "map.yaml").read_text())
    assert nav2["image"] == "map.pgm" and nav2["mode"] == "trinary" and nav2["negate"] == 0
    assert nav2["origin"][2] == 0.0 and nav2["resolution"] == 0.05
    assert all(abs(v / 0.05 - round(v / 0.05)) < 1e-6 for v in nav2["origin"][:2])  # on the cell lattice
    with Image.open(tmp_path / "loc" / "map.pgm") as img:
        assert img.format == "PPM" and img.mode == "L" and img.size == result.size
        assert set(np.unique(np.asarray(img))) <= {0, 205, 254}
    with Image.open(tmp_path / "loc" / "overhead.png") as pic:
        assert pic.size == result.size and pic.mode == "RGB"


def test_a_shelf_on_legs_is_walked_round_even_on_a_laser_height_map(tmp_path: Path) -> None:
    """A 4 x 1.2 m shelf whose top stands 0.75-1.5 m up on four legs, in the middle of the room: a map cut
    at 0.5 m shows its legs only, but people do not walk under it, so no node stands and no edge runs
    under its top (the scene graph comes from a person's slab)."""
    from socnavgen.location import load_location

    legs = "".join(static_model(f"leg{i}", f"{x} {y} 0.375 0 0 0", "<box><size>0.05 0.05 0.75</size></box>")
                   for i, (x, y) in enumerate([(-1.95, -0.55), (-1.95, 0.55), (1.95, -0.55), (1.95, 0.55)]))
    body = ROOM + legs + static_model("shelf", "0 0 1.125 0 0 0", "<box><size>4 1.2 0.75</size></box>")
    out = tmp_path / "loc"
    import_world(world_file(tmp_path / "src", body), out, [],
                 WorldImportOptions(slice=SliceOptions(resolution=0.05, head=0.5)))
    loc = load_location(out)
    under = loc.transform.world_to_pixel(0.0, 0.0)
    assert not loc.occupancy.is_blocked(*under)  # the laser map is free under the shelf
    t = loc.transform
    inside = [n.id for n in loc.scene_graph.nodes if abs(t.pixel_to_world(*n.pos)[0]) < 1.95
              and abs(t.pixel_to_world(*n.pos)[1]) < 0.55]
    assert inside == [], "a node stands under the shelf"
    for e in loc.scene_graph.links:
        a, b = (np.array(t.pixel_to_world(*loc.scene_graph.node(i).pos)) for i in (e.source, e.target))
        points = [a + (b - a) * k for k in np.linspace(0, 1, 200)]
        assert not any(abs(p[0]) < 1.95 and abs(p[1]) < 0.55 for p in points), f"edge {e.source}-{e.target}"
    assert loc.scene_graph.nodes


def test_rows_standing_in_open_ground_are_walked_round(tmp_path: Path) -> None:
    """Four 10 m rows of shelving 3 m apart with no walls round them: the map keeps 1.5 m of ground past
    the outermost rows (a building's outline would keep 0.3 m), so the three lanes between them join
    round the rows' ends and every lane is in the one graph (with 0.3 m each lane was cut off)."""
    from socnavgen.location import load_location

    rows = "".join(static_model(f"row{i}", f"5 {i * 3.5} 1 0 0 0", "<box><size>10 0.5 2</size></box>")
                   for i in range(4))
    result = import_world(world_file(tmp_path / "src", rows), tmp_path / "loc", [], WorldImportOptions())
    loc = load_location(tmp_path / "loc")
    assert result.origin[0] <= -1.5 + 1e-9  # the open-ground margin
    ys = [loc.transform.pixel_to_world(*n.pos)[1] for n in loc.scene_graph.nodes]
    for lane in range(3):  # between rows lane and lane + 1: y from 3.5 lane + 0.25 to 3.5 (lane + 1) - 0.25
        assert any(3.5 * lane + 0.25 < y < 3.5 * (lane + 1) - 0.25 for y in ys), f"lane {lane} has no node"
