"""Simulator speed: steps per second for 1..1000 pedestrians, beside the pedestrian simulators of the `bench`
extra (JuPedSim, ORCA via pyrvo, navground, pysocialforce) on the same crowd.

The crowd (benchmarks/_peers.py): n people in an open walled square at 0.1 pedestrians/m^2, each walking a
cyclic route start -> goal -> start, radius 0.4 m, desired speed 1.5 m/s, dt 0.05 s, the same number of steps
in every simulator, the fastest of 3 runs of each (--repeats). Ours runs every person's RegularNav tree
exactly as the generator writes it and a robot crossing with the `waypoints` plugin (the peers have no robot); "Python policy" calls a trivial user policy
between two compiled steps. Times are CPU seconds of the simulating thread (time.thread_time): one core,
unaffected by other load. Each simulator's mean speed at the end is printed, so a crowd that stands shows.

    python benchmarks/sim_bench.py                      # the table (~10 minutes: navground, pysocialforce)
    python benchmarks/sim_bench.py --quick              # fewer steps
    python benchmarks/sim_bench.py --counts 300 1000 --peers "JuPedSim SFM"
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from collections.abc import Callable
from functools import partial
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from _peers import DT, GOAL_RADIUS, PEERS, RADIUS, SPEED, Crowd, Timing, crowd, measure  # noqa: E402

from socnavgen.bt.library import regular_walker_xml  # noqa: E402
from socnavgen.sim import HumanSpec, RobotAction, SimConfig, Simulation, empty_room, load_policy  # noqa: E402
from socnavgen.sim.jit import AVAILABLE  # noqa: E402

COUNTS = (1, 5, 20, 100, 300, 1000)


class Toward:
    """A trivial robot policy of the user's: straight at its goal at 0.6 m/s."""

    def act(self, obs):  # noqa: ANN001, ANN201
        to = obs.waypoints_c[-1] - obs.position_c
        v = 0.6 * to / max(abs(to), 1e-9)
        return RobotAction(v.real, v.imag)


def ours(c: Crowd, steps: int, python_policy: bool) -> Timing:
    """CPU seconds per step of the full simulation loop (trees, physics, robot, trace)."""
    n = len(c.starts)
    humans = [HumanSpec(name=f"human{i + 1}", start=tuple(s), goals=[tuple(g), tuple(s)], cyclic=True,
                        radius=RADIUS, max_vel=SPEED, goal_radius=GOAL_RADIUS)
              for i, (s, g) in enumerate(zip(c.starts, c.goals, strict=True))]
    world = empty_room(c.side, c.side, resolution=0.1)
    policy = Toward() if python_policy else load_policy("waypoints")
    sim = Simulation(world, humans, [regular_walker_xml()] * n, [(0.8, c.side / 2), (c.side - 0.8, c.side / 2)],
                     policy, SimConfig(dt=DT, timeout=steps * DT, idle_end=1e9))
    start = time.thread_time()
    trace = sim.run()
    elapsed = time.thread_time() - start
    speed = float(np.mean(np.abs(sim.people.vel))) if n else 0.0
    return Timing(elapsed / max(trace.steps - 1, 1), speed)


def best(run: Callable[[], Timing | str], repeats: int) -> Timing | str:
    """The fastest of `repeats` runs (other jobs on the machine only ever slow a run down)."""
    results = [run() for _ in range(max(repeats, 1))]
    timings = [r for r in results if isinstance(r, Timing)]
    return min(timings, key=lambda t: t.per_step) if timings else results[0]


def steps_for(n: int, quick: bool) -> int:
    return (400 if n <= 20 else 200 if n <= 300 else 100) // (4 if quick else 1)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--quick", action="store_true", help="fewer steps per row")
    parser.add_argument("--counts", type=int, nargs="*", default=list(COUNTS))
    parser.add_argument("--peers", nargs="*", default=list(PEERS), help=f"of: {', '.join(PEERS)}")
    parser.add_argument("--repeats", type=int, default=3, help="runs of each cell; the fastest counts")
    args = parser.parse_args()
    ours(crowd(3), 5, True)  # compile / load the cache outside the timing
    ours(crowd(3), 5, False)
    names = ["socnavgen", "socnavgen, Python policy", *args.peers]
    table: dict[int, dict[str, Timing | str]] = {}
    for n in args.counts:
        c, steps = crowd(n), steps_for(n, args.quick)
        row: dict[str, Timing | str] = {
            "socnavgen": best(partial(ours, c, steps, False), args.repeats),
            "socnavgen, Python policy": best(partial(ours, c, steps, True), args.repeats)}
        for name in args.peers:
            row[name] = best(partial(measure, name, c, steps), args.repeats)
        table[n] = row
        print(f"{n} people done", file=sys.stderr)

    print(f"dt = {DT} s, walled square at 0.1 pedestrians/m^2, cyclic routes, numba "
          f"{'on' if AVAILABLE else 'OFF (plain Python)'}; cells: steps/s (us/step) [mean speed m/s at the end]")
    print("| pedestrians | " + " | ".join(names) + " |")
    print("|---:|" + "---:|" * len(names))
    for n, row in table.items():
        cells = [t if isinstance(t, str) else f"{1 / t.per_step:,.0f} ({t.per_step * 1e6:,.0f}) [{t.mean_speed:.2f}]"
                 for t in (row[k] for k in names)]
        print(f"| {n} | " + " | ".join(cells) + " |")
    ratios = [(n, row["socnavgen"].per_step / row["JuPedSim SFM"].per_step) for n, row in table.items()
              if isinstance(row.get("JuPedSim SFM"), Timing)]
    if ratios:
        print("\nsocnavgen / JuPedSim SFM time per step: " + ", ".join(f"{n}: {r:.2f}x" for n, r in ratios))
    times = [(n, row["socnavgen"].per_step) for n, row in table.items()]
    if len(times) >= 2:
        (n0, t0), (n1, t1) = times[-2], times[-1]
        print(f"cost growth {n0}->{n1} pedestrians: x{t1 / t0:.1f} for x{n1 / n0:.1f} pedestrians "
              f"(exponent {math.log(t1 / t0) / math.log(n1 / n0):.2f}; 1 = linear, 2 = quadratic)")


if __name__ == "__main__":
    main()
