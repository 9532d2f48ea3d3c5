"""`socnavgen verify RUN`: did the intended interactions happen in simulation?"""

from __future__ import annotations

from pathlib import Path

import typer

from socnavgen.cli.common import console


def register_verify(app: typer.Typer) -> None:
    """Add the top-level `verify` command to the main app."""

    @app.command("verify")
    def verify(
        run: Path = typer.Argument(..., help="Run folder written by `socnavgen generate` (paths.json, behaviors/).",
                                   exists=True, file_okay=False),
        distance: float = typer.Option(2.5, help="Robot-human centre distance (m) that counts as meeting."),
        near: float = typer.Option(3.0, help="How close (m) to the interaction point the meeting must happen."),
        passing: float = typer.Option(3.0, help="Robot distance (m) within which GiveWaytoRobot counts as "
                                                "giving way while the robot passes."),
        group_spread: float = typer.Option(3.0, help="Largest distance (m) between group members that still "
                                                     "counts as together."),
        group_fraction: float = typer.Option(0.8, help="Share of the run a group must stay together (0-1)."),
        location: Path | None = typer.Option(None, help="Location folder, if request.json's path does not "
                                                        "resolve from here."),
        simulate: bool = typer.Option(True, help="Run the simulator first when RUN/sim/trace.npz is missing."),
        robot: str = typer.Option("waypoints", help="Robot plugin for that simulation (see `socnavgen simulate "
                                                    "--help`)."),
        collisions_fail: bool = typer.Option(False, "--collisions-fail", help=(
            "Fail when the robot and a human overlap. By default a collision is a warning: it judges the "
            "robot under test, not whether the scenario happened.")),
        as_json: bool = typer.Option(False, "--json", help="Print the report as JSON instead of a table."),
    ) -> None:
        """Check that the scenario does what it says, on the headless simulation of the run.

        From paths.json and behaviors/*.xml it derives expectations: the robot meets each human that has an
        interaction point near that point; every interaction node of each tree (GiveWaytoRobot, BlockRobot,
        MakeGesture, the RobotSays / IsRobotVisible conditions gating them...) actually runs, GiveWaytoRobot
        while the robot passes; group members stay together; the robot reaches its goal; plus the scenario
        card's success criteria. Robot-human collisions are reported as warnings. Each is reported with its evidence (time, distance) and the report is
        written to RUN/sim/verify.json. Exit code 1 when any expectation fails.

        Example: socnavgen verify runs/blind_corner --distance 2.0
        """
        from socnavgen.verify import verify_run
        from socnavgen.verify.report import print_report

        report = verify_run(run, simulate_if_missing=simulate, location=location, distance=distance, near=near,
                            passing=passing, group_spread=group_spread, group_fraction=group_fraction,
                            collisions_fail=collisions_fail, simulate_options={"robot": robot})
        if as_json:
            print(report.model_dump_json(indent=2))
        else:
            print_report(report, console)
        if not report.passed:
            raise typer.Exit(1)
