"""Shared CLI helpers: one console, one way to report errors and progress."""

from __future__ import annotations

import contextlib

from rich.console import Console
from rich.progress import (
    BarColumn,
    MofNCompleteColumn,
    Progress,
    SpinnerColumn,
    TextColumn,
    TimeElapsedColumn,
)

console = Console()
err_console = Console(stderr=True)


def progress() -> Progress:
    """Progress bar used by every long command (hidden when output is not a terminal)."""
    return Progress(SpinnerColumn(), TextColumn("[progress.description]{task.description}"), BarColumn(),
                    MofNCompleteColumn(), TimeElapsedColumn(), console=err_console, transient=False)


received_signal: int | None = None


class Terminated(KeyboardInterrupt):
    """SIGTERM (a CI cancel, `timeout`, `kill`): unwinds like Ctrl+C, so every `finally` and the run
    folder's manifest handler run and the manifest never stays `running`."""


def install_signal_handlers() -> None:
    """Turn SIGTERM (and SIGHUP: the terminal closed) into a `Terminated` exception in the main thread."""
    import signal

    def handler(signum: int, _frame: object) -> None:
        global received_signal
        received_signal = signum  # click re-raises interrupts as new exceptions: main() reads this
        raise Terminated(signal.Signals(signum).name)

    for sig in (signal.SIGTERM, signal.SIGHUP):
        with contextlib.suppress(ValueError, OSError):  # not the main thread (embedded use): keep defaults
            signal.signal(sig, handler)


def os_error_message(exc: OSError) -> str:
    """One sentence for an OSError that reached the top: what failed, on which file, what to do."""
    import errno

    where = exc.filename if exc.filename is not None else ""
    what = exc.strerror or str(exc)
    hints = {errno.ENOSPC: "free some disk space, then re-run (finished stages are kept)",
             errno.EDQUOT: "free some disk space, then re-run (finished stages are kept)",
             errno.EROFS: "write to a folder on a writable file system (-o/--out)",
             errno.EACCES: "check the permissions of the folder, or write elsewhere (-o/--out)",
             errno.EPERM: "check the permissions of the folder, or write elsewhere (-o/--out)",
             errno.EISDIR: "a folder is in the way of a file: move it or choose another path",
             errno.ENOTDIR: "a file is in the way of a folder: move it or choose another path"}
    hint = hints.get(exc.errno or 0, "check the path and the file system")
    return f"{where}: {what}\n  -> {hint}" if where else f"{what}\n  -> {hint}"


def finite_between(low: float, high: float):  # noqa: ANN201 - a typer callback
    """Typer callback refusing NaN, infinity and values outside [low, high] (click's ranges let NaN pass)."""
    import math

    import typer

    def check(value: float | None) -> float | None:
        if value is not None and not (math.isfinite(value) and low <= value <= high):
            raise typer.BadParameter(f"{value} is not a finite number between {low:g} and {high:g}")
        return value

    return check


def non_finite_option(argv: list[str]) -> str | None:
    """`--option VALUE` (or `--option=VALUE`) whose value reads as NaN or infinity, else None.

    Checked for every command before parsing: a non-finite distance, time or speed never means
    anything here, and comparisons with NaN silently pass every threshold."""
    import math

    for i, token in enumerate(argv):
        if token.startswith("--") and "=" in token:
            name, value = token.split("=", 1)
        elif i > 0 and argv[i - 1].startswith("--") and "=" not in argv[i - 1]:
            name, value = argv[i - 1], token
        else:
            continue
        try:
            number = float(value)
        except ValueError:
            continue
        if not math.isfinite(number):
            return f"{name} {value}"
    return None
