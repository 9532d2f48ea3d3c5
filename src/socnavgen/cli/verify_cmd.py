"""`socnavgen verify RUN`: did the intended interactions happen in simulation?"""

from __future__ import annotations

from pathlib import Path

import typer

from socnavgen.cli.common import console
from socnavgen.verify.models import VerifySettings

_FIELDS = VerifySettings.model_fields  # the one source of the thresholds' defaults and meanings


def _option(name: str) -> object:
    """A typer option for the VerifySettings field `name`: its default and its description as help."""
    info = _FIELDS[name]
    text = info.description or ""
    return typer.Option(info.default, help=text[:1].upper() + text[1:] + ".")


def register_verify(app: typer.Typer) -> None:
    """Add the top-level `verify` command to the main app."""

    @app.command("verify")
    def verify(
        run: Path = typer.Argument(..., help="Run folder written by `socnavgen generate` (paths.json, behaviors/).",
                                   exists=True, file_okay=False),
        distance: float = _option("distance"),
        near: float = _option("near"),
        passing: float = _option("passing"),
        group_spread: float = _option("group_spread"),
        deadlock_seconds: float = _option("deadlock_seconds"),
        reaction_seconds: float = _option("reaction_seconds"),
        goal_radius: float | None = _option("goal_radius"),
        location: Path | None = typer.Option(None, help="Location folder, if request.json's path does not "
                                                        "resolve from here."),
        simulate: bool = typer.Option(True, help="Run the simulator first when RUN/sim/trace.npz is missing."),
        robot: str | None = typer.Option(None, help="Robot plugin for that simulation (default: the simulator's; "
                                                    "see `socnavgen simulate --help`)."),
        collisions_fail: bool = typer.Option(_FIELDS["collisions_fail"].default, "--collisions-fail/--collisions-warn",
                                             help="A robot-human contact (gap <= 0.05 m) fails verification "
                                                  "(default), or is only a warning."),
        as_json: bool = typer.Option(False, "--json", help="Print the report as JSON instead of a table."),
    ) -> None:
        """Check that the scenario does what it says, on the headless simulation of the run.

        The acceptance criteria of RUN/spec.json are monitored on the trace as signal temporal logic (rtamt),
        each reported with its robustness (how far from passing, in metres or seconds), its evidence (time,
        distance) and, when it fails, what can fix it: robot_script, paths, behaviors (which human) or spec.
        Runs without spec.json are judged on criteria derived from paths.json and the card with the same
        strict thresholds (meet within 2 m after an approach, within 1 m of the interaction point; no contact;
        no deadlock; goal reached), plus every interaction node of each tree really running after its cause.
        The report is written to RUN/sim/verify.json. Exit code 1 when a criterion fails.

        Example: socnavgen verify runs/blind_corner --distance 2.0
        """
        from socnavgen.errors import SocnavgenError
        from socnavgen.verify import verify_run
        from socnavgen.verify.report import print_report

        try:
            settings = VerifySettings.with_overrides(
                distance=distance, near=near, passing=passing, group_spread=group_spread,
                deadlock_seconds=deadlock_seconds, reaction_seconds=reaction_seconds, goal_radius=goal_radius,
                collisions_fail=collisions_fail)
        except ValueError as exc:
            raise SocnavgenError(str(exc), hint="see `socnavgen verify --help` for each option's range") from None
        report = verify_run(run, simulate_if_missing=simulate, location=location, settings=settings,
                            simulate_options={"robot": robot} if robot else None)
        if as_json:
            print(report.model_dump_json(indent=2))
        else:
            print_report(report, console)
        if not report.passed:
            raise typer.Exit(1)
