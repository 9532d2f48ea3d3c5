"""`socnavgen simulate` (and `verify`, added by its own function below): run a generated scenario in the
headless 2D simulator and check it."""

from __future__ import annotations

import time
from contextlib import nullcontext
from pathlib import Path

import typer

from socnavgen.cli.common import console, finite_between, progress, starting
from socnavgen.errors import SocnavgenError
from socnavgen.limits import MAX_SIM_SECONDS, MAX_SIM_STEPS


def simulate(
    run: Path = typer.Argument(..., help="Run folder (holds request.json, paths.json, behaviors/*.xml)."),
    robot: str = typer.Option("scripted", "--robot", help="Robot plugin: `scripted` (default: plays spec.json's "
                              "robot script - speech, waits, speed - and never pushes into people), `waypoints` "
                              "(follows its path, slows and stops for people in front, like the paper's "
                              "teleoperated robot), `sfm` (a social-force robot), `straight` (a deliberately rude "
                              "robot that drives through people), `orca` and `dwa` (the ORCA and Dynamic Window baselines), or your own policy as `package.module:Class` or "
                              "`path/to/file.py:Class` (the RobotPolicy protocol is described in docs/simulator.md)."),
    dt: float = typer.Option(0.05, "--dt", callback=finite_between(0.001, 0.5), help="Fixed time step in seconds."),
    timeout: float | None = typer.Option(None, "--timeout", callback=finite_between(0.1, MAX_SIM_SECONDS),
                                         help="Stop after this many simulated seconds (at most "
                                         f"{MAX_SIM_SECONDS:g}). Default: twice the time the robot's route takes at "
                                         "its cruise speed plus its script's waits plus 30 s, at least 120 s."),
    seed: int = typer.Option(0, "--seed", min=0, max=2**63 - 1,
                             help="Seed of the only randomness (spawn offsets): same seed, same run."),
    gif: bool = typer.Option(False, "--gif", help="Also write RUN/sim/animation.gif."),
    plot: bool = typer.Option(True, "--plot/--no-plot", help="Write the trajectory figure(s) (matplotlib: about "
                              "half a second of the command's time)."),
    mp4: bool = typer.Option(False, "--mp4", help="Also write RUN/sim/animation.mp4 (H.264, full colour; with the "
                             "ffmpeg the imageio-ffmpeg package ships)."),
    figures: str = typer.Option("png", "--figures", help="Formats of the trajectory figure, comma-separated: png, "
                                "svg, pdf (vector formats for papers)."),
    out: Path | None = typer.Option(None, "--out", help="Write the outputs (trace, metrics, figures) to this "
                                    "folder instead of RUN/sim, e.g. one folder per robot: two simulations of one "
                                    "run then never overwrite each other (`verify` still reads RUN/sim)."),
    no_throttle: bool = typer.Option(False, "--no-throttle", help="Do not hold humans back at the node before their "
                                     "interaction point (SocRATES does, so that the encounter happens there)."),
    location: Path | None = typer.Option(None, "--location", help="Location folder, if request.json's path does "
                                         "not resolve from here."),
    bag: Path | None = typer.Option(None, "--bag", "--mcap", help="Also write the episode as a ROS 2 bag folder "
                                    "(MCAP storage) that Foxglove and RViz open: odometry, tf, people as "
                                    "hunav_msgs, the map, scene graph and paths as markers."),
    bag_msgs: str = typer.Option("socrates", "--bag-msgs", help="hunav_msgs of the bag: socrates (the SocRATES "
                                 "fork's, with gestures) or hunav (upstream HuNavSim 1.x/2.x, without)."),
) -> None:
    """Simulate a run without ROS: humans walk with HuNavSim's social force model driven by the run's behavior
    trees, the robot by a plugin. Writes RUN/sim/trace.npz (per-step poses, velocities, active BT node,
    gestures), and when available metrics.json (HuNavSim evaluator metrics), trajectories.png and, with
    --gif, animation.gif. Deterministic for a seed.

    Example: socnavgen simulate runs/blind_corner --robot waypoints --gif

    Example: socnavgen simulate runs/blind_corner --robot sfm --out runs/blind_corner/sim_sfm --figures png,pdf

    Example: socnavgen simulate runs/blind_corner --bag runs/blind_corner/sim/episode_bag
    """
    if timeout is not None and timeout / dt > MAX_SIM_STEPS:
        raise SocnavgenError(f"--timeout {timeout:g} at --dt {dt:g} is {timeout / dt:.0f} steps, more than the "
                             f"{MAX_SIM_STEPS} allowed", hint="raise --dt or lower --timeout")
    if bag_msgs not in ("socrates", "hunav"):
        raise SocnavgenError(f"--bag-msgs {bag_msgs!r}", hint="socrates (the fork's hunav_msgs, with gestures) or hunav")
    if bag is not None and (bag.exists() or bag.is_symlink()):  # refused before minutes of simulation
        raise SocnavgenError("the bag folder already exists", file=bag, hint="remove it or choose another --bag name")
    formats = _figure_formats(figures)
    if out is not None and out.exists() and not out.is_dir():
        raise SocnavgenError("--out is a file, not a folder", file=out, hint="give a folder (it is created)")
    with starting():  # imports and loading without garbage collection
        from socnavgen.run import RunFolder
        from socnavgen.sim import (
            COMPILING_NOTE,
            MadeFrom,
            SimConfig,
            ThrottleConfig,
            cache_ready,
            folder_identity,
            load_policy,
            load_simulation,
            save_run_outputs,
        )
        if plot:
            import socnavgen.sim.outputs.plot  # noqa: F401 - matplotlib, imported with the rest (see starting)
        folder = RunFolder(run)
        folder.require()
        if out is None:
            folder.hold_lock()  # one writer of RUN/sim at a time (two simulations would mix their outputs)
        else:
            _hold_out_lock(out)
        identity = folder_identity(run)
        policy = load_policy(robot)
        config = SimConfig(dt=dt, timeout=timeout, seed=seed)
        loaded = folder.location(location)
    if not cache_ready():
        console.print(f"[dim]{COMPILING_NOTE}[/]", highlight=False)
    with starting() if cache_ready() else nullcontext():  # numba's compiling makes garbage: collected
        sim = load_simulation(run, policy, config, ThrottleConfig(enabled=not no_throttle), loaded)
    sim.meta["robot_plugin"] = robot
    total = sim.max_steps
    start = time.perf_counter()
    with progress() as bar:
        task = bar.add_task(f"simulating {run.name}", total=total)
        trace = sim.run(progress=lambda k, n: bar.update(task, completed=k))
    wall = time.perf_counter() - start
    written = save_run_outputs(trace, loaded, run, MadeFrom(robot, dt, sim.timeout, seed, not no_throttle),
                               identity=identity, plot=plot, gif=gif, out_dir=out, formats=formats, mp4=mp4)
    out = out if out is not None else folder.sim_dir
    sim_seconds = float(trace.t[-1]) if trace.steps else 0.0
    console.print(f"[bold]{trace.end_reason}[/] after {sim_seconds:.1f} s simulated ({trace.steps} steps) in "
                  f"{wall:.2f} s wall, {sim_seconds / max(wall, 1e-9):.0f}x real time -> {out / 'trace.npz'}",
                  highlight=False)
    held = trace.meta.get("held_seconds") or {}
    for name, seconds in held.items():
        console.print(f"  {name} held {seconds:.1f} s at the node before its interaction point", highlight=False)
    for note in trace.meta.get("throttle_skipped") or []:
        console.print(f"  [yellow]not throttled[/]: {note}", highlight=False)
    _print_outputs(trace, written)
    if bag is not None:
        from socnavgen.cli.bag_cmd import write_episode_bag

        mcap = write_episode_bag(trace, run, loaded, bag, bag_msgs)
        console.print(f"  bag -> {bag} (open {mcap} in Foxglove; `ros2 bag play {bag}` for RViz)", highlight=False)


def _figure_formats(text: str) -> tuple[str, ...]:
    from socnavgen.sim.outputs.files import FIGURE_FORMATS

    chosen = tuple(dict.fromkeys(f.strip().lower() for f in text.split(",") if f.strip()))
    wrong = [f for f in chosen if f not in FIGURE_FORMATS]
    if wrong or not chosen:
        raise SocnavgenError(f"--figures {text!r}: unknown format {', '.join(wrong) or '(none given)'}",
                             hint=f"give one or more of {', '.join(FIGURE_FORMATS)}, comma-separated")
    return chosen


_OUT_LOCKS: dict[str, int] = {}


def _hold_out_lock(out: Path) -> None:
    """One writer of an --out folder at a time, for the rest of the process (like the run folder's lock)."""
    from socnavgen.locks import acquire

    out.mkdir(parents=True, exist_ok=True)
    key = str(out.resolve())
    if key not in _OUT_LOCKS:
        _OUT_LOCKS[key] = acquire(out / ".socnavgen-lock", f"output folder {out}",
                                  "wait for the other simulation to finish, or choose another --out")


def _print_outputs(trace, written) -> None:  # noqa: ANN001 - Trace, SimOutputs
    """The key metrics, the contacts and every file written (metrics.json, trajectories.png, the GIF)."""
    metrics = written.metrics
    keys = ("success", "time_to_goal", "walkable_path_efficiency", "minimum_distance_to_people",
            "intimate_space_seconds", "collisions")
    console.print("  " + ", ".join(f"{k} = {_short(metrics[k])}" for k in keys if k in metrics), highlight=False)
    from socnavgen.sim.contact import summarize

    console.print(f"  contacts: {summarize(trace).describe()}", highlight=False)  # same numbers as verify
    for label, path in written.files.items():
        if label == "trace":
            continue
        console.print(f"  {label} -> {path}", highlight=False)


def _short(value: object) -> str:
    """Numbers as people read them (no 40.400000000000006)."""
    return f"{value:.3g}" if isinstance(value, float) else str(value)


def register(app: typer.Typer) -> None:
    """Add `simulate` to the main app (`verify` lives in verify_cmd)."""
    app.command("simulate")(simulate)
