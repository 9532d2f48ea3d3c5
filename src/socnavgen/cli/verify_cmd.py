"""`socnavgen verify RUN`: did the intended interactions happen in simulation?"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import typer

from socnavgen.cli.common import console, finite_between
from socnavgen.verify.models import VerifySettings

_FIELDS = VerifySettings.model_fields  # the one source of the thresholds' defaults, ranges and meanings


def _option(name: str) -> Any:
    """A typer option for the VerifySettings field `name`: its default, its range (NaN, infinity and values
    outside it refused with one message) and its description as help."""
    info = _FIELDS[name]
    low = next((float(getattr(m, "gt", getattr(m, "ge", 0.0))) for m in info.metadata
                if hasattr(m, "gt") or hasattr(m, "ge")), 0.0)
    high = next((float(getattr(m, "le", getattr(m, "lt", 0.0))) for m in info.metadata
                 if hasattr(m, "le") or hasattr(m, "lt")), 1e9)
    text = info.description or ""
    return typer.Option(info.default, callback=finite_between(low, high), help=text[:1].upper() + text[1:] + ".")


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
        simulate: bool = typer.Option(True, help="Run the simulator first when RUN/sim/trace.npz is missing or stale (made from files that changed since)."),
        robot: str | None = typer.Option(None, help="Robot plugin for that simulation (default: the simulator's; "
                                                    "see `socnavgen simulate --help`)."),
        collisions_fail: bool = typer.Option(_FIELDS["collisions_fail"].default, "--collisions-fail/--collisions-warn",
                                             help="A robot-human contact (gap <= 0.05 m) fails verification "
                                                  "(default), or is only a warning."),
        as_json: bool = typer.Option(False, "--json", help="Print the report as JSON instead of a table."),
        bag: Path | None = typer.Option(None, "--bag", exists=True, help=(
            "Judge a ROS 2 bag of the run recorded in HuNavSim (rosbag2 folder, .mcap or .db3) instead of the "
            "headless simulation; the trace, metrics.json and verify.json go to RUN/bags/NAME/.")),
        humans_topic: str = typer.Option("/human_states", help="--bag: topic of the humans (hunav_msgs/Agents)."),
        robot_topic: str = typer.Option("/robot_states", help="--bag: topic of the robot (hunav_msgs/Agent)."),
        goal_topic: str = typer.Option("/goal_pose", help="--bag: robot goal (PoseStamped), optional in the bag."),
        robot_gesture_topic: str = typer.Option("/robot_gesture", help="--bag: robot gesture (UInt32), optional."),
        agent_ids: str = typer.Option("auto", help="--bag: how agent ids number the humans: socrates (human1 = "
                                                   "0), hunav (human1 = 1, hunav2/hunav1 exports) or auto."),
        agent_map: str | None = typer.Option(None, help="--bag: explicit ids, e.g. 7=human1,8=human2."),
        hunav_msgs: str = typer.Option("auto", help="--bag: hunav_msgs definitions when the bag has none: "
                                                    "socrates (the fork), hunav (upstream) or auto."),
        dt: float | None = typer.Option(None, callback=finite_between(0.001, 1.0), help=(
            "--bag: resampling step in seconds (default: the bag's own for socnavgen bags, else 0.05).")),
        max_gap: float = typer.Option(2.0, callback=finite_between(0.01, 3600.0), help=(
            "--bag: longest pause (s) between human states before the recording counts as broken.")),
        start_tolerance: float = typer.Option(3.0, callback=finite_between(0.0, 1000.0), help=(
            "--bag: how far (m) an agent may start from the first node of its path.")),
    ) -> None:
        """Check that the scenario does what it says, on the headless simulation of the run.

        The acceptance criteria of RUN/spec.json are monitored on the trace as signal temporal logic (rtamt),
        each reported with its robustness (how far from passing, in metres or seconds), its evidence (time,
        distance) and, when it fails, what can fix it: robot_script, paths, behaviors (which human) or spec.
        Runs without spec.json are judged on criteria derived from paths.json and the card with the same
        strict thresholds (meet within 2 m after an approach, within 1 m of the interaction point; no contact;
        no deadlock; goal reached), plus every interaction node of each tree really running after its cause.
        The report is written to RUN/sim/verify.json. Exit code 1 when a criterion fails.

        With --bag, a recording of the run in HuNavSim (Gazebo) is judged instead, by the same criteria and
        metrics: docs/verify.md says which topics it reads and how agents are matched to the run's humans.

        Example: socnavgen verify runs/blind_corner --distance 2.0

        Example: socnavgen verify runs/blind_corner --bag recordings/blind_corner_0
        """
        from socnavgen.errors import SocnavgenError
        from socnavgen.run import RunFolder

        try:
            settings = VerifySettings.with_overrides(
                distance=distance, near=near, passing=passing, group_spread=group_spread,
                deadlock_seconds=deadlock_seconds, reaction_seconds=reaction_seconds, goal_radius=goal_radius,
                collisions_fail=collisions_fail)
        except ValueError as exc:
            raise SocnavgenError(str(exc), hint="see `socnavgen verify --help` for each option's range") from None
        folder = RunFolder(run)
        folder.hold_lock()  # verify writes RUN/sim (and may simulate): one writer at a time
        if bag is not None:
            from socnavgen.cli.bag_cmd import read_options, verify_bag

            options = read_options(humans_topic=humans_topic, robot_topic=robot_topic, goal_topic=goal_topic,
                                   gesture_topic=robot_gesture_topic, agent_ids=agent_ids, agent_map=agent_map,
                                   hunav_msgs=hunav_msgs, dt=dt, max_gap=max_gap, start_tolerance=start_tolerance)
            if not verify_bag(run, bag, location=location, settings=settings, options=options, as_json=as_json):
                raise typer.Exit(1)
            return
        from socnavgen.verify import verify_run
        from socnavgen.verify.report import print_report

        _say_if_stale(folder, location, simulate)
        report = verify_run(run, simulate_if_missing=simulate, location=location, settings=settings,
                            simulate_options={"robot": robot} if robot else None)
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
    from socnavgen.sim import stale_reason, unrecorded

    if unrecorded(folder.root):
        err_console.print(f"[yellow]note:[/] {escape(str(folder.sim_dir))} has no outputs.json (a trace made by hand "
                          "or by an older socnavgen): judged as it is", highlight=False)
    elif simulate and (folder.sim_dir / "trace.npz").is_file() and folder.paths_path.is_file():
        reason = stale_reason(folder.root, folder.location(location))
        if reason:
            err_console.print(f"[yellow]note:[/] {escape(reason)}: simulating again", highlight=False)
