"""The annotator's helpers: a suggested graph from extract, a guessed type for new nodes, the
description editor, and the PNG's colours served to the page."""

from __future__ import annotations

from pathlib import Path

import pytest
import yaml
from starlette.testclient import TestClient

from socnavgen.annotate.server import create_app
from socnavgen.location.extract import start_location_folder
from socnavgen.location.render import EDGE_COLOURS, NODE_COLOURS
from tests.extract.drawn_maps import office_map
from tests.extract.synthetic_maps import write_map

BASE = "http://127.0.0.1:8765"


@pytest.fixture
def office(tmp_path: Path) -> Path:
    """A new location as `annotate --map` starts it: the default schema, no graph yet."""
    return start_location_folder(write_map(tmp_path / "src", office_map(), "office"), tmp_path / "office")


@pytest.fixture
def client(office: Path) -> TestClient:
    return TestClient(create_app(office), base_url=BASE)


def test_default_schema_has_room_and_new_nodes_default_to_it(client: TestClient) -> None:
    state = client.get("/api/location").json()
    assert "ROOM" in state["schema"]["node_types"] and "DOORWAY" in state["schema"]["node_types"]
    assert state["default_node_type"] == "ROOM"
    assert state["palette"] == {"node": NODE_COLOURS, "edge": EDGE_COLOURS, "unknown": "#FF00FF"}


def test_guessed_type_follows_the_map(client: TestClient) -> None:
    types = ["ROOM", "DOORWAY", "INTERSECTION"]
    guess = lambda x, y, t=types: client.post("/api/guess-type", json={"x": x, "y": y, "node_types": t}).json()["type"]  # noqa: E731
    assert guess(69, 147) == "DOORWAY"  # in the north-west office's door
    assert guess(200, 60) == "ROOM"  # the middle of an office
    assert guess(200, 170) is None  # the corridor: the map does not say, the page keeps its type
    assert guess(0, 0) is None  # on a wall
    assert guess(69, 147, ["INTERSECTION"]) is None  # never a type outside the page's schema
    assert client.post("/api/guess-type", json={"x": "a"}).status_code == 422


def test_suggest_returns_an_extracted_graph_and_extends_the_schema(client: TestClient) -> None:
    body = {"nodes": [], "links": [], "schema": {"node_types": ["KITCHEN"], "edge_types": ["HALL"]}}
    data = client.post("/api/suggest", json=body).json()
    types = {n["type"] for n in data["graph"]["nodes"]}
    assert "ROOM" in types and "DOORWAY" in types
    assert data["schema"]["node_types"][0] == "KITCHEN" and set(types) <= set(data["schema"]["node_types"])
    saved = client.post("/api/save", json={**data["graph"], "schema": data["schema"]})  # the page then saves it
    assert saved.status_code == 200, saved.text
    assert not [w for w in saved.json()["warnings"] if w["severity"] == "error"]


def test_description_is_saved_and_checked(client: TestClient, office: Path) -> None:
    ok = client.post("/api/description", json={"description": "  An office floor with three offices.  "})
    assert ok.status_code == 200
    assert yaml.safe_load((office / "location.yaml").read_text())["description"] == "An office floor with three offices."
    assert (office / "location.yaml.bak").is_file()
    assert client.get("/api/location").json()["description"] == "An office floor with three offices."
    for bad in ({"description": ""}, {"description": "x" * 5000}, {"description": "bell\x07"}):
        assert client.post("/api/description", json=bad).status_code == 422
    assert client.post("/api/description", json={"text": "no"}).status_code == 422
    assert yaml.safe_load((office / "location.yaml").read_text())["description"] == "An office floor with three offices."


def test_the_page_and_location_check_give_the_same_level(tmp_path: Path) -> None:
    """An edge through racks is an error on the page (live check and after saving) exactly as in
    `location check`; an edge that only clips a wall corner is fine in both."""
    import shutil

    from socnavgen.location.check import check_location

    root = tmp_path / "warehouse"
    shutil.copytree(Path(__file__).resolve().parents[2] / "examples" / "locations" / "warehouse", root)
    client = TestClient(create_app(root), base_url=BASE)
    state = client.get("/api/location").json()
    graph = state["graph"]
    graph["links"].append({"source": "hd", "target": "qs", "type": "PASSAGEWAY"})  # across the racks
    body = {**graph, "schema": state["schema"]}
    live = client.post("/api/check", json=body).json()["warnings"]
    through = [w for w in live if w["edge"] and set(w["edge"]) == {"hd", "qs"}]
    assert [w["severity"] for w in through] == ["error"]
    assert client.post("/api/save", json=body).status_code == 200
    cli = [p for p in check_location(root).problems if p.edge and set(p.edge) == {"hd", "qs"}]
    assert [p.level for p in cli] == ["error"] and cli[0].message == through[0]["message"]
