"""Every way a world can be broken: listed and skipped (or refused with one message naming the file),
never a traceback, never unbounded work."""

from __future__ import annotations

import struct
from pathlib import Path

import pytest
from typer.testing import CliRunner

from socnavgen.errors import InputFileError, ValidationFailed
from socnavgen.location.world_import import import_world
from socnavgen.location.world_mesh import MAX_MESH_TRIANGLES, MeshError, load_mesh_file
from socnavgen.location.world_reader import read_world
from tests.world.conftest import static_model, world_file

WALL = static_model("wall", "0 0 1 0 0 0", "<box><size>4 0.2 2</size></box>")


def _mesh_model(models: Path, name: str, mesh_name: str, data: bytes, scale: str = "1 1 1") -> None:
    folder = models / name / "meshes"
    folder.mkdir(parents=True)
    (folder / mesh_name).write_bytes(data)
    (models / name / "model.sdf").write_text(
        f'<sdf version="1.6"><model name="{name}"><static>1</static><link name="l"><collision name="c"><geometry>'
        f'<mesh><uri>model://{name}/meshes/{mesh_name}</uri><scale>{scale}</scale></mesh></geometry></collision>'
        '</link></model></sdf>')


def test_a_missing_model_is_listed_not_fatal_unless_strict(tmp_path: Path) -> None:
    world = world_file(tmp_path, WALL + "<include><name>ghost</name><uri>model://no_such_model</uri></include>")
    result = import_world(world, tmp_path / "loc")
    assert any(s.startswith("ghost:") and "no_such_model" in s for s in result.skipped)
    assert (tmp_path / "loc" / "map.pgm").is_file()
    from socnavgen.location.world_import import WorldImportOptions

    with pytest.raises(ValidationFailed, match="ghost"):
        import_world(world, tmp_path / "strict", options=WorldImportOptions(strict=True))
    assert not (tmp_path / "strict").exists()  # nothing left behind


def test_online_models_and_paths_leaving_the_folders_are_refused(tmp_path: Path) -> None:
    body = (WALL + "<include><name>fuel</name><uri>https://fuel.gazebosim.org/1.0/x/models/box</uri></include>"
            + static_model("esc", "0 0 0 0 0 0", "<mesh><uri>file:///etc/passwd</uri></mesh>"))
    world = read_world(world_file(tmp_path, body))
    why = {p.model: p.what for p in world.problems}
    assert "online" in why["fuel"] and "outside" in why["esc"]


def test_garbage_mesh_is_listed(tmp_path: Path) -> None:
    _mesh_model(tmp_path / "models", "junk", "junk.dae", b"<COLLADA><library_geometries><oops")
    body = WALL + "<include><uri>model://junk</uri></include>"
    result = import_world(world_file(tmp_path, body), tmp_path / "loc", [tmp_path / "models"])
    assert any("junk" in s and "malformed XML" in s for s in result.skipped), result.skipped


def test_nan_pose_is_listed_with_its_line(tmp_path: Path) -> None:
    body = WALL + static_model("bad", "nan 0 0 0 0 0", "<box><size>1 1 1</size></box>")
    world = read_world(world_file(tmp_path, body))
    (problem,) = world.problems
    assert problem.model == "bad" and "NaN" in problem.what and ":2" in problem.where


@pytest.mark.parametrize("scale", ["1e9 1e9 1e9", "0 1 1"])
def test_absurd_scale_is_listed(scale: str, tmp_path: Path) -> None:
    import trimesh

    buffer = trimesh.creation.box(extents=[1, 1, 1]).export(file_type="stl")
    _mesh_model(tmp_path / "models", "huge", "huge.stl", buffer, scale)
    body = WALL + "<include><uri>model://huge</uri></include>"
    result = import_world(world_file(tmp_path, body), tmp_path / "loc", [tmp_path / "models"])
    assert any("huge" in s and ("absurd" in s) for s in result.skipped), result.skipped


def test_a_billion_triangle_claim_is_refused_before_reading(tmp_path: Path) -> None:
    stl = tmp_path / "claim.stl"
    stl.write_bytes(b"\0" * 80 + struct.pack("<I", 1_000_000_000) + b"\0" * 50)
    with pytest.raises(MeshError, match="claims 1000000000 triangles"):
        load_mesh_file(stl)
    dae = tmp_path / "claim.dae"
    dae.write_text('<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema"><library_geometries><geometry>'
                   f'<mesh><triangles count="{MAX_MESH_TRIANGLES + 1}"/></mesh></geometry></library_geometries></COLLADA>')
    with pytest.raises(MeshError, match="more than"):
        load_mesh_file(dae)


BILLION_LAUGHS = ('<?xml version="1.0"?><!DOCTYPE sdf [<!ENTITY a "aaaaaaaaaa"><!ENTITY b "&a;&a;&a;&a;&a;&a;'
                  '&a;&a;&a;&a;"><!ENTITY c "&b;&b;&b;&b;&b;&b;&b;&b;&b;&b;">]><sdf version="1.6"><world name="w">'
                  '<model name="&c;"/></world></sdf>')
EXTERNAL = ('<?xml version="1.0"?><!DOCTYPE sdf [<!ENTITY x SYSTEM "file:///etc/passwd">]>'
            '<sdf version="1.6"><world name="&x;"/></sdf>')


@pytest.mark.parametrize("text", [BILLION_LAUGHS, EXTERNAL, "<sdf>" + "<model>" * 200 + "</model>" * 200 + "</sdf>",
                                  "<sdf><world><model name='x'></world></sdf>"])
def test_xml_bombs_and_malformed_xml_are_one_message(text: str, tmp_path: Path) -> None:
    world = tmp_path / "bad.world"
    world.write_text(text)
    with pytest.raises(InputFileError) as info:
        read_world(world)
    assert str(world) in info.value.render()
    _mesh = tmp_path / "bomb.dae"  # a mesh file is read the same defended way
    _mesh.write_text(text.replace("sdf", "COLLADA"))
    with pytest.raises(MeshError):
        load_mesh_file(_mesh)


def test_an_include_cycle_is_listed(tmp_path: Path) -> None:
    for name, other in (("a", "b"), ("b", "a")):
        (tmp_path / "models" / name).mkdir(parents=True)
        (tmp_path / "models" / name / "model.sdf").write_text(
            f'<sdf version="1.6"><model name="{name}"><include><uri>model://{other}</uri></include></model></sdf>')
    world = read_world(world_file(tmp_path, WALL + "<include><uri>model://a</uri></include>"), [tmp_path / "models"])
    assert any("includes itself" in p.what for p in world.problems)


def test_cli_user_errors_exit_2_without_traceback(tmp_path: Path) -> None:
    import subprocess
    import sys

    bad = tmp_path / "bad.world"
    bad.write_text(BILLION_LAUGHS)
    cmd = [sys.executable, "-c", "from socnavgen.cli import main; main()"]
    result = subprocess.run([*cmd, "location", "from-world", str(bad), "-o", str(tmp_path / "out")],
                            capture_output=True, text=True, timeout=60)
    assert result.returncode == 2, result.stdout + result.stderr
    assert "Traceback" not in result.stderr and "DTD" in result.stdout + result.stderr
    assert not (tmp_path / "out").exists()


def test_cli_imports_a_world_and_lists_what_it_skipped(tmp_path: Path) -> None:
    from socnavgen.cli import app

    room = "".join(static_model(f"w{i}", p, f"<box><size>{s}</size></box>") for i, (p, s) in enumerate([
        ("0 -3 1 0 0 0", "8.2 0.2 2"), ("0 3 1 0 0 0", "8.2 0.2 2"), ("-4 0 1 0 0 0", "0.2 6.2 2"),
        ("4 0 1 0 0 0", "0.2 6.2 2")]))
    world = world_file(tmp_path, room + "<include><name>ghost</name><uri>model://nope</uri></include>")
    result = CliRunner().invoke(app, ["location", "from-world", str(world), "-o", str(tmp_path / "loc"), "--seed", "1"])
    assert result.exit_code == 0, result.output
    assert "skipped: ghost" in result.output and "location check: 0 error(s)" in result.output
    assert "cards that fit" in result.output
