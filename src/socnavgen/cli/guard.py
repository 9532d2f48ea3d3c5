"""The command's outer guard: every way a command can end becomes one message and a documented
exit code, never a traceback. Light on imports (rich is loaded only to print an error), so that
`--help` stays fast.

- SocnavgenError (a user error) and OSError (disk full, read-only folder, permissions): exit 2;
- Ctrl+C, SIGTERM, SIGHUP: unwound like KeyboardInterrupt (so the run folder's manifest says
  `failed`/interrupted, never `running`), exit 128 + signal;
- an option given NaN or infinity: refused before parsing, exit 2;
- every message passes the secret redactor.
"""

from __future__ import annotations

import contextlib
import sys
from collections.abc import Callable

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


def run_guarded(app: Callable[[], object]) -> None:
    """Run the typer app under the guard described above."""
    from socnavgen.errors import SocnavgenError

    install_signal_handlers()
    bad = non_finite_option(sys.argv[1:])
    if bad is not None:
        _fail(f"{bad}: not a finite number\n  -> give an ordinary number (NaN and infinity are refused)")
    try:
        app()
    except SocnavgenError as exc:
        _fail(exc.render())
    except KeyboardInterrupt:
        _interrupted()
    except SystemExit as exc:
        if exc.code == 130:  # typer turns an interrupt (Ctrl+C, or SIGTERM via Terminated) into exit 130
            _interrupted()
        raise
    except OSError as exc:  # disk full, read-only folder, permissions: one message, no traceback
        _fail(os_error_message(exc))


def _fail(message: str) -> None:
    from rich.markup import escape

    from socnavgen.cli.common import err_console
    from socnavgen.llm.redact import redact

    err_console.print(f"[bold red]error:[/] {escape(redact(message))}", highlight=False)
    sys.exit(2)


def _interrupted() -> None:
    from socnavgen.cli.common import err_console

    err_console.print("[yellow]interrupted[/]: files already written are complete; re-run to resume")
    sys.exit(128 + received_signal if received_signal else 130)
