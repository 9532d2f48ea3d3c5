"""`socnavgen verify RUN`: did the intended interactions happen in simulation?"""

from __future__ import annotations

from pathlib import Path

import typer

from socnavgen.cli.common import console, finite_between

DISTANCE = finite_between(0.0, 1000.0)  # metres: a negative or absurd threshold never means anything


def register_verify(app: typer.Typer) -> None:
    """Add the top-level `verify` command to the main app."""

    @app.command("verify")
    def verify(
        run: Path = typer.Argument(..., help="Run folder written by `socnavgen generate` (paths.json, behaviors/).",
                                   exists=True, file_okay=False),
        distance: float = typer.Option(2.0, callback=DISTANCE, help="Robot-human centre distance (m) that counts as meeting, unless "
                                                 "a criterion gives its own."),
        near: float = typer.Option(1.0, callback=DISTANCE, help="How close (m) to its encounter node a meeting must happen, for runs "
                                             "without spec.json (an encounter's `within` otherwise)."),
        passing: float = typer.Option(2.5, callback=DISTANCE, help="Robot distance (m) within which a tree's GiveWaytoRobot counts as "
                                                "giving way while the robot passes."),
        group_spread: float = typer.Option(2.5, callback=DISTANCE, help="Largest distance (m) between group members, the whole run."),
        deadlock_seconds: float = typer.Option(10.0, callback=finite_between(0.0, 3600.0), help="Longest (s) the robot may stand still with someone in its "
                                                          "way."),
        location: Path | None = typer.Option(None, help="Location folder, if request.json's path does not "
                                                        "resolve from here."),
        simulate: bool = typer.Option(True, help="Run the simulator first when RUN/sim/trace.npz is missing or stale (made from files that changed since)."),
        robot: str | None = typer.Option(None, help="Robot plugin for that simulation (default: the simulator's; "
                                                    "see `socnavgen simulate --help`)."),
        collisions_fail: bool = typer.Option(True, "--collisions-fail/--collisions-warn", help=(
            "A robot-human overlap fails verification (default), or is only a warning.")),
        as_json: bool = typer.Option(False, "--json", help="Print the report as JSON instead of a table."),
    ) -> None:
        """Check that the scenario does what it says, on the headless simulation of the run.

        The acceptance criteria of RUN/spec.json are monitored on the trace as signal temporal logic (rtamt),
        each reported with its robustness (how far from passing, in metres or seconds), its evidence (time,
        distance) and, when it fails, what can fix it: robot_script, paths, behaviors (which human) or spec.
        Runs without spec.json are judged on criteria derived from paths.json and the card with the same
        strict thresholds (meet within 2 m, within 1 m of the interaction point; no collision; no deadlock;
        goal reached), plus every interaction node of each tree really running after its cause. The report
        is written to RUN/sim/verify.json. Exit code 1 when a criterion fails.

        Example: socnavgen verify runs/blind_corner --distance 2.0
        """
        from socnavgen.run import RunFolder
        from socnavgen.verify import verify_run
        from socnavgen.verify.report import print_report

        folder = RunFolder(run)
        folder.hold_lock()  # verify writes RUN/sim (and may simulate): one writer at a time
        _say_if_stale(folder, location, simulate)
        report = verify_run(run, simulate_if_missing=simulate, location=location, distance=distance, near=near,
                            passing=passing, group_spread=group_spread, deadlock_seconds=deadlock_seconds,
                            collisions_fail=collisions_fail, simulate_options={"robot": robot} if robot else None)
        if as_json:
            print(report.model_dump_json(indent=2))
        else:
            print_report(report, console)
        if not report.passed:
            raise typer.Exit(1)


def _say_if_stale(folder, location: Path | None, simulate: bool) -> None:  # noqa: ANN001 - RunFolder
    """A note when RUN/sim/trace.npz is not the run's current simulation (verify simulates it again)."""
    from rich.markup import escape

    from socnavgen.cli.common import err_console
    from socnavgen.sim.outputs import stale_reason, unrecorded

    if unrecorded(folder.root):
        err_console.print(f"[yellow]note:[/] {escape(str(folder.sim_dir))} has no outputs.json (a trace made by hand "
                          "or by an older socnavgen): judged as it is", highlight=False)
    elif simulate and (folder.sim_dir / "trace.npz").is_file() and folder.paths_path.is_file():
        reason = stale_reason(folder.root, folder.location(location))
        if reason:
            err_console.print(f"[yellow]note:[/] {escape(reason)}: simulating again", highlight=False)
