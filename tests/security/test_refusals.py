"""Input that must be refused with one message (exit 2), before any work or any copy (issue 17)."""

from __future__ import annotations

import io
import json
import struct
import time
import zipfile
import zlib
from pathlib import Path

import numpy as np
import pytest
import yaml

from socnavgen.errors import InputFileError
from socnavgen.location.location import load_location
from socnavgen.run import RunFolder
from socnavgen.sim.trace import Trace

from .conftest import no_traceback


def refused_by_check(result, words: str) -> bool:  # noqa: ANN001
    """`location check` ends with 2 (unreadable input) or 1 (errors in its table), naming the problem."""
    return result.code in (1, 2) and words in result.out + result.err and "0 error(s)" not in result.out




# ---- symlinks leaving their folder ------------------------------------------------------------
def test_behavior_file_symlinked_outside_the_run_is_refused(run_dir, tmp_path, cli):
    secret = tmp_path / "secret.xml"
    secret.write_text("<root>outside content</root>")
    (run_dir / "behaviors" / "human1.xml").unlink()
    (run_dir / "behaviors" / "human1.xml").symlink_to(secret)
    with pytest.raises(InputFileError, match="leaves"):
        RunFolder(run_dir).behaviors()
    out = tmp_path / "export"
    result = cli("export", run_dir, "-o", out)
    assert result.code == 2 and "leaves" in result.err and not out.exists()


def test_behaviors_folder_symlinked_outside_the_run_is_refused(run_dir, tmp_path):
    outside = tmp_path / "elsewhere"
    (run_dir / "behaviors").rename(outside)
    (run_dir / "behaviors").symlink_to(outside)
    with pytest.raises(InputFileError, match="leaves"):
        RunFolder(run_dir).behaviors()


def test_scene_graph_symlinked_outside_the_location_is_refused(location, tmp_path, cli):
    outside = tmp_path / "outside.json"
    (location / "scene_graph.json").rename(outside)
    (location / "scene_graph.json").symlink_to(outside)
    with pytest.raises(InputFileError, match="leaves"):
        _ = load_location(location).scene_graph
    result = cli("location", "check", location)
    assert refused_by_check(result, "leaves") and no_traceback(result.err)


def test_run_file_symlinked_outside_is_refused(run_dir, tmp_path):
    outside = tmp_path / "paths_elsewhere.json"
    (run_dir / "paths.json").rename(outside)
    (run_dir / "paths.json").symlink_to(outside)
    with pytest.raises(InputFileError, match="leaves"):
        RunFolder(run_dir).read_paths()


def test_nav2_image_pointing_outside_is_not_copied_by_import(tmp_path, cli):
    secret = tmp_path / "id_rsa"
    secret.write_text("-----BEGIN KEY----- not an image")
    source = tmp_path / "socrates"
    source.mkdir()
    (source / "map.yaml").write_text(yaml.safe_dump({"image": str(secret), "resolution": 0.05, "origin": [0, 0, 0]}))
    (source / "scene_graph.json").write_text(json.dumps({"nodes": [], "links": []}))
    out = tmp_path / "imported"
    result = cli("location", "import-socrates", source, "-o", out)
    assert result.code == 2 and no_traceback(result.err)
    assert not out.exists() or not any("BEGIN KEY" in p.read_text(errors="ignore") for p in out.rglob("*")
                                       if p.is_file())


# ---- numbers and names that break downstream code ---------------------------------------------
def _edit_graph(location: Path, edit) -> None:  # noqa: ANN001
    data = json.loads((location / "scene_graph.json").read_text())
    edit(data)
    (location / "scene_graph.json").write_text(json.dumps(data))


@pytest.mark.parametrize("node_id", ["sk\n", "a\tb", "\x1b["])
def test_node_ids_with_control_characters_fail_location_check(location, cli, node_id):
    _edit_graph(location, lambda g: g["nodes"][0].update(id=node_id))
    result = cli("location", "check", location)
    assert refused_by_check(result, "control characters") and no_traceback(result.err)


@pytest.mark.parametrize("pos", [["NaN", 3], [3, "Infinity"], [1e300, 3]])
def test_non_finite_or_absurd_node_positions_are_refused_everywhere(location, run_dir, tmp_path, cli, pos):
    data = json.loads((location / "scene_graph.json").read_text())
    data["nodes"][0]["pos"] = "__POS__"
    literal = "[" + ", ".join(str(v) for v in pos) + "]"  # NaN / Infinity: what Python's json writes and reads
    (location / "scene_graph.json").write_text(json.dumps(data).replace('"__POS__"', literal))
    assert refused_by_check(cli("location", "check", location), "finite numbers")
    for command in (("simulate", run_dir, "--timeout", "1"), ("export", run_dir, "-o", tmp_path / "export")):
        result = cli(*command)
        assert result.code == 2 and "finite numbers" in result.err and no_traceback(result.err), command
    assert not (tmp_path / "export").exists() and not (run_dir / "sim").exists()


@pytest.mark.parametrize("matrix", [[[0.05, 0, float("nan")], [0, -0.05, 2], [0, 0, 1]],
                                    [[float("inf"), 0, 0], [0, -0.05, 2], [0, 0, 1]]])
def test_non_finite_pixel_to_world_is_refused(location, cli, matrix):
    config = yaml.safe_load((location / "location.yaml").read_text())
    config.pop("nav2_map")
    config["pixel_to_world"] = matrix
    (location / "location.yaml").write_text(yaml.safe_dump(config))
    result = cli("location", "check", location)
    assert refused_by_check(result, "finite") and no_traceback(result.err)


def test_non_finite_nav2_origin_is_refused(location, cli):
    nav2 = yaml.safe_load((location / "map.yaml").read_text())
    nav2["origin"] = [float("nan"), 0.0, 0.0]
    (location / "map.yaml").write_text(yaml.safe_dump(nav2))
    result = cli("location", "check", location)
    assert refused_by_check(result, "finite") and no_traceback(result.err)


@pytest.mark.parametrize("args", [("verify", "{run}", "--distance", "inf"), ("verify", "{run}", "--distance=nan"),
                                  ("verify", "{run}", "--passing", "-Infinity"),
                                  ("simulate", "{run}", "--timeout", "inf"), ("simulate", "{run}", "--timeout", "1e9"),
                                  ("simulate", "{run}", "--timeout", "1e999"), ("simulate", "{run}", "--dt", "0")])
def test_absurd_numbers_on_the_command_line_are_refused(run_dir, cli, args):
    started = time.monotonic()
    result = cli(*(a.format(run=run_dir) for a in args))
    assert result.code == 2 and "finite number" in result.err and no_traceback(result.err)
    assert time.monotonic() - started < 15 and not (run_dir / "sim").exists()


def test_a_step_count_beyond_the_cap_is_refused(run_dir, cli):
    result = cli("simulate", run_dir, "--timeout", "3600", "--dt", "0.001")
    assert result.code == 2 and "steps, more than" in result.err


def test_more_humans_than_the_cap_are_refused(run_dir, cli):
    data = json.loads((run_dir / "paths.json").read_text())
    data["humans"] = [{"name": f"human{i}", "path": ["aa"]} for i in range(1, 10_001)]
    (run_dir / "paths.json").write_text(json.dumps(data))
    started = time.monotonic()
    result = cli("simulate", run_dir, "--timeout", "10")
    assert result.code == 2 and "humans" in result.err and no_traceback(result.err)
    assert time.monotonic() - started < 20  # 10,000 humans would run for many minutes


# ---- deep JSON, huge integers, huge images ----------------------------------------------------
@pytest.mark.parametrize("payload", ["[" * 100_000 + "]" * 100_000, '{"nodes": ' + "[" * 100_000 + "]" * 100_000 + "}",
                                     '{"nodes": [], "links": [], "x": ' + "7" * 5000 + "}"])
def test_hostile_scene_graph_json_is_one_message(location, cli, payload):
    (location / "scene_graph.json").write_text(payload)
    result = cli("location", "check", location)
    assert refused_by_check(result, "refused") and no_traceback(result.err)


def test_deeply_nested_paths_json_is_one_message(run_dir, cli):
    (run_dir / "paths.json").write_text('{"robot": ' + "[" * 100_000 + "]" * 100_000 + "}")
    result = cli("simulate", run_dir, "--timeout", "1")
    assert result.code == 2 and "nested" in result.err and no_traceback(result.err)


def png_header_only(width: int, height: int) -> bytes:
    """A PNG that declares its size and holds (almost) no pixels: what a decompression bomb looks like."""
    def chunk(kind: bytes, data: bytes) -> bytes:
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))

    ihdr = struct.pack(">IIBBBBB", width, height, 8, 0, 0, 0, 0)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", zlib.compress(b"")) + chunk(b"IEND", b"")


def test_images_over_the_pixel_budget_are_refused_before_decoding(location, cli):
    config = yaml.safe_load((location / "location.yaml").read_text())
    (location / "huge.png").write_bytes(png_header_only(13000, 13000))
    config["map"] = "huge.png"
    config.pop("nav2_map")
    config["pixel_to_world"] = [[0.05, 0, 0], [0, -0.05, 2], [0, 0, 1]]
    (location / "location.yaml").write_text(yaml.safe_dump(config))
    started = time.monotonic()
    result = cli("location", "check", location)
    assert refused_by_check(result, "image is 13000 x") and "huge.png" in result.out and no_traceback(result.err)
    assert time.monotonic() - started < 15  # decoding would take seconds and gigabytes


# ---- malformed and hostile traces -------------------------------------------------------------
def _good_trace() -> Trace:
    steps, humans = 5, 2
    return Trace(dt=0.1, t=np.arange(steps) * 0.1, robot=np.zeros((steps, 6)), humans=np.zeros((steps, humans, 6)),
                 human_names=["human1", "human2"], group_ids=[-1, -1], human_radii=np.full(humans, 0.4),
                 robot_radius=0.35, node_names=["RegularNav"], action=np.zeros((steps, humans), np.int16),
                 succeeded=np.zeros((steps, humans), np.int64), human_gesture=np.zeros((steps, humans), np.int8),
                 robot_gesture=np.zeros(steps, np.int8), behavior_state=np.zeros((steps, humans), np.int8))


def _rewrite(path: Path, **replace: bytes | np.ndarray) -> None:
    with np.load(path) as data:
        arrays = {k: data[k] for k in data.files}
    for key, value in replace.items():
        arrays[key] = np.frombuffer(value, np.uint8) if isinstance(value, bytes) else value
    buf = io.BytesIO()
    np.savez_compressed(buf, **arrays)
    path.write_bytes(buf.getvalue())


def test_a_good_trace_round_trips(tmp_path):
    _good_trace().save(tmp_path / "trace.npz")
    assert Trace.load(tmp_path / "trace.npz").humans.shape == (5, 2, 6)


@pytest.mark.parametrize("damage", [
    {"humans": np.zeros((5, 3, 6))}, {"robot": np.zeros((4, 6))}, {"action": np.zeros((5,), np.int16)},
    {"meta": b"not json at all"}, {"meta": b'{"dt": 0.1}'}, {"meta": b"[" * 100_000},
    {"t": np.array(["a", "b"])},
])
def test_malformed_traces_are_one_message(tmp_path, damage):
    path = tmp_path / "trace.npz"
    _good_trace().save(path)
    _rewrite(path, **damage)
    with pytest.raises(InputFileError, match="not a usable trace"):
        Trace.load(path)


def test_not_a_zip_is_one_message(tmp_path):
    (tmp_path / "trace.npz").write_bytes(b"PK\x03\x04 garbage")
    with pytest.raises(InputFileError, match="not a usable trace"):
        Trace.load(tmp_path / "trace.npz")


def test_a_zip_bomb_trace_is_refused_from_its_headers(tmp_path, monkeypatch):
    import socnavgen.sim.trace as trace_module

    monkeypatch.setattr(trace_module, "MAX_TRACE_BYTES", 50_000_000)
    path = tmp_path / "trace.npz"
    _good_trace().save(path)
    with np.load(path) as data:
        arrays = {k: data[k] for k in data.files}
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as archive:
        for name, value in arrays.items():
            if name == "humans":  # 80 MB of zeros compress to ~80 kB
                with archive.open("humans.npy", "w", force_zip64=True) as fh:
                    np.lib.format.write_array(fh, np.zeros((10_000_000,), np.float64))
            else:
                buf = io.BytesIO()
                np.lib.format.write_array(buf, value)
                archive.writestr(f"{name}.npy", buf.getvalue())
    assert path.stat().st_size < 1_000_000
    with pytest.raises(InputFileError, match="more than the 50000000 allowed"):
        Trace.load(path)


def test_an_npy_header_lying_about_its_shape_is_refused(tmp_path):
    path = tmp_path / "trace.npz"
    _good_trace().save(path)
    with np.load(path) as data:
        arrays = {k: data[k] for k in data.files}
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as archive:
        for name, value in arrays.items():
            buf = io.BytesIO()
            np.lib.format.write_array(buf, value)
            raw = buf.getvalue()
            if name == "t":  # claim 10^12 floats in a tiny entry
                header = {"descr": "<f8", "fortran_order": False, "shape": (10**12,)}
                head = io.BytesIO()
                np.lib.format.write_array_header_1_0(head, header)
                raw = b"\x93NUMPY\x01\x00"[:0] + head.getvalue() + b"\0" * 40
            archive.writestr(f"{name}.npy", raw)
    with pytest.raises(InputFileError, match="claims"):
        Trace.load(path)
