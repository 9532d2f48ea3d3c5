"""The CLI's glue between ROS 2 bags and the rest: `verify RUN --bag FILE` (bag -> Trace -> the same verifier
and metrics as a simulation) and `simulate RUN --bag DIR` (trace -> MCAP). Only the CLI may see both the bag
package and the verifier, so the chain lives here."""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

from socnavgen.cli.common import console
from socnavgen.errors import SocnavgenError

BAGS_DIR = "bags"  # RUN/bags/<bag name>/: what a recorded run gave (trace.npz, metrics.json, verify.json, plot)
AGENT_IDS = {"auto": None, "socrates": 0, "hunav": 1, "hunav2": 1, "hunav1": 1}


def parse_agent_map(text: str | None) -> dict[int, str] | None:
    """`7=human1,8=human2` -> {7: "human1", 8: "human2"}."""
    if text is None:
        return None
    mapping: dict[int, str] = {}
    for item in filter(None, (p.strip() for p in text.split(","))):
        match = re.fullmatch(r"(-?\d{1,9})\s*=\s*(human[1-9]\d{0,3})", item)
        if match is None:
            raise SocnavgenError(f"--agent-map entry {item[:40]!r} is not ID=humanN",
                                 hint="e.g. --agent-map 7=human1,8=human2")
        if int(match.group(1)) in mapping:
            raise SocnavgenError(f"--agent-map maps id {match.group(1)} twice")
        mapping[int(match.group(1))] = match.group(2)
    if len(set(mapping.values())) != len(mapping):
        raise SocnavgenError("--agent-map maps two ids to one human")
    return mapping


def read_options(*, humans_topic: str, robot_topic: str, goal_topic: str, gesture_topic: str, agent_ids: str,
                 agent_map: str | None, hunav_msgs: str, dt: float | None, max_gap: float,
                 start_tolerance: float) -> Any:
    from socnavgen.bag import BagReadOptions, ReadTopics

    if agent_ids not in AGENT_IDS:
        raise SocnavgenError(f"--agent-ids {agent_ids!r}", hint="one of: " + ", ".join(AGENT_IDS))
    if hunav_msgs not in ("auto", "socrates", "hunav"):
        raise SocnavgenError(f"--hunav-msgs {hunav_msgs!r}", hint="one of: auto, socrates, hunav")
    return BagReadOptions(topics=ReadTopics(humans=humans_topic, robot=robot_topic, goal=goal_topic,
                                            robot_gesture=gesture_topic),
                          dt=dt, first_agent_id=AGENT_IDS[agent_ids], agent_map=parse_agent_map(agent_map),
                          hunav_msgs=hunav_msgs, max_gap=max_gap, start_tolerance=start_tolerance)


def bag_out_dir(run: Path, bag: Path) -> Path:
    name = re.sub(r"[^A-Za-z0-9_.-]+", "_", (bag.name if bag.is_dir() else bag.stem)).strip("._") or "bag"
    return run / BAGS_DIR / name[:80]


def verify_bag(run: Path, bag: Path, *, location: Path | None, settings: Any, options: Any,
               as_json: bool) -> bool:
    """Judge a recorded run: the bag as a Trace, the run's criteria and the metrics, written to RUN/bags/NAME/."""
    from socnavgen.bag import bag_to_trace
    from socnavgen.run import load_run
    from socnavgen.safeio import atomic_write_text
    from socnavgen.sim import write_outputs
    from socnavgen.verify import verify_trace
    from socnavgen.verify.report import print_report

    loaded = load_run(run)
    if not loaded.folder.paths_path.is_file():
        raise SocnavgenError("no paths.json in this run", file=run, hint="verify needs a generated run")
    loc = loaded.location(location)
    converted = bag_to_trace(bag, loaded.paths(), loc, options)
    report = verify_trace(loaded, converted.trace, location=loc, settings=settings)  # a VerifySettings
    report = report.model_copy(update={"run": f"{run} (recorded: {bag})"})
    out = bag_out_dir(run, bag)
    converted.trace.save(out / "trace.npz")
    written = write_outputs(converted.trace, loc, out)
    atomic_write_text(out / "verify.json", report.model_dump_json(indent=2) + "\n")
    if as_json:
        print(report.model_dump_json(indent=2))
        return report.passed
    for note in converted.notes:
        console.print(f"[dim]{note}[/]", highlight=False)
    print_report(report, console)
    metrics = written.metrics
    keys = ("success", "time_to_reach_goal", "minimum_distance_to_people", "collisions")
    console.print("metrics: " + ", ".join(f"{k} = {_short(metrics[k])}" for k in keys if k in metrics),
                  highlight=False)
    console.print(f"written: {out / 'trace.npz'}, {out / 'metrics.json'}, {out / 'verify.json'}", highlight=False)
    return report.passed


def write_episode_bag(trace: Any, run: Path, location: Any, out: Path, flavour: str) -> Path:
    """`simulate --bag`: the episode as a rosbag2 folder with MCAP storage."""
    from socnavgen.bag import BagWriteOptions, write_bag
    from socnavgen.run import RunFolder

    return write_bag(trace, out, location=location, plan=RunFolder(run).read_paths(),
                     options=BagWriteOptions(flavour=flavour))  # type: ignore[arg-type]


def _short(value: object) -> str:
    return f"{value:.3g}" if isinstance(value, float) else str(value)

