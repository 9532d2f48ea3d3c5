"""Every output folder is the old state or the new state after any failure (issue 17): exports,
annotator saves, multi-file transactions, imports that must not overwrite their own input."""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest
import yaml
from PIL import Image
from starlette.testclient import TestClient

from socnavgen.atomic_files import EXPORT_MARKER, write_files_atomically
from socnavgen.errors import InputFileError
from socnavgen.export import export_run

from .conftest import no_traceback


def snapshot(folder: Path) -> dict[str, bytes]:
    return {str(p.relative_to(folder)): p.read_bytes() for p in sorted(folder.rglob("*")) if p.is_file()}


def test_export_refuses_a_foreign_non_empty_folder_and_leaves_it_alone(run_dir, tmp_path, cli):
    out = tmp_path / "mine"
    out.mkdir()
    (out / "README.md").write_text("my own notes")
    before = snapshot(out)
    result = cli("export", run_dir, "-o", out)
    assert result.code == 2 and "not written by socnavgen export" in result.err and "--force" in result.err
    assert no_traceback(result.err) and snapshot(out) == before
    result = cli("export", run_dir, "-o", out, "--force")  # --force never replaces a file export did not write
    assert result.code == 2 and "it did not write" in result.err and "README.md" in result.err
    assert snapshot(out) == before and not (out / EXPORT_MARKER).exists()


def test_re_export_leaves_no_stale_file_of_the_earlier_export(run_dir, tmp_path):
    out = tmp_path / "export"
    first = export_run(run_dir, "socrates", out)
    assert "LLMBT_1.xml" in " ".join(first.files)
    paths = json.loads((run_dir / "paths.json").read_text())
    paths["humans"] = paths["humans"][:1]  # now one human: LLMBT_1.xml must go away
    (run_dir / "paths.json").write_text(json.dumps(paths))
    (run_dir / "behaviors" / "human2.xml").unlink()
    export_run(run_dir, "socrates", out)
    names = {p.name for p in out.rglob("*")}
    assert "LLMBT_0.xml" in names and "LLMBT_1.xml" not in names
    assert [p.name for p in tmp_path.iterdir() if p.name.startswith(".")] == []  # no temp folders left


def test_a_failure_half_way_through_an_export_keeps_the_old_export(run_dir, tmp_path, monkeypatch):
    out = tmp_path / "export"
    export_run(run_dir, "socrates", out)
    (out / "README.md").write_text((out / "README.md").read_text())  # same content: still the export's
    paths = json.loads((run_dir / "paths.json").read_text())
    paths["humans"][0]["group_id"] = 3  # the next export differs in its agents yaml
    (run_dir / "paths.json").write_text(json.dumps(paths))
    before = snapshot(out)
    calls = {"n": 0}
    real = os.replace

    def fail_on_third(src, dst):  # noqa: ANN001
        calls["n"] += 1
        if calls["n"] == 3:
            raise OSError(28, "No space left on device", str(dst))
        real(src, dst)

    monkeypatch.setattr("socnavgen.atomic_files.os.replace", fail_on_third)
    with pytest.raises(OSError):
        export_run(run_dir, "socrates", out)
    assert snapshot(out) == before
    assert [p.name for p in out.rglob(".*") if p.name != EXPORT_MARKER] == []  # no temp file left


def test_an_export_target_that_is_a_file_is_refused(run_dir, tmp_path):
    target = tmp_path / "a_file"
    target.write_text("x")
    with pytest.raises(InputFileError, match="not a folder"):
        export_run(run_dir, "socrates", target)
    assert target.read_text() == "x"


def test_multi_file_write_with_a_folder_in_the_way_changes_nothing(tmp_path):
    (tmp_path / "a.json").write_text("old a")
    (tmp_path / "b.png").mkdir()
    with pytest.raises(InputFileError, match="folder of that name"):
        write_files_atomically({tmp_path / "a.json": b"new a", tmp_path / "b.png": b"new b"})
    assert (tmp_path / "a.json").read_text() == "old a" and sorted(p.name for p in tmp_path.iterdir()) == [
        "a.json", "b.png"]


def test_multi_file_write_failing_on_a_later_rename_restores_the_earlier_files(tmp_path, monkeypatch):
    (tmp_path / "a.json").write_text("old a")
    (tmp_path / "b.png").write_text("old b")
    real_replace = os.replace
    renamed: list[str] = []

    def replace(src, dst):  # noqa: ANN001
        if Path(dst).name == "b.png" and Path(src).name.startswith(".b.png") and not renamed:
            renamed.append("refused")
            raise PermissionError(13, "Permission denied", str(dst))
        real_replace(src, dst)

    monkeypatch.setattr("socnavgen.atomic_files.os.replace", replace)
    with pytest.raises(PermissionError):
        write_files_atomically({tmp_path / "a.json": b"new a", tmp_path / "b.png": b"new b"})
    assert (tmp_path / "a.json").read_text() == "old a" and (tmp_path / "b.png").read_text() == "old b"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.json", "b.png"]


def _room(tmp_path: Path) -> Path:
    root = tmp_path / "room"
    root.mkdir()
    Image.new("L", (200, 150), 254).save(root / "map.png")
    (root / "location.yaml").write_text(yaml.safe_dump({
        "name": "room", "description": "d", "map": "map.png",
        "pixel_to_world": [[0.05, 0, 0], [0, -0.05, 7.5], [0, 0, 1]],
        "schema": {"node_types": ["OPEN AREA"], "edge_types": ["PASSAGEWAY"]}}))
    return root


def _graph_body(*nodes: tuple[str, int, int]) -> dict:
    return {"nodes": [{"id": i, "type": "OPEN AREA", "pos": [x, y]} for i, x, y in nodes], "links": [],
            "schema": {"node_types": ["OPEN AREA"], "edge_types": ["PASSAGEWAY"]}}


def test_annotator_save_failing_on_the_image_keeps_the_old_scene_graph(tmp_path):
    from socnavgen.annotate.server import create_app

    root = _room(tmp_path)
    client = TestClient(create_app(root), base_url="http://127.0.0.1:8765")
    assert client.post("/api/save", json=_graph_body(("a1", 20, 20))).status_code == 200
    before = snapshot(root)
    (root / "scene_graph.png").unlink()
    (root / "scene_graph.png").mkdir()  # the image cannot be written
    before = {k: v for k, v in before.items() if k != "scene_graph.png"}
    response = client.post("/api/save", json=_graph_body(("a1", 20, 20), ("b2", 60, 60)))
    assert response.status_code >= 400 and "Traceback" not in response.text
    assert snapshot(root) == before  # scene_graph.json and its .bak untouched


@pytest.mark.parametrize("body", [b"[" * 100_000 + b"]" * 100_000, b'{"nodes": ' + b"[" * 50_000 + b"]" * 50_000 + b"}",
                                  b'{"nodes": [], "links": [], "n": ' + b"9" * 5000 + b"}"])
def test_annotator_refuses_hostile_json_bodies_without_a_500(tmp_path, body):
    from socnavgen.annotate.server import create_app

    client = TestClient(create_app(_room(tmp_path)), base_url="http://127.0.0.1:8765", raise_server_exceptions=False)
    response = client.post("/api/save", content=body, headers={"content-type": "application/json"})
    assert 400 <= response.status_code < 500 and "refused" in response.json()["error"]
    assert not (tmp_path / "room" / "scene_graph.json").exists()


def test_import_socrates_keeps_a_map_named_scene_graph_png(tmp_path, cli):
    source = tmp_path / "socrates"
    source.mkdir()
    Image.new("L", (60, 40), 254).save(source / "scene_graph.png")
    (source / "map.yaml").write_text(yaml.safe_dump({"image": "scene_graph.png", "resolution": 0.05,
                                                     "origin": [0.0, 0.0, 0.0], "negate": 0,
                                                     "occupied_thresh": 0.65, "free_thresh": 0.196}))
    (source / "scene_graph.json").write_text(json.dumps({"nodes": [{"id": "aa", "type": "A", "pos": [10, 10]}],
                                                         "links": [{"source": "aa", "target": "aa", "type": "P"}]}))
    out = tmp_path / "imported"
    result = cli("location", "import-socrates", source, "-o", out)
    assert result.code in (0, 1) and "map_image.png" in result.out, result.err  # 1: check warns on the toy graph
    config = yaml.safe_load((out / "location.yaml").read_text())
    assert config["map"] != "scene_graph.png"
    with Image.open(out / config["map"]) as kept:
        assert kept.size == (60, 40) and kept.getpixel((5, 5)) == 254  # the map itself, not the rendering
    assert yaml.safe_load((out / "map.yaml").read_text())["image"] == config["map"]
