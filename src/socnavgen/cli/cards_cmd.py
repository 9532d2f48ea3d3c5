"""`socnavgen cards ...` commands."""

from __future__ import annotations

import typer

app = typer.Typer(help="cards commands", no_args_is_help=True)
