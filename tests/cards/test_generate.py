"""Every card that fits a bundled location becomes an ordinary run folder (paths, trees, spec.json) that
exports."""

from __future__ import annotations

from pathlib import Path

import networkx as nx
import pytest

from socnavgen.bt.validate import validate_bt_text
from socnavgen.cards.generate import fit_all, place_card, write_card_run
from socnavgen.cards.library import get_card
from socnavgen.errors import SocnavgenError
from socnavgen.export import export_run
from socnavgen.location import load_location
from socnavgen.proposal.tree_needs import tree_need_mistakes
from socnavgen.run import RunFolder

MUST_FIT = {
    "warehouse": {"blind-corner", "narrow-hallway", "intersection-wait", "frontal-approach", "crowd-navigation",
                  "join-group"},
    "hospital": {"entering-elevator", "exiting-elevator", "entering-room", "exiting-room", "narrow-doorway",
                 "circular-crossing"},
    "home": {"entering-room", "exiting-room", "narrow-doorway", "blind-corner"},
}
MUST_NOT_FIT = {"warehouse": {"entering-elevator": "ELEVATOR", "entering-room": "ROOM"},
                "hospital": {}, "home": {"exiting-elevator": "ELEVATOR"}}


def check_run(run: RunFolder, graph: nx.Graph) -> None:
    request, plan, trees = run.read_request(), run.read_paths(), run.behaviors()
    assert request.card and request.rough == get_card(request.card).rough
    assert run.read_manifest().status == "done"
    assert run.read_scenario().number_of_humans == len(plan.humans) == len(trees)
    ids = {h.agent_id for h in plan.humans}
    # one start node per agent, except that a group starts together (on a small circle around its node)
    starts = [plan.robot[0]] + [h.path[0] for h in plan.humans if h.group_id == -1]
    starts += list({h.group_id: h.path[0] for h in plan.humans if h.group_id != -1}.values())
    assert len(starts) == len(set(starts)), "two agents spawn on the same node"
    for who, path in [("robot", plan.robot)] + [(h.name, h.path) for h in plan.humans]:
        assert all(graph.has_edge(a, b) for a, b in zip(path, path[1:], strict=False)), who
    for h in plan.humans:
        if h.interaction_point:
            assert h.interaction_point in h.path and h.interaction_point in plan.robot, h.name
        assert validate_bt_text(trees[h.name], h.name, human_ids=ids, agent_id=h.agent_id) == []


def test_every_fitting_card_generates_exports_and_writes_its_spec(bundled_location: Path, tmp_path: Path) -> None:
    """Generation side (the simulation and verdict of every card: test_scenarios.py)."""
    location = load_location(bundled_location)
    fits = fit_all(location)
    fitting = {f.card.name for f in fits if f.fits}
    assert MUST_FIT[bundled_location.name] <= fitting
    for fit in fits:
        if not fit.fits:
            assert fit.reason
            continue
        run = write_card_run(fit.card.name, bundled_location, tmp_path / fit.card.name)
        check_run(run, location.graph)
        spec, plan = run.read_spec(), run.read_paths()
        assert spec is not None, fit.card.name
        assert {c.kind for c in spec.criteria} >= {"robot_reaches_goal", "no_collision", "no_deadlock"}
        for enc in spec.encounters:  # grounded on both paths; a doorway encounter in the doorway itself
            part = enc.humans[0]
            path = next(h.path for h in plan.humans if h.name == part.human)
            assert enc.node in path and enc.node in plan.robot, (fit.card.name, enc.node)
            if fit.card.place == "doorway":
                assert enc.node == fit.placement.place.node
        for name, xml in run.behaviors().items():  # each tree does what the card's spec says of its human
            assert tree_need_mistakes(xml, name, spec) == [], (fit.card.name, name)
        for h in plan.humans:  # nobody starts on the robot's goal (it would drive into them)
            assert h.path[0] != plan.robot[-1] or fit.card.route in ("into", "out_of"), (fit.card.name, h.name)
        result = export_run(run.root, "socrates", tmp_path / "out" / fit.card.name)
        assert "hunav_agent_manager/config/custom_agents.yaml" in result.files
        try:
            export_run(run.root, "hunav2", tmp_path / "out2" / fit.card.name)
        except SocnavgenError as exc:  # allowed only for nodes 2.x lacks, each named
            assert "no HuNavSim 2.x equivalent" in str(exc)
    for name, word in MUST_NOT_FIT[bundled_location.name].items():
        reason = next(f.reason for f in fits if f.card.name == name)
        assert word in reason and "schema has none" in reason


def test_generation_is_deterministic(tmp_path: Path, repo_root: Path) -> None:
    loc = repo_root / "examples/locations/hospital"
    if not loc.is_dir():
        pytest.fail("hospital location not present")
    a = write_card_run("crowd-navigation", loc, tmp_path / "a")
    b = write_card_run("crowd-navigation", loc, tmp_path / "b")
    assert a.read_paths() == b.read_paths()
    assert a.behaviors() == b.behaviors()


def test_pick_gives_another_place_and_too_large_pick_is_explained(repo_root: Path) -> None:
    loc = repo_root / "examples/locations/warehouse"
    if not loc.is_dir():
        pytest.fail("warehouse location not present")
    location = load_location(loc)
    first = place_card(get_card("intersection-no-gesture"), location, 0)
    second = place_card(get_card("intersection-no-gesture"), location, 1)
    assert first.fits and second.fits and first.placement.place != second.placement.place
    assert "too large" in place_card(get_card("intersection-no-gesture"), location, 99).reason


def test_card_that_does_not_fit_raises_with_reason(tmp_path: Path, repo_root: Path) -> None:
    loc = repo_root / "examples/locations/warehouse"
    if not loc.is_dir():
        pytest.fail("warehouse location not present")
    with pytest.raises(SocnavgenError, match="ELEVATOR"):
        write_card_run("entering-elevator", loc, tmp_path / "x")
    assert not (tmp_path / "x").exists()


def test_crossing_people_never_walk_to_where_the_robot_starts(repo_root: Path) -> None:
    """A crossing person with no branch of their own past P turns into the robot's way in; walking on to the robot's
    start they walked up to a robot that had not left and stood in its way for the whole run (home, 3-way hallway)."""
    crossing_cards = 0
    for name in ("home", "hospital", "warehouse"):
        for fit in fit_all(load_location(repo_root / "examples" / "locations" / name)):
            if not fit.fits:
                continue
            for human in fit.placement.humans:
                if human.role.role == "crossing":
                    crossing_cards += 1
                    assert human.path[-1] != fit.placement.robot[0], (name, fit.card.name, human.path)
    assert crossing_cards >= 5  # the warehouse's intersection cards still place their crossing people
    home = load_location(repo_root / "examples" / "locations" / "home")
    fit = place_card(get_card("perpendicular-traffic"), home)  # its 3-way hallway would need that walk
    assert not fit.fits and "side branch at i6" in fit.reason


def test_a_person_waiting_for_the_robot_starts_their_waiting_distance_past_its_goal(tmp_path: Path) -> None:
    """exiting-elevator's person waits (looking at the robot) while it is within 2.5 m: they start that far and
    both bodies past the robot's goal, along the corridor (SocRATES's hospital started them on the next node,
    1.5 m from the goal: each waited for the other for 100 s). A corridor that ends too soon after the robot's
    goal does not fit the card (no start past the goal is far enough)."""
    from socnavgen.bodies import PERSON_RADIUS, ROBOT_RADIUS
    from socnavgen.cards.trees import sight_distance
    from socnavgen.location.places import PlaceFinder
    from tests.cards.cards_helpers import lift_corridor

    card = get_card("exiting-elevator")
    wait = sight_distance(card.humans[0].tree)  # the one condition of its tree: it waits while the robot is this near
    location = load_location(lift_corridor(tmp_path / "long", 10))
    fit = place_card(card, location)
    assert fit.fits, fit.reason
    start, goal = fit.placement.humans[0].path[0], fit.placement.robot[-1]
    assert PlaceFinder(location).distance(start, goal) >= wait + PERSON_RADIUS + ROBOT_RADIUS
    short = place_card(card, load_location(lift_corridor(tmp_path / "short", 5)))
    assert not short.fits and "m from it" in short.reason
