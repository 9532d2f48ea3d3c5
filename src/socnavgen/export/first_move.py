"""What a person's tree does before anything happens: the first action that moves them when the robot is far,
nothing has been said, no goal is reached and no clock has run out.

The simulator's pacing holds a person only through RegularNav (the fork's pause_nav): a person whose tree
starts by following someone, or standing until a phrase, is never held by it. The export's timing
(export.timing) replaces a timed person's whole tree until the release, so it must time only the people
pacing would hold at the start: those whose tree first walks (`first_move(tree) == WALK`)."""

from __future__ import annotations

from typing import Literal

from socnavgen.bt.expand import load_instance
from socnavgen.bt.model import Node

WALK = "RegularNav"  # the one action pacing holds
Status = Literal["SUCCESS", "FAILURE", "RUNNING"]


def _tick(n: Node) -> tuple[Status, str | None]:
    """(status, the moving action that runs) of one tick of `n` in the quiet start: every condition fails (the
    robot is not near, nothing heard, no goal reached, no time expired), a moving action runs, other actions and
    built-ins succeed."""
    spec = n.spec
    kind = spec.kind if spec is not None else n.kind
    if kind == "condition":
        return "FAILURE", None
    if kind in ("action", "builtin", "unknown") or not n.children:
        moves = spec is not None and spec.moves
        return ("RUNNING", n.name) if moves else ("SUCCESS", None)
    if kind == "decorator":
        status, mover = _tick(n.children[0])
        rule = spec.rule if spec is not None else None
        if rule == "invert" and status != "RUNNING":
            return ("FAILURE" if status == "SUCCESS" else "SUCCESS"), mover
        if rule == "force_success" and status != "RUNNING":
            return "SUCCESS", mover
        if rule == "force_failure" and status != "RUNNING":
            return "FAILURE", mover
        if rule == "keep_running" and status == "SUCCESS":
            return "RUNNING", mover
        return status, mover
    stop: Status = "SUCCESS" if spec is not None and spec.flow == "fallback" else "FAILURE"
    for child in n.children:  # a control: a sequence stops at a failure, a fallback at a success
        status, mover = _tick(child)
        if status == "RUNNING" or status == stop:
            return status, mover
    return ("FAILURE" if stop == "SUCCESS" else "SUCCESS"), None


def first_move(tree_xml: str) -> str | None:
    """The moving action the tree runs first in the quiet start, or None when it moves no one (it stands)."""
    return _tick(load_instance(tree_xml, "<first_move>").root)[1]


__all__ = ["WALK", "first_move"]
