"""Importing the real SocRATES small_warehouse annotator folder."""

from __future__ import annotations

import json

import pytest
import yaml
from typer.testing import CliRunner

from socnavgen.cli import app
from socnavgen.errors import InputFileError
from socnavgen.location import load_location
from socnavgen.location.check import check_location
from socnavgen.location.importer import import_socrates


def test_import_socrates_warehouse_passes_check(reference_dir, tmp_path) -> None:
    src = reference_dir / "socrates" / "small_warehouse"
    out = tmp_path / "sw"
    result = import_socrates(src, out)
    report = check_location(out)
    # no error; the only warnings are its hand-drawn edges through gaps a person passes and the 0.8 m robot does not
    assert report.errors == []
    assert sorted(p.edge for p in report.warnings) == [("2f", "cf"), ("3e", "35"), ("cf", "32")]
    assert all("not for the robot" in p.message for p in report.warnings)
    assert report.nodes == 18 and report.edges == 19
    # graph kept as is: same ids, types and pixel positions as the source
    original = json.loads((src / "scene_graph.json").read_text())
    imported = json.loads((out / "scene_graph.json").read_text())
    assert imported == original
    assert set(result.schema.node_types) == {n["type"] for n in original["nodes"]}
    loc = load_location(out)
    # node 49 at pixel (134, 101) on a 250 px, 0.1 m map with origin (-12.5, -12.5): centre (0.95, 2.35)
    assert loc.node_world("49") == pytest.approx((0.95, 2.35))
    assert (out / "scene_graph.png").is_file()


def test_import_with_annotator_config_adds_missing_types(reference_dir, tmp_path) -> None:
    src = reference_dir / "socrates" / "small_warehouse"
    config = reference_dir / "data" / "socrates-generator" / "annotator" / "config.yaml"
    result = import_socrates(src, tmp_path / "sw", config=config)
    assert result.schema.node_types[:5] == ["INTERSECTION", "OPEN AREA", "SIMPLE NODE", "BLIND CORNER",
                                            "ENTRANCE/EXIT"]
    assert "PASSAGEWAY_END" in result.schema.node_types  # used by the graph, absent from the config
    assert "NARROW PASSAGEWAY" in result.schema.edge_types
    assert any("PASSAGEWAY_END" in n for n in result.notes)
    cfg = yaml.safe_load((tmp_path / "sw" / "location.yaml").read_text())
    assert cfg["nav2_map"] == "map.yaml" and cfg["map"] == "map.pgm"
    assert check_location(tmp_path / "sw").ok


def test_import_refuses_to_overwrite(reference_dir, tmp_path) -> None:
    src = reference_dir / "socrates" / "small_warehouse"
    import_socrates(src, tmp_path / "sw")
    with pytest.raises(InputFileError, match="already holds a location"):
        import_socrates(src, tmp_path / "sw")
    import_socrates(src, tmp_path / "sw", force=True)


def test_import_cli(reference_dir, tmp_path) -> None:
    src = reference_dir / "socrates" / "small_warehouse"
    result = CliRunner().invoke(app, ["location", "import-socrates", str(src), "-o", str(tmp_path / "sw"),
                                      "--name", "socrates_warehouse"])
    assert result.exit_code == 0, result.output
    assert "18 nodes, 19 edges; check: 0 error(s), 3 warning(s)" in result.output
    assert load_location(tmp_path / "sw").name == "socrates_warehouse"


def test_import_missing_folder(tmp_path) -> None:
    with pytest.raises(InputFileError, match="not found"):
        import_socrates(tmp_path / "nope", tmp_path / "out")


def test_import_socrates_arena_whose_edge_clips_a_wall_by_one_pixel(tmp_path) -> None:
    """The issue's case: an edge of SocRATES's arena graph touches one occupied pixel. With the
    clearance rule that is a step around, not a wall crossing: the import passes `location check`,
    and the same CLI exit code 0 follows."""
    from pathlib import Path

    from socnavgen.location.traverse import first_tight_pixel

    src = Path(__file__).resolve().parents[1] / "extract" / "data" / "socrates_arena"
    import_socrates(src, tmp_path / "arena")
    location = load_location(tmp_path / "arena")
    touching = [e for e in location.scene_graph.links
                if first_tight_pixel(location.occupancy.clearance_px, location.scene_graph.node(e.source).pos,
                                     location.scene_graph.node(e.target).pos, 1.0) is not None]
    assert touching, "the arena graph should have an edge that touches an occupied pixel"
    assert check_location(tmp_path / "arena").errors == []
    result = CliRunner().invoke(app, ["location", "import-socrates", str(src), "-o", str(tmp_path / "cli")])
    assert result.exit_code == 0, result.output
