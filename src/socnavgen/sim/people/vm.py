"""The behavior-tree interpreter: ticks one person's tree of the lowered program (people.trees) once per
step. Nodes are numbered in pre-order, so a node's subtree is the range [k, end) and a halt (forget the
running child of every Sequence below) is one slice; recursion becomes an explicit stack whose frames are
(node, position: -1 on entry, else the child that just returned, counter).

A leaf's ports are read into `trees.args` by column (blackboard entries converted by the port's type), the
person it acts for checked, and the leaf function of its library row called. A tree that cannot go on (a
port reading a key nobody wrote, text that is not a number, an agent id that names nobody) stops the step:
the error is written to the clock record (engine.state) and the engine raises it with the file and line.
"""

from __future__ import annotations

import math

from socnavgen.sim.jit import dispatcher, jit
from socnavgen.sim.people import give_way, leaves_hunav2  # noqa: F401 - register their leaves
from socnavgen.sim.people.leaves import BAD_PORT, LEAVES
from socnavgen.sim.people.trees import (
    ACTION,
    BOOL,
    CONDITION,
    DOUBLE,
    FAILURE,
    FALLBACK,
    FORCE_FAILURE,
    FORCE_SUCCESS,
    INT,
    INVERTER,
    KEEP_RUNNING,
    LEAF_NAMES,
    LITERAL,
    REACTIVE_FALLBACK,
    REACTIVE_SEQUENCE,
    REPEAT,
    RUNNING,
    SEQUENCE,
    SET_BLACKBOARD,
    SUCCESS,
    TEXT,
    UNSET,
    Port,
)

ERROR = -1  # a tick's status when the tree cannot go on
# what went wrong (clock.error_kind)
UNSET_KEY, NOT_CONVERTIBLE, NOT_AN_AGENT, UNUSABLE, COPY_UNSET = 1, 2, 3, 4, 5

_missing = [name for name in LEAF_NAMES if name not in LEAVES]
if _missing:
    raise ImportError(f"library leaves without a function in sim.people: {_missing}")
call_leaf = dispatcher("call_leaf", [LEAVES[name] for name in LEAF_NAMES], 4)


@jit
def fail(s, k, kind, column, value):  # noqa: ANN001, ANN201
    c = s.clock[0]
    c.error_node, c.error_kind, c.error_port, c.error_value = k, kind, column, value
    return ERROR


@jit(inline=True)
def read_port(ports, slots, texts, args, port):  # noqa: ANN001, ANN201
    """Port `port` of a leaf into args[its column]: 0, or what went wrong (UNSET_KEY, NOT_CONVERTIBLE)."""
    pr = ports[port]
    if pr.slot == LITERAL:
        args[pr.column] = pr.literal
        return 0
    slot = slots[pr.slot]
    if slot.type == UNSET:
        return UNSET_KEY
    if slot.type != TEXT:
        args[pr.column] = slot.value
        return 0
    text = texts[int(slot.value)]
    if pr.type == INT and text.int_ok:
        args[pr.column] = text.as_int
    elif pr.type == DOUBLE and text.double_ok:
        args[pr.column] = text.as_double
    elif pr.type == BOOL and text.bool_ok:
        args[pr.column] = text.as_bool
    elif pr.type == TEXT:
        args[pr.column] = text.gesture
    else:
        return NOT_CONVERTIBLE
    return 0


@jit(inline=True)
def run_leaf(s, people, nodes, ports, slots, texts, args, k):  # noqa: ANN001, ANN201
    """A leaf's tick: its ports, the person it acts for, the leaf, and what the trace records of it."""
    node = nodes[k]
    has_agent = False
    for port in range(node.first_port, node.first_port + node.port_count):
        problem = read_port(ports, slots, texts, args, port)
        if problem:
            return fail(s, k, problem, ports[port].column, slots[ports[port].slot].value)
        has_agent = has_agent or ports[port].column == Port.agent_id
    i = node.owner
    if has_agent:
        v = args[Port.agent_id]
        if not (v == math.floor(v) and 0 <= v < people.shape[0]):
            return fail(s, k, NOT_AN_AGENT, Port.agent_id, v)
        i = int(v)
    st = call_leaf(node.leaf, s, node, i, args)
    if st <= BAD_PORT:
        column = BAD_PORT - st
        return fail(s, k, UNUSABLE, column, args[column])
    owner = people[node.owner]
    if st == SUCCESS or (node.kind == CONDITION and st != FAILURE):
        owner.succeeded |= 1 << node.leaf
    if node.kind == ACTION and (node.moves or not owner.action_moves):
        owner.action, owner.action_moves = node.leaf, node.moves
    return st


@jit
def tick(s, nodes, ports, slots, texts, kids, stack, args, dt, i):  # noqa: ANN001, ANN201, C901
    """Tick person i's tree once from its root: SUCCESS, FAILURE, RUNNING, or ERROR. The program's arrays
    (trees.Trees) come one by one: the interpreter runs for every person every step."""
    people = s.people
    person = people[i]
    slots[person.dt_slot].value = dt
    slots[person.dt_slot].type = DOUBLE
    stack[0, 0], stack[0, 1], stack[0, 2] = person.tree, -1, 0
    depth = 1
    ret = SUCCESS
    while depth > 0:
        top = depth - 1
        k, pos = stack[top, 0], stack[top, 1]
        node = nodes[k]
        kind = node.kind
        if kind in (CONDITION, ACTION):
            ret = run_leaf(s, people, nodes, ports, slots, texts, args, k)
            if ret == ERROR:
                return ERROR
            depth -= 1
            continue
        if kind == SET_BLACKBOARD:
            source = slots[node.source_slot]
            if source.type == UNSET:
                return fail(s, k, COPY_UNSET, -1, 0.0)
            slots[node.out_slot].value, slots[node.out_slot].type = source.value, source.type
            ret = SUCCESS
            depth -= 1
            continue
        child = -1
        if kind in (SEQUENCE, FALLBACK):
            go_on = SUCCESS if kind == SEQUENCE else FAILURE
            j = node.current if pos < 0 else pos
            finished = False
            if pos >= 0:
                if ret == go_on:
                    j += 1
                else:  # stopped here: remember a running child, else start over next time
                    node.current = j if ret == RUNNING else 0
                    finished = True
            if not finished:
                if j < node.count:
                    child = j
                else:
                    node.current = 0
                    ret = go_on
        elif kind in (REACTIVE_SEQUENCE, REACTIVE_FALLBACK):
            go_on = SUCCESS if kind == REACTIVE_SEQUENCE else FAILURE
            j = 0 if pos < 0 else pos + 1
            if pos >= 0 and ret != go_on:
                if pos + 1 < node.count:  # halt the children after the one that did not go on
                    for m in range(kids[node.first + pos + 1], node.end):
                        nodes[m].current = 0
            elif j < node.count:
                child = j
            else:
                ret = go_on
        elif kind == REPEAT:
            cycles = node.cycles
            if node.cycles_slot != LITERAL:  # num_cycles / num_attempts from the blackboard
                held = slots[node.cycles_slot]
                cycles = int(texts[int(held.value)].as_int if held.type == TEXT else held.value)
            limit = max(cycles, 1)
            stop = FAILURE if node.until == SUCCESS else SUCCESS
            if pos < 0:
                stack[top, 2] = 0
                child = 0
            elif ret != RUNNING and ret != stop:
                stack[top, 2] += 1
                if stack[top, 2] < limit:
                    child = 0
                else:
                    ret = node.until
        else:  # decorators with one child
            if pos < 0:
                child = 0
            elif kind == INVERTER:
                ret = ret if ret == RUNNING else SUCCESS - ret
            elif kind == FORCE_SUCCESS:
                ret = RUNNING if ret == RUNNING else SUCCESS
            elif kind == FORCE_FAILURE:
                ret = RUNNING if ret == RUNNING else FAILURE
            elif kind == KEEP_RUNNING:
                ret = FAILURE if ret == FAILURE else RUNNING
        if child >= 0:
            stack[top, 1] = child
            stack[depth, 0], stack[depth, 1], stack[depth, 2] = kids[node.first + child], -1, 0
            depth += 1
        else:
            depth -= 1
    return ret

