"""Stage 2's reply grammar: with an in-process model, only VALID answers can be sampled.

A context-free grammar cannot remember an arbitrary node chosen earlier, so the grammar chooses the
meeting point X first (one top-level branch per candidate X) and, inside that branch, only admits
paths through X: every path walks TOWARD X (each step one hop closer) and then AWAY from X (each
step one hop farther). This covers every shortest route through the meeting point, makes every step
an edge of the graph, rules out back-and-forth (A B A) and guarantees the path ends. The humans'
names are exactly stage 1's, their interaction point is X (on their path and the robot's), and group
ids come from {-1, 1, 2} with every used group of at least two members. Given where people may start for
each robot start (`clear_starts`, the start rule), the grammar also chooses the robot's start S inside X's
branch and admits only human walks starting clear of S, and none starting at X when X is too near S for a
meeting with an approach (`too_near`). Size: about 3·V² small rules.
"""

from __future__ import annotations

import json
from functools import cache

import networkx as nx

from socnavgen.proposal.gbnf import Grammar, Lit, Ref, Symbol, text_rules
from socnavgen.run.spec import ScenarioSpec

REASONING_CHARS = 160
GROUP_IDS = (1, 2)


def _q(node: str) -> Lit:
    return Lit(json.dumps(node))


def _meeting_candidates(graph: nx.Graph, spec: ScenarioSpec | None, cramped: set[str]) -> set[str] | None:
    """With a spec, the meeting point is also every encounter's node: it must be of each encounter's place,
    and where someone gives way, not `cramped` (no room to step aside)."""
    if spec is None or not spec.encounters:
        return None
    places = {e.place.strip().upper() for e in spec.encounters}
    fitting = {n for n, data in graph.nodes(data=True) if str(data.get("type", "")).upper() in places}
    if any(p.reaction == "give_way" for e in spec.encounters for p in e.humans) and fitting - cramped:
        fitting -= cramped
    return fitting if len(places) == 1 and fitting else None


def build_paths_grammar(graph: nx.Graph, humans: list[str], spec: ScenarioSpec | None = None,
                        cramped: set[str] | None = None,
                        clear_starts: dict[str, frozenset[str]] | None = None,
                        too_near: frozenset[tuple[str, str]] = frozenset()) -> Grammar:
    """`too_near`: (robot start, meeting point) pairs where nobody may wait at the meeting point (path_checks'
    approach rule: a meeting needs an approach), so a human's walk does not start there."""
    g = Grammar()
    nodes = sorted(graph.nodes)
    index = {n: i for i, n in enumerate(nodes)}
    text_rules(g, "reasoning", REASONING_CHARS, non_empty=False)
    meets: list[list[Symbol]] = []
    candidates = _meeting_candidates(graph, spec, cramped or set())
    encounter_ids = [e.id for e in spec.encounters] if spec is not None else []
    for x in nodes:
        if graph.degree(x) == 0 or (candidates is not None and x not in candidates):
            continue
        xi = index[x]
        dist = nx.single_source_shortest_path_length(graph, x)
        _add_walks(g, graph, x, xi, dist, index)
        reachable = sorted(dist, key=index.__getitem__)
        starts_at: dict[str, list[list[Symbol]]] = {u: [[Ref(f"to{xi}-{index[u]}")]] for u in reachable if u != x}
        starts_at[x] = [[_q(x), Lit(", "), _q(w), Ref(f"away{xi}-{index[w]}")]
                        for w in sorted(graph.neighbors(x), key=index.__getitem__)]
        points = ", ".join(f'"{h}": {json.dumps(x)}' for h in humans)
        # after X's shared prefix, one alternative per robot start S (clear_starts), or one for any start: the
        # choice of S is made where the robot's path begins, so the sampler never tracks more than ~V branches
        by_start = [(s, [u for u in reachable if u in clear_starts.get(s, ())]) for s in reachable] \
            if clear_starts is not None else [(None, reachable)]
        tails: list[list[Symbol]] = []
        for s, walkable in by_start:
            if (s, x) in too_near:
                walkable = [u for u in walkable if u != x]
            if not walkable or (s is not None and not starts_at[s]):
                continue
            key = f"{xi}" if s is None else f"{xi}-{index[s]}"
            g.add(f"robot{key}", *(starts_at[s] if s is not None else [a for u in reachable for a in starts_at[u]]))
            g.add(f"walk{key}", *[[Ref(f"to{xi}-{index[u]}")] for u in walkable])
            tail: list[Symbol] = [Ref(f"robot{key}"), Lit("]")]
            for h in humans:
                tail += [Lit(f', "{h}": ['), Ref(f"walk{key}"), Lit("]")]
            tails.append(tail)
        if not tails:
            continue
        g.add(f"paths{xi}", *tails)
        body: list[Symbol] = [Lit("{" + points + '}, "trajectories": {"robot": ['), Ref(f"paths{xi}"),
                              Lit('}, "group_ids": '), Ref("groups")]
        if encounter_ids:
            grounded = ", ".join(f'"{e}": {json.dumps(x)}' for e in encounter_ids)
            body.append(Lit(', "encounter_nodes": {' + grounded + "}"))
        meets.append([*body, Lit("}")])
    if not meets:
        raise ValueError("the scene graph has no edge: no path can be planned")
    g.add("meet", *meets)
    _add_groups(g, humans)
    g.add("root", [Lit('{"reasoning": "'), Ref("reasoning"), Lit('", "interaction_points": '), Ref("meet")])
    # order the root first for readability of the GBNF
    g.rules = {"root": g.rules.pop("root"), **g.rules}
    return g


def _add_walks(g: Grammar, graph: nx.Graph, x: str, xi: int, dist: dict[str, int], index: dict[str, int]) -> None:
    """to{X}-{u}: a walk from u to X (each step one hop closer) continuing away from X;
    away{X}-{u}: the rest of a walk leaving X (each step one hop farther), possibly empty."""
    for u in sorted(dist, key=index.__getitem__):
        ui = index[u]
        if u == x:
            g.add(f"to{xi}-{ui}", [_q(x), Ref(f"away{xi}-{ui}")])
        else:
            alts: list[list[Symbol]] = []
            for w in sorted(graph.neighbors(u), key=index.__getitem__):
                if dist.get(w) == dist[u] - 1:
                    if w == x:  # arriving at X from u: do not leave X back to u
                        alts.append([Lit(", "), _q(x), Ref(f"leave{xi}-{ui}")])
                    else:
                        alts.append([Lit(", "), Ref(f"to{xi}-{index[w]}")])
            g.add(f"to{xi}-{ui}", *[[_q(u), *alt] for alt in alts])
        farther = [w for w in sorted(graph.neighbors(u), key=index.__getitem__) if dist.get(w) == dist[u] + 1]
        away: list[list[Symbol]] = [[Lit(", "), _q(w), Ref(f"away{xi}-{index[w]}")] for w in farther]
        g.add(f"away{xi}-{ui}", [], *away)
        if dist[u] == 1:
            others = [w for w in sorted(graph.neighbors(x), key=index.__getitem__) if w != u]
            leave: list[list[Symbol]] = [[Lit(", "), _q(w), Ref(f"away{xi}-{index[w]}")] for w in others]
            g.add(f"leave{xi}-{ui}", [], *leave)


def _add_groups(g: Grammar, humans: list[str]) -> None:
    """group ids as a small automaton: state = members so far of group 1 and 2 (0, 1, 2 = two or more);
    group 2 opens only after group 1; every group that is used ends with at least two members."""
    n = len(humans)

    @cache
    def alive(k: int, c1: int, c2: int) -> bool:
        if k == n:
            return c1 != 1 and c2 != 1
        return any(alive(k + 1, *s) for _, s in _moves(c1, c2))

    def rule(k: int, c1: int, c2: int) -> str:
        name = f"grp{k}-{c1}{c2}"
        if name in g.rules:
            return name
        if k == n:
            g.add(name, [Lit("}")])
            return name
        sep = "{" if k == 0 else ", "
        alts: list[list[Symbol]] = []
        for gid, state in _moves(c1, c2):
            if alive(k + 1, *state):
                alts.append([Lit(f'{sep}"{humans[k]}": {gid}'), Ref(rule(k + 1, *state))])
        g.add(name, *alts)
        return name

    g.add("groups", [Ref(rule(0, 0, 0))])


def _moves(c1: int, c2: int) -> list[tuple[int, tuple[int, int]]]:
    moves = [(-1, (c1, c2)), (GROUP_IDS[0], (min(c1 + 1, 2), c2))]
    if c1 > 0:
        moves.append((GROUP_IDS[1], (c1, min(c2 + 1, 2))))
    return moves


def paths_grammar(graph: nx.Graph, humans: list[str], spec: ScenarioSpec | None = None,
                  cramped: set[str] | None = None, clear_starts: dict[str, frozenset[str]] | None = None,
                  too_near: frozenset[tuple[str, str]] = frozenset()) -> str:
    """The GBNF text passed as `grammar=` to `llm.chat` for stage 2."""
    return build_paths_grammar(graph, humans, spec, cramped, clear_starts, too_near).to_gbnf()


__all__ = ["build_paths_grammar", "paths_grammar"]
