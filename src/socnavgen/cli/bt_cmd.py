"""`socnavgen bt ...` commands."""

from __future__ import annotations

import typer

app = typer.Typer(help="bt commands", no_args_is_help=True)
