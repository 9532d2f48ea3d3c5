"""Export a run folder to the files HuNavSim loads (SocRATES fork, upstream 2.x, upstream 1.x)."""

from __future__ import annotations

from pathlib import Path

from socnavgen.export.models import FORMATS, ExportedFile, ExportFormat, ExportResult, ExportScene
from socnavgen.export.scene import build_scene
from socnavgen.export.targets import get_target
from socnavgen.export.writer import write_export
from socnavgen.run import RunFolder
from socnavgen.run.verification import VerificationStatus, verification_status


def build_files(scene: ExportScene, fmt: ExportFormat, *, base: str | None = None,
                simulator: str = "Gazebo Classic") -> list[ExportedFile]:
    """All files of one target, in memory (raises before anything is written)."""
    return get_target(fmt).build(scene, base=base or "", simulator=simulator)


def export_run(run_dir: Path | str, fmt: ExportFormat, out_dir: Path | str, *, location_dir: Path | str | None = None,
               base: str | None = None, simulator: str = "Gazebo Classic", force: bool = False,
               seed: int = 0) -> ExportResult:
    """Read the run, build every file of `fmt`, then write them atomically under out_dir (replacing only what an
    earlier export wrote there). `seed`: where people start around their first node, as `simulate --seed`
    spawns them. The result says whether the run passed verification (its README says it too)."""
    from socnavgen.sim.outputs.files import stale_reason

    scene, location = build_scene(run_dir, location_dir, seed=seed)
    status = verification_status(RunFolder(Path(run_dir)), stale_reason(run_dir, location))
    files = [f if f.path != "README.md" else f.model_copy(update={"text": f.text + _verification_section(status)})
             for f in build_files(scene, fmt, base=base, simulator=simulator)]
    result = write_export(out_dir, files, force=force)
    out = Path(out_dir)
    return ExportResult(format=fmt, out_dir=str(out), files=[str(p.relative_to(out.resolve())) for p in result.written],
                        kept=result.kept, removed=result.removed, verification=status.state,
                        verification_message=status.message)


def _verification_section(status: VerificationStatus) -> str:
    return f"\n## Verification\n\n{status.message}.\n"




def target_refusals(run_dir: Path | str, *, location_dir: Path | str | None = None) -> dict[str, str]:
    """Every export target that would refuse this run -> its message (the same one `export` prints), built in
    memory from one scene; targets missing from the result export it. For `generate`: say it before anyone
    tries to export."""
    from socnavgen.errors import SocnavgenError

    scene, _ = build_scene(run_dir, location_dir)
    refused: dict[str, str] = {}
    for fmt in FORMATS:
        try:
            build_files(scene, fmt)
        except SocnavgenError as exc:
            refused[fmt] = exc.message
    return refused


def hunav2_approximations(run_dir: Path | str, *, location_dir: Path | str | None = None) -> list[str]:
    """What a hunav2 export approximates (each phrase condition that becomes the robot script's geometric
    condition), one line per node: what `generate --target hunav2` says beside any refusal."""
    from socnavgen.export.hunav2 import translate_person
    from socnavgen.export.timing import with_waiting_goals

    scene, holds = with_waiting_goals(build_scene(run_dir, location_dir)[0])
    lines = []
    for human in scene.humans:
        for s in translate_person(human, None, scene, holds.get(human.name)).spoken:
            if not s.refused:
                lines.append(f"{human.tree_file}:{s.line}: {s.node} becomes: {s.text}")
    return lines


__all__ = ["FORMATS", "ExportResult", "build_files", "build_scene", "export_run", "hunav2_approximations",
           "target_refusals"]
