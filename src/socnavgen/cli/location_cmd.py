"""`socnavgen location ...` commands: check, show, import-socrates (and extract, added by its own module)."""

from __future__ import annotations

import json
from pathlib import Path

import typer
from rich.table import Table

from socnavgen.cli import typer_app
from socnavgen.cli.common import console
from socnavgen.errors import InputFileError
from socnavgen.location.check import check_location
from socnavgen.location.location import SCENE_GRAPH_IMAGE, load_location

app = typer_app(help="location commands", no_args_is_help=True)


@app.command("check")
def check(
    folder: Path = typer.Argument(..., help="Location folder (holds location.yaml, the map, scene_graph.json)."),
    as_json: bool = typer.Option(False, "--json", help="Print the problems as JSON (for scripts and CI)."),
) -> None:
    """Check a location folder and list every problem with file, line and what to do.

    Checks files (missing, malformed), node ids (unique, 2 lowercase letters/digits), node and edge
    types against the schema, edges naming unknown nodes, self loops, duplicate edges, nodes outside
    the image or off free floor, edges a person cannot walk (a 0.4 m-radius disc along the line, or a
    short step around a small obstacle beside it; a squeeze is a warning, a wall, rack or unknown
    space an error: the same rule as the annotator and the importer), and connectivity (a warning). Exit code 0 when there is no error (warnings allowed), 1 otherwise.

    Example: socnavgen location check examples/locations/warehouse
    """
    if not folder.is_dir():  # a user error (exit 2), not a finding of the check (exit 1)
        from socnavgen.location.location import nearby_locations

        raise InputFileError("no such location folder", file=folder, hint=nearby_locations(folder) or
                             "give the folder that holds location.yaml, the map and scene_graph.json")
    report = check_location(folder)
    if as_json:
        print(json.dumps({"location": str(folder), "ok": report.ok, "nodes": report.nodes, "edges": report.edges,
                          "errors": len(report.errors), "warnings": len(report.warnings),
                          "problems": [p.to_dict() for p in report.problems]}, indent=2))
    else:
        if report.problems:
            table = Table(title=f"location check: {folder}", show_lines=True)
            table.add_column("level")
            table.add_column("where", overflow="fold")
            table.add_column("problem", overflow="fold")
            table.add_column("what to do", overflow="fold")
            for p in report.problems:
                colour = "red" if p.level == "error" else "yellow"
                table.add_row(f"[{colour}]{p.level}[/]", _short_where(p.where, folder), p.message, p.hint)
            console.print(table)
        verdict = "[green]OK[/]" if report.ok else "[red]FAILED[/]"
        console.print(f"{verdict} {folder}: {report.nodes} nodes, {report.edges} edges, "
                      f"{len(report.errors)} error(s), {len(report.warnings)} warning(s)", highlight=False, soft_wrap=True)
    raise typer.Exit(0 if report.ok else 1)


def _short_where(where: str, folder: Path) -> str:
    """File names relative to the location folder: the table stays readable in an 80-column terminal."""
    prefix = str(folder).rstrip("/") + "/"
    return where[len(prefix):] if where.startswith(prefix) else where


@app.command("show")
def show(
    folder: Path = typer.Argument(..., help="Location folder."),
    output: Path | None = typer.Option(None, "-o", "--output",
                                        help="PNG to write (default: scene_graph.png inside the folder)."),
) -> None:
    """Render the annotated map (the picture a vision LLM reads) to a PNG.

    Nodes are boxes labelled with their id, edges are lines, both coloured by type, with a legend of
    all types and a scale bar. The picture is cropped to the mapped part of the image, and labels
    never overlap (crowded ones move aside with a leader line, or are left out). Small maps are
    upscaled so the long side is about 1280 px. The same input always gives the same bytes.

    Example: socnavgen location show examples/locations/hospital -o /tmp/hospital.png
    """
    from socnavgen.location.render import write_location_png

    location = load_location(folder)
    location.transform  # noqa: B018 - a broken transform (NaN, infinite resolution) is one message, not a picture
    out = output or folder / SCENE_GRAPH_IMAGE
    write_location_png(location, out)
    console.print(f"wrote {out}", highlight=False, soft_wrap=True)


@app.command("import-socrates")
def import_socrates(
    source: Path = typer.Argument(..., help="SocRATES annotator folder with map.pgm, map.yaml, scene_graph.json."),
    output: Path = typer.Option(..., "-o", "--output", help="New location folder to write."),
    config: Path | None = typer.Option(None, "--config",
                                       help="Annotator config.yaml whose node_types/edge_types become the schema "
                                            "(types used in the graph but missing there are added)."),
    name: str | None = typer.Option(None, "--name", help="Location name (default: the source folder's name)."),
    description: str | None = typer.Option(None, "--description",
                                           help="Description for the prompts (default: a generic one naming the "
                                                "types; edit location.yaml afterwards)."),
    force: bool = typer.Option(False, "--force", help="Overwrite files in an existing output folder."),
) -> None:
    """Turn a SocRATES annotator folder into a location folder, then check it.

    Copies the map and its nav2 yaml, keeps the scene graph as is, writes location.yaml (schema from
    the types in the graph, or from --config) and scene_graph.png. Exit code 1 if the check fails.

    Example: socnavgen location import-socrates ~/SocRATES/locations/small_warehouse -o locations/small_warehouse
    """
    from socnavgen.location.importer import import_socrates as run_import

    result = run_import(source, output, config=config, name=name, description=description, force=force)
    for note in result.notes:
        console.print(f"[yellow]note:[/] {note}", highlight=False, soft_wrap=True)
    report = check_location(output)
    console.print(f"imported {source} -> {output}: {report.nodes} nodes, {report.edges} edges; check: "
                  f"{len(report.errors)} error(s), {len(report.warnings)} warning(s)", highlight=False, soft_wrap=True)
    if not report.ok:
        console.print(f"run `socnavgen location check {output}` for the details", highlight=False, soft_wrap=True)
    raise typer.Exit(0 if report.ok else 1)
