"""`cards generate`: a card + a location -> an ordinary run folder, with no LLM.

Finds the card's place on the scene graph (location/places.py), builds the robot's route and every human's
path (routes.py), writes trees from the card's templates (trees.py), and checks the result like
stage 2 and 3 answers are checked (edges exist, interaction points on both paths, trees valid)."""

from __future__ import annotations

from dataclasses import dataclass
from datetime import UTC, datetime
from pathlib import Path

from socnavgen import __version__
from socnavgen.bt.validate import format_problems, validate_bt_text
from socnavgen.cards.library import all_cards, get_card
from socnavgen.cards.models import Card
from socnavgen.cards.routes import DoesNotFit, Placement, RouteBuilder
from socnavgen.cards.spec import card_spec
from socnavgen.cards.trees import render_template
from socnavgen.errors import ValidationFailed
from socnavgen.location import Location, load_location
from socnavgen.location.places import PlaceFinder
from socnavgen.run import (
    HumanPlan,
    Manifest,
    PathPlan,
    RunFolder,
    ScenarioProposal,
    ScenarioRequest,
    StageRecord,
)
from socnavgen.run.checks import plan_mistakes

GENERATOR = "cards"  # what request.json / manifest.json say instead of a model


@dataclass
class Fit:
    """Whether a card fits a location, with the placement or the reason it does not."""

    card: Card
    placement: Placement | None
    reason: str = ""

    @property
    def fits(self) -> bool:
        return self.placement is not None


def place_card(card: Card, location: Location, pick: int = 0, finder: PlaceFinder | None = None) -> Fit:
    """The `pick`-th placement of the card on the location (0 = the best), or why there is none."""
    finder = finder or PlaceFinder(location)
    builder = RouteBuilder(finder)
    for feature in card.requires:
        if not finder.candidates(feature):
            return Fit(card, None, finder.why_missing(feature))
    candidates = finder.candidates(card.place)
    if not candidates:
        return Fit(card, None, finder.why_missing(card.place))
    reasons: list[str] = []
    found = 0
    for cand in candidates:
        try:
            placement = builder.place(card, cand)
        except DoesNotFit as exc:
            reasons.append(f"{cand.node}: {exc}")
            continue
        if found == pick:
            return Fit(card, placement)
        found += 1
    if found:
        return Fit(card, None, f"only {found} placement(s) exist; --pick {pick + 1} is too large")
    shown = "; ".join(dict.fromkeys(r.split(": ", 1)[1] for r in reasons))
    return Fit(card, None, f"no {card.place.replace('_', ' ')} of this location fits: {shown}")


def fit_all(location: Location) -> list[Fit]:
    finder = PlaceFinder(location)
    return [place_card(card, location, finder=finder) for card in all_cards()]


def _plan(placement: Placement, location: Location) -> PathPlan:
    humans = [HumanPlan(name=f"human{k + 1}", path=h.path, group_id=h.group_id, interaction_point=h.meets_at)
              for k, h in enumerate(placement.humans)]
    plan = PathPlan(reasoning=f"scenario card {placement.card.name} placed at {placement.place.node}: "
                              f"{placement.place.evidence}",
                    robot=placement.robot, humans=humans, robot_gestures=placement.card.robot_gestures)
    mistakes = plan_mistakes(plan, location.scene_graph)
    if mistakes:  # a generator bug: say so loudly rather than write a broken run
        raise ValidationFailed("card generator produced invalid paths: " + "; ".join(mistakes))
    return plan


def _tree_id(template: str) -> str:
    return "".join(part.capitalize() for part in template.split("_")) + "Tree"


def _trees(placement: Placement) -> dict[str, str]:
    ids = set(range(len(placement.humans)))
    trees = {}
    for k, h in enumerate(placement.humans):
        xml = render_template(h.role.tree, _tree_id(h.role.tree))
        problems = validate_bt_text(xml, f"human{k + 1}", human_ids=ids, agent_id=k)
        if problems:
            raise ValidationFailed("card tree is invalid:\n" + format_problems(problems))
        trees[f"human{k + 1}"] = xml
    return trees


def write_card_run(card_name: str, location_dir: Path | str, out_dir: Path | str, pick: int = 0) -> RunFolder:
    """Generate the run folder of one card on one location (raises ValidationFailed if it does not fit)."""
    card = get_card(card_name)
    location = load_location(location_dir)
    fit = place_card(card, location, pick)
    if fit.placement is None:
        raise ValidationFailed(f"card {card.name} does not fit location {location.name}: {fit.reason}",
                               hint="socnavgen cards generate --all --location ... lists which cards fit")
    placement = fit.placement
    plan = _plan(placement, location)
    trees = _trees(placement)
    run = RunFolder(Path(out_dir))
    run.root.mkdir(parents=True, exist_ok=True)
    p = placement.place
    run.write_request(ScenarioRequest(location=str(Path(location_dir)), context=card.context, task=card.task,
                                      rough=card.rough, card=card.name, llm=GENERATOR))
    where = f"at node {p.node} ({location.graph.nodes[p.node].get('type', '')}; {p.evidence})"
    run.write_scenario(ScenarioProposal(
        scenario_description=f"{card.title}: {card.summary} The encounter happens {where}.",
        number_of_humans=len(plan.humans),
        human_behaviors={h.name: r.role.behavior for h, r in zip(plan.humans, placement.humans, strict=True)},
        expected_robot_behavior=card.expected_robot_behavior))
    run.write_paths(plan)
    run.write_spec(card_spec(placement, plan, location))
    for name, xml in trees.items():
        run.write_behavior(name, xml)
    done = StageRecord(status="done", attempts=1)
    run.write_manifest(Manifest(socnavgen_version=__version__, created=datetime.now(UTC).isoformat(timespec="seconds"),
                                llm=GENERATOR, status="done",
                                stages={"scenario": done, "paths": done, "behaviors": done},
                                message=f"scenario card {card.name} placed {where}"))
    return run
