"""The annotator's HTTP API without a browser: shapes, limits, refusals and atomic saves."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from starlette.testclient import TestClient

from socnavgen.annotate.server import MAX_BODY_BYTES, create_app  # noqa: E402

BASE = "http://127.0.0.1:8765"


@pytest.fixture
def client(room_location: Path) -> TestClient:
    return TestClient(create_app(room_location), base_url=BASE)


def body(nodes=None, links=None, schema=None) -> dict:
    return {"nodes": nodes if nodes is not None else [
                {"id": "a1", "type": "OPEN AREA", "pos": [20, 20]},
                {"id": "b2", "type": "INTERSECTION", "pos": [50.4, 130.6]}],
            "links": links if links is not None else [{"source": "a1", "target": "b2", "type": "PASSAGEWAY"}],
            "schema": schema or {"node_types": ["INTERSECTION", "BLIND CORNER", "OPEN AREA"],
                                 "edge_types": ["PASSAGEWAY", "NARROW"]}}


def test_location_state_and_map(client: TestClient) -> None:
    state = client.get("/api/location").json()
    assert state["name"] == "room"
    assert state["image_size"] == [200, 150]
    assert state["graph"] == {"nodes": [], "links": []}
    assert state["schema"]["edge_types"] == ["PASSAGEWAY", "NARROW"]
    image = client.get("/api/map")
    assert image.headers["content-type"] == "image/png"
    assert image.content.startswith(b"\x89PNG")
    page = client.get("/")
    assert "annotator.js" in page.text and "Content-Security-Policy" in page.headers


def test_save_writes_socrates_layout_and_keeps_a_backup(client: TestClient, room_location: Path) -> None:
    first = client.post("/api/save", json=body())
    assert first.status_code == 200, first.text
    text = (room_location / "scene_graph.json").read_text()
    data = json.loads(text)
    assert data["directed"] is False and data["multigraph"] is False and data["graph"] == {}
    assert data["nodes"][1] == {"type": "INTERSECTION", "pos": [50, 131], "id": "b2"}  # integer pixels
    assert list(data["nodes"][0]) == ["type", "pos", "id"] and text.startswith('{\n    "directed"')
    assert (room_location / "scene_graph.png").read_bytes().startswith(b"\x89PNG")
    second = client.post("/api/save", json=body(links=[]))
    assert second.status_code == 200
    assert json.loads((room_location / "scene_graph.json.bak").read_text()) == data
    assert json.loads((room_location / "scene_graph.json").read_text())["links"] == []


@pytest.mark.parametrize(("payload", "status", "needle"), [
    (body(nodes=[{"id": "A1", "type": "OPEN AREA", "pos": [1, 1]}], links=[]), 422, "nodes.0.id"),
    (body(nodes=[{"id": "a1", "type": "OPEN AREA", "pos": [1, 1], "extra": 1}], links=[]), 422, "extra"),
    (body(nodes=[{"id": "a1", "type": "OPEN AREA", "pos": [1]}], links=[]), 422, "nodes.0.pos"),
    (body(nodes=[{"id": "a1", "type": "NOT A TYPE", "pos": [1, 1]}], links=[]), 422, "NOT A TYPE"),
    (body(nodes=[{"id": "a1", "type": "OPEN AREA", "pos": [500, 1]}], links=[]), 422, "outside"),
    (body(links=[{"source": "a1", "target": "zz", "type": "PASSAGEWAY"}]), 422, "'zz' does not exist"),
    (body(links=[{"source": "a1", "target": "a1", "type": "PASSAGEWAY"}]), 422, "two different nodes"),
    (body(links=[{"source": "a1", "target": "b2", "type": "PASSAGEWAY"},
                 {"source": "b2", "target": "a1", "type": "NARROW"}]), 422, "already joined"),
    (body(links=[{"source": "a1", "target": "b2", "type": "WIDE"}]), 422, "'WIDE' is not in the schema"),
    (body(nodes=[{"id": "a1", "type": "OPEN AREA", "pos": [1, 1]}, {"id": "a1", "type": "OPEN AREA", "pos": [2, 2]}],
          links=[]), 422, "used twice"),
    (body(schema={"node_types": ["A", "A"], "edge_types": ["E"]}), 422, "unique"),
    (body(schema={"node_types": ["bad\nname"], "edge_types": ["E"]}), 422, "printable"),
    (body(schema={"node_types": [], "edge_types": ["E"]}), 422, "schema.node_types"),
])
def test_bad_payloads_are_refused_with_a_reason(client: TestClient, room_location: Path, payload: dict,
                                                status: int, needle: str) -> None:
    client.post("/api/save", json=body())
    before = (room_location / "scene_graph.json").read_bytes()
    reply = client.post("/api/save", json=payload)
    assert reply.status_code == status
    assert needle in json.dumps(reply.json())
    assert (room_location / "scene_graph.json").read_bytes() == before


def test_request_limits_and_origin(client: TestClient, room_location: Path) -> None:
    huge = client.post("/api/save", content=b" " * (MAX_BODY_BYTES + 1), headers={"content-type": "application/json"})
    assert huge.status_code == 413
    assert client.post("/api/save", content=b"{not json", headers={"content-type": "application/json"}).status_code == 400
    form = client.post("/api/save", content=json.dumps(body()), headers={"content-type": "text/plain"})
    assert form.status_code == 415
    foreign = client.post("/api/save", json=body(), headers={"origin": "http://evil.example"})
    assert foreign.status_code == 403
    rebinding = TestClient(client.app, base_url="http://evil.example:8765")
    assert rebinding.get("/api/location").status_code == 400
    too_many = body(nodes=[{"id": f"{a}{b}", "type": "OPEN AREA", "pos": [1, 1]}
                           for a in "abcdefghijklmnopqrstuvwxyz0123456789" for b in "abcdefghijklmnopqrstuvwxyz0123456789"]
                    + [{"id": "zz", "type": "OPEN AREA", "pos": [1, 1]}], links=[])
    assert client.post("/api/save", json=too_many).status_code == 422
    assert not (room_location / "scene_graph.json").exists()


@pytest.mark.parametrize("path", ["/static/../store.py", "/static/..%2fstore.py", "/static/%2e%2e%2fserver.py",
                                  "/static/index.html/../../models.py", "/api/map/../../location.yaml",
                                  "/static/annotator.js%00.png", "/static/"])
def test_paths_outside_the_page_are_refused(client: TestClient, path: str) -> None:
    reply = client.get(path)
    assert reply.status_code == 404
    assert "pydantic" not in reply.text and "schema" not in reply.text


def test_map_outside_the_folder_is_refused(room_location: Path) -> None:
    config = room_location / "location.yaml"
    config.write_text(config.read_text().replace("map: room.pgm", "map: ../src/room.pgm"))
    from socnavgen.errors import InputFileError

    with pytest.raises(InputFileError, match="leaves"):
        create_app(room_location)


def test_check_endpoint_reports_walls_for_unsaved_graph(client: TestClient) -> None:
    crossing = body(nodes=[{"id": "a1", "type": "OPEN AREA", "pos": [40, 60]},
                           {"id": "b2", "type": "OPEN AREA", "pos": [160, 60]},
                           {"id": "c3", "type": "OPEN AREA", "pos": [100, 60]}],
                    links=[{"source": "a1", "target": "b2", "type": "PASSAGEWAY"}])
    warnings = client.post("/api/check", json=crossing).json()["warnings"]
    assert any(w["edge"] and set(w["edge"]) == {"a1", "b2"} for w in warnings), warnings
    assert any("c3" in w["nodes"] and not w["edge"] for w in warnings), warnings  # on the wall block
    assert client.get("/api/check").json() == {"warnings": []}  # nothing saved yet


def test_failed_render_writes_nothing(client: TestClient, room_location: Path, monkeypatch) -> None:
    assert client.post("/api/save", json=body()).status_code == 200
    before = (room_location / "scene_graph.json").read_bytes()
    png_before = (room_location / "scene_graph.png").read_bytes()

    def broken(location):
        raise OSError("disk full while rendering")

    monkeypatch.setattr("socnavgen.annotate.store.render_png", broken)
    reply = TestClient(client.app, base_url=BASE, raise_server_exceptions=False).post("/api/save", json=body(links=[]))
    assert reply.status_code == 500
    assert "disk full" in reply.json()["error"]
    assert (room_location / "scene_graph.json").read_bytes() == before
    assert (room_location / "scene_graph.png").read_bytes() == png_before


def _png(width: int, height: int, value: int = 254) -> bytes:
    import io

    from PIL import Image

    buf = io.BytesIO()
    Image.new("L", (width, height), value).save(buf, format="PNG")
    return buf.getvalue()


def test_map_replacement_is_checked_and_backed_up(client: TestClient, room_location: Path) -> None:
    old = (room_location / "room.pgm").read_bytes()
    ok = client.post("/api/map", content=_png(200, 150), headers={"content-type": "image/png"})
    assert ok.status_code == 200, ok.text
    assert (room_location / "room.pgm.bak").read_bytes() == old
    new = (room_location / "room.pgm").read_bytes()
    assert new.startswith(b"P5") and new != old  # stored in the file's own format (PGM)
    assert client.get("/api/map").content == client.get("/api/map").content
    wrong_size = client.post("/api/map", content=_png(100, 100), headers={"content-type": "image/png"})
    assert wrong_size.status_code == 422 and "size must not change" in wrong_size.text
    gif = client.post("/api/map", content=b"GIF89a" + b"\0" * 100, headers={"content-type": "image/png"})
    assert gif.status_code == 422 and "PNG or a PGM" in gif.text
    corrupt = client.post("/api/map", content=b"\x89PNG\r\n\x1a\n" + b"\0" * 50, headers={"content-type": "image/png"})
    assert corrupt.status_code == 422
    assert client.post("/api/map", content=_png(200, 150), headers={"content-type": "text/html"}).status_code == 415
    big = client.post("/api/map", content=b"P5" + b"\0" * (16 * 1024 * 1024), headers={"content-type": "image/png"})
    assert big.status_code == 413
    assert (room_location / "room.pgm").read_bytes() == new
