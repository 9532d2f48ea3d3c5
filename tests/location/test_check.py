"""`location check` on broken copies of the bundled warehouse: each kind of problem, precise messages."""

from __future__ import annotations

import math

import numpy as np
import pytest
from PIL import Image

from socnavgen.location import load_location
from socnavgen.location.check import Problem, check_location
from tests.extract.synthetic_maps import blank, carve, write_map
from tests.location.conftest import BUNDLED, EXAMPLES, read_graph, write_graph


def messages(problems: list[Problem], level: str = "error") -> list[str]:
    return [p.message for p in problems if p.level == level]


def node_index(data: dict, node_id: str) -> int:
    return next(i for i, n in enumerate(data["nodes"]) if n["id"] == node_id)


@pytest.mark.parametrize("name", BUNDLED)
def test_bundled_locations_pass(name: str) -> None:
    report = check_location(EXAMPLES / name)
    assert report.problems == []
    assert report.ok and 12 <= report.nodes <= 30


def test_duplicate_id(location_copy) -> None:
    loc = location_copy()
    data = read_graph(loc)
    data["nodes"][1]["id"] = data["nodes"][0]["id"]
    write_graph(loc, data)
    first = data["nodes"][0]["id"]
    assert f"duplicate node id '{first}' (nodes 0 and 1)" in messages(check_location(loc).problems)


@pytest.mark.parametrize("bad_id", ["Sk", "abc", "a", "a-"])
def test_id_not_two_lowercase_alnum(location_copy, bad_id: str) -> None:
    loc = location_copy()
    data = read_graph(loc)
    old = data["nodes"][0]["id"]
    data["nodes"][0]["id"] = bad_id
    for link in data["links"]:
        for end in ("source", "target"):
            if link[end] == old:
                link[end] = bad_id
    write_graph(loc, data)
    errors = messages(check_location(loc).problems)
    assert errors == [f"node id {bad_id!r} is not 2 lowercase letters or digits"]


def test_unknown_node_in_edge(location_copy) -> None:
    loc = location_copy()
    data = read_graph(loc)
    a = data["nodes"][0]["id"]
    data["links"].append({"type": "PASSAGEWAY", "source": a, "target": "zz"})
    write_graph(loc, data)
    assert messages(check_location(loc).problems) == [f"edge {a}-zz names unknown node 'zz'"]


def test_self_loop(location_copy) -> None:
    loc = location_copy()
    data = read_graph(loc)
    a = data["nodes"][3]["id"]
    data["links"].append({"type": "PASSAGEWAY", "source": a, "target": a})
    write_graph(loc, data)
    assert messages(check_location(loc).problems) == [f"edge {a}-{a} is a self loop"]


def test_duplicate_edge_reversed(location_copy) -> None:
    loc = location_copy()
    data = read_graph(loc)
    first = data["links"][0]
    data["links"].append({"type": first["type"], "source": first["target"], "target": first["source"]})
    write_graph(loc, data)
    last = len(data["links"]) - 1
    assert messages(check_location(loc).problems) == [
        f"duplicate edge {first['target']}-{first['source']} (links 0 and {last}; edges are undirected)"]


def test_types_outside_schema(location_copy) -> None:
    loc = location_copy()
    data = read_graph(loc)
    data["nodes"][2]["type"] = "FORKLIFT"
    data["links"][4]["type"] = "RAMP"
    write_graph(loc, data)
    problems = check_location(loc).problems
    node, link = data["nodes"][2], data["links"][4]
    assert messages(problems) == [
        f"node {node['id']} has type 'FORKLIFT', not in the schema",
        f"edge {link['source']}-{link['target']} has type 'RAMP', not in the schema",
    ]
    assert "ENTRANCE, INTERSECTION, BLIND CORNER" in problems[0].hint


def test_node_outside_image(location_copy) -> None:
    loc = location_copy()
    data = read_graph(loc)
    data["nodes"][0]["pos"] = [5000, 10]
    write_graph(loc, data)
    assert messages(check_location(loc).problems) == [
        f"node {data['nodes'][0]['id']} at pixel (5000, 10) is outside the 480x320 map image"]


def test_node_on_occupied_and_on_unknown_pixel(location_copy) -> None:
    loc = location_copy()
    occupancy = load_location(loc).occupancy
    wy, wx = (int(v) for v in np.argwhere(occupancy.occupied)[0])
    data = read_graph(loc)
    a, b = data["nodes"][0]["id"], data["nodes"][1]["id"]
    data["nodes"][0]["pos"] = [wx, wy]
    data["nodes"][1]["pos"] = [0, 0]  # the margin outside the walls is unknown
    write_graph(loc, data)
    # world points computed by hand: origin (-3, -5.5), 0.05 m/px, 320 rows
    ex, ey = -3 + (wx + 0.5) * 0.05, -5.5 + (320 - wy - 0.5) * 0.05
    assert messages(check_location(loc).problems) == [
        f"node {a} at pixel ({wx}, {wy}) = world ({ex:.2f}, {ey:.2f}) m is on an occupied pixel",
        f"node {b} at pixel (0, 0) = world (-2.98, 10.48) m is on an unknown pixel",
    ]


def test_edge_through_a_wall_names_first_blocked_pixel(location_copy) -> None:
    loc = location_copy()
    data = read_graph(loc)
    pos = {n["id"]: n["pos"] for n in data["nodes"]}
    a, b = "hd", "qs"  # north-west intersection to the south end of an aisle: across the racks
    data["links"].append({"type": "PASSAGEWAY", "source": a, "target": b})
    write_graph(loc, data)
    errors = messages(check_location(loc).problems)
    assert len(errors) == 1
    assert errors[0].startswith(f"edge {a}-{b} crosses a wall (occupied): ")
    px, py = (int(v) for v in errors[0].split("first at pixel (")[1].split(")")[0].split(", "))
    occupancy = load_location(loc).occupancy
    assert occupancy.occupied[py, px]
    # the pixel lies on the segment, and the segment is free from `a` up to it
    (ax, ay), (bx, by) = pos[a], pos[b]
    dist = abs((bx - ax) * (ay - py) - (ax - px) * (by - ay)) / math.hypot(bx - ax, by - ay)
    assert dist < 1.0
    t_hit = ((px - ax) * (bx - ax) + (py - ay) * (by - ay)) / ((bx - ax) ** 2 + (by - ay) ** 2)
    for t in np.linspace(0, t_hit - 2 / math.hypot(bx - ax, by - ay), 50):
        assert not occupancy.blocked[round(ay + t * (by - ay)), round(ax + t * (bx - ax))]
    ex, ey = -3 + (px + 0.5) * 0.05, -5.5 + (320 - py - 0.5) * 0.05
    assert f"= world ({ex:.2f}, {ey:.2f}) m" in errors[0]


def test_edge_through_unknown_space(location_copy) -> None:
    """Unknown space across the whole aisle blocks the edge; a chair-sized blob beside the line does not
    (a person steps around it: the one traversability rule)."""
    loc = location_copy()
    data = read_graph(loc)
    pos = {n["id"]: n["pos"] for n in data["nodes"]}
    (ax, ay), (bx, by) = pos["sh"], pos["sw"]  # along the south cross aisle
    original = np.asarray(Image.open(loc / "map.pgm")).copy()
    mx, my = (ax + bx) // 2, (ay + by) // 2
    image = original.copy()
    image[my - 3:my + 4, mx - 3:mx + 4] = 205
    Image.fromarray(image).save(loc / "map.pgm")
    assert check_location(loc).problems == []
    image = original.copy()
    image[my - 40:my + 40, mx - 3:mx + 4] = 205  # a 4 m long unknown band across the aisle
    Image.fromarray(image).save(loc / "map.pgm")
    errors = messages(check_location(loc).problems)
    assert len(errors) == 1, errors
    assert errors[0].startswith("edge sh-sw crosses unmapped (unknown) space: 7 blocked pixel(s), first at pixel "
                                f"({mx - 3}, {my})"), errors


def test_disconnected_is_a_warning_only(location_copy) -> None:
    loc = location_copy()
    data = read_graph(loc)
    data["links"] = [e for e in data["links"] if "sk" not in (e["source"], e["target"])]
    write_graph(loc, data)
    report = check_location(loc)
    assert report.ok
    assert messages(report.problems, "warning") == [
        "the graph has 2 disconnected parts: the largest has 18 nodes, cut off: {sk}"]


@pytest.mark.parametrize(("missing", "message"), [
    ("scene_graph.json", "scene_graph.json is missing"),
    ("map.pgm", "map image not found"),
    ("map.yaml", "file not found"),
    ("location.yaml", "no location.yaml in"),
])
def test_missing_files(location_copy, missing: str, message: str) -> None:
    loc = location_copy()
    (loc / missing).unlink()
    report = check_location(loc)
    assert not report.ok
    assert any(p.message.startswith(message) for p in report.errors), report.problems
    hit = next(p for p in report.errors if p.message.startswith(message))
    assert hit.file.endswith(missing) or missing == "location.yaml"


def test_missing_png_is_a_warning(location_copy) -> None:
    loc = location_copy()
    (loc / "scene_graph.png").unlink()
    report = check_location(loc)
    assert report.ok
    assert messages(report.problems, "warning") == ["scene_graph.png is missing"]


def test_malformed_json_gives_file_and_line(location_copy) -> None:
    loc = location_copy()
    lines = (loc / "scene_graph.json").read_text().splitlines()
    lines[9] = lines[9] + ","  # a trailing comma JSON does not allow
    (loc / "scene_graph.json").write_text("\n".join(lines))
    (problem,) = check_location(loc).problems
    assert problem.file.endswith("scene_graph.json")
    assert problem.message.startswith("malformed JSON")
    assert problem.line in (10, 11)


def test_malformed_yaml_gives_file_and_line(location_copy) -> None:
    loc = location_copy()
    text = (loc / "location.yaml").read_text().replace("map: map.pgm", "map: [map.pgm")
    (loc / "location.yaml").write_text(text)
    problems = check_location(loc).problems
    assert problems[0].file.endswith("location.yaml")
    assert problems[0].message.startswith("malformed YAML")
    assert problems[0].line is not None and problems[0].line >= text.splitlines().index("map: [map.pgm") + 1


def test_invalid_config_key_names_its_line(location_copy) -> None:
    loc = location_copy("home")
    with (loc / "location.yaml").open("a") as fh:
        fh.write("colour: red\n")
    (problem,) = check_location(loc).problems
    assert "colour: Extra inputs are not permitted" in problem.message
    assert problem.line == len((loc / "location.yaml").read_text().splitlines())


def test_node_problem_points_at_its_line(location_copy) -> None:
    loc = location_copy()
    data = read_graph(loc)
    i = node_index(data, "9z")
    data["nodes"][i]["type"] = "FORKLIFT"
    write_graph(loc, data)
    (problem,) = check_location(loc).problems
    text = (loc / "scene_graph.json").read_text().splitlines()
    assert text[problem.line - 1].strip() == "{"
    assert '"id": "9z"' in "\n".join(text[problem.line - 1:problem.line + 8])


def test_every_problem_reported_at_once(location_copy) -> None:
    loc = location_copy("hospital")
    data = read_graph(loc)
    data["nodes"][0]["type"] = "CAFETERIA"
    data["nodes"][1]["pos"] = [-4, 3]
    data["links"].append({"type": "CORRIDOR", "source": "cs", "target": "cs"})
    data["links"].append({"type": "CORRIDOR", "source": "cs", "target": "q1"})
    data["links"].append({"type": "CORRIDOR", "source": "g3", "target": "nt"})  # through two walls
    write_graph(loc, data)
    (loc / "scene_graph.png").unlink()
    report = check_location(loc)
    assert len(report.errors) == 5 and len(report.warnings) == 1
    assert not report.ok


def _use_matrix(loc, matrix) -> None:
    import yaml

    cfg = yaml.safe_load((loc / "location.yaml").read_text())
    cfg.pop("nav2_map")
    cfg["pixel_to_world"] = matrix
    (loc / "location.yaml").write_text(yaml.safe_dump(cfg, sort_keys=False))


def test_explicit_matrix_location_passes_and_matches_nav2(location_copy) -> None:
    loc = location_copy("home")
    before = load_location(loc).node_world("g9")
    # the same transform as the nav2 yaml (0.05 m/px, origin (-2, -1.5), 200 rows), written out
    _use_matrix(loc, [[0.05, 0, -2 + 0.025], [0, -0.05, -1.5 + 199.5 * 0.05], [0, 0, 1]])
    assert check_location(loc).problems == []
    assert load_location(loc).node_world("g9") == pytest.approx(before)


def test_singular_matrix_is_reported(location_copy) -> None:
    loc = location_copy("home")
    _use_matrix(loc, [[0.05, 0.1, 0], [0.1, 0.2, 0], [0, 0, 1]])
    (problem,) = check_location(loc).problems
    assert problem.message.startswith("bad pixel_to_world: transform is singular")
    assert problem.file.endswith("location.yaml") and problem.line is not None


def test_graph_still_checked_when_location_yaml_is_broken(location_copy) -> None:
    loc = location_copy("home")
    (loc / "location.yaml").write_text("name: home\n")
    data = read_graph(loc)
    data["nodes"][1]["id"] = data["nodes"][0]["id"]
    write_graph(loc, data)
    errors = messages(check_location(loc).problems)
    assert errors[0].startswith("invalid location config: description: Field required")
    assert f"duplicate node id '{data['nodes'][0]['id']}' (nodes 0 and 1)" in errors


def test_check_an_edited_location_in_memory(location_copy) -> None:
    """The annotator checks unsaved edits: a loaded Location with a modified graph, file untouched."""
    from socnavgen.location.models import Edge

    loc = load_location(location_copy("warehouse"))
    loc.scene_graph.links.append(Edge(type="PASSAGEWAY", source="hd", target="qs"))
    report = check_location(loc)
    (problem,) = list(report)
    assert problem.severity == "error" and problem.edge == ("hd", "qs") and problem.line is None
    assert check_location(loc.root).ok  # the file on disk is still sound


def test_problems_name_what_to_highlight(location_copy) -> None:
    loc = location_copy()
    data = read_graph(loc)
    data["nodes"][0]["type"] = "FORKLIFT"
    data["links"] = [e for e in data["links"] if "sk" not in (e["source"], e["target"])]
    write_graph(loc, data)
    type_problem, parts = check_location(loc).problems
    assert type_problem.nodes == ["sk"] and parts.nodes == ["sk"]


def test_loaded_unedited_location_keeps_line_numbers(location_copy) -> None:
    loc = location_copy()
    data = read_graph(loc)
    data["nodes"][0]["type"] = "FORKLIFT"
    write_graph(loc, data)
    location = load_location(loc)
    _ = location.scene_graph  # cached, but equal to the file
    (problem,) = check_location(location).problems
    assert problem.line is not None


@pytest.mark.parametrize(("door_px", "warned"), [(13, True), (18, False)])
def test_an_edge_a_person_walks_but_the_robot_does_not_fit_is_a_warning(location_copy, door_px: int,
                                                                         warned: bool) -> None:
    """SocRATES's hand-drawn graphs put nodes in 0.6-0.7 m doorways: people pass (an end node in a narrow spot
    lowers what the edge must keep), the 0.8 m robot (bodies.ROBOT_PASSAGE_WIDTH) scraped the walls or stalled
    there without a word from the check. A room, a node in its door and one in the corridor outside: a 0.65 m door
    warns on both of the door node's edges, a 0.9 m one on neither."""
    loc = location_copy()
    img = blank(300, 400)
    carve(img, 30, 270, 30, 230)  # the room
    carve(img, 150 - door_px // 2, 150 - door_px // 2 + door_px, 230, 240)  # its door in a 0.5 m wall
    carve(img, 30, 270, 240, 272)  # the corridor
    write_map(loc, img, "map")
    data = read_graph(loc)
    data["nodes"] = [{**data["nodes"][0], "id": i, "type": t, "pos": p}
                     for i, t, p in (("rm", "OPEN AREA", [130, 150]), ("dr", "ENTRANCE", [235, 150]),
                                     ("co", "INTERSECTION", [256, 150]))]
    data["links"] = [{"type": "PASSAGEWAY", "source": "rm", "target": "dr"},
                     {"type": "PASSAGEWAY", "source": "dr", "target": "co"}]
    write_graph(loc, data)
    problems = check_location(loc).problems
    assert messages(problems) == []
    robot = [p for p in problems if p.level == "warning" and "not for the robot" in p.message]
    if warned:
        assert sorted(p.edge for p in robot) == [("dr", "co"), ("rm", "dr")], problems
        assert robot[0].message.startswith(f"edge {robot[0].edge[0]}-{robot[0].edge[1]} is wide enough for a "
                                           "person but not for the robot (0.80 m wall to wall)")
    else:
        assert robot == [], problems
