"""Time the cost-to-go fields on the bundled locations (a fresh World each round, so nothing is cached):
the robot planner's fields for one card's waypoints, the people's route fields for its landmarks, the
verifier's walkable distances and the metrics' shortest walkable route; then a card's simulate time (a
warm process: the World's fields are then kept). One command, a printed table:

    python benchmarks/fields_bench.py
"""

from __future__ import annotations

import tempfile
import time
from pathlib import Path

import numpy as np

from socnavgen.cards.generate import fit_all, write_card_run
from socnavgen.location import load_location
from socnavgen.run import load_run
from socnavgen.sim import World, simulate_run
from socnavgen.sim.engine.scenario import node_worlds
from socnavgen.sim.robot.fields import route_fields
from socnavgen.sim.world.routes import RouteGrid
from socnavgen.sim.world.walkable import WalkableDistance

LOCATIONS = Path(__file__).resolve().parents[1] / "examples" / "locations"
ROUNDS = 3


def fresh(location) -> World:  # noqa: ANN001
    """A new World (World.from_location keeps one per Location, with its fields)."""
    return World(location.occupancy, location.transform)


def best(fn, location) -> float:  # noqa: ANN001
    """Milliseconds of fn(a fresh World) (the World built outside the clock), best of ROUNDS."""
    times = []
    for _ in range(ROUNDS):
        world = fresh(location)
        start = time.perf_counter()
        fn(world)
        times.append(time.perf_counter() - start)
    return min(times) * 1000


def row(name: str, tmp: Path) -> str:
    """One location's row: its first fitting card."""
    location = load_location(LOCATIONS / name)
    fit = next(f for f in fit_all(location) if f.fits)
    run = load_run(write_card_run(fit.card.name, LOCATIONS / name, tmp / name, 0).root)
    at = node_worlds(run, location)
    waypoints = [complex(*at[n]) for n in run.paths().robot]

    def people(world: World) -> None:
        grid = RouteGrid.of(world)
        for p in waypoints:
            grid.field(p)

    def walk(world: World) -> None:
        ways = WalkableDistance.of(world)
        for p in waypoints:
            ways.field(*(int(x[0]) for x in ways.cells(np.array([p]))))

    planner = best(lambda world: route_fields(world, np.array(waypoints), 0.3), location)
    routes = best(people, location)
    walkable = best(walk, location)
    length = best(lambda world: WalkableDistance.of(world, 0.3).route_length(waypoints), location)
    simulate_run(run, location=location, save=False)  # compile
    times = []
    for _ in range(ROUNDS):
        fresh_location = load_location(LOCATIONS / name)
        start = time.perf_counter()
        simulate_run(run, location=fresh_location, save=False)
        times.append(time.perf_counter() - start)
    return (f"{name:10} {fit.card.name:22} {len(waypoints):>3} {planner:>10.1f} {routes:>9.1f} {walkable:>11.1f} "
            f"{length:>12.1f} {min(times):>10.2f}")


def main() -> None:
    print(f"{'location':10} {'card':22} {'wps':>3} {'planner ms':>10} {'routes ms':>9} {'walkable ms':>11} "
          f"{'route len ms':>12} {'simulate s':>10}")
    with tempfile.TemporaryDirectory() as tmp:
        for name in ("warehouse", "hospital", "home"):
            print(row(name, Path(tmp)))
    print("(field columns: milliseconds for every waypoint's field on a fresh World; simulate: a "
          "fresh Location, compiled code warm; best of", ROUNDS, "rounds)")


if __name__ == "__main__":
    main()
