"""Do the planning robots reach the goal on every card of every bundled location and of the extracted SocRATES
maps (tests/extract/data, imported as `location-from-world` does)? Each card's robot route, nobody else there
(as tests/sim/test_planner.py, which asserts it for scripted, orca and dwa), 120 s; prints the misses.

    python scripts/planner_reach.py [--robots scripted sfm orca dwa]
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "src"))

from socnavgen.cards.generate import fit_all, write_card_run  # noqa: E402
from socnavgen.location import load_location  # noqa: E402
from socnavgen.location.importer import import_socrates  # noqa: E402
from socnavgen.run import load_run  # noqa: E402
from socnavgen.sim import SimConfig, Simulation, World, load_policy  # noqa: E402
from socnavgen.sim.engine.scenario import node_worlds  # noqa: E402

BUNDLED = ("warehouse", "hospital", "home")
SOCRATES = ("socrates_arena", "socrates_hospital", "socrates_small_warehouse")


def routes(location_dir: Path, out: Path) -> list[tuple[str, World, list]]:
    location = load_location(location_dir)
    world = World.from_location(location)
    found = []
    for fit in fit_all(location):
        if fit.fits:
            run = load_run(write_card_run(fit.card.name, location_dir, out / fit.card.name, 0).root)
            at = node_worlds(run, location)
            found.append((fit.card.name, world, [at[n] for n in run.paths().robot]))
    return found


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--robots", nargs="+", default=["scripted", "sfm", "orca", "dwa"])
    args = parser.parse_args()
    misses, total = [], 0
    with tempfile.TemporaryDirectory() as tmp:
        places = [(n, ROOT / "examples" / "locations" / n) for n in BUNDLED]
        for name in SOCRATES:
            import_socrates(ROOT / "tests" / "extract" / "data" / name, Path(tmp) / name)
            places.append((name, Path(tmp) / name))
        for name, location_dir in places:
            cards = routes(location_dir, Path(tmp) / "runs" / name)
            for robot in args.robots:
                t0, missed = time.process_time(), 0
                for card, world, waypoints in cards:
                    trace = Simulation(world, [], [], waypoints, load_policy(robot), SimConfig(timeout=120)).run()
                    total += 1
                    if trace.end_reason != "robot_goal":
                        missed += 1
                        misses.append(f"{name}/{card} {robot}: {trace.end_reason} at "
                                      f"{trace.robot[-1, :2].round(2).tolist()}, goal {tuple(round(v, 2) for v in waypoints[-1])}")
                print(f"{name:26s} {robot:9s} {len(cards) - missed:3d} / {len(cards):3d} reached  "
                      f"({time.process_time() - t0:.1f} CPU s)", flush=True)
    print(f"\n{total - len(misses)} / {total} reached; misses:" if misses else f"\nall {total} reached")
    for line in misses:
        print("  " + line)


if __name__ == "__main__":
    main()
