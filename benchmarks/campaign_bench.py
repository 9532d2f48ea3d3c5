"""Campaign throughput: episodes per second for the 5-person cards (crowd-navigation on the warehouse; the
hospital's lobby fits only 3 people of that card), 60 s scenarios, no plots, `waypoints` robot, with verification and every metric; beside a loop of
`socnavgen simulate` calls and of in-process `simulate_run` + metrics (which reload the location each time).
Also: cost growth with the campaign size (one process), and `socnavgen --help` start-up. CPU seconds are
those of the thread that runs the episodes. Run it once before measuring on a new machine: the first
compiled episode compiles the simulator (~40 s, cached).

    python benchmarks/campaign_bench.py            # the table (under a minute)
    python benchmarks/campaign_bench.py --quick    # smaller counts
    python benchmarks/campaign_bench.py --full     # + the 10,000-episode point of the growth table
    python benchmarks/campaign_bench.py --dt-check # does dt 0.1 s change outcomes? (every card, bundled maps)
    python benchmarks/campaign_bench.py --parts    # CPU ms of each part of one worker's episode
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
LOCATIONS = [REPO / "examples" / "locations" / "warehouse"]
CLI = "import sys; from socnavgen.cli import main; sys.argv = ['socnavgen', *sys.argv[1:]]; main()"


def spec_for(seeds: int, card: str = "crowd-navigation", locations: list[Path] = LOCATIONS,  # noqa: ANN201
             policy: str = "waypoints", dt: float = 0.05):
    from socnavgen.campaign.spec import parse_campaign

    listed = ", ".join(str(p) for p in locations)
    return parse_campaign(f"scenarios:\n  - cards: [{card}]\n    locations: [{listed}]\n"
                          f"policies: [{policy}]\nseeds: {seeds}\nsimulation: {{timeout: 60, dt: {dt}}}\n")


def campaign_rate(seeds: int, executor: str, workers: int | None, root: Path, tag: str,
                  card: str = "crowd-navigation", locations: list[Path] = LOCATIONS, policy: str = "waypoints",
                  dt: float = 0.05) -> tuple[int, float, float]:
    """(episodes, wall seconds, CPU seconds of this thread) of one campaign run. The calling thread's CPU
    time: the inline executor runs every episode on it, and numpy's idle BLAS threads (which spin after a
    small matrix product) would otherwise count as work."""
    from socnavgen.campaign.runner import run_campaign

    spec = spec_for(seeds, card, locations, policy, dt)
    out = root / tag
    from socnavgen.campaign.scenarios import build_suite

    build_suite(spec, out)  # cards instantiated before the clock starts (a campaign does it once)
    start, cpu = time.perf_counter(), time.thread_time()
    result = run_campaign(spec, out, executor=executor, workers=workers, batch_size=8)
    return result.total, time.perf_counter() - start, time.thread_time() - cpu


def simulate_loop(runs: list[Path], count: int) -> float:
    """Episodes/s of the old way in one process: simulate_run (loads the location each time) + metrics."""
    from socnavgen.sim import simulate_run
    from socnavgen.sim.metrics import compute_metrics

    start = time.perf_counter()
    for k in range(count):
        run = runs[k % len(runs)]
        trace = simulate_run(run, "waypoints", timeout=60.0, seed=k, save=False)
        compute_metrics(trace, None)
    return count / (time.perf_counter() - start)


def cli_loop(runs: list[Path], count: int) -> float:
    env = {**os.environ, "PYTHONPATH": str(REPO / "src")}
    start = time.perf_counter()
    for k in range(count):
        subprocess.run([sys.executable, "-c", CLI, "simulate", str(runs[k % len(runs)]), "--timeout", "60",
                        "--seed", str(k)], env=env, check=True, capture_output=True, timeout=300)
    return count / (time.perf_counter() - start)


def simulate_cpu(run: Path, plot: bool, repeats: int = 3) -> float:
    """CPU seconds (user + sys, best of `repeats`) of `socnavgen simulate RUN` with a warm cache: the whole
    command, start-up, imports, simulation, outputs and the interpreter's exit."""
    import resource

    env = {**os.environ, "PYTHONPATH": str(REPO / "src")}
    best = float("inf")
    for _ in range(repeats):
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        subprocess.run([sys.executable, "-c", CLI, "simulate", str(run), "--plot" if plot else "--no-plot"],
                       env=env, check=True, capture_output=True, timeout=300)
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        best = min(best, after.ru_utime - before.ru_utime + after.ru_stime - before.ru_stime)
    return best


def help_seconds(repeats: int = 5) -> float:
    env = {**os.environ, "PYTHONPATH": str(REPO / "src")}
    best = float("inf")
    for _ in range(repeats):
        start = time.perf_counter()
        subprocess.run([sys.executable, "-c", CLI, "--help"], env=env, check=True, capture_output=True)
        best = min(best, time.perf_counter() - start)
    return best


def dt_check(root: Path, seeds: int = 2) -> None:
    """Every card on every bundled location, default robot, at dt 0.05 and 0.1 s: how often the episode's
    success and the verifier's verdict agree, and the CPU cost of each."""
    from socnavgen.campaign.runner import run_campaign
    from socnavgen.campaign.spec import parse_campaign
    from socnavgen.campaign.store import read_episodes

    maps = ", ".join(str(REPO / "examples" / "locations" / m) for m in ("warehouse", "hospital", "home"))
    tables, costs = {}, {}
    for dt in (0.05, 0.1):
        spec = parse_campaign(f"scenarios:\n  - cards: all\n    locations: [{maps}]\npolicies: [scripted]\n"
                              f"seeds: {seeds}\nsimulation: {{timeout: 60, dt: {dt}}}\n")
        cpu = time.process_time()
        run_campaign(spec, root / f"dt{dt}", executor="inline", workers=1, batch_size=8)
        costs[dt] = time.process_time() - cpu
        tables[dt] = {(r["scenario"], r["seed"]): r for r in read_episodes(root / f"dt{dt}")[0].to_pylist()}
    keys = sorted(tables[0.05])
    n = len(keys)
    print(f"\nTime step check: {n} episodes (every card x bundled location x {seeds} seeds, scripted robot)")
    print("| | dt 0.05 s | dt 0.1 s |\n|---|---:|---:|")
    print(f"| CPU ms per episode (incl. building the cards) | {1000 * costs[0.05] / n:.1f} | {1000 * costs[0.1] / n:.1f} |")
    for col in ("success", "verified"):
        rate = [sum(bool(tables[dt][k].get(col)) for k in keys) / n for dt in (0.05, 0.1)]
        print(f"| {col} rate | {rate[0]:.3f} | {rate[1]:.3f} |")
    for col in ("success", "verified"):
        same = sum(bool(tables[0.05][k].get(col)) == bool(tables[0.1][k].get(col)) for k in keys)
        print(f"| same `{col}` in both | {same}/{n} | |")


def episode_parts(root: Path, episodes: int = 100) -> None:
    """CPU ms per episode of each part of a worker's episode loop (run_episode on the 5-person card, one
    thread): each part's function wrapped in a thread_time clock; `rest` is the episode's own bookkeeping."""
    from collections import defaultdict

    import socnavgen.campaign.variation as variation
    import socnavgen.sim as sim
    import socnavgen.sim.metrics as metrics
    import socnavgen.sim.outputs.trajectory as trajectory
    import socnavgen.sim.social_metrics as social
    import socnavgen.verify.runner as verify
    from socnavgen.campaign import episode as ep
    from socnavgen.campaign.scenarios import build_suite
    from socnavgen.sim.engine.simulation import Simulation

    scenario = build_suite(spec_for(1), root / "parts").scenarios[0]
    settings = ep.EpisodeSettings()
    for seed in range(3):  # compiled, every location and run file loaded, the default robot's route fields
        ep.run_episode(ep.Episode(scenario, "waypoints", "waypoints", seed), settings)  # (the blame's re-runs plan)
        ep.run_episode(ep.Episode(scenario, "scripted", "scripted", seed), settings)
    spent: dict[str, float] = defaultdict(float)

    def clocked(owner: object, name: str, label: str) -> None:
        inner = getattr(owner, name)

        def wrapper(*args: object, **kwargs: object) -> object:
            start = time.thread_time()
            try:
                return inner(*args, **kwargs)
            finally:
                spent[label] += time.thread_time() - start

        setattr(owner, name, wrapper)

    for owner, name, label in [(sim, "load_simulation", "building the Simulation (load_simulation)"),
                               (Simulation, "run", "simulation (Simulation.run)"),
                               (variation, "draw_people", "drawing the people's traits"),
                               (metrics, "compute_metrics", "evaluator metrics (compute_metrics)"),
                               (metrics, "navigation_metrics", "navigation metrics"),
                               (social, "social_metrics", "social metrics"),
                               (ep, "expected_behaviour", "card's expected-behaviour checks"),
                               (trajectory, "trajectory_bytes", "trajectory file (trajectory_bytes)"),
                               (verify, "verify_trace", "verifier (verify_trace)")]:
        clocked(owner, name, label)
    start = time.thread_time()
    for seed in range(episodes):
        ep.run_episode(ep.Episode(scenario, "waypoints", "waypoints", 100 + seed), settings)
    total = time.thread_time() - start
    spent["rest (rows, bookkeeping)"] = total - sum(spent.values())
    print(f"\nParts of an episode: {episodes} episodes of crowd-navigation on the warehouse, waypoints robot, one "
          f"thread, {1000 * total / episodes:.2f} CPU ms each = {episodes / total:.0f} episodes per CPU second")
    print("| part | CPU ms per episode | share |\n|---|---:|---:|")
    for label, seconds in sorted(spent.items(), key=lambda kv: -kv[1]):
        print(f"| {label} | {1000 * seconds / episodes:.2f} | {100 * seconds / total:.0f} % |")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--full", action="store_true")
    parser.add_argument("--dt-check", action="store_true", help="only compare outcomes at dt 0.05 and 0.1 s")
    parser.add_argument("--parts", action="store_true", help="only the CPU time of each part of an episode")
    args = parser.parse_args()
    cores = os.cpu_count() or 1
    if args.parts:
        with tempfile.TemporaryDirectory() as tmp:
            episode_parts(Path(tmp))
        return
    if args.dt_check:
        with tempfile.TemporaryDirectory() as tmp:
            dt_check(Path(tmp))
        return
    with tempfile.TemporaryDirectory() as tmp:
        root = Path(tmp)
        from socnavgen.campaign.scenarios import build_suite

        suite = build_suite(spec_for(1), root / "suite")
        runs = [Path(s.run_dir) for s in suite.scenarios]
        assert all(s.humans == 5 for s in suite.scenarios), [s.humans for s in suite.scenarios]
        from socnavgen.campaign.episode import WORKER_CACHE, run_episode  # noqa: F401 - warm the kernels
        n_small = 4 if args.quick else 10
        rows = [("socnavgen simulate (CLI, one call per episode)", n_small // 2, cli_loop(runs, n_small // 2)),
                ("simulate_run + metrics in one process (reloads the location)", n_small,
                 simulate_loop(runs, n_small))]
        seeds = 20 if args.quick else 100
        total, wall, cpu = campaign_rate(seeds, "inline", 1, root, "inline")
        rows.append(("campaign, one process (inline)", total, total / wall))
        rows.append(("campaign, one process, per CPU second (load-independent)", total, total / cpu))
        total, _, cpu = campaign_rate(seeds, "inline", 1, root, "scripted", policy="scripted")
        rows.append(("  the same with the default (scripted) robot, per CPU second", total, total / cpu))
        total, _, cpu = campaign_rate(seeds, "inline", 1, root, "three", policy="scripted, waypoints, straight")
        rows.append(("  three robots (scripted, waypoints, straight), per CPU second", total, total / cpu))
        total, _, cpu = campaign_rate(seeds, "inline", 1, root, "dt10", dt=0.1)
        rows.append(("  the same at dt 0.1 s (simulation: {dt: 0.1}), per CPU second", total, total / cpu))
        total, wall, _ = campaign_rate(seeds, "local", cores, root, "local")
        rows.append((f"campaign, local executor ({cores} workers)", total, total / wall))
        print(f"\nEpisodes/s, 5-person 60 s scenarios (crowd-navigation on the warehouse), waypoints robot, "
              f"metrics + verification, no plots; {cores} cores, load average {os.getloadavg()[0]:.1f}")
        print(f"| {'mode':<62} | {'episodes':>8} | {'episodes/s':>10} | {'per core':>8} |")
        print(f"|{'-' * 64}|{'-' * 9}:|{'-' * 11}:|{'-' * 9}:|")
        for name, count, rate in rows:
            per_core = rate / cores if "local executor" in name else rate
            print(f"| {name:<62} | {count:>8} | {rate:>10.1f} | {per_core:>8.1f} |")

        sizes = [100, 1000] if not args.full else [100, 1000, 10000]
        if args.quick:
            sizes = [40, 200]
        print("\nCost growth with the campaign size: one process (CPU time, so other load does not distort it), "
              "blind-corner on the warehouse (1 person, ~20 s simulated), metrics + verification")
        print("| episodes | CPU s | wall s | CPU ms per episode |")
        print("|---:|---:|---:|---:|")
        for size in sizes:
            total, wall, cpu = campaign_rate(size, "inline", 1, root, f"grow{size}", "blind-corner", LOCATIONS[:1])
            print(f"| {total} | {cpu:.1f} | {wall:.1f} | {1000 * cpu / total:.2f} |", flush=True)
        print(f"\n`socnavgen simulate` on a card (warm cache, CPU s, best of 3; target < 1 s): "
              f"{simulate_cpu(runs[0], True):.2f} s, {simulate_cpu(runs[0], False):.2f} s with --no-plot")
    print(f"\n`socnavgen --help` start-up: {help_seconds():.3f} s (best of 5; target < 0.3 s)")


if __name__ == "__main__":
    main()
