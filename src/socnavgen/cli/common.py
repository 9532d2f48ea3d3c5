"""Shared CLI helpers: one console, one way to report errors and progress."""

from __future__ import annotations

import gc
from collections.abc import Iterator
from contextlib import contextmanager

from rich.console import Console
from rich.progress import (
    BarColumn,
    MofNCompleteColumn,
    Progress,
    SpinnerColumn,
    TextColumn,
    TimeElapsedColumn,
)

# soft_wrap: prose lines (messages, file paths) are never broken by us; the terminal wraps them, and a
# pipe gets them whole. Tables still fit the width (80 columns when piped).
console = Console(soft_wrap=True)
err_console = Console(stderr=True, soft_wrap=True)


def print_machine(text: str) -> None:
    """Machine-readable output (YAML, JSON, Markdown): written verbatim, never wrapped or styled."""
    import sys

    sys.stdout.write(text if text.endswith("\n") else text + "\n")
    sys.stdout.flush()


@contextmanager
def starting() -> Iterator[None]:
    """A command's imports and set-up without garbage collection: they make ~10^6 objects and hardly any garbage
    (numba's, scipy's and matplotlib's imports run ~15 % faster), which are then set aside from later
    collections (gc.freeze). Around imports and loading only, never a loop that makes garbage."""
    gc.disable()
    try:
        yield
    finally:
        gc.freeze()
        gc.enable()


def progress() -> Progress:
    """Progress bar used by every long command (hidden when output is not a terminal)."""
    return Progress(SpinnerColumn(), TextColumn("[progress.description]{task.description}"), BarColumn(),
                    MofNCompleteColumn(), TimeElapsedColumn(), console=err_console, transient=False)


def finite_between(low: float, high: float):  # noqa: ANN201 - a typer callback
    """Typer callback refusing NaN, infinity and values outside [low, high] (click's ranges let NaN pass)."""
    import math

    import typer

    def check(value: float | None) -> float | None:
        if value is not None and not (math.isfinite(value) and low <= value <= high):
            raise typer.BadParameter(f"{value} is not a finite number between {low:g} and {high:g}")
        return value

    return check
