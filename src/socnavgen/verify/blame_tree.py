"""What a person's tree did while the robot was near: the facts behind "did not react as asked".

A bare "did not react" left round-22 players guessing whether their trigger ever held, or whether the robot was
standing (warehouse_17: IsRobotBlocking held on every step on which RobotMoved did too, so the `Inverter(RobotMoved)`
gate never opened and the corrected tree failed with the same numbers). The trace records, per step and person,
the leaf that acted and every leaf that returned SUCCESS (sim.trace.Trace.executed / fired); this module turns
them into one sentence the model can act on: which actions ran, which conditions held and for how long, and which
conditions held only together with another (a gate vetoed by its partner).
"""

from __future__ import annotations

import re

import numpy as np

from socnavgen.bt.library import LIBRARY
from socnavgen.verify.signals import Signals

# Conditions that say nothing about the robot: a tree's bookkeeping, not a cause.
_BOOKKEEPING = frozenset({"IsGoalReached"})
# The facts travel in a finding's blame reason between these marks: diagnostics of the tree that ran, not the
# outcome, so the --verify loop's "the same findings came back" compares the reason without them (a changed tree
# changes them even when what happened did not).
FACTS_OPEN, FACTS_CLOSE = " [what its tree did: ", "]"
_FACTS = re.compile(re.escape(FACTS_OPEN) + r"[^\]]*" + re.escape(FACTS_CLOSE))


def without_tree_facts(text: str) -> str:
    """`text` with the tree facts this module wrote taken out (what the --verify loop compares round to round)."""
    return _FACTS.sub("", text)


def _seconds(mask: np.ndarray, dt: float) -> str:
    return f"{float(mask.sum()) * dt:.1f} s"


def tree_activity(s: Signals, human: str, near: np.ndarray, reach: float) -> str:
    """One sentence on what `human`'s tree did on the steps `near` (the robot within `reach` m); "" when there
    are no such steps."""
    trace = s.trace
    if not near.any() or not trace.node_names:
        return ""
    i, dt = s.human(human), float(trace.dt)
    t = s.t[near]
    ran = [f"{name} {_seconds(m, dt)}" for name in trace.node_names
           if (m := trace.executed(i, name) & near).any() and LIBRARY.get(name) is not None
           and LIBRARY[name].kind == "action"]
    conditions = [name for name in trace.node_names if name not in _BOOKKEEPING and name in LIBRARY
                  and LIBRARY[name].kind == "condition"]
    fired = {name: trace.fired(i, name) & near for name in conditions}
    held = {name: m for name, m in fired.items() if m.any()}
    still = near & (s.get("robot_still") > 0.5)
    text = (f"while the robot was within {reach:g} m of {human} (t={t[0]:.1f}-{t[-1]:.1f} s, {_seconds(near, dt)}, "
            f"standing still {_seconds(still, dt)} of it) its tree ran {', '.join(ran) or 'no action'}; conditions that held then: "
            + (", ".join(f"{name} {_seconds(m, dt)}" for name, m in held.items()) or "none"))
    names = list(held)
    together = [f"{b} held on every step {a} did" for a in names for b in names
                if a != b and not (held[a] & ~held[b]).any()
                and ((held[b] & ~held[a]).any() or names.index(a) < names.index(b))]
    if together:
        text += (" (" + "; ".join(together) + ": a sequence that needs the first and NOT the second never ran its "
                 "reaction)")
    return text
