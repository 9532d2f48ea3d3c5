"""`socnavgen campaign run|report|metrics`: robot policies over scenario suites x seeds."""

from __future__ import annotations

from pathlib import Path

import typer

from socnavgen.cli import typer_app

app = typer_app(no_args_is_help=True, help="Run robot policies over scenario suites x seeds; report with CIs.")

EXAMPLE = """# A campaign: robot policies x scenarios x seeds. Run it as it is:
#   socnavgen campaign run suite.yaml -o campaigns/suite
# Paths are relative to this file (or absolute).
name: smoke
scenarios:
  - cards: [blind-corner, frontal-approach]   # or `cards: all`; cards that do not fit a location are skipped
    locations: [{warehouse}]
  # - runs: [runs/blind_corner]     # run folders written by `socnavgen generate` / `cards generate`
  # - folder: runs/                 # every run folder inside a folder
policies:
  - scripted                        # built-in robots: scripted, waypoints, sfm, straight
  - waypoints
  # - {{name: mine, robot: my_robot.py:MyPolicy}}   # your own: file.py:Class or package.module:Class
seeds: 3                            # 0..2, or a list [1, 5, 7]
simulation: {{dt: 0.05, timeout: route, throttle: true, wall_timeout: 30}}
# metrics: [success, collisions, path_efficiency]   # default: every metric (`socnavgen campaign metrics`)
"""


def example_text() -> str:
    """The example campaign, naming the bundled warehouse where it is (so it runs from any folder)."""
    bundled = Path(__file__).resolve().parents[3] / "examples" / "locations" / "warehouse"
    return EXAMPLE.format(warehouse=bundled if (bundled / "location.yaml").is_file() else
                          "examples/locations/warehouse")


@app.command("run")
def run(
    file: Path = typer.Argument(..., help="Campaign YAML (see `socnavgen campaign example`)."),
    out: Path = typer.Option(..., "-o", "--out", help="Output folder (re-run the same command to resume)."),
    executor: str = typer.Option("local", "--executor", help="local (worker processes, default), ray, or inline "
                                 "(this process only)."),
    workers: int | None = typer.Option(None, "--workers", min=1, help="Worker processes (default: all cores)."),
    address: str | None = typer.Option(None, "--address", help="Ray cluster to join (host:port or auto); "
                                       "default: start a local one."),
    batch: int = typer.Option(4, "--batch", min=1, max=1000, help="Episodes per task sent to a worker."),
) -> None:
    """Run every scenario x policy x seed of FILE, one row per episode in OUT/episodes.parquet. Killed
    (even with kill -9)? Run the same command again: finished episodes are kept, none is run twice.

    Example: socnavgen campaign run suite.yaml -o campaigns/suite --executor ray
    """
    from rich.markup import escape
    from rich.progress import (
        BarColumn,
        MofNCompleteColumn,
        Progress,
        TextColumn,
        TimeElapsedColumn,
        TimeRemainingColumn,
    )

    from socnavgen.campaign.runner import run_campaign
    from socnavgen.campaign.spec import load_campaign
    from socnavgen.cli.common import console, err_console
    from socnavgen.text import count

    spec = load_campaign(file)
    from socnavgen.sim import COMPILING_NOTE, cache_ready

    if not cache_ready():
        err_console.print(f"[dim]{COMPILING_NOTE}[/]", highlight=False)
    columns = (TextColumn("[progress.description]{task.description}"), BarColumn(), MofNCompleteColumn(),
               TimeElapsedColumn(), TextColumn("ETA"), TimeRemainingColumn())
    with Progress(*columns, console=err_console) as bar:
        task = bar.add_task(f"campaign {spec.name}", total=None)

        def progress(done: int, total: int) -> None:
            if bar.tasks[task].total is None:  # the first call: what was already on disk is not "speed"
                bar.update(task, total=total, completed=done)
                bar.reset(task, total=total, completed=done)
            bar.update(task, completed=done)

        result = run_campaign(spec, out, executor=executor, workers=workers, address=address, batch_size=batch,
                              progress=progress)
    for note in result.suite.skipped:
        console.print(f"  [yellow]skipped[/] {note}", highlight=False)
    for problem in result.problems:
        err_console.print(f"[yellow]warning:[/] {escape(problem)}", highlight=False)
    for why, n in result.rerun.items():
        console.print(f"  [yellow]run again[/]: {count(n, 'episode')} ({escape(why)})", highlight=False)
    console.print(f"[bold]{result.total}[/] episodes ({result.skipped_done} already done, {result.ran} run, "
                  f"{result.failed} failed) -> {result.out / 'episodes.parquet'}", highlight=False)
    console.print(f"  next: socnavgen campaign report {result.out}", highlight=False)


@app.command("report")
def report(
    out: Path = typer.Argument(..., help="A campaign output folder."),
    gifs: int = typer.Option(3, "--gifs", min=0, max=50, help="Render the GIFs of this many worst episodes."),
    boot: int = typer.Option(2000, "--bootstrap", min=100, max=100000, help="Bootstrap resamples for the CIs."),
    baseline: str | None = typer.Option(None, "--baseline", help="Policy the others are compared with "
                                        "(default: the first of the campaign)."),
    markdown: bool = typer.Option(False, "--markdown", help="Also print the ranking table (markdown, with CIs) to "
                                  "stdout: the README's table, regenerated by this one command."),
    width: int | None = typer.Option(None, "--width", min=0, max=1000,
                                     help="Columns the printed table may use: split by columns to fit, the first "
                                     "repeated. 0 = one wide table (for the README). Default: the terminal's "
                                     "width when stdout is a terminal, else 0."),
) -> None:
    """Aggregates per policy and per scenario with bootstrap 95% CIs, paired comparisons on the same
    scenarios and seeds, plots, and the worst episodes with their GIFs: OUT/report/index.html (one
    self-contained file) and OUT/report/summary.md.

    Example: socnavgen campaign report campaigns/suite --gifs 5

    Example: socnavgen campaign report campaigns/ranking --gifs 0 --markdown > table.md

    Example: socnavgen campaign report campaigns/ranking --gifs 0 --markdown --width 80
    """
    from rich.markup import escape

    from socnavgen.campaign.report import write_report
    from socnavgen.cli.common import console, err_console

    if not out.is_dir():
        from socnavgen.errors import InputFileError

        raise InputFileError("no such campaign folder", file=out, hint="give the -o folder of `socnavgen campaign run`")
    notes: list[str] = []
    paths = write_report(out, gifs=gifs, resamples=boot, baseline=baseline, notes=notes)
    for note in notes:
        err_console.print(f"[yellow]warning:[/] {escape(note)}", highlight=False)
    if markdown:  # plain print: the table goes to stdout as it is (rich would wrap it), the paths to stderr
        import shutil
        import sys

        from socnavgen.campaign.report import RANKING_FILE, fit_markdown

        if width is None:
            width = shutil.get_terminal_size().columns if sys.stdout.isatty() else 0
        print(fit_markdown((out / "report" / RANKING_FILE).read_text(), width), end="")
    for path in paths:
        (err_console if markdown else console).print(f"  -> {path}", highlight=False)


@app.command("metrics")
def metrics() -> None:
    """List every metric column with its unit and meaning (formulas for the navigation metrics)."""
    from socnavgen.cli.common import console
    from socnavgen.sim.metric_definitions import metric_definitions

    for name, d in metric_definitions().items():
        console.print(f"[bold]{name}[/] [{d['unit']}]: {d['meaning']}", highlight=False)
        if d.get("formula"):
            console.print(f"    {d['formula']}", highlight=False)


@app.command("example")
def example() -> None:
    """Print an example campaign file that runs as it is.

    Example: socnavgen campaign example > suite.yaml && socnavgen campaign run suite.yaml -o campaigns/suite
    """
    print(example_text(), end="")
