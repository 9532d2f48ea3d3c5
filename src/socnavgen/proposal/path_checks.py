"""Rules a stage-2 answer must satisfy, each broken rule reported in words that name the exact mistake
(the message goes back to the model as its correction, so it must say what to fix)."""

from __future__ import annotations

import math
from collections import defaultdict
from typing import TypeVar

import networkx as nx

from socnavgen.bodies import TOUCH_DISTANCE
from socnavgen.location import Location
from socnavgen.location.inventory import BLIND_MARGIN, PASS_WIDTH
from socnavgen.location.placement import Walker, node_distance, route_problems, start_problems
from socnavgen.location.places import type_matches
from socnavgen.location.scene_graph import path_mistakes
from socnavgen.proposal.conversation import Upstream
from socnavgen.proposal.facts import approach_room
from socnavgen.proposal.prose_checks import way_in_mistakes
from socnavgen.proposal.replies import PathsReply, human_name
from socnavgen.proposal.spec_checks import HIDDEN_UNTIL_DEFAULT
from socnavgen.run import HumanPlan, PathPlan
from socnavgen.run.spec import Encounter, ScenarioSpec
from socnavgen.verify.derive import SHOWS_ENCOUNTER
from socnavgen.verify.thresholds import APPROACH, MEET_DISTANCE, MOVED_DISTANCE

_V = TypeVar("_V")


def _names(humans: list[str]) -> str:
    return f"the scenario has {len(humans)} human(s): {', '.join(humans)}"


def _by_human(mapping: dict[str, _V], what: str, humans: list[str], mistakes: list[str]) -> dict[str, _V]:
    """Normalise 'Human 1' style keys; report keys that are not humans of the scenario."""
    out: dict[str, _V] = {}
    for key, value in mapping.items():
        name = human_name(key)
        if name is None or name not in humans:
            mistakes.append(f"{what}: '{key}' is not a human of the scenario ({_names(humans)})")
        else:
            out[name] = value
    return out


def check_paths(reply: PathsReply, graph: nx.Graph, humans: list[str], spec: ScenarioSpec | None = None,
                location: Location | None = None, behaviors: dict[str, str] | None = None) -> list[str]:
    """Every mistake of a stage-2 answer, given the scene graph, stage 1's human names and its spec; with the
    location, also where everybody starts (location/placement.py: nobody on or against another body); with stage 1's
    behaviors, also that each person comes into their encounter the way their text says (prose_checks.py)."""
    mistakes: list[str] = []
    trajectories = dict(reply.trajectories)
    robot_key = next((k for k in trajectories if k.strip().lower() == "robot"), None)
    robot = trajectories.pop(robot_key) if robot_key is not None else None
    if robot is None:
        mistakes.append("trajectories: the robot has no path (add \"robot\": [start, ..., goal])")
        robot = []
    elif len(robot) < 2:
        mistakes.append(f"the robot path needs at least two nodes (a start and a goal), it has {len(robot)}")
    mistakes += path_mistakes(graph, "robot path", robot)
    mistakes += route_problems(robot)
    mistakes += doorway_goal(graph, robot)

    paths = _by_human(trajectories, "trajectories", humans, mistakes)
    groups = _by_human(reply.group_ids, "group_ids", humans, mistakes)
    points = _by_human(reply.interaction_points, "interaction_points", humans, mistakes)
    for name in humans:
        path = paths.get(name)
        if path is None:
            mistakes.append(f"trajectories: {name} has no path ({_names(humans)})")
            continue
        if not path:
            mistakes.append(f"{name}'s path is empty; give at least one node (where {name} starts)")
        mistakes += path_mistakes(graph, f"{name}'s path", path)
        if name not in groups:
            mistakes.append(f"group_ids: {name} has no group id (use -1 for a human who is not in a group)")
        point = points.get(name)
        if point is not None:
            if point not in graph:
                mistakes.append(f"interaction point of {name}: node '{point}' is not in the scene graph")
            else:
                if point not in path:
                    mistakes.append(f"the interaction point {point} of {name} is not on {name}'s path")
                if point not in robot:
                    mistakes.append(f"the interaction point {point} of {name} is not on the robot's path")
    mistakes += _group_mistakes(groups)
    if location is not None and robot:  # where everybody starts
        walkers = [Walker(name, list(paths[name]), int(groups.get(name, -1)))
                   for name in humans if paths.get(name)]
        mistakes += [p for p in start_problems(location, robot, walkers) if p not in route_problems(robot)]
    if spec is not None:
        mistakes += _encounter_mistakes(reply, graph, spec, robot, paths, points)
        mistakes += _standing_stop_mistakes(reply, spec, paths)
        mistakes += _cue_node_mistakes(spec, graph, robot)
        if location is not None:
            mistakes += _stands_away_mistakes(reply, spec, location, paths)
        if behaviors:
            mistakes += way_in_mistakes(graph, spec, behaviors, paths, dict(reply.encounter_nodes))
        if location is not None:
            mistakes += _blind_mistakes(reply, spec, location, robot, paths)
            mistakes += _room_mistakes(reply, spec, location)
            mistakes += _approach_mistakes(reply, spec, location, robot, paths)
    return mistakes


def doorway_goal(graph: nx.Graph, robot: list[str]) -> list[str]:
    """A robot route may not end in a doorway between two spaces (a doorway-family node with two or more
    neighbours; an outer door, one neighbour, is a place to go to): a doorway is a passage, and a robot stopping in it
    blocks it, or is held back in the hall by whoever stops just past it and counts as arrived there (hospital_04:
    the route ended in the door x5 while its text has the robot stop just inside the room)."""
    goal = robot[-1] if robot else None
    if goal is None or goal not in graph or graph.degree(goal) < 2 or \
            not type_matches(str(graph.nodes[goal].get("type", "")), "doorway"):
        return []
    sides = " or ".join(sorted(str(n) for n in graph.neighbors(goal)))
    return [Upstream(
        f"the robot's path ends in the doorway {goal}: a doorway is a passage, not a place to stop (the robot would "
        f"block it, or be held back by anyone who stops just past it); end the robot's path on either side of it "
        f"({sides}): in the room, or before the door; if the text has the robot stop in the doorway itself, keep "
        f"your answer and say so: stage 1 is then asked",
        key=f"doorway_goal:{goal}", upstream=(
            f"the text has the robot stop in the doorway {goal}, a passage (it would block it, or be held back by "
            f"anyone who stops just past it): have it stop in the room beyond ({sides}) or before the door"))]


def _met(spec: ScenarioSpec, enc: Encounter, human: str) -> bool:
    """Whether the verifier judges `human` at `enc` by a meeting (a meets criterion, or the one every encounter
    implies unless a keeps_away / follows_robot criterion shows it: verify/derive.py)."""
    mine = [c for c in spec.criteria if human in [c.human, *c.humans] and c.encounter in (None, enc.id)]
    return any(c.kind == "meets" for c in mine) or not any(c.kind in SHOWS_ENCOUNTER for c in mine)


def _approach_mistakes(reply: PathsReply, spec: ScenarioSpec, location: Location, robot: list[str],
                       paths: dict[str, list[str]]) -> list[str]:
    """A person waiting at an encounter's node (their path starts within its `within`) is met only after an
    approach: the node must be approach_room() from the robot's start, or they meet before anyone moved. The room
    needed is the spec's meeting distance + APPROACH, so the mistake is an Upstream one: when stage 2 cannot move
    the node, the person or the robot's start (hospital_10: the task fixes the start, one CORRIDOR node on the way),
    stage 1 is asked with the meeting distance that fits."""
    mistakes: list[str] = []
    if not robot or robot[0] not in location.inventory.nodes:
        return mistakes
    for enc in spec.encounters:
        node = reply.encounter_nodes.get(enc.id)
        if node is None or node not in location.inventory.nodes:
            continue
        gap = node_distance(location, robot[0], node)
        waiting: dict[tuple[str, str], list[str]] = {}  # (cause, what sets it) -> who waits too near
        for part in enc.humans:
            path = paths.get(part.human) or []
            if not path or path[0] not in location.inventory.nodes or not _met(spec, enc, part.human):
                continue
            if node_distance(location, path[0], node) <= enc.within and gap < approach_room(spec, enc, part.human):
                waiting.setdefault(_meeting_cause(spec, enc, part.human), []).append(part.human)
        for (cause, knob), humans in waiting.items():
            need = approach_room(spec, enc, humans[0])
            fits = math.floor((gap - APPROACH) * 10 + 1e-6) / 10
            who = ", ".join(humans)
            upstream = (f"{who} {'waits' if len(humans) == 1 else 'wait'} at node {node}, where stage 2 put encounter "
                        f"{enc.id} (a {enc.place} on the robot's way), {gap:.2f} m from the robot's start {robot[0]}; "
                        f"a meeting counts only after the two came {APPROACH:g} m closer, so with {cause} the node "
                        f"must be at least {need:g} m from the robot's start. " +
                        (f"With {knob} at most {fits:g} m, {node} fits; or " if fits > TOUCH_DISTANCE else "Either ") +
                        f"let {who} come to {enc.id} from farther away (walking in, not waiting there), or put "
                        f"{enc.id} at another place, or start the robot farther away, if the task allows")
            for human in humans:
                mistakes.append(Upstream(
                    f"encounter {enc.id}: {human} waits at node {node}, only {gap:.2f} m from the robot's start "
                    f"{robot[0]} ({human} starts within {enc.within:g} m of it, {enc.id}'s `within`), so they are "
                    f"together before anyone moved; a meeting needs the two to come {APPROACH:g} m closer, so put "
                    f"{enc.id} at least {need:g} m from the robot's start (or start the robot farther away, or start "
                    f"{human} farther than {enc.within:g} m from {node} so they walk in). The {need:g} m are {cause} + "
                    f"{APPROACH:g} m, which stage 1 set: if no answer of yours can do any of this without changing what "
                    f"the scenario says, keep your answer and say why; stage 1 is then asked",
                    key=f"approach:{enc.id}:{human}", upstream=upstream))
    return mistakes


def _meeting_cause(spec: ScenarioSpec, enc: Encounter, human: str) -> tuple[str, str]:
    """Where the meeting distance of `human` at `enc` comes from, and what in the spec sets it, in words (as
    verify/derive.meeting_distance finds it)."""
    for c in spec.criteria:
        if c.kind == "meets" and c.encounter == enc.id and human in [c.human, *c.humans] and c.distance:
            return f"criterion {c.id}'s meets distance {c.distance:g} m", f"criterion {c.id}'s distance"
    return (f"the verifier's default meeting distance {MEET_DISTANCE:g} m",
            f"a meets criterion for {human} at {enc.id} whose distance is")


STOPS = ("stop", "wait_then_go")  # reactions the verifier sees as a stop after walking (verify/signals.reaction_evidence)


def _standing_stop_mistakes(reply: PathsReply, spec: ScenarioSpec, paths: dict[str, list[str]]) -> list[str]:
    """A stop checked by reacts_after_phrase shows only AFTER the person walked MOVED_DISTANCE from their start
    (facts.stop_evidence_text): a person who starts at the node where they stop shows none."""
    mistakes: list[str] = []
    for c in spec.criteria:
        if c.kind != "reacts_after_phrase" or c.reaction not in STOPS or not c.human:
            continue
        encounters = [e for e, part in spec.parts_of(c.human) if part.reaction == c.reaction
                      and c.encounter in (None, e.id)]
        path = paths.get(c.human) or []
        for enc in encounters[:1]:
            node = reply.encounter_nodes.get(enc.id)
            if path and node is not None and path[0] == node:
                mistakes.append(Upstream(
                    f"criterion {c.id} sees {c.human}'s {c.reaction} at node {node} only after they walked "
                    f"{MOVED_DISTANCE:g} m from their start, but {c.human} starts at {node}: start them at a node "
                    f"before it on their way (pacing holds them there until it is time); if the scenario has them "
                    f"wait there, keep your answer and say so: stage 1 is then asked",
                    key=f"standing_stop:{c.id}", upstream=(
                        f"criterion {c.id} (reacts_after_phrase, {c.reaction}) sees {c.human}'s {c.reaction} only "
                        f"after they walked {MOVED_DISTANCE:g} m from their start, and stage 2 kept {c.human} waiting "
                        f"at node {node} of encounter {enc.id} from the start: someone who stands already shows no "
                        f"{c.reaction}. Let {c.human} walk in to {enc.id}, or check what the prose says with another "
                        f"criterion (e.g. stops_near_robot)")))
    return mistakes


def _cue_node_mistakes(spec: ScenarioSpec, graph: nx.Graph, robot: list[str]) -> list[str]:
    """An `at_node` cue fires where the robot comes near that node: it must be a node of the robot's route."""
    mistakes: list[str] = []
    for k, cue in enumerate(spec.script.cues, 1):
        node = cue.trigger.node if cue.trigger.when == "at_node" else None
        if node is None or node in robot:
            continue
        where = "is not a node of the scene graph" if node not in graph else "is not on the robot's path"
        mistakes.append(Upstream(
            f"cue {k} of the robot's script fires at node {node}, which {where}: route the robot through {node}; if "
            f"the scenario has it wait elsewhere, keep your answer and say so: stage 1 is then asked",
            key=f"cue_node:{k}:{node}", upstream=(
                f"cue {k} of the robot's script (at_node {node}) names a node that {where}: name a node of the "
                f"robot's route (the route is stage 2's, and it goes where the scenario says)")))
    return mistakes


STANDING_REACTIONS = ("stop", "look", "say")  # reactions that keep a person where they stand (none walks them)


def _stands_away_mistakes(reply: PathsReply, spec: ScenarioSpec, location: Location,
                          paths: dict[str, list[str]]) -> list[str]:
    """A person who stands all the run ("otherwise": "stand", and only STANDING_REACTIONS) is met where they
    stand: their start must be within the `within` of each encounter's node where they are met, or they never
    come to the place (home_08: the wife stood at the stove 2.1 m from the kitchen node the robot stopped at,
    `within` 1.5 m)."""
    mistakes: list[str] = []
    nodes = location.inventory.nodes
    for enc in spec.encounters:
        node = reply.encounter_nodes.get(enc.id)
        for part in enc.humans:
            who, path = part.human, paths.get(part.human) or []
            person = spec.people.get(who)
            if person is None or person.otherwise != "stand" or node not in nodes or not path or path[0] not in \
                    nodes or path[0] == node or not _met(spec, enc, who) or \
                    any(p.reaction not in STANDING_REACTIONS for _, p in spec.parts_of(who)):
                continue
            gap = node_distance(location, path[0], node)
            if gap <= enc.within:
                continue
            mistakes.append(Upstream(
                f"encounter {enc.id}: {who} stands all the run (\"otherwise\": \"stand\", and only "
                f"{'/'.join(STANDING_REACTIONS)} reactions) at their start {path[0]}, {gap:.2f} m from node {node} of "
                f"{enc.id}, farther than its `within` ({enc.within:g} m): they never come to the place where the robot "
                f"meets them. Start {who} at {node} (or within {enc.within:g} m of it), or put {enc.id} at {path[0]} "
                f"if it is of the encounter's place; if the scenario has them stand elsewhere, keep your answer and "
                f"say so: stage 1 is then asked",
                key=f"stands_away:{enc.id}:{who}", upstream=(
                    f"{who} stands all the run (\"otherwise\": \"stand\", only {'/'.join(STANDING_REACTIONS)}), and "
                    f"stage 2 has them stand at {path[0]}, {gap:.2f} m from node {node} of encounter {enc.id} "
                    f"(`within` {enc.within:g} m): let them walk to the robot, or give {enc.id} a `within` of at "
                    f"least {math.ceil(gap * 10) / 10:g} m")))
    return mistakes


def _blind_mistakes(reply: PathsReply, spec: ScenarioSpec, location: Location, robot: list[str],
                    paths: dict[str, list[str]]) -> list[str]:
    """A hidden_until criterion needs its encounter at a node where the robot's way in and the person's way in
    hide each other on this map until they are close enough (location/inventory.py's blind turns)."""
    mistakes: list[str] = []
    inventory = location.inventory
    for c in spec.criteria:
        if c.kind != "hidden_until" or not c.human:
            continue
        enc = spec.encounter(c.encounter) if c.encounter else next((e for e, _ in spec.parts_of(c.human)), None)
        node = reply.encounter_nodes.get(enc.id) if enc is not None else None
        if enc is None or node not in inventory.nodes:
            continue
        person = paths.get(c.human, [])
        legs = {_before(robot, node), _before(person, node)}
        ways = {_before(robot, node): _from(robot, node), _before(person, node): _from(person, node)}
        turns = [t for t in inventory.blind_turns if t.node == node and (None in legs or {t.a, t.b} == legs)
                 and (None in legs or t.hidden(ways[t.a], ways[t.b]))]
        distance = c.distance or HIDDEN_UNTIL_DEFAULT
        if turns and min(t.sight_m for t in turns) <= distance:
            continue
        fitting = [t.text(enc.place) for t in inventory.blind_nodes(enc.place) if t.sight_m + BLIND_MARGIN <= distance]
        hint = f"; blind enough for {distance:g} m with a {BLIND_MARGIN:g} m margin: {', '.join(fitting)}" if fitting \
            else ""
        seen = f"from {min(t.sight_m for t in turns):.1f} m" if turns else "from afar"
        fits = f"set its distance to at least {math.ceil(2 * (min(t.sight_m for t in turns) + BLIND_MARGIN)) / 2:g} " \
            "m, or " if turns else ""
        mistakes.append(Upstream(
            f"criterion {c.id} needs the robot and {c.human} hidden from each other until {distance:g} m, but coming "
            f"into node {node} of encounter {enc.id} the way they do, they see each other {seen}{hint}",
            key=f"blind:{c.id}", upstream=(
                f"criterion {c.id} (hidden_until) needs the robot and {c.human} hidden from each other until "
                f"{distance:g} m at encounter {enc.id} ({enc.place}); stage 2 brought them into node {node} the way "
                f"they walk, and there they see each other {seen}: {fits}put {enc.id} at another place, or have "
                f"them come from other sides")))
    return mistakes


def _room_mistakes(reply: PathsReply, spec: ScenarioSpec, location: Location) -> list[str]:
    """Giving way is stepping aside: the encounter's node needs the room the robot and a person need to pass
    each other (location/inventory.py: PASS_WIDTH)."""
    inventory = location.inventory
    mistakes: list[str] = []
    for enc in spec.encounters:
        facts = inventory.nodes.get(reply.encounter_nodes.get(enc.id) or "")
        if facts is None or facts.turnable:
            continue
        roomy = [n.id for n in inventory.of_type(enc.place) if n.turnable]
        for part in enc.humans:
            if part.reaction == "give_way":
                hint = f" ({enc.place} nodes with room: {', '.join(roomy)})" if roomy else ""
                mistakes.append(Upstream(
                    f"{part.human} gives way in encounter {enc.id} at node {facts.id}, which has only "
                    f"{facts.free_width_m:.1f} m free: nobody can step aside there (the robot passes a person only "
                    f"where {PASS_WIDTH:g} m is free); ground {enc.id} at a node with room{hint}; if none is on the "
                    f"robot's way, keep your answer and say so: stage 1 is then asked",
                    key=f"room:{enc.id}:{part.human}", upstream=(
                        f"{part.human} gives way in encounter {enc.id} at a {enc.place}, and stage 2 found no "
                        f"{enc.place} node with room to step aside ({PASS_WIDTH:g} m free{hint}) that it could put on "
                        f"the robot's way (it chose {facts.id}, {facts.free_width_m:.1f} m free): put {enc.id} at "
                        f"another place, or give {part.human} a reaction that needs no room (walk_past ahead of the "
                        f"robot, stop or wait_then_go before the narrow part)")))
    return mistakes


def _from(path: list[str], node: str) -> str | None:
    """The node a path comes from into the node before `node` (that node itself when the path starts there)."""
    i = path.index(node) if node in path else 0
    return path[i - 2] if i > 1 else path[0] if i == 1 else None


def _before(path: list[str], node: str) -> str | None:
    """The node a path comes from into `node` (None: it starts there or never gets there)."""
    i = path.index(node) if node in path else 0
    return path[i - 1] if i > 0 else None


def _encounter_mistakes(reply: PathsReply, graph: nx.Graph, spec: ScenarioSpec, robot: list[str],
                        paths: dict[str, list[str]], points: dict[str, str | None]) -> list[str]:
    """Each encounter grounded on one node of its kind of place, on the robot's path and its humans'."""
    mistakes: list[str] = []
    ids = [e.id for e in spec.encounters]
    for key in reply.encounter_nodes:
        if key not in ids:
            mistakes.append(f"encounter_nodes: '{key}' is not an encounter of the scenario ({', '.join(ids)})")
    first = {h: parts[0][0].id for h in paths if (parts := spec.parts_of(h))}  # where pacing brings them
    for human in paths:  # TWO_ENCOUNTERS: one person's meetings are told apart by their nodes
        at: dict[str, str] = {}
        for enc, _ in spec.parts_of(human):
            node = reply.encounter_nodes.get(enc.id)
            if node is not None and node in at:
                mistakes.append(Upstream(
                    f"encounters {at[node]} and {enc.id} of {human} are both at node {node}: the two meetings cannot "
                    f"be told apart there; ground {enc.id} at another {enc.place} node of the robot's and {human}'s "
                    f"paths (they part in between)", key=f"two:{human}:{enc.id}", upstream=(
                        f"encounters {at[node]} and {enc.id} of {human} need two different nodes, and stage 2 found "
                        f"no second {enc.place} node on the robot's and {human}'s ways (both at {node}): put one of "
                        f"them at another place, or make them one encounter")))
            elif node is not None:
                at[node] = enc.id
    for enc in spec.encounters:
        node = reply.encounter_nodes.get(enc.id)
        if node is None:
            mistakes.append(f"encounter_nodes: {enc.id} has no node; give the {enc.place} node where encounter "
                            f"{enc.id} happens")
            continue
        if node not in graph:
            mistakes.append(f"encounter {enc.id}: node '{node}' is not in the scene graph")
            continue
        kind = str(graph.nodes[node].get("type", ""))
        if kind.upper() != enc.place.strip().upper():
            fitting = sorted(n for n, d in graph.nodes(data=True)
                             if str(d.get("type", "")).upper() == enc.place.strip().upper())
            hint = f" (nodes of that type: {', '.join(fitting)})" if fitting else ""
            mistakes.append(Upstream(
                f"encounter {enc.id} happens at a {enc.place} but node {node} is a {kind}; choose a {enc.place} "
                f"node{hint}", key=f"place:{enc.id}", upstream=(
                    f"encounter {enc.id} happens at a {enc.place}, and stage 2 put it at {node}, a {kind}: no "
                    f"{enc.place} node{hint} fitted the robot's and its people's ways; put {enc.id} at a kind of place "
                    f"the robot passes")))
        if node not in robot:
            mistakes.append(f"the node {node} of encounter {enc.id} is not on the robot's path")
        for part in enc.humans:
            path = paths.get(part.human)
            if path is None:
                continue
            if node not in path:
                mistakes.append(f"the node {node} of encounter {enc.id} is not on {part.human}'s path")
            point = points.get(part.human)
            if point is not None and point != node and first.get(part.human) == enc.id:
                mistakes.append(f"the interaction point {point} of {part.human} differs from the node {node} of its "
                                f"{'first ' if len(spec.parts_of(part.human)) > 1 else ''}encounter {enc.id}; use "
                                f"{node}")
    return mistakes


def ground_spec(spec: ScenarioSpec, reply: PathsReply) -> ScenarioSpec:
    """The spec with each encounter's node set from a CHECKED stage-2 reply."""
    grounded = spec.model_copy(deep=True)
    for enc in grounded.encounters:
        enc.node = reply.encounter_nodes.get(enc.id, enc.node)
    return grounded


def _group_mistakes(groups: dict[str, int]) -> list[str]:
    mistakes: list[str] = []
    members: dict[int, list[str]] = defaultdict(list)
    for name, gid in groups.items():
        if gid < -1:
            mistakes.append(f"group_ids: {name} has group id {gid}; use -1 for a lone human or an id of 0 or more "
                            f"shared by all members of a group")
        elif gid >= 0:
            members[gid].append(name)
    for gid, names in sorted(members.items()):
        if len(names) < 2:
            mistakes.append(f"group_ids: group {gid} has only one member ({names[0]}); a group needs at least two "
                            f"members, and a human who is alone has group id -1")
    return mistakes


def to_path_plan(reply: PathsReply, humans: list[str], spec: ScenarioSpec | None = None) -> PathPlan:
    """Convert a CHECKED reply into the stored model (a human without an interaction point meets the
    robot at the node of its first encounter)."""
    trajectories = {("robot" if k.strip().lower() == "robot" else human_name(k) or k): v
                    for k, v in reply.trajectories.items()}
    groups = {human_name(k): v for k, v in reply.group_ids.items()}
    points = {human_name(k): v for k, v in reply.interaction_points.items()}
    if spec is not None:
        for enc in sorted(spec.encounters, key=lambda e: e.order):
            for part in enc.humans:
                if points.get(part.human) is None and enc.id in reply.encounter_nodes:
                    points[part.human] = reply.encounter_nodes[enc.id]
    return PathPlan(reasoning=reply.reasoning, robot=list(trajectories["robot"]),
                    humans=[HumanPlan(name=name, path=list(trajectories[name]), group_id=groups.get(name, -1),
                                      interaction_point=points.get(name)) for name in humans])
