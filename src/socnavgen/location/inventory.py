"""The place inventory of a location: what a planner must know about the places of THIS map before it
puts an encounter there, measured on the scene graph and the occupancy map (never taken from prose):
each kind of place with its nodes, which are dead ends, how much free floor each has, which doorways
lead where and how wide they are, which turns are blind (from which two ways, and how close people
come before they see each other), and where a group can stand.

Stage 1's prompt shows it as text (`inventory_text`), stage 1's checks refuse places that cannot work
here (`unworkable_reason`, `blind_nodes`), stage 2's scene graph gives the same edge widths, and the
scenario cards take their blind-corner distance from here."""

from __future__ import annotations

import itertools
from dataclasses import dataclass, field

from socnavgen.bodies import GROUP_SPAWN_RADIUS, PERSON_RADIUS, PERSON_TOUCH_DISTANCE, ROBOT_RADIUS
from socnavgen.location.location import Location
from socnavgen.location.passages import approach_sights, passage_width_m
from socnavgen.location.places import CORNER_TURN_DEG, PlaceFinder

PASS_MARGIN = 0.1  # m of slack the robot needs beside a person
# A passage narrower than this cannot hold the robot beside a person: they cannot pass each other.
PASS_WIDTH = round(PERSON_TOUCH_DISTANCE + 2 * ROBOT_RADIUS + PASS_MARGIN, 2)
# A passage narrower than this is closed to the robot by one person standing in its middle.
BLOCKING_WIDTH = round(PERSON_TOUCH_DISTANCE + 2 * (2 * ROBOT_RADIUS) + PASS_MARGIN, 2)
# Free radius a standing group needs at its node (members on their circle, plus their own radius) ...
GROUP_RADIUS = round(GROUP_SPAWN_RADIUS + PERSON_RADIUS, 2)
# ... and to let the robot pass beside it.
GROUP_PASS_RADIUS = round(GROUP_RADIUS + 2 * ROBOT_RADIUS + PASS_MARGIN, 2)
BLIND_SIGHT_M = 5.0  # m: a turn is blind when people approaching it see each other only this close (centres)
# How a blind turn is measured (passages.approach_sights): the robot and a person come in along every way into it
# (the edge and the edge before it), arriving together, the person at each of these times the robot's speed (a
# paced person walks from 0.3 m/s, sim/people/pacing.min_pace, to a brisk 1.2 m/s, against the robot's 0.6); the
# listed distance is the worst of them ...
APPROACH_RATIOS = (0.5, 1.0, 2.0)
# ... and a hidden_until distance needs this much more (the simulated approach is never exactly the measured one:
# people keep to a side, the robot slows; round-5 players saw 3.08-3.44 m at a corner measured at 3.0 m).
BLIND_MARGIN = 0.5
MAX_LISTED = 12  # nodes / passages listed per line of the text; more are counted


@dataclass(frozen=True)
class NodeFacts:
    id: str
    type: str
    neighbours: tuple[str, ...]
    free_width_m: float  # diameter of the free disc at the node

    @property
    def dead_end(self) -> bool:
        return len(self.neighbours) <= 1

    @property
    def turnable(self) -> bool:
        """Room for the robot to pass a person here (a dead end is where the robot must turn around)."""
        return self.free_width_m >= PASS_WIDTH

    @property
    def group_fits(self) -> bool:
        return self.free_width_m / 2 >= GROUP_RADIUS

    @property
    def group_passable(self) -> bool:
        return self.free_width_m / 2 >= GROUP_PASS_RADIUS


@dataclass(frozen=True)
class Passage:
    a: str
    b: str
    type: str
    width_m: float

    @property
    def narrow(self) -> bool:
        """One person standing in it closes it to the robot."""
        return self.width_m < BLOCKING_WIDTH

    @property
    def squeeze(self) -> bool:
        """Narrower than a person: people only get through sideways, if at all."""
        return self.width_m < PERSON_TOUCH_DISTANCE


@dataclass(frozen=True)
class Doorway:
    node: str
    width_m: float
    sides: tuple[str, ...]


@dataclass(frozen=True)
class BlindTurn:
    node: str
    a: str
    b: str
    sight_m: float  # centre distance at which people coming from a and from b first see each other
    # the approaches (node the robot or person comes from into a, into b) on which they see each other earlier
    unless: tuple[tuple[str, str], ...] = ()

    def hidden(self, from_a: str | None, from_b: str | None) -> bool:
        """Blind on this approach: coming into a from `from_a` and into b from `from_b` (a or b itself for a way
        that starts there)."""
        return (from_a, from_b) not in self.unless

    def text(self, node_type: str) -> str:
        unless = "; ".join(f"{p} and {q}" for p, q in self.unless)
        return (f"{self.node} ({node_type}) between {self.a} and {self.b}: {self.sight_m:.1f} m"
                + (f" (not coming from {unless}: seen from farther)" if unless else ""))


@dataclass
class PlaceInventory:
    nodes: dict[str, NodeFacts]
    passages: dict[tuple[str, str], Passage]
    doorways: list[Doorway] = field(default_factory=list)
    blind_turns: list[BlindTurn] = field(default_factory=list)

    def of_type(self, place: str) -> list[NodeFacts]:
        key = place.strip().upper()
        return [n for n in self.nodes.values() if n.type.strip().upper() == key]

    def passage(self, a: str, b: str) -> Passage | None:
        return self.passages.get((a, b)) or self.passages.get((b, a))

    def width(self, a: str, b: str) -> float:
        found = self.passage(a, b)
        return found.width_m if found is not None else float("inf")

    def narrow_passages(self) -> list[Passage]:
        """Every edge one standing person closes to the robot, narrowest first: the one list stage 1's inventory
        text names and stage 2's scene graph marks `"narrow": true` (Passage.narrow for both; doorway edges too)."""
        return sorted((p for p in self.passages.values() if p.narrow), key=lambda p: (p.width_m, p.a, p.b))

    def blind_nodes(self, place: str) -> list[BlindTurn]:
        """The blind turns at nodes of this type, blindest first."""
        ids = {n.id for n in self.of_type(place)}
        return sorted((t for t in self.blind_turns if t.node in ids), key=lambda t: (t.sight_m, t.node))

    def unworkable_reason(self, place: str) -> str | None:
        """Why no encounter can happen at any node of this type on this map (None: some node can work).
        An encounter needs the robot and a person at the node: nobody reaches a node whose every way in is
        narrower than a person, and a dead end is where the robot must turn around, which it cannot do
        beside a person without room to pass them."""
        nodes = self.of_type(place)
        if not nodes:
            return f"this map has no {place} node"
        why = {n.id: self._unusable(n) for n in nodes}
        if not all(why.values()):
            return None
        listed = "; ".join(f"{n} is {reason}" for n, reason in list(why.items())[:MAX_LISTED])
        return f"no {place} node can hold an encounter on this map: {listed}"

    def no_room_to_step_aside(self, place: str) -> str | None:
        """Why nobody can give way (step aside and let the robot pass) at any node of this type (None: at
        some node one can): stepping aside needs the room the robot and a person need to pass each other."""
        nodes = self.of_type(place)
        if not nodes or any(n.turnable for n in nodes):
            return None
        widths = ", ".join(f"{n.id} {n.free_width_m:.1f} m" for n in nodes[:MAX_LISTED])
        return f"no {place} node has room to step aside ({PASS_WIDTH:g} m free; {widths})"

    def _unusable(self, node: NodeFacts) -> str | None:
        if not node.neighbours:
            return "connected to nothing"
        widths = [self.width(node.id, m) for m in node.neighbours]
        if all(w < PERSON_TOUCH_DISTANCE for w in widths):
            return f"reached only through a way narrower than a person ({max(widths):.1f} m)"
        if node.dead_end and not node.turnable:
            return (f"a dead end reached only from {node.neighbours[0]}, {node.free_width_m:.1f} m free: too tight "
                    f"for the robot to pass a person there ({PASS_WIDTH:g} m)")
        return None


def place_inventory(location: Location) -> PlaceInventory:
    """Measure the inventory of a location (use `Location.inventory`, which keeps it)."""
    finder = PlaceFinder(location)
    graph = location.graph
    nodes = {n: NodeFacts(id=n, type=finder.type_of(n), neighbours=tuple(sorted(graph.neighbors(n))),
                          free_width_m=round(2 * finder.clearance_m(n), 2)) for n in sorted(graph.nodes)}
    passages = {}
    for edge in location.scene_graph.links:
        passages[(edge.source, edge.target)] = Passage(edge.source, edge.target, edge.type,
                                                       passage_width_m(location, edge.source, edge.target))
    inventory = PlaceInventory(nodes=nodes, passages=passages)
    for cand in finder.candidates("doorway"):
        node = nodes[cand.node]
        widths = [node.free_width_m, *(inventory.width(node.id, m) for m in node.neighbours)]
        inventory.doorways.append(Doorway(node.id, round(min(widths), 2), node.neighbours))
    for p in sorted(graph.nodes):
        for a, b in itertools.combinations(nodes[p].neighbours, 2):
            if finder.turn_deg(a, p, b) < CORNER_TURN_DEG:
                continue
            sights = approach_sights(location, p, a, b, APPROACH_RATIOS)
            blind = [v for v in sights.values() if v is not None and v <= BLIND_SIGHT_M]
            if blind:
                unless = tuple(k for k, v in sorted(sights.items()) if v is None or v > BLIND_SIGHT_M)
                inventory.blind_turns.append(BlindTurn(p, a, b, max(blind), unless))
    return inventory


# ---- text for the prompts ------------------------------------------------------------------------
def _position(location: Location, node: str) -> tuple[float, float]:
    from socnavgen.location.placement import shown_position

    return shown_position(location, node)


def _listing(items: list[str]) -> str:
    shown = ", ".join(items[:MAX_LISTED])
    return shown + (f" and {len(items) - MAX_LISTED} more" if len(items) > MAX_LISTED else "")


def _node_words(n: NodeFacts, blind: dict[str, float], at: tuple[float, float] | None, sight: bool = True) -> str:
    if n.dead_end and n.neighbours:
        ways = f"dead end from {n.neighbours[0]}"
    else:
        ways = f"{len(n.neighbours)} ways" if n.neighbours else "not connected"
    words = [ways, f"{n.free_width_m:.1f} m free"]
    if n.id in blind:
        words.append(f"blind turn: seen within {blind[n.id]:.1f} m" if sight else "blind turn")
    where = f"at {at[0]:g},{at[1]:g}; " if at is not None else ""
    return f"{n.id} ({where}{', '.join(words)})"


def inventory_text(location: Location, *, positions: bool = True, detail: bool = True) -> str:
    """The inventory in words, for the prompts. `positions`: each node's position (stage 1 names places by
    where they are: "the north elevator"; stage 2 has them in its scene graph). `detail` False leaves out
    the lists a small model needs least (narrow passages, each blind turn's two ways and how near it is seen,
    group places): the kinds of place with their nodes, the places that cannot work, the doorways and where
    nobody can step aside stay."""
    inv = location.inventory
    blind: dict[str, float] = {}
    for turn in inv.blind_turns:
        blind[turn.node] = min(turn.sight_m, blind.get(turn.node, turn.sight_m))
    where = ("at = position x,y in metres (x east, y north); " if positions else "")
    lines = ["PLACE INVENTORY of this map (measured on its scene graph and map; plan the scenario with it):",
             f"Kinds of place, each node type with its nodes ({where}ways = edges leaving the node; a dead end has "
             f"one, so a route can only start, end or turn around there; free = width of free floor at the node). "
             f"The robot and a person pass each other only where at least {PASS_WIDTH:g} m is free, whether both "
             f"move or one of them stands (a robot that waits leaves no room in a narrower place; a person who "
             f"gives way steps aside only where there is room):"]
    types = list(location.schema.node_types) or sorted({n.type for n in inv.nodes.values()})
    for kind in types:
        members = inv.of_type(kind)
        if members:
            lines.append(f"- {kind}: " + _listing([_node_words(n, blind, _position(location, n.id) if positions
                                                               else None, sight=detail) for n in members]))
    unworkable = [reason for kind in types if inv.of_type(kind) and (reason := inv.unworkable_reason(kind))]
    lines += [f"NOTE: {reason}. A route may still start or end there." for reason in unworkable]
    cramped = [n.id for n in inv.nodes.values() if n.neighbours and not n.turnable]
    if cramped:
        lines.append(f"No room to step aside (give_way) at: {_listing(cramped)} (under {PASS_WIDTH:g} m free): there "
                     f"a person lets the robot by only by walking out ahead of it or waiting before the narrow part.")
    if inv.doorways:
        lines.append("Doorways and other pinch points (a person standing in one closes it to the robot; narrower "
                     f"than {PASS_WIDTH:g} m: one body at a time):")
        lines += [f"- {d.node} ({inv.nodes[d.node].type}): {d.width_m:.1f} m wide, between "
                  + " and ".join(f"{s} ({inv.nodes[s].type})" for s in d.sides) for d in inv.doorways[:MAX_LISTED]]
    if not detail:
        return "\n".join(lines)
    narrow = inv.narrow_passages()
    if narrow:  # all of them (the edges stage 2's scene graph marks narrow), the doorways' edges included
        lines.append(f"Narrow passages (every edge narrower than {BLOCKING_WIDTH:g} m, doorways' edges included: one "
                     "standing person closes them to the robot, and to a walker whose path goes through them: "
                     "plan walkers' paths round a node where someone stands): "
                     + ", ".join(f"{p.a}-{p.b} {p.width_m:.1f} m" for p in narrow) + ".")
    squeezes = [p for p in inv.passages.values() if p.squeeze]
    if squeezes:
        lines.append(f"Too narrow for a person ({PERSON_TOUCH_DISTANCE:g} m): "
                     + _listing([f"{p.a}-{p.b} {p.width_m:.1f} m" for p in squeezes]) + ".")
    if inv.blind_turns:
        turns = sorted(inv.blind_turns, key=lambda t: (t.sight_m, t.node))
        lines.append("Blind turns (a person coming from one way and the robot from the other, arriving together, "
                     "first see each other this close, centre to centre, on every approach but those named; a "
                     f"hidden_until distance needs {BLIND_MARGIN:g} m more, and nobody waiting at the turn's node): "
                     + _listing([t.text(inv.nodes[t.node].type) for t in turns]) + ".")
    else:
        lines.append(f"Blind turns: none (at every turn people see each other from farther than {BLIND_SIGHT_M:g} m).")
    fits = [n.id for n in inv.nodes.values() if n.group_fits and not n.dead_end]
    passable = [n.id for n in inv.nodes.values() if n.group_passable and not n.dead_end]
    lines.append(f"Where a standing group of three fits on a through route ({GROUP_RADIUS:g} m free around the "
                 f"node): {_listing(fits) or 'nowhere'}; with room for the robot to pass beside it "
                 f"({GROUP_PASS_RADIUS:g} m): {_listing(passable) or 'nowhere'}.")
    return "\n".join(lines)
