"""Which criteria a run is judged on, and where its encounters are.

- With spec.json: its criteria, plus the ones its encounters imply (every encounter's human meets the
  robot at the encounter's node, unless another criterion already shows that encounter: a meeting, keeping
  away, following); and what every run is judged on: the robot reaches its goal; no contact unless the robot
  misbehaves on purpose; no deadlock unless it misbehaves or someone is meant to block it.
- Without (older runs): a spec derived from paths.json (an encounter at each human's interaction
  point, groups, the robot's goal) and the scenario card's criteria, with the SAME strict thresholds
  (a card's looser meeting distance is capped at the strict one).
"""

from __future__ import annotations

from typing import Any

from socnavgen.run.models import PathPlan
from socnavgen.run.spec import Criterion, Encounter, HumanPart, ScenarioSpec
from socnavgen.verify.criteria import stays_while_near
from socnavgen.verify.models import Source, VerifySettings
from socnavgen.verify.thresholds import HELD_ON, KIND_DISTANCE, STOP_SPEED, WAIT_MARGIN

Judged = list[tuple[Criterion, Source]]
_PEOPLE_APART = Criterion(id="people_apart", kind="people_apart", text="no two people touch each other")
SHOWS_ENCOUNTER = {"meets", "keeps_away", "follows_robot", "follows_human"}  # kinds that already show an encounter
NOT_MET = ("avoid",)  # reactions of a part that gets no implied meets (they keep away from the robot)
WALKS_ON = "walks_on_"  # id prefix of the implied criterion that a stop lasting while the robot is near ends
FOLLOW_KIND = {"follow": "follows_robot", "follow_human": "follows_human"}  # the criterion that sees a follow reaction
FILE_STEP = 1.2  # m: each further follower of the robot walks about a body and a gap farther back (a file)


def _together_at(human: str, enc: Encounter, distance: float) -> str:
    """Robot and human within `distance` of each other at the encounter's place (approach or not: ordering
    encounters needs only when each happens; whether it is a real meeting the meets criteria judge)."""
    return f"((dist_{human} <= {distance:g}) and (mid_{human}_to_{enc.id} <= {enc.within:g}))"


def meeting_distance(spec: ScenarioSpec, enc: Encounter, human: str, settings: VerifySettings) -> float:
    """How close counts as meeting `human` at `enc`: the distance of the spec's own `meets` criterion for it
    (so the order of two encounters is judged on the same meetings their criteria found), else the default."""
    for c in spec.criteria:
        if c.kind == "meets" and c.encounter == enc.id and human in [c.human, *c.humans] and c.distance:
            return c.distance
    return settings.distance


def _happens(spec: ScenarioSpec, enc: Encounter, settings: VerifySettings) -> str:
    """The robot is together with ANY of the encounter's people at its place: an encounter of a group happens when
    the robot meets the first of them (round 22's hospital_17: the order of a lobby meeting with four students
    waited for the one on the far side of their circle, who never came within 2 m behind the other three)."""
    parts = [_together_at(p.human, enc, meeting_distance(spec, enc, p.human, settings)) for p in enc.humans]
    return parts[0] if len(parts) == 1 else "(" + " or ".join(parts) + ")"


def _order_criteria(spec: ScenarioSpec, settings: VerifySettings) -> Judged:
    """Encounters with a smaller `order` happen first: for each pair of consecutive orders, the later
    encounter does not happen before the earlier one (an stl criterion, blamed on paths)."""
    ordered = sorted((e for e in spec.encounters if e.humans), key=lambda e: e.order)
    out: Judged = []
    for first, then in zip(ordered, ordered[1:], strict=False):
        if first.order == then.order:
            continue
        a, b = ", ".join(p.human for p in first.humans), ", ".join(p.human for p in then.humans)
        out.append((Criterion(id=f"order_{first.id}_{then.id}", kind="stl",
                              formula=f"(not {_happens(spec, then, settings)}) until {_happens(spec, first, settings)}",
                              text=f"{first.id} ({a}) happens before {then.id} ({b})"), "implied"))
    return out


def _node_type(location: Any, node: str) -> str:
    try:
        return str(location.scene_graph.node(node).type)
    except (AttributeError, KeyError, StopIteration, ValueError):
        return "INTERACTION POINT"


def derive_spec(plan: PathPlan, location: Any, card_criteria: list[dict] | None,
                settings: VerifySettings) -> tuple[ScenarioSpec, Judged]:
    """A spec for a run that has none: (spec, criteria with where each came from)."""
    card = [c for c in card_criteria or [] if isinstance(c, dict)]
    card_meet = {c.get("human") for c in card if c.get("kind") == "meets_human"}

    def card_within(kind: str, human: str | None) -> float | None:
        for c in card:
            if c.get("kind") == kind and c.get("human") in (None, human) and isinstance(c.get("within"), int | float):
                return float(c["within"])
        return None

    encounters: list[Encounter] = []
    judged: Judged = []
    for h in plan.humans:
        if not h.interaction_point:
            continue
        enc = Encounter(id=f"e{len(encounters) + 1}", place=_node_type(location, h.interaction_point),
                        node=h.interaction_point, humans=[HumanPart(human=h.name)], within=settings.near)
        encounters.append(enc)
        within = card_within("meets_human", h.name)
        distance = min(within, settings.distance) if within else settings.distance
        source: Source = "card" if (h.name in card_meet or None in card_meet) else "paths"
        judged.append((Criterion(id=f"meet_{h.name}", kind="meets", human=h.name, encounter=enc.id,
                                 distance=distance, text=f"robot meets {h.name} at {h.interaction_point}"), source))
    groups: dict[int, list[str]] = {}
    for h in plan.humans:
        if h.group_id != -1:
            groups.setdefault(h.group_id, []).append(h.name)
    for gid, members in sorted(groups.items()):
        if len(members) > 1:
            spread = card_within("group_together", None)
            judged.append((Criterion(id=f"group_{gid}", kind="group_together", humans=members,
                                     distance=min(spread, settings.group_spread) if spread else None,
                                     text=f"group {gid} ({', '.join(members)}) stays together"),
                           "card" if spread else "paths"))
    if plan.robot:
        from_card = any(c.get("kind") == "robot_reaches_goal" for c in card)
        judged.append((Criterion(id="goal", kind="robot_reaches_goal", text=f"robot reaches its goal {plan.robot[-1]}"),
                       "card" if from_card else "paths"))
    if plan.humans:
        judged.append((Criterion(id="no_collision", kind="no_collision", text="robot never touches a person"),
                       "paths"))
        judged.append((Criterion(id="no_deadlock", kind="no_deadlock",
                                 text="robot never stuck behind a person"), "paths"))
    if len(plan.humans) >= 2:
        judged.append((_PEOPLE_APART, "paths"))
    spec = ScenarioSpec(encounters=encounters, criteria=[c for c, _ in judged])
    return spec, judged


def implied_follows(spec: ScenarioSpec, kinds_of: dict[str | None, set[str]]) -> Judged:
    """A follow to the end (a `follow` / `follow_human` part without `lasts`) is judged by follows_robot /
    follows_human even when the spec names none: round 35's home_27 had the guest follow the robot for good after
    FOLLOW ME, and its criteria (she stood near it, stayed within 3.5 m, was within 3 m at its goal, where she had
    started) passed a guest who stepped back and stood still while the robot drove to her. A timed follow (`lasts`:
    come to the robot for a handover) is left to the spec's own criteria. The distance allows a file of followers
    (KIND_DISTANCE, FILE_STEP more per other follower of the robot)."""
    followers = sum(1 for e in spec.encounters for p in e.humans if p.reaction == "follow" and p.lasts is None)
    out: Judged = []
    for enc in spec.encounters:
        for part in enc.humans:
            kind = FOLLOW_KIND.get(part.reaction)
            if kind is None or part.lasts is not None or kind in kinds_of.get(part.human, set()):
                continue
            if part.reaction == "follow_human" and not part.other:
                continue
            distance = KIND_DISTANCE[kind] + FILE_STEP * max(followers - 1, 0)
            whom = "the robot" if kind == "follows_robot" else part.other
            out.append((Criterion(id=f"follow_{part.human}_{enc.id}", kind=kind, human=part.human, encounter=enc.id,
                                  distance=distance,
                                  text=f"{part.human} follows {whom} from {enc.node or enc.place} ({enc.id}), within "
                                       f"{distance:g} m along the way"), "implied"))
            kinds_of.setdefault(part.human, set()).add(kind)
    return out


def walks_on(spec: ScenarioSpec, plan: PathPlan | None) -> Judged:
    """A stop on robot_near without `lasts` lasts while the robot is within its distance; where the person's path
    goes on beyond the encounter, the run must not end with them still standing there with the robot that near
    for its last HELD_ON s: they would never walk on (round 34's warehouse_26: a picker told to stop while the robot is within 4 m and
    then join the queue stood to the end, the robot's goal 3.3 m from her; every criterion passed)."""
    if plan is None:
        return []
    out: Judged = []
    for enc in spec.encounters:
        for part in enc.humans:
            near = stays_while_near(part)
            human = next((h for h in plan.humans if h.name == part.human), None)
            if near is None or near == float("inf") or human is None:
                continue
            at = enc.node if enc.node in human.path else human.interaction_point
            if at not in human.path or human.path[-1] == at:
                continue  # their path ends where they stop: standing there to the end breaks no promise
            h = part.human
            held = f"((speed_{h} <= {STOP_SPEED:g}) and (dist_{h} <= {near:g}))"
            out.append((Criterion(
                id=f"{WALKS_ON}{h}_{enc.id}", kind="stl", human=h, encounter=enc.id,
                formula=f"not (eventually ((historically[0:{HELD_ON:g}] {held}) and (always {held})))",
                text=f"{h} walks on along its path after its stop at {at} ({enc.id}), which lasts while the robot "
                     f"is within {near:g} m of {h}: the run must not end with {h} standing there, the robot that "
                     f"near, for its last {HELD_ON:g} s"),
                "implied"))
    return out


def with_implied(spec: ScenarioSpec, settings: VerifySettings, people: int | None = None,
                 plan: PathPlan | None = None) -> Judged:
    """The spec's criteria and those its encounters imply, and those every run is judged on (source `implied`).
    `people`: how many humans the run has (paths.json; default: those the encounters name); `plan`: the paths
    (for walks_on)."""
    judged: Judged = [(c, "spec") for c in spec.criteria]
    kinds_of: dict[str | None, set[str]] = {}
    for c in spec.criteria:
        for name in [c.human, *c.humans]:
            kinds_of.setdefault(name, set()).add(c.kind)
    groups = [set(c.humans) for c in spec.criteria if c.kind == "group_together" and len(c.humans) >= 2]
    judged.extend(implied_follows(spec, kinds_of))
    for enc in spec.encounters:
        for group in groups:  # a group is met where the robot meets any member (one stepping aside is the
            members = [p.human for p in enc.humans if p.human in group]  # reaction); group_together keeps
            if len(members) < 2:  # every member near the others
                continue
            if not any(SHOWS_ENCOUNTER & kinds_of.get(h, set()) for h in members):
                judged.append((Criterion(id=f"meet_group_{enc.id}", kind="meets", humans=members, encounter=enc.id,
                                         text=f"robot meets the group ({', '.join(members)}) at "
                                              f"{enc.node or enc.place} ({enc.id})"), "implied"))
            for h in members:
                kinds_of.setdefault(h, set()).add("meets")
        for part in enc.humans:
            if SHOWS_ENCOUNTER & kinds_of.get(part.human, set()) or part.reaction in NOT_MET:
                continue
            judged.append((Criterion(id=f"meet_{part.human}_{enc.id}", kind="meets", human=part.human,
                                     encounter=enc.id, text=f"robot meets {part.human} at {enc.node or enc.place} "
                                                            f"({enc.id})"), "implied"))
    judged.extend(_order_criteria(spec, settings))
    judged.extend(walks_on(spec, plan))
    present = {c.kind for c in spec.criteria}
    blocking = any(p.reaction == "block" for e in spec.encounters for p in e.humans)
    if "robot_reaches_goal" not in present:  # always judged, whether or not the spec names it
        judged.append((Criterion(id="goal", kind="robot_reaches_goal", text="robot reaches its goal"), "implied"))
    if "no_collision" not in present and not spec.script.misbehave:
        judged.append((Criterion(id="no_collision", kind="no_collision", text="robot never touches a person"),
                       "implied"))
    if "people_apart" not in present and (len(spec.humans()) if people is None else people) >= 2:
        judged.append((_PEOPLE_APART, "implied"))  # whatever the robot does: nothing in a spec makes people touch
    if "no_deadlock" not in present and not spec.script.misbehave and not blocking:
        longest_wait = max((cue.wait for cue in spec.script.cues), default=0.0)
        seconds = max(settings.deadlock_seconds, longest_wait + WAIT_MARGIN)  # a scripted wait is no deadlock
        judged.append((Criterion(id="no_deadlock", kind="no_deadlock", seconds=seconds,
                                 text="robot never stuck behind a person"), "implied"))
    return judged


def encounter_places(spec: ScenarioSpec, plan: PathPlan | None, location: Any) -> dict[str, tuple[float, float]]:
    """World point of each encounter: its node, else the interaction point paths.json gives its first human."""
    out: dict[str, tuple[float, float]] = {}
    if location is None:
        return out
    for enc in spec.encounters:
        node = enc.node
        if node is None and plan is not None:
            node = next((h.interaction_point for p in enc.humans for h in plan.humans
                         if h.name == p.human and h.interaction_point), None)
        if node is None:
            continue
        try:
            out[enc.id] = tuple(location.node_world(node))
        except (KeyError, StopIteration, ValueError):
            continue
    return out
