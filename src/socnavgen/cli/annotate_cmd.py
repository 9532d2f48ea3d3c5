"""`socnavgen annotate`: the browser tool for drawing and fixing a location's scene graph."""

from __future__ import annotations

import socket
import webbrowser
from pathlib import Path

import typer

from socnavgen.cli.common import console
from socnavgen.errors import InputFileError, SocnavgenError


def annotate(
    location: Path = typer.Argument(..., help="Location folder (holds location.yaml). With --map it may be new."),
    port: int = typer.Option(8765, "--port", "-p", min=1, max=65535,
                             help="Port on 127.0.0.1 to serve the page on (the server never listens elsewhere)."),
    no_browser: bool = typer.Option(False, "--no-browser", help="Do not open a browser tab; just print the URL."),
    map_yaml: Path | None = typer.Option(
        None, "--map", help="Start a NEW location folder from this nav2 map yaml (copies the map and writes "
                            "location.yaml with a default schema), then open it."),
) -> None:
    """Open a location in the browser to draw its scene graph over the map.

    Draw tool: click the map to add a node of the selected type, drag from one node to another to join them with an edge of the selected type, drag empty map to pan, wheel to zoom, Shift+drag a node to move it, Delete to remove the selection, Ctrl+Z / Ctrl+Y to undo / redo, Ctrl+S to save. Saving writes scene_graph.json (SocRATES node-link layout) and scene_graph.png atomically and keeps the previous scene_graph.json as scene_graph.json.bak; `location check` problems are listed beside the map after every save.

    Example:

        socnavgen annotate examples/locations/warehouse

        socnavgen annotate locations/lab --map ~/maps/lab.yaml --port 8800
    """
    try:
        from socnavgen.annotate.server import LOOPBACK, create_app, make_server
    except ImportError as exc:  # starlette / uvicorn live in the `web` extra
        raise SocnavgenError(f"the annotator needs the web extra ({exc.name} is missing)",
                             hint='pip install "socnavgen[web]"') from exc
    if map_yaml is not None:
        from socnavgen.location.extract import start_location_folder

        if not map_yaml.is_file():
            raise InputFileError("nav2 map yaml not found", file=map_yaml)
        start_location_folder(map_yaml, location)
        console.print(f"created location folder [bold]{location}[/] from {map_yaml}")
    _port_free(LOOPBACK, port)
    app = create_app(location)
    url = f"http://{LOOPBACK}:{port}/"
    console.print(f"annotating [bold]{location}[/] at [link={url}]{url}[/]  (Ctrl+C to stop)")
    server = make_server(app, port)
    if not no_browser:
        webbrowser.open(url)
    server.run()


def _port_free(host: str, port: int) -> None:
    """Fail with a clear message (not a uvicorn traceback) when the port is taken."""
    with socket.socket() as probe:
        try:
            probe.bind((host, port))
        except OSError as exc:
            raise SocnavgenError(f"port {port} on {host} is not available ({exc.strerror})",
                                 hint="choose another one with --port") from exc


def register(app: typer.Typer) -> None:
    """Add `annotate` to the main app."""
    app.command("annotate")(annotate)
