"""What the Gymnasium env's range scan and route give a policy: on every card of the bundled locations where a
wall stands between the robot's start and its goal (no line of sight), goals reached by a simple reactive
policy that reads the scan and the route, against one that reads today's observation only (go to the goal).

    python benchmarks/gym_bench.py                    # warehouse, hospital, home; 1 seed; 60 s episodes
    python benchmarks/gym_bench.py --seeds 1 --locations home

Both policies drive at up to 0.8 m/s. `go-to-goal` heads straight for obs["goal"]. `scan+route` heads for the
route point LOOK_AHEAD m ahead, slows down for scan returns in the band CORRIDOR m either side of that way and is
pushed off returns closer than PUSH_RANGE (people and walls alike); after standing PATIENCE s it backs off
BACK_OFF s (someone in a doorway waiting for it to make way). `scan+route (unicycle)` is the same policy
sending differential-drive commands (action="unicycle"). The people of each card walk as the card says. CPU
seconds of this process per policy.
"""

from __future__ import annotations

import argparse
import math
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "src"))

from socnavgen.cards.generate import fit_all, write_card_run  # noqa: E402
from socnavgen.location import load_location  # noqa: E402
from socnavgen.run import load_run  # noqa: E402
from socnavgen.sim import World  # noqa: E402
from socnavgen.sim.engine.scenario import node_worlds  # noqa: E402

SPEED = 0.8  # m/s
LOOK_AHEAD = 1.0  # m along the route
CORRIDOR = 0.32  # m each side of its way: the band whose returns slow it down
STOP_GAP = 0.45  # m of scan range ahead at which it stands
PUSH_RANGE, PUSH_GAIN = 0.7, 24.0  # m; 1/s per metre inside PUSH_RANGE, over the beams' count
PATIENCE, BACK_OFF, BACK_SPEED = 3.0, 2.0, 0.3  # s standing, s backing off, m/s
STILL = 0.05  # m/s: slower counts as standing


def walled_cards(location_dir: Path, out: Path) -> list[tuple[str, Path]]:
    """(card, run folder) of every fitting card whose robot start and goal are not in line of sight."""
    location = load_location(location_dir)
    world = World.from_location(location)
    found = []
    for fit in fit_all(location):
        if not fit.fits:
            continue
        run = load_run(write_card_run(fit.card.name, location_dir, out / location_dir.name / fit.card.name).root)
        at = node_worlds(run, location)
        nodes = run.paths().robot
        start, goal = complex(*at[nodes[0]]), complex(*at[nodes[-1]])
        if not world.line_of_sight(start, goal)[0]:
            found.append((f"{location_dir.name}/{fit.card.name}", run.root))
    return found


def go_to_goal(obs: dict) -> np.ndarray:
    g = obs["goal"].astype(float)
    return SPEED * g / max(float(np.hypot(*g)), 1e-6)


class ScanRoute:
    """Heads along the route, slows for scan returns in its way, is pushed off near ones, and after standing
    PATIENCE s backs off for BACK_OFF s (someone waiting for it to make way)."""

    def __init__(self, dt: float) -> None:
        self.dt, self.stood, self.backing = dt, 0.0, 0.0

    def __call__(self, obs: dict) -> np.ndarray:
        route = obs["route"].astype(float)
        spacing = float(np.hypot(*route[0])) or 0.5
        target = route[min(len(route) - 1, max(0, round(LOOK_AHEAD / max(spacing, 1e-3)) - 1))]
        heading = math.atan2(target[1], target[0])
        way = np.array([math.cos(heading), math.sin(heading)])
        if self.backing > 0:
            self.backing -= self.dt
            return -BACK_SPEED * way
        scan, yaw = obs["scan"].astype(float), float(obs["robot"][2])
        angles = yaw + 2 * np.pi * np.arange(len(scan)) / len(scan)
        along, across = scan * np.cos(angles - heading), scan * np.sin(angles - heading)
        ahead = along[(along > 0) & (np.abs(across) < CORRIDOR)]  # returns in the band it would sweep
        free = float(ahead.min()) if ahead.size else math.inf
        speed = min(SPEED, max(0.0, free - STOP_GAP), float(np.hypot(*target)))
        moving = float(np.hypot(*obs["robot"][3:5]))
        self.stood = self.stood + self.dt if moving < STILL else 0.0
        if self.stood >= PATIENCE:
            self.stood, self.backing = 0.0, BACK_OFF
        push = -(np.maximum(PUSH_RANGE - scan, 0.0) * np.stack([np.cos(angles), np.sin(angles)])).sum(axis=1)
        push *= PUSH_GAIN / len(scan)
        return speed * way + push


def as_unicycle(v: np.ndarray, yaw: float) -> np.ndarray:
    error = (math.atan2(v[1], v[0]) - yaw + math.pi) % (2 * math.pi) - math.pi
    return np.array([float(np.hypot(*v)) * max(0.0, math.cos(error)), 3.0 * error])


POLICIES = {"go-to-goal": ("velocity", lambda dt: go_to_goal), "scan+route": ("velocity", ScanRoute),
            "scan+route (unicycle)": ("unicycle", ScanRoute)}


def episode(env, make, key: str, scenario: int, seed: int) -> bool:  # noqa: ANN001
    obs, _ = env.reset(seed=seed, options={"scenario": scenario})
    policy = make(env.dt)
    while True:
        v = policy(obs)
        command = as_unicycle(v, float(obs["robot"][2])) if key == "unicycle" else v
        obs, _, terminated, truncated, _ = env.step({key: command.astype(np.float32), "gesture": 0})
        if terminated or truncated:
            return bool(terminated)


def main() -> None:
    from socnavgen.campaign.gym_env import SocNavEnv

    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--locations", nargs="+", default=["warehouse", "hospital", "home"])
    parser.add_argument("--seeds", type=int, default=1)
    parser.add_argument("--timeout", type=float, default=60.0)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        cards = [c for name in args.locations
                 for c in walled_cards(REPO / "examples" / "locations" / name, Path(tmp))]
        print(f"{len(cards)} cards with a wall between start and goal: {', '.join(c for c, _ in cards)}\n")
        rows, reached_by = [], {}
        for name, (key, policy) in POLICIES.items():
            env = SocNavEnv([run for _, run in cards], timeout=args.timeout, action=key)
            t0, reached = time.process_time(), []
            for i, (card, _) in enumerate(cards):
                for seed in range(args.seeds):
                    if episode(env, policy, key, i, seed):
                        reached.append(card)
            cpu = time.process_time() - t0
            reached_by[name] = reached
            rows.append((name, len(reached), len(cards) * args.seeds, cpu))
    print("| policy | goals reached / episodes | CPU s |")
    print("|---|---:|---:|")
    for name, n, total, cpu in rows:
        print(f"| {name} | {n} / {total} | {cpu:.1f} |")
    for name, reached in reached_by.items():
        missed = sorted({c for c, _ in cards} - set(reached))
        print(f"\n{name} never reached: {', '.join(missed) or '-'}")


if __name__ == "__main__":
    main()
