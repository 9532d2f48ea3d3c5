"""The `socnavgen` command. Each area registers its commands from its own module.

Command modules are imported only when their command runs (LazyGroup): `socnavgen --help` lists every
command from the short help below without importing numpy, networkx or the simulator."""

from __future__ import annotations

import importlib
from collections.abc import Callable
from functools import cache
from typing import Any

import click
import typer
from typer.core import TyperGroup

from socnavgen import __version__


def typer_app(**kwargs: Any) -> typer.Typer:
    """Every Typer app of the command line: click's plain help (whole option names, wrapped between words, no
    `<bool>` after a flag, no box that truncates at 80 columns), no shell-completion options in every command's
    help, no pretty tracebacks (cli.guard turns errors into one message)."""
    return typer.Typer(rich_markup_mode=None, add_completion=False, pretty_exceptions_enable=False, **kwargs)


def _group(module: str, extra: tuple[str, str] | None = None) -> Callable[[], click.Command]:
    """Loader of a command group: `module.app` (+ `extra` = (module, register function) adding to it)."""

    def load() -> click.Command:
        app = importlib.import_module(f"socnavgen.cli.{module}").app
        if extra is not None:
            getattr(importlib.import_module(f"socnavgen.cli.{extra[0]}"), extra[1])(app)
        return typer.main.get_command(app)

    return load


def _single(module: str, register: str, name: str) -> Callable[[], click.Command]:
    """Loader of one command that `module.register(app)` adds to an app."""

    def load() -> click.Command:
        holder = typer_app()
        getattr(importlib.import_module(f"socnavgen.cli.{module}"), register)(holder)
        group = typer.main.get_command(holder)
        command = group.commands[name] if isinstance(group, click.Group) else group
        command.name = name
        return command

    return load


# name -> (loader, one-line help shown by `socnavgen --help`), in the order of the typical flow
COMMANDS: dict[str, tuple[Callable[[], click.Command], str]] = {
    "location": (_group("location_cmd", ("extract_cmd", "register_extract")),
                 "Check, render, import and extract locations (map + scene graph)."),
    "annotate": (_single("annotate_cmd", "register", "annotate"), "Draw or fix a scene graph in the browser."),
    "generate": (_single("generate_cmd", "register", "generate"),
                 "Generate a scenario: scenario -> paths -> behavior trees (SocRATES pipeline)."),
    "cards": (_group("cards_cmd"), "The 25 canonical scenario cards of Francis et al."),
    "run": (_group("run_cmd"), "Bring in runs made elsewhere (SocRATES's saved scenarios)."),
    "bt": (_group("bt_cmd"), "Behavior-tree tools: validate hand-written trees, show the node library."),
    "export": (_single("export_cmd", "register", "export"), "Write the files HuNavSim loads for a run."),
    "simulate": (_single("sim_cmd", "register", "simulate"), "Simulate a run headless (2D, no ROS)."),
    "verify": (_single("verify_cmd", "register_verify", "verify"), "Check that the intended interaction happened."),
    "campaign": (_group("campaign_cmd"), "Run robot policies over scenario suites x seeds; report with CIs."),
    "eval": (_single("eval_cmd", "register", "eval"), "The paper's Tables I-III on any model."),
}


class LazyGroup(TyperGroup):
    """A Typer group whose subcommands are imported on first use."""

    _listing = False

    def list_commands(self, ctx: click.Context) -> list[str]:
        return [*COMMANDS, *(n for n in super().list_commands(ctx) if n not in COMMANDS)]

    def get_command(self, ctx: click.Context, cmd_name: str) -> click.Command | None:
        if cmd_name not in COMMANDS:
            return super().get_command(ctx, cmd_name)
        if self._listing:  # help listing: name and short help only
            return click.Command(cmd_name, help=COMMANDS[cmd_name][1])
        return _load(cmd_name)

    def format_help(self, ctx: click.Context, formatter: click.HelpFormatter) -> None:
        self._listing = True
        try:
            super().format_help(ctx, formatter)
        finally:
            self._listing = False


@cache
def _load(name: str) -> click.Command:
    return COMMANDS[name][0]()


app = typer_app(
    name="socnavgen",
    cls=LazyGroup,
    help="Generate social navigation scenarios (paths + behavior trees) for HuNavSim from text and a map.\n\n"
         "Typical flow: location check -> generate -> export -> simulate -> verify; campaign to test robots.",
    no_args_is_help=True,
)


def _print_version(value: bool) -> None:
    if value:
        print(f"socnavgen {__version__}")
        raise typer.Exit()


@app.callback()
def _root(
    version: bool = typer.Option(False, "--version", is_eager=True, callback=_print_version,
                                 help="Print the version and exit."),
) -> None:
    """(Keeps `socnavgen` a group of commands.)"""


@app.command("version")
def version() -> None:
    """Print the socnavgen version."""
    print(__version__)


def main() -> None:
    """Entry point: user errors become one clear message and exit code 2, never a traceback."""
    import atexit
    import gc

    from socnavgen.cli.guard import run_guarded  # signals, OSError, NaN options, redacted messages

    atexit.register(gc.freeze)  # no collection of every object at exit (~0.2 s after the simulator's imports)
    run_guarded(app)
