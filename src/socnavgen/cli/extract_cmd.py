"""`socnavgen location extract`: a draft scene graph from an occupancy map alone."""

from __future__ import annotations

from pathlib import Path

import typer
from rich.table import Table

from socnavgen.bodies import ROBOT_PASSAGE_WIDTH
from socnavgen.cli.common import console, err_console


def extract(
    map_yaml: Path = typer.Argument(..., help="nav2 / ROS map_server yaml (image, resolution, origin)."),
    out: Path = typer.Option(..., "--out", "-o", help="Location folder to create (map copied, location.yaml, "
                                                      "scene_graph.json, scene_graph.png)."),
    detail: float = typer.Option(1.0, "--detail", "--density", min=0.1, max=10.0,
                                 help="Finer (>1) or coarser (<1) graph: divides the longest corridor edge (10 m), "
                                      "the merge distance (2 m) and the room coverage radius (4.5 m)."),
    rooms: bool = typer.Option(True, "--rooms/--no-rooms",
                               help="Segment rooms (one ROOM node each, DOORWAY nodes at their openings); "
                                    "--no-rooms gives the bare skeleton graph."),
    min_spur: float = typer.Option(1.0, "--min-spur", min=0.0,
                                   help="Side branches shorter than this many metres (or than the local "
                                        "width) are pruned."),
    narrow_width: float = typer.Option(1.2, "--narrow-width", min=0.1,
                                       help="Passages narrower than this (metres) are NARROW; short ones "
                                            "between wider space become DOORWAY nodes."),
    open_width: float = typer.Option(3.0, "--open-width", min=0.1,
                                     help="Free width (metres) from which a junction or end is an OPEN AREA."),
    min_gap: float = typer.Option(0.5, "--min-gap", min=0.0,
                                  help="Gaps narrower than this (metres) are treated as closed."),
    robot_width: float = typer.Option(ROBOT_PASSAGE_WIDTH, "--robot-width", min=0.0,
                                      help="No edge narrower than this (metres, wall to wall) is kept: the robot's "
                                           "body and its margin must pass (0 keeps every edge a person can walk)."),
    all_components: bool = typer.Option(False, "--all-components",
                                        help="Keep every free region, not only the largest connected one."),
    name: str | None = typer.Option(None, "--name", help="Location name (default: the folder name)."),
    seed: int | None = typer.Option(None, "--seed", help="Make the random node ids reproducible."),
    force: bool = typer.Option(False, "--force", help="Replace the scene graph of an existing location folder "
                                                      "(the previous one is kept as scene_graph.json.bak)."),
) -> None:
    """Suggest a scene graph from an occupancy map: rooms, doorways, then the corridors' junctions and corners.

    Furniture is ignored; the free space is cut at its doorways and every room becomes one ROOM node (large rooms get OPEN AREA nodes too) joined to its DOORWAY nodes. Corridors and halls are thinned to their centre lines: junctions, corners (BLIND when the walls hide the other leg), dead ends and narrow passages become nodes, about 2 m apart or more, and every edge is a straight segment a person can walk. Open the result in `socnavgen annotate` to fix it.

    Example:

        socnavgen location extract ~/maps/lab.yaml -o locations/lab --detail 1.5
    """
    from socnavgen.location.extract import ExtractOptions, extract_location
    from socnavgen.location.location import SCENE_GRAPH_FILE

    options = ExtractOptions(detail=detail, rooms=rooms, min_spur_m=min_spur, narrow_width_m=narrow_width,
                             open_width_m=open_width, min_gap_m=min_gap, keep_all_components=all_components,
                             robot_width_m=robot_width, seed=seed)
    previous = out / SCENE_GRAPH_FILE
    if force and previous.is_file():
        from socnavgen.safeio import atomic_write_bytes

        atomic_write_bytes(previous.with_name(previous.name + ".bak"), previous.read_bytes())
    with err_console.status("extracting the scene graph"):
        location, stats = extract_location(map_yaml, out, options, name=name, force=force)
    table = Table(title=f"{location.name}: {stats.nodes} nodes, {stats.edges} edges")
    table.add_column("node type")
    table.add_column("count", justify="right")
    for node_type, count in sorted(stats.types.items()):
        table.add_row(node_type, str(count))
    console.print(table)
    from socnavgen.location.check import check_location

    report = check_location(out)
    for problem in report.problems:
        console.print(f"[yellow]{problem.level}[/]: {problem.message}", highlight=False)
    console.print(f"location check: {len(report.errors)} error(s), {len(report.warnings)} warning(s)")
    console.print(f"wrote {out}/location.yaml, scene_graph.json, scene_graph.png - "
                  f"review with: socnavgen annotate {out}")


def register_extract(location_app: typer.Typer) -> None:
    """Add `extract` to the `socnavgen location` sub-app."""
    location_app.command("extract")(extract)
