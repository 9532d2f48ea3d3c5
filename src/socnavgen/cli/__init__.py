"""The `socnavgen` command. Each area registers its commands from its own module."""

from __future__ import annotations

import typer

from socnavgen import __version__
from socnavgen.cli import (
    annotate_cmd,
    bt_cmd,
    cards_cmd,
    eval_cmd,
    export_cmd,
    extract_cmd,
    generate_cmd,
    location_cmd,
    sim_cmd,
    verify_cmd,
)

app = typer.Typer(
    name="socnavgen",
    help="Generate social navigation scenarios (paths + behavior trees) for HuNavSim from text and a map.\n\n"
         "Typical flow: location check -> generate -> export -> simulate -> verify.",
    no_args_is_help=True,
    pretty_exceptions_enable=False,
    add_completion=False,
)
app.add_typer(location_cmd.app, name="location", help="Check, render, import and extract locations (map + scene graph).")
app.add_typer(bt_cmd.app, name="bt", help="Behavior-tree tools: validate hand-written trees, show the node library.")
app.add_typer(cards_cmd.app, name="cards", help="The 25 canonical scenario cards of Francis et al.")
extract_cmd.register_extract(location_cmd.app)
for module in (generate_cmd, export_cmd, sim_cmd, annotate_cmd, eval_cmd):
    module.register(app)
verify_cmd.register_verify(app)


@app.command("version")
def version() -> None:
    """Print the socnavgen version."""
    print(__version__)


def main() -> None:
    """Entry point: user errors become one clear message and exit code 2, never a traceback."""
    from socnavgen.cli.guard import run_guarded  # signals, OSError, NaN options, redacted messages

    run_guarded(app)
