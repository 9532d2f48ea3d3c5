"""`socnavgen location ...` commands."""

from __future__ import annotations

import typer

app = typer.Typer(help="location commands", no_args_is_help=True)
