"""The behavior-tree interpreter, compiled: the twin of sim.bt_runtime (the reference) over the flat program
built by compiled.lower. Nodes are numbered in pre-order, so a node's subtree is the range [k, end) and a
halt (bt_runtime's reset: forget the running child of every Sequence below) is one slice. Recursion becomes
an explicit stack: each frame is (node, position: -1 on entry, else the child that just returned, counter).

P = (ni, current, leaf_state, port_slot, port_value, port_type, slot_value, slot_type, kids, roots,
     dt_slots, stack)."""

from __future__ import annotations

from socnavgen.sim.compiled.layout import (
    ERROR,
    FAILURE,
    HI_ACTION,
    HI_MOTION,
    HI_SUCCESS,
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
    NI_SB_OUT,
    NI_SB_SRC,
    NI_UNTIL,
    RUNNING,
    SUCCESS,
    T_FLOAT,
    T_INT,
    T_UNSET,
)
from socnavgen.sim.compiled.leaves import port, tick_leaf
from socnavgen.sim.kernels import no_alloc


@no_alloc(inline=True)
def leaf_agent(k, S, P):  # noqa: ANN001, ANN201
    """Leaf.agent(): the `agent_id` port (the owner without one); -1 where the reference raises."""
    p = P[0][NI_AGENT_PORT, k]
    if p < 0:
        return P[0][NI_OWNER, k]
    v, t = port(P, k, p)
    n = S[0].shape[1]
    if t != T_INT or not 0 <= v < n:
        return -1
    return int(v)


@no_alloc(inline=True)
def run_leaf(k, S, W, P, dt):  # noqa: ANN001, ANN201
    """ConditionLeaf.tick / ActionLeaf.tick: the leaf, then what the trace records of it."""
    ni, hi = P[0], S[5]
    i = leaf_agent(k, S, P)
    if i < 0:
        return ERROR
    code = ni[NI_LEAF, k]
    st = tick_leaf(code, k, i, S, W, P, dt)
    if st == ERROR:
        return ERROR
    owner = ni[NI_OWNER, k]
    if ni[NI_KIND, k] == K_CONDITION:
        if st != FAILURE:
            hi[HI_SUCCESS][owner] |= 1 << code
        return st
    if st == SUCCESS:
        hi[HI_SUCCESS][owner] |= 1 << code
    motion = ni[NI_MOTION, k]
    if motion or not hi[HI_MOTION][owner]:
        hi[HI_ACTION][owner] = code
        hi[HI_MOTION][owner] = motion
    return st


@no_alloc(inline=True)
def tick_tree(agent, S, W, P, dt):  # noqa: ANN001, ANN201, C901
    """BehaviorTree.tick for one agent's tree: set its `dt`, tick from the root; ERROR where the reference
    raises."""
    ni, cur, slot_val, slot_type, kids, stack = P[0], P[1], P[6], P[7], P[8], P[11]
    dt_slot = P[10][agent]
    slot_val[dt_slot] = dt
    slot_type[dt_slot] = T_FLOAT
    stack[0, 0], stack[0, 1], stack[0, 2] = P[9][agent], -1, 0
    sp = 1
    ret = SUCCESS
    while sp > 0:
        top = sp - 1
        k, pos = stack[top, 0], stack[top, 1]
        kind = ni[NI_KIND, k]
        if kind in (K_CONDITION, K_ACTION):
            ret = run_leaf(k, S, W, P, dt)
            if ret == ERROR:
                return ERROR
            sp -= 1
            continue
        if kind == K_SET_BLACKBOARD:
            src, out = ni[NI_SB_SRC, k], ni[NI_SB_OUT, k]
            if slot_type[src] == T_UNSET:
                return ERROR
            slot_val[out], slot_type[out] = slot_val[src], slot_type[src]
            ret = SUCCESS
            sp -= 1
            continue
        first, count = ni[NI_FIRST, k], ni[NI_COUNT, k]
        child = -1
        if kind in (K_SEQUENCE, K_FALLBACK):
            go_on = SUCCESS if kind == K_SEQUENCE else FAILURE
            i = cur[k] if pos < 0 else pos
            done = False
            if pos >= 0:
                if ret == go_on:
                    i += 1
                else:
                    cur[k] = i if ret == RUNNING else 0
                    done = True
            if not done:
                if i < count:
                    child = i
                else:
                    cur[k] = 0
                    ret = go_on
        elif kind in (K_REACTIVE_SEQUENCE, K_REACTIVE_FALLBACK):
            go_on = SUCCESS if kind == K_REACTIVE_SEQUENCE else FAILURE
            i = 0 if pos < 0 else pos + 1
            if pos >= 0 and ret != go_on:
                if pos + 1 < count:  # halt the children after the one that did not go on
                    for j in range(kids[first + pos + 1], ni[NI_END, k]):
                        cur[j] = 0
            elif i < count:
                child = i
            else:
                ret = go_on
        elif kind == K_REPEAT:
            limit = max(ni[NI_REPEAT, k], 1) if ni[NI_REPEAT, k] >= 0 else 1000
            until = ni[NI_UNTIL, k]
            stop = FAILURE if until == SUCCESS else SUCCESS
            if pos < 0:
                stack[top, 2] = 0
                child = 0
            elif ret != RUNNING and ret != stop:
                stack[top, 2] += 1
                if stack[top, 2] < limit:
                    child = 0
                else:
                    ret = until
        else:  # decorators with one child
            if pos < 0:
                child = 0
            elif kind == K_INVERTER:
                ret = ret if ret == RUNNING else SUCCESS - ret
            elif kind == K_FORCE_SUCCESS:
                ret = RUNNING if ret == RUNNING else SUCCESS
            elif kind == K_FORCE_FAILURE:
                ret = RUNNING if ret == RUNNING else FAILURE
            elif kind == K_KEEP_RUNNING:
                ret = FAILURE if ret == FAILURE else RUNNING
        if child >= 0:
            stack[top, 1] = child
            stack[sp, 0], stack[sp, 1], stack[sp, 2] = kids[first + child], -1, 0
            sp += 1
        else:
            sp -= 1
    return ret
