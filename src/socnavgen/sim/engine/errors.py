"""A tree that could not go on while running, told as the user needs it: the file and line of the node,
what it read and what was wrong (the compiled step records the node and the kind of error; the lowering's
node table says where the node comes from)."""

from __future__ import annotations

from socnavgen.errors import ValidationFailed
from socnavgen.sim.engine.state import State
from socnavgen.sim.people import vm
from socnavgen.sim.people.trees import PORT_NAMES, Program


class BTRuntimeError(ValidationFailed):
    """A tree failed while running (e.g. a port reads a blackboard key nobody wrote)."""


def tree_error(state: State, program: Program) -> BTRuntimeError:
    clock = state.clock[0]
    k, kind, column, value = int(clock.error_node), int(clock.error_kind), int(clock.error_port), float(clock.error_value)
    info = program.info[k]
    port = PORT_NAMES[column] if 0 <= column < len(PORT_NAMES) else "?"
    key = info.keys.get(column, "?")
    shown = int(value) if value == int(value) else value
    n = state.people.shape[0]
    if kind == vm.UNSET_KEY:
        message, hint = (f"{info.tag}: port `{port}` reads blackboard key `{key}` that is not set",
                         "write it with SetBlackboard or remap it in the SubTree")
    elif kind == vm.NOT_CONVERTIBLE:
        text = next((t for t, j in program.texts.items() if j == int(value)), "?")
        message, hint = f"{info.tag}: port `{port}` got {text!r}", "write a value of the port's type"
    elif kind == vm.NOT_AN_AGENT:
        message, hint = f"{info.tag}: agent_id {shown!r} is not an agent (0..{n - 1})", 'write agent_id="{id}"'
    elif kind == vm.UNUSABLE:
        message, hint = (f"{info.tag}: port `{port}` = {shown!r} is not a human id (0..{n - 1})",
                         "ids are 0-based: human1 is 0 (HuNavSim 2.x ids start at 1)")
    else:
        message, hint = (f"{info.tag}: value reads blackboard key `{info.keys.get(-1, '?')}` that is not set",
                         "write the key first, or remap it in the SubTree")
    return BTRuntimeError(message, file=info.source, line=info.line, hint=hint)
