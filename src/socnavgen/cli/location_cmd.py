"""`socnavgen location ...` commands: check, show, import-socrates (and extract, added by its own module)."""

from __future__ import annotations

import json
from pathlib import Path

import typer
from rich.table import Table

from socnavgen.bodies import PERSON_HEIGHT
from socnavgen.cli import typer_app
from socnavgen.cli.common import console, finite_between
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


@app.command("from-world")
def from_world(
    world: Path = typer.Argument(..., help="Gazebo world file (.world or .sdf, SDF 1.4-1.9)."),
    output: Path = typer.Option(..., "-o", "--output", help="Location folder to create."),
    models: list[Path] = typer.Option([], "--models", help="Folder of Gazebo models (NAME/model.sdf) for "
                                                          "model:// URIs; repeat it. GAZEBO_MODEL_PATH and "
                                                          "GZ_SIM_RESOURCE_PATH are searched too."),
    resolution: float = typer.Option(0.05, "--resolution", callback=finite_between(0.005, 1.0),
                                     help="Metres per map cell."),
    ankle: float = typer.Option(0.1, "--ankle", callback=finite_between(0.0, 10.0),
                                help="Bottom of the slab (m above the floor): lower things are walked over."),
    head: float = typer.Option(PERSON_HEIGHT, "--head", callback=finite_between(0.01, 20.0),
                               help="Top of the slab (m above the floor): higher things are walked under. "
                                    "0.5 gives what a robot's laser sees (shelves on legs become their legs); "
                                    "the scene graph still keeps people out from under the shelves."),
    floor_z: float = typer.Option(0.0, "--floor-z", callback=finite_between(-1e4, 1e4),
                                  help="Height of the floor in the world (m)."),
    bounds: tuple[float, float, float, float] | None = typer.Option(
        None, "--bounds", help="Map only XMIN YMIN XMAX YMAX (metres); default: everything, plus a 0.3 m margin."),
    strict: bool = typer.Option(False, "--strict", help="Fail when a model or mesh cannot be found or read "
                                                        "(default: list them and go on)."),
    name: str | None = typer.Option(None, "--name", help="Location name (default: the folder name)."),
    detail: float = typer.Option(1.0, "--detail", min=0.1, max=10.0,
                                 help="Finer (>1) or coarser (<1) scene graph, as in `location extract`."),
    seed: int | None = typer.Option(None, "--seed", help="Make the random node ids reproducible."),
    force: bool = typer.Option(False, "--force", help="Replace a location already in the output folder."),
) -> None:
    """Turn a Gazebo world into a ready location: map, overhead picture, scene graph, description draft.

    Reads the world and the models it includes (model://NAME from --models and the Gazebo model
    paths), slices every collision shape (box, cylinder, sphere, capsule, ellipsoid, plane,
    polyline, DAE/STL/OBJ mesh) between --ankle and --head into a nav2 map (map.pgm + map.yaml, world
    frame, origin on a multiple of the resolution), draws overhead.png with the same transform,
    extracts the scene graph, drafts location.yaml's description from the model names, runs
    `location check` and lists the scenario cards that fit. Models that cannot be used are listed by
    name (exit code 0) unless --strict.

    Example: socnavgen location from-world worlds/small_warehouse.world --models models -o locations/warehouse
    """
    from socnavgen.cli.common import progress as progress_bar
    from socnavgen.location.extract import ExtractOptions
    from socnavgen.location.world_import import WorldImportOptions, import_world
    from socnavgen.location.world_raster import SliceOptions

    if head <= ankle:
        raise typer.BadParameter(f"--head {head} must be above --ankle {ankle}")
    options = WorldImportOptions(
        slice=SliceOptions(resolution=resolution, ankle=ankle, head=head, floor_z=floor_z, bounds=bounds),
        extract=ExtractOptions(detail=detail, seed=seed), strict=strict, name=name, force=force)
    with progress_bar() as bar:
        task = bar.add_task("reading the world", total=None)

        def report(stage: str, done: int, total: int) -> None:
            bar.update(task, description=stage, completed=done, total=total)

        result = import_world(world, output, list(models), options, progress=report)
        bar.update(task, description="done", completed=1, total=1)
    for line in result.skipped:
        console.print(f"[yellow]skipped:[/] {line}", highlight=False, soft_wrap=True)
    w, h = result.size
    console.print(f"{world}: {len(result.world.models)} models, {len(result.world.shapes)} collision shapes "
                  f"({result.footprints} distinct slices); map {w} x {h} cells at {resolution} m, origin "
                  f"({result.origin[0]:g}, {result.origin[1]:g}); {result.stats.nodes} nodes, {result.stats.edges} "
                  f"edges; {sum(result.seconds.values()):.1f} s", highlight=False, soft_wrap=True)
    report_check = check_location(output)
    console.print(f"location check: {len(report_check.errors)} error(s), {len(report_check.warnings)} warning(s)",
                  highlight=False)
    if report_check.ok:
        from socnavgen.cards.generate import fit_all

        fitting = [f.card.name for f in fit_all(load_location(output)) if f.fits]
        console.print(f"cards that fit ({len(fitting)}): {', '.join(fitting) or 'none'}", highlight=False,
                      soft_wrap=True)
    console.print(f"wrote {output}/ (map.pgm, map.yaml, overhead.png, location.yaml, scene_graph.json, "
                  f"scene_graph.png) - review with: socnavgen annotate {output}", highlight=False, soft_wrap=True)
    raise typer.Exit(0 if report_check.ok else 1)
