"""One person alone walks every edge of every bundled location and of SocRATES's arena and hospital (their own
scene graphs and the graphs `location extract` drafts on their scans), and every person's path of every card
that fits: they must arrive. Doors (the home's 0.9 m bedroom doors), corners and aisles must let a walker
through as they let a person through (issue 25: the bedroom doors stopped walkers 0.7 m before the door).

An edge narrower than a person passes (location.passages.passage_width_m under PASSABLE) is no way for a
person: the drafts `location extract` makes have some (0.2 - 0.6 m gaps between furniture; an extraction
matter); they are not walked, and the drawn maps (bundled and imported) must have none."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from socnavgen.bodies import PERSON_GOAL_RADIUS, PERSON_GOAL_SLACK
from socnavgen.cards.generate import fit_all
from socnavgen.location import Location, load_location
from socnavgen.location.extract import ExtractOptions, extract_location
from socnavgen.location.importer import import_socrates
from socnavgen.location.passages import passage_width_m
from socnavgen.sim import HumanSpec, SimConfig, Simulation, World

from .simhelpers import REGULAR, Stay, tree_xml

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "locations"
SOCRATES = Path(__file__).resolve().parents[1] / "extract" / "data"
MAPS = ["warehouse", "hospital", "home", "socrates_arena", "socrates_hospital", "socrates_arena extracted",
        "socrates_hospital extracted"]
ARRIVED = PERSON_GOAL_RADIUS + PERSON_GOAL_SLACK
PACE = 0.5  # m/s: the slowest average a walk may take (straight-line length; a detour round a wall included)
SLACK = 20.0  # s on top
PASSABLE = 0.7  # m: the narrowest way a person walks through (sideways); the home's bedroom doors are 0.9 m


@pytest.fixture(scope="module")
def locations(tmp_path_factory: pytest.TempPathFactory) -> dict[str, tuple[Location, World]]:
    out = tmp_path_factory.mktemp("maps")
    found = {name: load_location(EXAMPLES / name) for name in ("warehouse", "hospital", "home")}
    for name in ("socrates_arena", "socrates_hospital"):
        import_socrates(SOCRATES / name, out / name)
        found[name] = load_location(out / name)
        found[f"{name} extracted"], _ = extract_location(SOCRATES / name / "map.yaml", out / f"{name}_x",
                                                         ExtractOptions(seed=1))
    return {name: (loc, World.from_location(loc)) for name, loc in found.items()}


def walks(location: Location, world: World, nodes: list[str]) -> str | None:
    """Walk `nodes` alone (RegularNav, goals = the nodes after the first); None when they arrive, else where
    they stopped. The robot stands at the node farthest from the walk, out of the way (its goal 3 m off, so
    the run ends once the walker is done)."""
    points = [location.node_world(n) for n in nodes]
    others = [n for n in location.scene_graph.node_ids() if n not in nodes] or nodes
    far = max(others, key=lambda n: min(math.dist(location.node_world(n), p) for p in points))
    robot = location.node_world(far)
    length = sum(math.dist(a, b) for a, b in zip(points, points[1:], strict=False))
    sim = Simulation(world, [HumanSpec(name="human1", start=points[0], goals=points[1:])], [tree_xml(REGULAR)],
                     [robot, (robot[0] + 3.0, robot[1])], Stay(), SimConfig(timeout=length / PACE + SLACK))
    trace = sim.run()
    end = (float(trace.humans[-1, 0, 0]), float(trace.humans[-1, 0, 1]))
    if math.dist(end, points[-1]) <= ARRIVED:
        return None
    return f"{' -> '.join(nodes)}: stopped at ({end[0]:.2f}, {end[1]:.2f}), {math.dist(end, points[-1]):.2f} m short"


@pytest.mark.slow
@pytest.mark.parametrize("name", MAPS)
def test_one_person_walks_every_edge_both_ways(locations: dict[str, tuple[Location, World]], name: str) -> None:
    location, world = locations[name]
    stuck, narrow = [], []
    for edge in location.scene_graph.links:
        width = passage_width_m(location, edge.source, edge.target)
        if width < PASSABLE:
            narrow.append(f"{edge.source}-{edge.target} {width:.2f} m")
            continue
        for a, b in ((edge.source, edge.target), (edge.target, edge.source)):
            why = walks(location, world, [a, b])
            if why:
                stuck.append(why)
    assert not stuck, f"{len(stuck)} edge walk(s) of {name} do not arrive:\n" + "\n".join(stuck)
    assert name.endswith("extracted") or not narrow, f"edges of a drawn map no person fits through: {narrow}"


@pytest.mark.slow
@pytest.mark.parametrize("name", MAPS)
def test_one_person_walks_every_cards_path(locations: dict[str, tuple[Location, World]], name: str) -> None:
    location, world = locations[name]
    stuck = []
    for fit in fit_all(location):
        if not fit.fits:
            continue
        for k, h in enumerate(fit.placement.humans):
            path = [n for j, n in enumerate(h.path) if j == 0 or n != h.path[j - 1]]
            if len(path) >= 2:
                why = walks(location, world, path)
                if why:
                    stuck.append(f"{fit.card.name} human{k + 1}: {why}")
    assert not stuck, f"{len(stuck)} card path(s) on {name} do not arrive:\n" + "\n".join(stuck)
