"""Interpreter of BehaviorTree.CPP v3 and v4 XML for the simulator - the runtime half: blackboards,
control nodes, decorators and library leaves. Trees are built once by `socnavgen.sim.bt_build` and ticked
once per step. While ticking, leaves record into the simulation which action ran and which leaves returned
SUCCESS (for the trace)."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from socnavgen.bt.library import PortType
from socnavgen.errors import ValidationFailed

FAILURE, SUCCESS, RUNNING = 0, 1, 2
MAX_SUBTREE_DEPTH = 16

# Nodes outside the library table that BT.CPP provides and cost nothing to support.
EXTRA_DECORATORS = {"Repeat": "num_cycles", "RetryUntilSuccessful": "num_attempts", "KeepRunningUntilFailure": None}
EXPLICIT_TAGS = {"Action", "Condition", "Control", "Decorator"}  # v3 <Action ID="X"/> form


class BTRuntimeError(ValidationFailed):
    """A tree failed while running (e.g. a port reads a blackboard key nobody wrote)."""


def _to_bool(text: str) -> bool:
    if text in ("true", "True", "TRUE", "1"):
        return True
    if text in ("false", "False", "FALSE", "0"):
        return False
    raise ValueError(f"not a bool: {text!r}")


CONVERTERS: dict[PortType, Callable[[str], Any]] = {
    PortType.INT: lambda s: int(float(s)) if "." in s else int(s),
    PortType.DOUBLE: float,
    PortType.BOOL: _to_bool,
    PortType.STRING: str,
}


class Blackboard:
    """Key-value store of one tree or subtree; remapped keys read and write the parent's entry live."""

    __slots__ = ("data", "parent", "remap", "autoremap")

    def __init__(self, parent: Blackboard | None = None, remap: dict[str, str] | None = None,
                 autoremap: bool = False) -> None:
        self.data: dict[str, Any] = {}
        self.parent = parent
        self.remap = remap or {}
        self.autoremap = autoremap

    def get(self, key: str) -> Any:
        if key in self.remap:
            return self.parent.get(self.remap[key])
        if key in self.data:
            return self.data[key]
        if self.autoremap and self.parent is not None:
            return self.parent.get(key)
        raise KeyError(key)

    def resolve(self, key: str) -> tuple[dict, str] | None:
        """(dict, key) holding `key` after following remaps; None when autoremap makes it dynamic."""
        bb = self
        while key in bb.remap:
            key = bb.remap[key]
            bb = bb.parent
        return None if bb.autoremap else (bb.data, key)

    def set(self, key: str, value: Any) -> None:
        if key in self.remap:
            self.parent.set(self.remap[key], value)
        elif self.autoremap and self.parent is not None and key not in self.data:
            self.parent.set(key, value)
        else:
            self.data[key] = value


def _blackboard_key(value: str) -> str | None:
    """`{key}` -> key; anything else -> None (a literal)."""
    if len(value) >= 2 and value[0] == "{" and value[-1] == "}":
        return value[1:-1].strip()
    return None


# ---- nodes -----------------------------------------------------------------------------------
class Node:
    __slots__ = ("line",)

    def tick(self) -> int:  # pragma: no cover - abstract
        raise NotImplementedError

    def reset(self) -> None:
        """Halt: forget a RUNNING child (called when a reactive parent interrupts this branch)."""


class Sequence(Node):
    __slots__ = ("children", "current")

    def __init__(self, children: list[Node]) -> None:
        self.children, self.current = children, 0

    def tick(self) -> int:
        children = self.children
        i = self.current
        n = len(children)
        while i < n:
            st = children[i].tick()
            if st == SUCCESS:
                i += 1
                continue
            if st == RUNNING:
                self.current = i
                return RUNNING
            self.current = 0  # nothing below is running any more: the running child just finished
            return FAILURE
        self.current = 0
        return SUCCESS

    def reset(self) -> None:
        self.current = 0
        for c in self.children:
            c.reset()


class Fallback(Sequence):
    __slots__ = ()

    def tick(self) -> int:
        children = self.children
        i = self.current
        n = len(children)
        while i < n:
            st = children[i].tick()
            if st == FAILURE:
                i += 1
                continue
            if st == RUNNING:
                self.current = i
                return RUNNING
            self.current = 0
            return SUCCESS
        self.current = 0
        return FAILURE


class ReactiveSequence(Sequence):
    """Re-evaluates from the first child every tick; a RUNNING child halts the ones after it."""

    __slots__ = ()

    def tick(self) -> int:
        for k, child in enumerate(self.children):
            st = child.tick()
            if st == SUCCESS:
                continue
            for later in self.children[k + 1:]:
                later.reset()
            return st
        return SUCCESS


class ReactiveFallback(Sequence):
    __slots__ = ()

    def tick(self) -> int:
        for k, child in enumerate(self.children):
            st = child.tick()
            if st == FAILURE:
                continue
            for later in self.children[k + 1:]:
                later.reset()
            return st
        return FAILURE


class Decorator(Node):
    __slots__ = ("child",)

    def __init__(self, child: Node) -> None:
        self.child = child

    def reset(self) -> None:
        self.child.reset()


class Inverter(Decorator):
    __slots__ = ()

    def tick(self) -> int:
        st = self.child.tick()
        return st if st == RUNNING else SUCCESS - st


class ForceSuccess(Decorator):
    __slots__ = ()

    def tick(self) -> int:
        return RUNNING if self.child.tick() == RUNNING else SUCCESS


class ForceFailure(Decorator):
    __slots__ = ()

    def tick(self) -> int:
        return RUNNING if self.child.tick() == RUNNING else FAILURE


class Repeat(Decorator):
    """Ticks the child up to `count` times within one tick while it succeeds (synchronous leaves)."""

    __slots__ = ("count", "until")

    def __init__(self, child: Node, count: int, until: int) -> None:
        super().__init__(child)
        self.count, self.until = count, until

    def tick(self) -> int:
        stop = FAILURE if self.until == SUCCESS else SUCCESS
        for _ in range(max(self.count, 1) if self.count >= 0 else 1_000):
            st = self.child.tick()
            if st == RUNNING:
                return RUNNING
            if st == stop:
                return stop
        return self.until


class KeepRunningUntilFailure(Decorator):
    __slots__ = ()

    def tick(self) -> int:
        return FAILURE if self.child.tick() == FAILURE else RUNNING


class SetBlackboard(Node):
    __slots__ = ("bb", "key", "source", "literal", "out", "src")

    def __init__(self, bb: Blackboard, key: str, value: str) -> None:
        self.bb, self.key = bb, key
        self.source = _blackboard_key(value)
        self.literal = value
        # remaps are static: resolve both ends once (None = dynamic through autoremap)
        self.out = bb.resolve(key)
        self.src = bb.resolve(self.source) if self.source is not None else None

    def tick(self) -> int:
        out, src = self.out, self.src
        if src is not None:
            try:
                value = src[0][src[1]]
            except KeyError:
                value = self.bb.get(self.source)  # raises the KeyError the builder reports
        elif self.source is not None:
            value = self.bb.get(self.source)
        else:
            value = self.literal
        if out is not None:
            out[0][out[1]] = value
        else:
            self.bb.set(self.key, value)
        return SUCCESS


class Leaf(Node):
    """A library leaf bound to one agent's tree. The node function gets (sim, leaf, agent index) and reads
    other ports through `leaf.get`. Port keys are resolved through SubTree remapping once, at build time
    (remaps are static; only values change), so a read is one dict lookup."""

    __slots__ = ("name", "fn", "sim", "owner", "bb", "ports", "bit", "index", "motion", "state", "source",
                 "agent_port", "last_agent")

    def __init__(self, name: str, fn: Callable, sim: Any, owner: int, bb: Blackboard,
                 ports: dict[str, tuple[str | None, Any, Callable]], index: int, line: int | None,
                 source: str) -> None:
        self.name, self.fn, self.sim, self.owner, self.bb = name, fn, sim, owner, bb
        self.ports = {k: (bb.resolve(key) if key is not None else None, key, value, conv)
                      for k, (key, value, conv) in ports.items()}
        self.agent_port = self.ports.get("agent_id")
        self.last_agent = None
        self.index, self.bit = index, 1 << index
        self.motion = name not in ("MakeGesture", "UpdateGoal")
        self.state: dict[str, Any] = {}
        self.line, self.source = line, source

    def get(self, name: str) -> Any:
        resolved, key, value, conv = self.ports[name]
        if key is None:
            return value
        try:
            value = resolved[0][resolved[1]] if resolved is not None else self.bb.get(key)
        except KeyError as exc:
            raise BTRuntimeError(f"{self.name}: port `{name}` reads blackboard key `{key}` that is not set",
                                 file=self.source, line=self.line,
                                 hint="write it with SetBlackboard or remap it in the SubTree") from exc
        if type(value) is str:
            try:
                return conv(value)
            except ValueError as exc:
                raise BTRuntimeError(f"{self.name}: port `{name}` got {value!r}", file=self.source,
                                     line=self.line) from exc
        return value

    def agent(self) -> int:
        """The `agent_id` port, checked to name an agent (checked again only when it changes)."""
        port = self.agent_port
        if port is None:
            return self.owner
        resolved = port[0]
        if resolved is not None:
            try:
                i = resolved[0][resolved[1]]
            except KeyError:
                i = self.get("agent_id")
        else:
            i = self.get("agent_id")
        if i is not self.last_agent:
            if type(i) is str:
                i = self.get("agent_id")
            if type(i) is not int or not 0 <= i < self.sim.crowd.n:
                raise BTRuntimeError(f"{self.name}: agent_id {i!r} is not an agent (0..{self.sim.crowd.n - 1})",
                                     file=self.source, line=self.line, hint="write agent_id=\"{id}\"")
            self.last_agent = i
        return i


class ConditionLeaf(Leaf):
    __slots__ = ()

    def tick(self) -> int:
        st = self.fn(self.sim, self, self.agent())
        if st:
            self.sim.tick_success[self.owner] |= self.bit
        return st


class ActionLeaf(Leaf):
    __slots__ = ()

    def tick(self) -> int:
        sim, owner = self.sim, self.owner
        st = self.fn(sim, self, self.agent())
        if st == SUCCESS:
            sim.tick_success[owner] |= self.bit
        if self.motion or not sim.tick_action_motion[owner]:
            sim.tick_action[owner] = self.index
            sim.tick_action_motion[owner] = self.motion
        return st


# ---- building --------------------------------------------------------------------------------
class BehaviorTree:
    """One agent's instantiated tree: tick() evaluates it once from the root."""

    def __init__(self, root: Node, blackboard: Blackboard) -> None:
        self.root = root
        self.blackboard = blackboard

    def tick(self, dt: float) -> int:
        self.blackboard.data["dt"] = dt
        return self.root.tick()
