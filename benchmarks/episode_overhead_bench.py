"""What a campaign episode costs outside the simulation loop: building the Simulation from the run
(`load_simulation`), the metrics (`compute_metrics`) and the verifier (`verify_trace`), in ms per call, for
the 5-person crowd-navigation card on the warehouse (60 s timeout, `waypoints` robot, one process).

"before" runs the same measurement on another revision of the source (extracted with `git archive`, in a
subprocess), calling with run folder paths (all the old API had); "after" is this tree as a campaign worker
calls it (one LoadedRun per scenario, kept across episodes); "after, paths" is this tree called with paths
(a caller that keeps nothing). The last line says whether every column gave the same re-simulated trace,
metrics and verify report.

    python benchmarks/episode_overhead_bench.py --before 4425df4 [--before-mode loaded]
    python benchmarks/episode_overhead_bench.py                 # this tree only
"""

from __future__ import annotations

import argparse
import hashlib
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
WAREHOUSE = REPO / "examples" / "locations" / "warehouse"
CAMPAIGN = ("scenarios:\n  - cards: [crowd-navigation]\n    locations: [{loc}]\npolicies: [waypoints]\nseeds: 1\n"
            "simulation: {{timeout: 60, dt: 0.05}}\n")
PARTS = ("load", "metrics", "verify")


def _median_ms(fn, repeats: int) -> float:  # noqa: ANN001 - any zero-argument callable
    fn()  # warm: caches of the location, parsed formulas, the kept run
    times = []
    for _ in range(repeats):
        start = time.thread_time()  # CPU time of this thread: a busy machine does not count
        fn()
        times.append(time.thread_time() - start)
    return statistics.median(times) * 1000


def measure(mode: str, repeats: int) -> dict:
    """ms per call of the three parts; `mode` paths (every call gets the run folder path) or loaded."""
    from socnavgen.campaign.scenarios import build_suite
    from socnavgen.campaign.spec import parse_campaign

    with tempfile.TemporaryDirectory(prefix="episode-overhead-") as tmp:
        scenario = build_suite(parse_campaign(CAMPAIGN.format(loc=WAREHOUSE)), Path(tmp)).scenarios[0]
        return _measure(scenario, mode, repeats)


def _measure(scenario, mode: str, repeats: int) -> dict:  # noqa: ANN001 - a campaign Scenario
    from socnavgen.campaign.episode import Episode, EpisodeSettings, simulate_episode
    from socnavgen.sim import SimConfig, ThrottleConfig, load_policy, load_simulation
    from socnavgen.sim.metrics import compute_metrics
    from socnavgen.verify.runner import verify_trace

    trace, location, world = simulate_episode(Episode(scenario, "waypoints", "waypoints", 0), EpisodeSettings())
    run: object = Path(scenario.run_dir)
    if mode == "loaded":
        from socnavgen.run.loaded import LoadedRun

        run = LoadedRun(Path(scenario.run_dir))

    def load() -> object:
        return load_simulation(run, load_policy("waypoints"), SimConfig(timeout=60), ThrottleConfig(),
                               location=location, world=world)

    def metrics() -> dict:
        return compute_metrics(trace, location)

    def verify() -> object:
        return verify_trace(run, trace, location=location)

    out = {name: _median_ms(fn, repeats) for name, fn in zip(PARTS, (load, metrics, verify), strict=True)}
    rerun = load().run()  # the Simulation built here gives the episode's trace again
    values = json.dumps({k: repr(v) for k, v in metrics().items()}, sort_keys=True)
    report = verify().model_dump_json().replace(str(scenario.run_dir), "RUN")
    digest = hashlib.sha256(rerun.robot.tobytes() + rerun.humans.tobytes() + (values + report).encode())
    out["digest"] = digest.hexdigest()
    out["steps"] = trace.steps
    return out


def _in_subprocess(src: Path, mode: str, repeats: int) -> dict:
    env = {**os.environ, "PYTHONPATH": str(src)}
    done = subprocess.run([sys.executable, __file__, "--measure", mode, "--repeats", str(repeats)], env=env,
                          check=True, capture_output=True, text=True)
    return json.loads(done.stdout.strip().splitlines()[-1])


def _extract(revision: str, into: Path) -> Path:
    archive = subprocess.run(["git", "-C", str(REPO), "archive", revision, "src"], check=True, capture_output=True)
    subprocess.run(["tar", "-x", "-C", str(into)], input=archive.stdout, check=True)
    return into / "src"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--before", help="git revision to compare with (e.g. the commit before the change)")
    parser.add_argument("--before-mode", choices=("paths", "loaded"), default="paths",
                        help="how the earlier revision is called (loaded: one LoadedRun kept, if it has one)")
    parser.add_argument("--repeats", type=int, default=200)
    parser.add_argument("--measure", choices=("paths", "loaded"), help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.measure:
        print(json.dumps(measure(args.measure, args.repeats)))
        return
    columns: dict[str, dict] = {}
    with tempfile.TemporaryDirectory() as tmp:
        if args.before:
            columns[f"before ({args.before}, {args.before_mode})"] = _in_subprocess(
                _extract(args.before, Path(tmp)), args.before_mode, args.repeats)
        columns["after (LoadedRun kept)"] = _in_subprocess(REPO / "src", "loaded", args.repeats)
        columns["after, paths"] = _in_subprocess(REPO / "src", "paths", args.repeats)
    names = list(columns)
    load = ", ".join(f"{x:.2f}" for x in os.getloadavg())
    print(f"CPU ms per call, median of {args.repeats}, one {next(iter(columns.values()))['steps']}-step trace; "
          f"load average {load} (1, 5, 15 min) on {os.cpu_count()} CPUs\n")
    print("| part | " + " | ".join(names) + " |")
    print("|---|" + "---:|" * len(names))
    for part in (*PARTS, "total"):
        cells = [sum(c[p] for p in PARTS) if part == "total" else c[part] for c in columns.values()]
        print(f"| {part} | " + " | ".join(f"{v:.2f}" for v in cells) + " |")
    same = len({c["digest"] for c in columns.values()}) == 1
    print(f"\nre-simulated trace, metrics and verify report identical in every column: {'yes' if same else 'NO'}")


if __name__ == "__main__":
    main()
