"""Tree-level checks: each key node of a human's tree (an interaction action, the conditions gating it)
must really run in the trace, AFTER the conditions that gate it first held, and a MakeGesture counts
only on the steps its own gesture is shown, and GiveWaytoRobot only where the body then gives way (out of the
robot's way within the reaction time: signals.aside). With spec.json they are diagnostics behind the criteria;
without it they are required."""

from __future__ import annotations

import numpy as np

from socnavgen.bt.library import HUMAN_GESTURES, LIBRARY, ROBOT_GESTURES
from socnavgen.sim import contact
from socnavgen.sim.trace import Trace
from socnavgen.text import count
from socnavgen.verify.models import Expectation, Finding, VerifySettings
from socnavgen.verify.signals import Signals, aside
from socnavgen.verify.windows import held_within


def _finding(exp: Expectation, passed: bool, evidence: str, *, time: float | None = None,
             distance: float | None = None, human: str | None = None) -> Finding:
    return Finding(name=exp.name, kind=exp.kind, passed=passed, evidence=evidence,
                   time=None if time is None else round(float(time), 3),
                   distance=None if distance is None else round(float(distance), 2),
                   human=human if human is not None else exp.human, node=exp.node, source=exp.source)


def _robot_human_distance(trace: Trace, i: int) -> np.ndarray:
    return contact.lengths(trace.robot[:, :2] - trace.humans[:, i, :2])


def node_steps(trace: Trace, i: int, node: str, message: int | None) -> np.ndarray:
    """(T,) steps on which human i's `node` ran (actions) or succeeded (conditions). A gesture node with a
    message counts only where that message is really shown (human's gesture, or the robot's for
    RobotSays): executing MakeGesture(0) is not "saying WAIT"."""
    if node == "MakeGesture":
        gest = np.asarray(trace.human_gesture[:, i])
        return gest == message if message is not None else gest != 0
    steps = trace.executed(i, node) | trace.fired(i, node)
    if node == "RobotSays" and message is not None:
        steps = steps & (np.asarray(trace.robot_gesture) == message)
    return steps


def _label(node: str, message: int | None) -> str:
    if node == "MakeGesture":
        return f"MakeGesture({HUMAN_GESTURES.get(message, message)})" if message is not None \
            else "MakeGesture(any gesture)"
    if node == "RobotSays" and message is not None:
        return f"RobotSays({ROBOT_GESTURES.get(message, message)})"
    return node


def _never(trace: Trace, i: int, node: str, label: str) -> str:
    name = trace.human_names[i]
    spec = LIBRARY.get(node)
    verb = "never succeeded" if spec is not None and spec.kind == "condition" else "never ran"
    text = f"{name}: {label} {verb}"
    if node not in trace.node_names and node != "MakeGesture":
        text += " (the simulator recorded no such node)"
    if node == "RobotSays":
        said = sorted({ROBOT_GESTURES.get(int(g), str(g)) for g in np.unique(trace.robot_gesture) if g != 0})
        text += f"; the robot's gestures were {said or 'none'}"
    acts = trace.action[:, i]
    if (acts >= 0).any():
        counts = np.bincount(acts[acts >= 0], minlength=len(trace.node_names))
        text += f"; it mostly ran {trace.node_names[int(np.argmax(counts))]}"
    return text


def _one(exp: Expectation, trace: Trace, i: int, settings: VerifySettings) -> tuple[Finding, bool]:
    """(finding, failed because the action preceded its cause)."""
    node = exp.node or ""
    name = trace.human_names[i]
    steps = node_steps(trace, i, node, exp.message)
    label = _label(node, exp.message)
    dist = _robot_human_distance(trace, i)
    if exp.kind == "gives_way_while_passing":
        passing = exp.within if exp.within is not None else settings.passing
        steps = steps & (dist <= passing)
        label += f" with the robot within {passing:g} m"
        if steps.any():  # the node ran: the body must be out of the robot's way within the reaction time after
            out = aside(Signals(trace), name)
            soon = max(1, int(round(settings.reaction_seconds / trace.dt)))
            later = held_within(out, soon, ahead=True)
            if not (steps & later).any():
                k = int(np.argmax(steps))
                return _finding(exp, False, f"{name}: {label} from t={trace.t[k]:.2f} s, but its body never got "
                                            f"out of the robot's way within {settings.reaction_seconds:g} s after it "
                                            "(a node that ran is no giving way)", time=trace.t[k], distance=dist[k],
                                human=name), False
            steps = steps & later
    if not steps.any():
        return _finding(exp, False, _never(trace, i, node, label), human=name), False
    k = int(np.argmax(steps))
    for gate, message in exp.caused_by:
        cause = node_steps(trace, i, gate, message)
        if not cause[: k + 1].any():
            first = f"first at t={trace.t[int(np.argmax(cause))]:.1f} s" if cause.any() else "never"
            return _finding(exp, False, f"{name}: {label} first at t={trace.t[k]:.2f} s, before its cause "
                                        f"{_label(gate, message)} held ({first})", time=trace.t[k],
                            distance=dist[k], human=name), True
    return _finding(exp, True, f"{name}: {label} first at t={trace.t[k]:.2f} s (robot {dist[k]:.2f} m away), "
                               f"{count(int(steps.sum()), 'step')}", time=trace.t[k], distance=dist[k], human=name), False


def evaluate(expectations: list[Expectation], trace: Trace,
             settings: VerifySettings | None = None) -> list[tuple[Finding, bool]]:
    """Judge every tree expectation: (finding, the failure is a reaction before its cause)."""
    settings = settings or VerifySettings()
    out: list[tuple[Finding, bool]] = []
    for exp in expectations:
        if trace.steps == 0:
            out.append((_finding(exp, False, "the trace is empty"), False))
            continue
        if not exp.node:
            out.append((_finding(exp, False, f"cannot check: {exp.detail or 'no node given'}"), False))
            continue
        if exp.human is None:
            cands = list(range(len(trace.human_names)))
        elif exp.human in trace.human_names:
            cands = [trace.human_names.index(exp.human)]
        else:
            out.append((_finding(exp, False, f"{exp.human} is not in the trace"), False))
            continue
        if not cands:
            out.append((_finding(exp, False, "the trace has no humans"), False))
            continue
        results = [_one(exp, trace, i, settings) for i in cands]
        best = next((r for r in results if r[0].passed), results[0])
        out.append((best[0].model_copy(update={"name": exp.name}), best[1]))
    return out
