"""Every card that fits, on every bundled location and on SocRATES's arena and hospital (their own scene
graphs, and the graphs `location extract` drafts on their scans: maps nobody here drew), starts nobody on
or against anybody: the gaps at the start nodes are computed here from the bodies (socnavgen.bodies), a
group's members anywhere on their circle, and nobody starts on the robot's goal unless they walk away."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from socnavgen.bodies import CONTACT_MARGIN, GROUP_SPAWN_RADIUS, PERSON_RADIUS, ROBOT_RADIUS
from socnavgen.cards.generate import fit_all
from socnavgen.location import Location, load_location
from socnavgen.location.extract import ExtractOptions, extract_location
from socnavgen.location.importer import import_socrates

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "locations"
SOCRATES = Path(__file__).resolve().parents[1] / "extract" / "data"
MAPS = ["warehouse", "hospital", "home", "socrates_arena", "socrates_hospital", "socrates_arena extracted",
        "socrates_hospital extracted"]


@pytest.fixture(scope="module")
def locations(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Location]:
    out = tmp_path_factory.mktemp("maps")
    found = {name: load_location(EXAMPLES / name) for name in ("warehouse", "hospital", "home")}
    for name in ("socrates_arena", "socrates_hospital"):
        import_socrates(SOCRATES / name, out / name)
        found[name] = load_location(out / name)
        location, _ = extract_location(SOCRATES / name / "map.yaml", out / f"{name}_x", ExtractOptions(seed=1))
        found[f"{name} extracted"] = location
    return found


def _gaps(location: Location, robot: list[str], humans: list[tuple[list[str], int]]) -> list[tuple[str, float]]:
    """(who, smallest surface gap) of every pair of bodies at their starts."""
    def at(node: str) -> tuple[float, float]:
        return location.node_world(node)

    sizes: dict[int, int] = {}
    for _, gid in humans:
        if gid >= 0:
            sizes[gid] = sizes.get(gid, 0) + 1

    def ring(gid: int) -> float:
        return GROUP_SPAWN_RADIUS if gid >= 0 and sizes[gid] > 1 else 0.0

    gaps = []
    for k, (path, gid) in enumerate(humans):
        d = math.dist(at(path[0]), at(robot[0]))
        gaps.append((f"robot-human{k + 1}", d - ring(gid) - PERSON_RADIUS - ROBOT_RADIUS))
        for j, (other, ogid) in enumerate(humans[:k]):
            if gid >= 0 and gid == ogid:
                continue  # one group: its members stand on their circle around the shared node
            d = math.dist(at(path[0]), at(other[0]))
            gaps.append((f"human{j + 1}-human{k + 1}", d - ring(gid) - ring(ogid) - 2 * PERSON_RADIUS))
    return gaps


@pytest.mark.parametrize("name", MAPS)
def test_no_card_starts_anybody_on_anybody(locations: dict[str, Location], name: str) -> None:
    location = locations[name]
    fits = [f for f in fit_all(location) if f.fits]
    assert len(fits) >= 15, [f.reason for f in fit_all(location) if not f.fits]
    for fit in fits:
        placement = fit.placement
        robot = placement.robot
        assert robot[0] != robot[-1], (fit.card.name, robot)
        humans = [(h.path, h.group_id) for h in placement.humans]
        touching = [(who, round(gap, 2)) for who, gap in _gaps(location, robot, humans) if gap <= CONTACT_MARGIN]
        assert touching == [], (fit.card.name, robot, humans)
        for path, _ in humans:  # on the robot's goal only to leave it (someone coming out of the room it enters)
            if path[0] == robot[-1]:
                assert len(set(path)) > 1 and path[-1] != robot[-1], (fit.card.name, robot, path)
