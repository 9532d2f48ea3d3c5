"""What a person's tree did while the robot was near: the facts behind "did not react as asked", the tree checks'
blame (rules T1-T3), and a give-way that ran its time without effect (rule R7).

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

from socnavgen.bt.library import LIBRARY, REACTION_NODES
from socnavgen.verify.models import Verdict
from socnavgen.verify.runs import runlength
from socnavgen.verify.signals import Signals
from socnavgen.verify.thresholds import PASSING_DISTANCE, REACTION_SECONDS

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


def tree_activity(s: Signals, human: str, near: np.ndarray, reach: float, reaction: str | None = None) -> str:
    """One sentence on what `human`'s tree did on the steps `near` (the robot within `reach` m); "" when there
    are no such steps. The hint on a gate vetoed by its partner only when `reaction`'s nodes never ran then (round
    29: a give-way that ran 10 s was told its gate "never ran its reaction")."""
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
            f"the robot standing still {_seconds(still, dt)} of it) its tree ran {', '.join(ran) or 'no action'}; conditions that held then: "
            + (", ".join(f"{name} {_seconds(m, dt)}" for name, m in held.items()) or "none"))
    names = list(held)
    together = [f"{b} held on every step {a} did" for a in names for b in names
                if a != b and not (held[a] & ~held[b]).any()
                and ((held[b] & ~held[a]).any() or names.index(a) < names.index(b))]
    reacted = reaction is not None and any((trace.executed(i, n) & near).any() for n in REACTION_NODES.get(reaction, ())
                                               if n in trace.node_names)
    if together and not reacted:
        text += (" (" + "; ".join(together) + ": a sequence that needs the first and NOT the second never ran its "
                 "reaction)")
    return text


GIVE_WAY_NODE = "GiveWaytoRobot"


def gave_way_in_vain(s: Signals, human: str, near: np.ndarray, seconds: float) -> Verdict | None:
    """Rule R7: `human`'s tree ran GiveWaytoRobot `seconds` at once while the robot was near (`near`) and the body
    never got out of the robot's way: the tree did its part, the place did not let them (no room beside the robot's
    way, or they met where the robot turns off): stage 2 / stage 1 can move the meeting, a re-asked tree cannot
    (round 29, home_21: three tree re-asks for a father met where the robot turned off, in a 1.7 m passage)."""
    trace = s.trace
    if GIVE_WAY_NODE not in trace.node_names:
        return None
    run = runlength(trace.executed(s.human(human), GIVE_WAY_NODE) & near, float(trace.dt))
    if not len(run) or run.max() < seconds:
        return None
    k = int(np.argmax(run >= seconds))
    start = float(s.t[k] - run[k]) + float(trace.dt)  # the run's first step
    return "spec", None, (f"{human}'s tree ran {GIVE_WAY_NODE} {float(run.max()):.1f} s at once from t={start:.1f} s "
                          f"with the robot near, but {human} never got out of its way: where they meet leaves no room "
                          f"to step aside (or the robot turns there); put the encounter on a stretch with room beside "
                          f"the robot's way, where it drives on straight, or have the robot wait for {human} "
                          f"(wait_until_clear) - no tree of {human}'s can make the room")


def blame_tree_check(node: str | None, message: int | None, human: str | None, s: Signals | None,
                     before_cause: bool, ran_at: float | None = None) -> Verdict:
    """Rules T1-T3 for a failing tree expectation. `ran_at`: when the node ran, for a check that failed although
    it ran (its effect never showed)."""
    if before_cause:
        return "behaviors", human, f"{human}'s {node} ran before its cause"
    if node == "RobotSays" and s is not None:
        said = message is not None and (np.asarray(s.trace.robot_gesture) == message).any()
        if not said:
            return "robot_script", None, "the robot never made the gesture this tree waits for: script it"
    if node in ("IsRobotVisible", "IsRobotNearby"):
        return "paths", None, f"the robot never came where {human} could see it"
    if ran_at is not None and s is not None and human and (vain := gave_way_in_vain(s, human, s.get(
            f"dist_{human}") <= PASSING_DISTANCE, REACTION_SECONDS)):
        return vain  # it ran its time at once: the place, not the tree (rule R7)
    if ran_at is not None:  # the node ran, its effect did not show (evaluate.py: GiveWaytoRobot without stepping aside)
        return "behaviors", human, (f"{human}'s tree ran {node} (from t={ran_at:.1f} s) but its body did not get out "
                                    f"of the robot's way: keep {node} running until {human} stands aside (do not cut "
                                    "it short with another node), or start it earlier, where there is room to step aside")
    return "behaviors", human, f"{human}'s tree never ran {node}"
