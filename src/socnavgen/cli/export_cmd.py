"""`socnavgen export`: a run folder -> the files HuNavSim loads."""

from __future__ import annotations

from pathlib import Path

import typer

from socnavgen.cli.common import console, err_console
from socnavgen.errors import ValidationFailed
from socnavgen.export import FORMATS, export_run


def register(app: typer.Typer) -> None:
    """Add this module's top-level command(s) to the main app."""

    @app.command("export")
    def export(
        run: Path = typer.Argument(..., help="run folder (request.json, paths.json, behaviors/*.xml)"),
        fmt: str = typer.Option("socrates", "--format", "-f",
                                help="socrates = the SocRATES fork (BT.CPP v3, LLMBT_<i>.xml, behavior 7+i); "
                                     "hunav2 = upstream HuNavSim 2.x (BT.CPP v4, per-agent trees, global_goals); "
                                     "hunav1 = upstream 1.x, built-in behaviors only (refuses custom trees)"),
        out: Path = typer.Option(..., "--out", "-o", help="output folder; files are written only inside it"),
        location: Path | None = typer.Option(None, "--location", "-l",
                                             help="location folder, if it moved since the run was generated"),
        name: str | None = typer.Option(None, "--name",
                                        help="hunav2: yaml_base_name (default socnavgen_<run folder name>)"),
        simulator: str = typer.Option("Gazebo Classic", "--simulator",
                                      help="hunav2: Gazebo Classic, Gazebo Fortress, Isaac Sim or Webots"),
        force: bool = typer.Option(False, "--force", help="write into a non-empty folder no export wrote; its files "
                                   "are never replaced or deleted (an export that would overwrite one is refused)"),
        seed: int = typer.Option(0, "--seed", help="where people start around their first node: the same spread as "
                                 "`simulate --seed` (so a group does not start inside each other)"),
    ) -> None:
        """Write the agents yaml, behavior trees, robot waypoints and a README telling where they go.

        Coordinates come from the location's own pixel->world transform. Nothing is written if any tree cannot be exported; the error lists every node that blocks it (file:line).

        Example: socnavgen export runs/blind_corner --format hunav2 -o out/blind_corner_hunav2
        """
        if fmt not in FORMATS:
            raise ValidationFailed(f"unknown --format {fmt!r}", hint="one of: " + ", ".join(FORMATS))
        result = export_run(run, fmt, out, location_dir=location, base=name, simulator=simulator,
                            force=force, seed=seed)
        console.print(f"[green]exported[/] {run} as [bold]{fmt}[/] to {out}:")
        for f in result.files:
            console.print(f"  {f}")
        if result.removed:
            console.print(f"removed {len(result.removed)} file(s) of the earlier export: {', '.join(result.removed)}",
                          highlight=False)
        if result.kept:
            console.print(f"left alone {len(result.kept)} file(s) no export wrote: {', '.join(result.kept[:10])}",
                          highlight=False)
        console.print(f"see {Path(out) / 'README.md'} for where the files go and how to launch")
        if result.verification != "passed":
            err_console.print(f"[yellow]warning[/]: {result.verification_message}", highlight=False)
