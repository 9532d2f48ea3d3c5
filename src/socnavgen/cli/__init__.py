"""The `socnavgen` command. Each area registers its commands from its own module."""

from __future__ import annotations

import sys

import typer

from socnavgen import __version__
from socnavgen.cli import (
    annotate_cmd,
    bt_cmd,
    cards_cmd,
    common,
    eval_cmd,
    export_cmd,
    extract_cmd,
    generate_cmd,
    location_cmd,
    sim_cmd,
    verify_cmd,
)
from socnavgen.cli.common import err_console, install_signal_handlers, non_finite_option, os_error_message
from socnavgen.errors import SocnavgenError

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
    install_signal_handlers()
    bad = non_finite_option(sys.argv[1:])
    if bad is not None:
        err_console.print(f"[bold red]error:[/] {_redact(bad)}: not a finite number\n  -> give an ordinary number "
                          "(NaN and infinity are refused)", highlight=False)
        sys.exit(2)
    try:
        app()
    except SocnavgenError as exc:
        err_console.print(f"[bold red]error:[/] {_redact(exc.render())}", highlight=False)
        sys.exit(2)
    except KeyboardInterrupt:
        _interrupted()
    except SystemExit as exc:
        if exc.code == 130:  # typer turns an interrupt (Ctrl+C, or SIGTERM via Terminated) into exit 130
            _interrupted()
        raise
    except OSError as exc:  # disk full, read-only folder, permissions: one message, no traceback
        err_console.print(f"[bold red]error:[/] {_redact(os_error_message(exc))}", highlight=False)
        sys.exit(2)


def _interrupted() -> None:
    err_console.print("[yellow]interrupted[/]: files already written are complete; re-run to resume")
    signum = common.received_signal
    sys.exit(128 + signum if signum else 130)


def _redact(text: str) -> str:
    """No key in any form on the terminal; brackets in file names are not rich markup."""
    from rich.markup import escape

    from socnavgen.llm.redact import redact

    return escape(redact(text))
