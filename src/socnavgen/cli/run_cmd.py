"""`socnavgen run ...`: run folders made elsewhere, brought in (SocRATES's saved scenarios)."""

from __future__ import annotations

from pathlib import Path

import typer

from socnavgen.cli import typer_app
from socnavgen.cli.common import console

app = typer_app(help="run folder commands", no_args_is_help=True)


@app.callback()
def _group() -> None:
    """Run folders made elsewhere, brought in."""


@app.command("import-socrates")
def import_socrates(
    source: Path = typer.Argument(..., help="What SocRATES saved: a scenarios/*.json or <experiment>_response_traj"
                                            ".json file (scenario, groupids, trajectories, interaction_points, "
                                            "behavior_trees), or a folder of its response files."),
    location: Path = typer.Option(..., "--location", "-l", help="The location the scenario was made for (a "
                                  "socnavgen location folder; `location import-socrates` converts SocRATES's "
                                  "annotator folder)."),
    out: Path = typer.Option(..., "--out", "-o", help="New run folder to write."),
) -> None:
    """Bring a SocRATES scenario in as a run folder: its trajectories become paths.json (checked on the
    location's scene graph), its trees behaviors/*.xml (checked on the node library), its scenario
    scenario.json; then simulate, verify and export it like any run.

    Example: socnavgen run import-socrates scenarios/follow_corner.json --location locations/small_warehouse -o runs/follow_corner
    """
    from socnavgen.run.socrates_import import import_socrates_run

    folder, notes = import_socrates_run(source, location, out)
    for note in notes:
        console.print(f"[yellow]note[/]: {note}", highlight=False)
    paths = folder.read_paths()
    console.print(f"[green]imported[/] {source} -> {folder.root} ({len(paths.humans)} human(s); robot "
                  f"{' -> '.join(paths.robot)})", highlight=False)
    console.print(f"next: socnavgen simulate {folder.root}; socnavgen verify {folder.root}; "
                  f"socnavgen export {folder.root} --format socrates -o OUT", highlight=False)
