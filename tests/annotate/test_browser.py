"""Drives the real annotator page in headless Chromium: clicks add nodes, drags add edges, Save
writes scene_graph.json, undo works, and a refused save leaves the previous file untouched."""

from __future__ import annotations

import json
import re
import socket
from pathlib import Path

import pytest
from PIL import Image

from socnavgen.annotate.server import create_app, serve_in_thread

CHROMIUM = Path("/usr/bin/chromium")
ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
        "--disable-background-networking", "--disable-component-update", "--disable-sync"]

pytestmark = [pytest.mark.browser, pytest.mark.timeout(120)]


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.fixture
def page(room_location: Path, tmp_path: Path):
    from playwright import sync_api  # installed by `make test`: missing = failure, not skip
    if not CHROMIUM.exists():
        pytest.fail("Debian's chromium is not installed at /usr/bin/chromium (make test installs it)")
    port = free_port()
    server, thread = serve_in_thread(create_app(room_location), port)
    with sync_api.sync_playwright() as pw:
        context = pw.chromium.launch_persistent_context(
            str(tmp_path / "profile"), executable_path=str(CHROMIUM), args=ARGS, headless=True,
            viewport={"width": 1200, "height": 800})
        pg = context.new_page()
        errors: list[str] = []
        pg.on("pageerror", lambda exc: errors.append(str(exc)))
        pg.goto(f"http://127.0.0.1:{port}/")
        pg.wait_for_selector("body[data-ready='1']", timeout=10_000)
        yield pg
        context.close()
    server.should_exit = True
    thread.join(timeout=5)
    assert not errors, f"JavaScript errors on the page: {errors}"


def at(page, x: float, y: float) -> tuple[float, float]:
    """Client coordinates of the centre of image pixel (x, y) in the current view."""
    cx, cy = page.evaluate("([x, y]) => window.annotator.imageToClient(x, y)", [x, y])
    return cx, cy


def click_pixel(page, x: float, y: float, **kw) -> None:
    page.mouse.click(*at(page, x, y), **kw)


def drag(page, a: tuple[float, float], b: tuple[float, float], shift: bool = False) -> None:
    if shift:
        page.keyboard.down("Shift")
    page.mouse.move(*at(page, *a))
    page.mouse.down()
    page.mouse.move(*at(page, *b), steps=8)
    page.mouse.up()
    if shift:
        page.keyboard.up("Shift")


def save_and_wait(page) -> str:
    page.click("#save")
    page.wait_for_function("() => !/saving/.test(document.querySelector('#status').textContent)")
    return page.text_content("#status")


def read_graph(folder: Path) -> dict:
    return json.loads((folder / "scene_graph.json").read_text())


def test_draw_save_undo_and_refused_save(page, room_location: Path, tmp_path: Path) -> None:
    click_pixel(page, 30, 40)
    click_pixel(page, 60, 120)
    page.check("input[name='node-type'][data-type='OPEN AREA']")
    click_pixel(page, 160, 40)
    page.check("input[name='edge-type'][data-type='NARROW']")
    drag(page, (30, 40), (60, 120))
    page.check("input[name='edge-type'][data-type='PASSAGEWAY']")
    drag(page, (30, 40), (160, 40))  # crosses the wall block: a warning after saving
    assert page.text_content("#counts") == "3 nodes, 2 edges"

    status = save_and_wait(page)
    assert status.startswith("saved 3 nodes, 2 edges"), status
    graph = read_graph(room_location)
    assert (room_location / "scene_graph.png").stat().st_size > 0
    by_pos = {tuple(n["pos"]): n for n in graph["nodes"]}
    assert len(graph["nodes"]) == 3
    for n in graph["nodes"]:
        assert re.fullmatch(r"[a-z0-9]{2}", n["id"])
    expected = {(30, 40): "INTERSECTION", (60, 120): "INTERSECTION", (160, 40): "OPEN AREA"}
    ids = {}
    for (x, y), node_type in expected.items():
        near = [n for p, n in by_pos.items() if abs(p[0] - x) <= 1 and abs(p[1] - y) <= 1]
        assert len(near) == 1, f"no saved node near ({x}, {y}): {graph['nodes']}"
        assert near[0]["type"] == node_type
        ids[(x, y)] = near[0]["id"]
    links = {(frozenset((e["source"], e["target"])), e["type"]) for e in graph["links"]}
    assert links == {(frozenset((ids[(30, 40)], ids[(60, 120)])), "NARROW"),
                     (frozenset((ids[(30, 40)], ids[(160, 40)])), "PASSAGEWAY")}
    page.screenshot(path=str(tmp_path / "annotator_warnings.png"))
    warnings = page.locator("#warnings li").all_text_contents()
    assert any(ids[(30, 40)] in w and ids[(160, 40)] in w for w in warnings), warnings

    # move a node with Shift+drag, then undo it; add a node and undo / redo it
    drag(page, (60, 120), (70, 130), shift=True)
    moved = page.evaluate("() => window.annotator.state().graph.nodes")
    assert any(n["pos"] == [70, 130] for n in moved)
    page.keyboard.press("Control+z")
    assert any(n["pos"] == [60, 120] for n in page.evaluate("() => window.annotator.state().graph.nodes"))
    click_pixel(page, 40, 130)
    assert page.text_content("#counts") == "4 nodes, 2 edges"
    page.keyboard.press("Control+z")
    assert page.text_content("#counts") == "3 nodes, 2 edges"
    page.keyboard.press("Control+y")
    assert page.text_content("#counts") == "4 nodes, 2 edges"
    page.click("#undo")
    assert page.text_content("#counts") == "3 nodes, 2 edges"

    # delete the crossing edge with the Delete tool, save, and the warning is gone
    page.check("input[name='tool'][value='delete']")
    click_pixel(page, 120, 40)
    assert page.text_content("#counts") == "3 nodes, 1 edges"
    assert save_and_wait(page).startswith("saved 3 nodes, 1 edges")
    assert len(read_graph(room_location)["links"]) == 1
    assert page.locator("#warnings li.error").count() == 0
    before = (room_location / "scene_graph.json").read_bytes()
    page.screenshot(path=str(tmp_path / "annotator.png"))

    # remove a node type that nodes still use: the server refuses the save, the file is untouched
    page.locator("#node-types li", has_text="OPEN AREA").locator("button").click()
    status = save_and_wait(page)
    assert "not saved" in status and "OPEN AREA" in status, status
    assert (room_location / "scene_graph.json").read_bytes() == before
    assert "OPEN AREA" in (room_location / "location.yaml").read_text()

    # a schema edit that is valid is saved into location.yaml
    page.keyboard.press("Control+z")
    page.fill("#add-edge-type input", "CROWDED AISLE")
    page.click("#add-edge-type button")
    assert save_and_wait(page).startswith("saved")
    assert "CROWDED AISLE" in (room_location / "location.yaml").read_text()
    assert (room_location / "location.yaml.bak").is_file()


def test_opening_existing_location_shows_its_graph(room_location: Path, tmp_path: Path) -> None:
    (room_location / "scene_graph.json").write_text(json.dumps({
        "directed": False, "multigraph": False, "graph": {},
        "nodes": [{"type": "OPEN AREA", "pos": [20, 20], "id": "k1"}, {"type": "OPEN AREA", "pos": [50, 20], "id": "k2"}],
        "links": [{"type": "PASSAGEWAY", "source": "k1", "target": "k2"}]}))
    from playwright import sync_api  # installed by `make test`: missing = failure, not skip
    port = free_port()
    server, thread = serve_in_thread(create_app(room_location), port)
    try:
        with sync_api.sync_playwright() as pw:
            context = pw.chromium.launch_persistent_context(
                str(tmp_path / "profile2"), executable_path=str(CHROMIUM), args=ARGS, headless=True)
            pg = context.new_page()
            pg.goto(f"http://127.0.0.1:{port}/")
            pg.wait_for_selector("body[data-ready='1']", timeout=10_000)
            assert pg.text_content("#counts") == "2 nodes, 1 edges"
            click_pixel(pg, 20, 20)  # selecting a node shows its id
            assert "node k1" in pg.text_content("#selection")
            edited = tmp_path / "edited.png"
            img = Image.open(room_location / "room.pgm").convert("L")
            img.paste(0, (30, 10, 40, 140))  # a new wall across the k1-k2 edge
            img.save(edited)
            pg.set_input_files("#map-file", str(edited))
            pg.wait_for_function("() => /map replaced|not replaced/.test(document.querySelector('#status').textContent)")
            assert "map replaced" in pg.text_content("#status")
            assert "k1-k2" in " ".join(pg.locator("#warnings li").all_text_contents())
            assert (room_location / "room.pgm.bak").is_file()
            context.close()
    finally:
        server.should_exit = True
        thread.join(timeout=5)
