"""A robot policy of your own, called between two steps: steps per second with 1, 5 and 20 people, beside
the built-in robot compiled into the step, the ORCA and DWA baselines (Python policies: `--robot orca|dwa`)
and the Gymnasium env (a 5-person card), and - with `--before SRC`
- the same scenes on another version of socnavgen (e.g. a checkout of the commit before the simulator
became one implementation, whose Python step loop ran every user policy), in one table.

Scene: sim_bench's open walled square (0.1 pedestrians/m^2, RegularNav trees), the robot driving to its goal
with a trivial policy (straight at the goal at 0.6 m/s, one RobotAction per step). CPU seconds of the
simulating thread.

    python benchmarks/policy_bench.py
    git worktree add /tmp/before b64c84a && python benchmarks/policy_bench.py --before /tmp/before/src
"""

from __future__ import annotations

import argparse
import json
import math
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[1]
DT, DENSITY, STEPS = 0.05, 0.1, 2000
KINDS = ("builtin", "python", "orca", "dwa")


def scene(n: int) -> tuple[float, list[tuple[tuple[float, float], list[tuple[float, float]]]]]:
    side = max(20.0, math.sqrt(n / DENSITY))
    rng = np.random.default_rng(0)
    people = []
    for _ in range(n):
        start, goal = rng.uniform(1.0, side - 1.0, 2), rng.uniform(1.0, side - 1.0, 2)
        people.append((tuple(start), [tuple(goal), tuple(start)]))
    return side, people


def measure(n: int, kind: str) -> float:
    """Seconds per step of this process's socnavgen: a trivial Python policy ('python'), the built-in waypoints
    robot ('builtin') or a named robot ('orca', 'dwa'); works with the facade (socnavgen.sim) and with the modules of older versions."""
    try:
        from socnavgen.sim import HumanSpec, RobotAction, SimConfig, Simulation, empty_room, load_policy
    except ImportError:  # before the facade
        from socnavgen.sim.agents import HumanSpec

        from socnavgen.sim.engine import SimConfig, Simulation
        from socnavgen.sim.robot import RobotAction, load_policy
        from socnavgen.sim.world import empty_room
    from socnavgen.bt.library import regular_walker_xml

    class Toward:
        def act(self, obs):  # noqa: ANN001, ANN202
            to = obs.waypoints_c[-1] - obs.position_c
            v = 0.6 * to / max(abs(to), 1e-9)
            return RobotAction(v.real, v.imag)

    side, people = scene(n)
    humans = [HumanSpec(name=f"human{i + 1}", start=s, goals=g, cyclic=True) for i, (s, g) in enumerate(people)]
    best = math.inf
    for _ in range(3):
        sim = Simulation(empty_room(side, side, resolution=0.1), humans, [regular_walker_xml()] * n,
                         [(0.8, side / 2), (side - 0.8, side / 2)], Toward() if kind == "python" else
                         load_policy("waypoints" if kind == "builtin" else kind),
                         SimConfig(dt=DT, timeout=STEPS * DT, idle_end=1e9))
        start = time.thread_time()
        trace = sim.run()
        best = min(best, (time.thread_time() - start) / max(trace.steps - 1, 1))
    return best


def measure_gym(run_dir: str) -> float:
    from socnavgen.campaign.gym_env import SocNavEnv

    env = SocNavEnv(run_dir, timeout=60.0)
    env.reset(seed=0)
    action = {"velocity": np.array([0.3, 0.0], dtype=np.float32), "gesture": 0}
    best = math.inf
    for seed in range(3):
        env.reset(seed=seed)
        steps, start = 0, time.thread_time()
        done = False
        while not done:
            _, _, terminated, truncated, _ = env.step(action)
            steps, done = steps + 1, terminated or truncated
        best = min(best, (time.thread_time() - start) / steps)
    return best


def child(counts: list[int], run_dir: str) -> dict:
    rows = {}
    for n in counts:
        for kind in KINDS:
            try:
                rows[f"{kind} {n}"] = measure(n, kind)
            except Exception as exc:  # noqa: BLE001 - a version without this robot (--before)
                if kind in ("builtin", "python"):
                    raise
                print(f"{kind}: {exc}", file=sys.stderr)
    rows["gym 5"] = measure_gym(run_dir)
    return rows


def run_child(src: str | None, counts: list[int], run_dir: str) -> dict:
    env = dict(os.environ)
    if src is not None:
        env["PYTHONPATH"] = os.pathsep.join([str(Path(src).resolve()), str(Path(src).resolve().parent)])
    out = subprocess.run([sys.executable, __file__, "--child", run_dir, "--counts", *map(str, counts)], env=env,
                         capture_output=True, text=True, check=True, timeout=3600)
    return json.loads(out.stdout.strip().splitlines()[-1])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--before", help="src folder of another socnavgen version to measure beside this one")
    parser.add_argument("--counts", type=int, nargs="*", default=[1, 5, 20])
    parser.add_argument("--child", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:
        print(json.dumps(child(args.counts, args.child)))
        return
    from socnavgen.cards.generate import write_card_run

    with tempfile.TemporaryDirectory(prefix="policy-bench-") as tmp:
        run = write_card_run("crowd-navigation", REPO / "examples" / "locations" / "warehouse", Path(tmp) / "run")
        now = run_child(str(REPO / "src"), args.counts, str(run.root))
        before = run_child(args.before, args.counts, str(run.root)) if args.before else None
    print(f"dt = {DT} s, open walled square at {DENSITY} pedestrians/m^2, RegularNav trees; gym: the "
          f"crowd-navigation card (5 people) on the warehouse; CPU time of the simulating thread")
    head = "| robot | people | steps/s | real-time factor | us/step |" + (" before: steps/s | speed-up |" if before else "")
    print(head)
    print("|---|---:|---:|---:|---:|" + ("---:|---:|" if before else ""))
    names = {"builtin": "built-in waypoints (compiled in the step)", "python": "a Python policy",
             "orca": "orca (Python: ORCA's linear program)", "dwa": "dwa (Python: numpy over the window)",
             "gym": "the Gymnasium env, a constant action"}
    for key, sec in now.items():
        kind, n = key.split()
        row = f"| {names[kind]} | {n} | {1 / sec:,.0f} | {DT / sec:,.0f}x | {sec * 1e6:.1f} |"
        if before:
            row += f" {1 / before[key]:,.0f} | x{before[key] / sec:.1f} |" if key in before else " - | - |"
        print(row)


if __name__ == "__main__":
    main()
