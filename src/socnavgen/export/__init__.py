"""Export a run folder to the files HuNavSim loads (SocRATES fork, upstream 2.x, upstream 1.x)."""

from __future__ import annotations

from pathlib import Path

from socnavgen.export.models import FORMATS, ExportedFile, ExportFormat, ExportResult, ExportScene
from socnavgen.export.scene import build_scene
from socnavgen.export.targets import get_target
from socnavgen.export.writer import write_export


def build_files(scene: ExportScene, fmt: ExportFormat, *, base: str | None = None,
                simulator: str = "Gazebo Classic") -> list[ExportedFile]:
    """All files of one target, in memory (raises before anything is written)."""
    return get_target(fmt).build(scene, base=base or "", simulator=simulator)


def export_run(run_dir: Path | str, fmt: ExportFormat, out_dir: Path | str, *, location_dir: Path | str | None = None,
               base: str | None = None, simulator: str = "Gazebo Classic", force: bool = False) -> ExportResult:
    """Read the run, build every file of `fmt`, then write them atomically under out_dir."""
    scene, _ = build_scene(run_dir, location_dir)
    files = build_files(scene, fmt, base=base, simulator=simulator)
    written = write_export(out_dir, files, force=force)
    out = Path(out_dir)
    return ExportResult(format=fmt, out_dir=str(out),
                        files=[str(p.relative_to(out.resolve())) for p in written])


__all__ = ["FORMATS", "ExportResult", "build_files", "build_scene", "export_run"]
