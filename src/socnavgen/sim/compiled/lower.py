"""Lowering a ready Simulation's Python objects into the compiled run's arrays: the built behavior trees
(bt_build's node objects, already checked) into one flat program, the interaction throttle, the robot's
script and its gesture rules. Anything outside what the compiled twins do raises Unsupported with the
reason, and the simulation runs the reference instead."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from socnavgen.sim import bt_runtime as rt
from socnavgen.sim.compiled.layout import (
    K_ACTION,
    K_CONDITION,
    K_FALLBACK,
    K_FORCE_FAILURE,
    K_FORCE_SUCCESS,
    K_INVERTER,
    K_KEEP_RUNNING,
    K_REACTIVE_FALLBACK,
    K_REACTIVE_SEQUENCE,
    K_REPEAT,
    K_SEQUENCE,
    K_SET_BLACKBOARD,
    NI_AGENT_PORT,
    NI_COUNT,
    NI_END,
    NI_FIRST,
    NI_KIND,
    NI_LEAF,
    NI_MOTION,
    NI_OWNER,
    NI_REPEAT,
    NI_ROWS,
    NI_SB_OUT,
    NI_SB_SRC,
    NI_UNTIL,
    PORT_ABSENT,
    PORT_DYNAMIC,
    PORT_LITERAL,
    T_BOOL,
    T_FLOAT,
    T_INT,
    T_UNSET,
)
from socnavgen.sim.compiled.leaves import GESTURE_OF_WORD, LEAF_NAMES, MAX_PORTS, PORT_NAMES
from socnavgen.sim.compiled.script import (
    CF_DISTANCE,
    CF_HOLD,
    CF_SECONDS,
    CF_SPEED,
    CF_WAIT,
    CI_HAS_POINT,
    CI_ONCE,
    CI_PHRASE,
    CI_SAY,
    CI_UNTIL_CLEAR,
    CI_WHEN,
    CI_WHO,
    CS_FIRED,
    CS_REPEATS,
    CS_UNTIL_CLEAR,
    CS_WAS_TRUE,
    CT_CLEAR_SINCE,
    CT_SAY_UNTIL,
    CT_WAIT_UNTIL,
    CUE_WHEN,
    RULE_ETA,
    RULE_SOCRATES,
    RULE_WHEN,
    TI_AGENT,
    TI_GOALS,
    TI_NODE_AT,
    TI_ROBOT_INDEX,
    TI_SPAWN_IS_NODE,
    empty_rules,
)
from socnavgen.sim.gestures import HUMAN_PHRASE_CODE, ROBOT_PHRASE_CODE, _human_index

MAX_GESTURE = 62  # the robot's gestures so far are a bit mask (RobotSaid)
_MISSING = object()


class Unsupported(Exception):
    """This simulation has something the compiled run does not do (the message says what)."""


_CONTROL = {rt.Sequence: K_SEQUENCE, rt.Fallback: K_FALLBACK, rt.ReactiveSequence: K_REACTIVE_SEQUENCE,
            rt.ReactiveFallback: K_REACTIVE_FALLBACK}
_DECORATOR = {rt.Inverter: K_INVERTER, rt.ForceSuccess: K_FORCE_SUCCESS, rt.ForceFailure: K_FORCE_FAILURE,
              rt.KeepRunningUntilFailure: K_KEEP_RUNNING, rt.Repeat: K_REPEAT}


def _typed(value: Any) -> tuple[int, float]:
    """(type, number) of a blackboard value as the reference keeps it; text is not lowered."""
    if value is _MISSING:
        return T_UNSET, 0.0
    if isinstance(value, bool):
        return T_BOOL, float(value)
    if type(value) is int:
        return T_INT, float(value)
    if isinstance(value, float):
        return T_FLOAT, float(value)
    raise Unsupported(f"a blackboard holds {type(value).__name__} {value!r}")


class _Program:
    """Pre-order numbering of every tree's nodes, their ports and the blackboard entries they read."""

    def __init__(self) -> None:
        self.rows: list[list[int]] = []
        self.kids: list[int] = []
        self.current: list[int] = []
        self.ports: list[list[tuple[int, float, int]]] = []
        self.slot_of: dict[tuple[int, str], int] = {}
        self.slot_value: list[float] = []
        self.slot_type: list[int] = []
        self._alive: list[dict] = []  # keeps the dicts whose id() names a slot

    def slot(self, resolved: tuple[dict, str]) -> int:
        data, key = resolved
        ident = (id(data), key)
        if ident not in self.slot_of:
            typ, value = _typed(data.get(key, _MISSING))
            self.slot_of[ident] = len(self.slot_value)
            self.slot_value.append(value)
            self.slot_type.append(typ)
            self._alive.append(data)
        return self.slot_of[ident]

    def node(self, obj: rt.Node) -> int:
        k = len(self.rows)
        row = [0] * NI_ROWS
        self.rows.append(row)
        self.current.append(0)
        self.ports.append([])
        cls = type(obj)
        children: list[rt.Node] = []
        if cls in _CONTROL:
            row[NI_KIND], children = _CONTROL[cls], list(obj.children)
            self.current[k] = int(obj.current)
        elif cls in _DECORATOR:
            row[NI_KIND], children = _DECORATOR[cls], [obj.child]
            if cls is rt.Repeat:
                row[NI_REPEAT], row[NI_UNTIL] = int(obj.count), int(obj.until)
        elif cls is rt.SetBlackboard:
            if obj.out is None or obj.source is None or obj.src is None:
                raise Unsupported("SetBlackboard of a literal or through an autoremapped key")
            row[NI_KIND], row[NI_SB_OUT], row[NI_SB_SRC] = K_SET_BLACKBOARD, self.slot(obj.out), self.slot(obj.src)
        elif cls in (rt.ConditionLeaf, rt.ActionLeaf):
            self._leaf(obj, row)
        else:
            raise Unsupported(f"tree node {cls.__name__}")
        first = len(self.kids)
        self.kids.extend([0] * len(children))
        for j, child in enumerate(children):
            self.kids[first + j] = self.node(child)
        row[NI_FIRST], row[NI_COUNT], row[NI_END] = first, len(children), len(self.rows)
        return k

    def _leaf(self, leaf: rt.Leaf, row: list[int]) -> None:
        if leaf.name not in PORT_NAMES or leaf.state:
            raise Unsupported(f"leaf {leaf.name}")
        row[NI_KIND] = K_CONDITION if isinstance(leaf, rt.ConditionLeaf) else K_ACTION
        row[NI_LEAF], row[NI_OWNER], row[NI_MOTION] = LEAF_NAMES.index(leaf.name), leaf.owner, int(leaf.motion)
        assert row[NI_LEAF] == leaf.index  # the trace's node index is the library's order
        row[NI_AGENT_PORT] = -1
        ports = self.ports[-1]
        for p, name in enumerate(PORT_NAMES[leaf.name]):
            if name not in leaf.ports:
                ports.append((PORT_ABSENT, 0.0, T_UNSET))
                continue
            resolved, key, value, _ = leaf.ports[name]
            if name == "agent_id":
                row[NI_AGENT_PORT] = p
            if key is not None:
                ports.append((self.slot(resolved), 0.0, T_UNSET) if resolved is not None else
                             (PORT_DYNAMIC, 0.0, T_UNSET))
            elif isinstance(value, str):
                if (leaf.name, name) != ("SaySomething", "message"):
                    ports.append((PORT_DYNAMIC, 0.0, T_UNSET))
                else:  # nodes_hunav2.say_something's word -> gesture
                    ports.append((PORT_LITERAL, float(GESTURE_OF_WORD.get(value.strip(), 0)), T_INT))
            else:
                typ, number = _typed(value)
                ports.append((PORT_LITERAL, number, typ))

    def arrays(self, roots: list[int], dt_slots: list[int]) -> tuple:
        n = len(self.rows)
        pslot = np.full((n, MAX_PORTS), PORT_ABSENT, dtype=np.int64)
        pval = np.zeros((n, MAX_PORTS))
        ptype = np.zeros((n, MAX_PORTS), dtype=np.int64)
        for k, ports in enumerate(self.ports):
            for p, (slot, value, typ) in enumerate(ports):
                pslot[k, p], pval[k, p], ptype[k, p] = slot, value, typ
        ni = np.ascontiguousarray(np.array(self.rows, dtype=np.int64).reshape(n, NI_ROWS).T)
        return (ni, np.array(self.current, dtype=np.int64), np.zeros(n), pslot, pval, ptype,
                np.array(self.slot_value + [0.0]), np.array(self.slot_type + [T_UNSET], dtype=np.int64),
                np.array(self.kids + [0], dtype=np.int64), np.array(roots, dtype=np.int64),
                np.array(dt_slots, dtype=np.int64), np.zeros((n + 1, 3), dtype=np.int64))


def lower_trees(trees: list[rt.BehaviorTree]) -> tuple:
    """P: one program for every agent's tree (agent i's root is roots[i], its `dt` entry dt_slots[i])."""
    program = _Program()
    roots, dt_slots = [], []
    for tree in trees:
        roots.append(program.node(tree.root))
        dt_slots.append(program.slot((tree.blackboard.data, "dt")))
    return program.arrays(roots, dt_slots)


# which arrays of P an episode changes (current child, leaf states, blackboard, the interpreter's stack)
_MUTABLE = (1, 2, 6, 7, 11)


def program_of(trees: list, tree_names: list[str] | None, base_dir: Any) -> tuple | None:
    """The lowered program of these trees (XML or parsed), built once and copied for every Simulation of them
    (fresh_program): a campaign runs one scenario's trees thousands of times. None when they cannot be
    lowered, or do not build (the Simulation then builds them itself and reports what is wrong)."""
    from socnavgen.sim.bt_build import build_tree
    from socnavgen.sim.engine import NODE_INDEX
    from socnavgen.sim.nodes import IMPLEMENTATIONS

    try:
        built = [build_tree(tree, None, i, IMPLEMENTATIONS, NODE_INDEX, base_dir=base_dir,
                            name=(tree_names[i] if tree_names else f"tree of agent {i}"))
                 for i, tree in enumerate(trees)]
        return lower_trees(built)
    except Exception:  # noqa: BLE001 - Unsupported, or a tree error the Simulation raises itself
        return None


def fresh_program(template: tuple) -> tuple:
    """A copy of a lowered program an episode may change (the read-only parts are shared)."""
    return tuple(a.copy() if k in _MUTABLE else a for k, a in enumerate(template))


def lower_throttle(throttle: Any, specs: list[Any]) -> tuple[tuple, bool]:
    """(T, in use) for an InteractionThrottle (or None)."""
    if throttle is None:
        held, config = [], None
    else:
        held, config = throttle.held, throttle.config
        if config.rule not in ("eta", "socrates"):
            raise Unsupported(f"throttle rule {config.rule!r}")
    h = len(held)
    goals = max([len(x.goals) for x in held] + [1])
    robot_goals = [] if throttle is None else throttle.robot_goals
    ti = np.zeros((5, max(h, 1)), dtype=np.int64)
    points = np.zeros((max(h, 1), goals), dtype=complex)
    goal_is_node = np.zeros((max(h, 1), goals), dtype=bool)
    robot_goal_is_node = np.zeros((max(h, 1), max(len(robot_goals), 1)), dtype=bool)
    for j, x in enumerate(held):
        ti[TI_AGENT, j], ti[TI_GOALS, j], ti[TI_NODE_AT, j] = x.agent, len(x.goals), throttle.node_at[x.agent]
        ti[TI_SPAWN_IS_NODE, j], ti[TI_ROBOT_INDEX, j] = int(x.spawn == x.node), x.robot_index
        for g, point in enumerate(specs[x.agent].goals):
            points[j, g] = complex(*point)
        for g, node in enumerate(x.goals):
            goal_is_node[j, g] = node == x.node
        for g, node in enumerate(robot_goals):
            robot_goal_is_node[j, g] = node == x.node
    rpoints = np.array(list(throttle.robot_points) if throttle is not None else [], dtype=complex)
    cumulative = np.array(throttle.cumulative if throttle is not None else [], dtype=float)
    conf = np.zeros(5)
    state = np.zeros(4, dtype=np.int64)
    if config is not None:
        conf[:] = (config.waypoint_radius, config.release_distance, config.robot_speed, config.min_pace,
                   config.robot_near)
        state[:] = (throttle.k, int(config.enabled), RULE_ETA if config.rule == "eta" else RULE_SOCRATES, h)
    rpoints = rpoints if rpoints.size else np.zeros(1, dtype=complex)
    cumulative = cumulative if cumulative.size else np.zeros(1)
    return (ti, points, goal_is_node, robot_goal_is_node, rpoints, cumulative, conf, state), throttle is not None


def lower_script(script: Any, cues: Any, n: int, max_steps: int) -> tuple[tuple, bool]:
    """(C, in use) for a RobotScriptRunner (or None) and the CueState every policy reads."""
    items = [] if script is None else list(script.script.cues)
    c = len(items)
    ci = np.zeros((max(c, 1), 7), dtype=np.int64)
    cf = np.zeros((max(c, 1), 5))
    cpoints = np.zeros(max(c, 1), dtype=complex)
    state = np.zeros((max(c, 1), 4), dtype=np.int64)
    times = np.full((max(c, 1), 3), -math.inf)
    for k, cue in enumerate(items):
        trig = cue.trigger
        who = _human_index(trig.human, n)
        point = script.points.get(trig.encounter or "")
        ci[k, CI_WHEN], ci[k, CI_WHO] = CUE_WHEN[trig.when], -1 if who is None else who
        ci[k, CI_PHRASE] = HUMAN_PHRASE_CODE.get(trig.phrase or "", -1)
        ci[k, CI_SAY] = ROBOT_PHRASE_CODE[cue.say] if cue.say else 0
        ci[k, CI_ONCE], ci[k, CI_UNTIL_CLEAR], ci[k, CI_HAS_POINT] = cue.once, cue.wait_until_clear, point is not None
        cf[k, CF_SECONDS], cf[k, CF_DISTANCE], cf[k, CF_HOLD], cf[k, CF_WAIT] = trig.seconds, trig.distance, cue.hold, cue.wait
        cf[k, CF_SPEED] = math.nan if cue.speed is None else cue.speed
        cpoints[k] = point if point is not None else 0j
        state[k, CS_FIRED], state[k, CS_WAS_TRUE] = script.fired[k], script.was_true[k]
        state[k, CS_UNTIL_CLEAR], state[k, CS_REPEATS] = script.until_clear[k], script.repeats[k]
        times[k, CT_SAY_UNTIL], times[k, CT_WAIT_UNTIL] = script.say_until[k], script.wait_until[k]
        times[k, CT_CLEAR_SINCE] = script.clear_since[k]
    if max(ci[:, CI_SAY].max(), 0) > MAX_GESTURE:
        raise Unsupported("a robot phrase code beyond the gesture mask")
    cue_state = np.array([cues.say, float(cues.wait), cues.speed, float(cues.misbehave)])
    capacity = max(c, 1) * 2 * (max_steps + 1)
    return (ci, cf, cpoints, state, times, cue_state, np.zeros(capacity), np.zeros((capacity, 2), dtype=np.int64),
            np.array([0, c], dtype=np.int64)), script is not None


def lower_rules(gestures: Any) -> tuple[tuple, bool]:
    """(G, in use) for ScriptedGestures (or None)."""
    if gestures is None:
        return empty_rules(), False
    rules = gestures.rules
    r = len(rules)
    gi = np.zeros((r, 2), dtype=np.int64)
    gf = np.zeros((r, 2))
    gpoints = np.zeros(r, dtype=complex)
    has_point = np.zeros(r, dtype=bool)
    for k, rule in enumerate(rules):
        if not 0 <= rule.gesture <= MAX_GESTURE:
            raise Unsupported(f"robot gesture code {rule.gesture}")
        gi[k] = (RULE_WHEN[rule.when], rule.gesture)
        gf[k] = (rule.distance, rule.duration)
        point = gestures.node_points.get(rule.node or "")
        has_point[k] = point is not None
        gpoints[k] = point if point is not None else 0j
    return (gi, gf, gpoints, has_point, np.array(gestures.last_true, dtype=float)), True
