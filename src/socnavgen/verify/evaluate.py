"""Judge each expectation on a simulation trace and say why, with the time and distance of the evidence."""

from __future__ import annotations

import itertools
import math

import numpy as np

from socnavgen.bt.library import HUMAN_GESTURES, LIBRARY
from socnavgen.sim.trace import VX, VY, Trace
from socnavgen.verify.models import Expectation, Finding, VerifySettings

DEFAULT_GOAL_RADIUS = 0.5  # m, when neither the settings nor the trace give one
STOPPED_SPEED = 0.05  # m/s: the robot counts as standing still below this


def _finding(exp: Expectation, passed: bool, evidence: str, *, time: float | None = None,
             distance: float | None = None, human: str | None = None) -> Finding:
    return Finding(name=exp.name, kind=exp.kind, passed=passed, evidence=evidence,
                   time=None if time is None else round(float(time), 3),
                   distance=None if distance is None else round(float(distance), 2),  # cm, as in the evidence text
                   human=human if human is not None else exp.human, node=exp.node, source=exp.source,
                   stage=exp.stage)


def _human_index(trace: Trace, name: str) -> int | None:
    return trace.human_names.index(name) if name in trace.human_names else None


def _robot_human_distance(trace: Trace, i: int) -> np.ndarray:
    return np.linalg.norm(trace.robot[:, :2] - trace.humans[:, i, :2], axis=1)


def _meets_one(exp: Expectation, trace: Trace, i: int, settings: VerifySettings) -> Finding:
    within = exp.within if exp.within is not None else settings.distance
    name = trace.human_names[i]
    dist = _robot_human_distance(trace, i)
    if exp.point is not None:
        midpoint = 0.5 * (trace.robot[:, :2] + trace.humans[:, i, :2])
        from_point = np.linalg.norm(midpoint - np.asarray(exp.point), axis=1)
        at_point = from_point <= settings.near
    else:
        from_point = np.zeros(trace.steps)
        at_point = np.ones(trace.steps, dtype=bool)
    where = f"interaction point {exp.point_id}" if exp.point_id else "anywhere"
    ok = (dist <= within) & at_point
    if ok.any():
        k = int(np.argmin(np.where(ok, dist, np.inf)))
        first = int(np.argmax(ok))
        place = f", {from_point[k]:.1f} m from {where}" if exp.point is not None else ""
        return _finding(exp, True, f"{name} met at t={trace.t[first]:.1f} s; closest {dist[k]:.2f} m at "
                                   f"t={trace.t[k]:.1f} s{place}", time=trace.t[k], distance=dist[k], human=name)
    k = int(np.argmin(dist))
    reason = (f"closest approach {dist[k]:.2f} m at t={trace.t[k]:.1f} s (needs <= {within:g} m)")
    if exp.point is not None:
        near_k = np.where(at_point, dist, np.inf)
        reason += f", {from_point[k]:.1f} m from {where} (needs <= {settings.near:g} m)"
        if np.isfinite(near_k).any():
            j = int(np.argmin(near_k))
            reason += f"; near the point the closest was {dist[j]:.2f} m at t={trace.t[j]:.1f} s"
        robot_to_point = np.linalg.norm(trace.robot[:, :2] - np.asarray(exp.point), axis=1)
        reason += f"; the robot came within {robot_to_point.min():.1f} m of the point"
    return _finding(exp, False, reason, time=trace.t[k], distance=dist[k], human=name)


def _candidates(exp: Expectation, trace: Trace) -> list[int] | str:
    """Trace indices of the humans an expectation is about, or an error text."""
    if exp.human is None:
        return list(range(len(trace.human_names)))
    i = _human_index(trace, exp.human)
    return [i] if i is not None else f"{exp.human} is not in the trace"


def check_meets_human(exp: Expectation, trace: Trace, settings: VerifySettings) -> Finding:
    cands = _candidates(exp, trace)
    if isinstance(cands, str) or not cands:
        return _finding(exp, False, cands or "the trace has no humans")
    results = [_meets_one(exp, trace, i, settings) for i in cands]
    passed = [r for r in results if r.passed]
    best = min(passed or results, key=lambda r: r.distance if r.distance is not None else math.inf)
    return best.model_copy(update={"name": exp.name})


def _executes_one(exp: Expectation, trace: Trace, i: int, settings: VerifySettings) -> Finding:
    node = exp.node or ""
    name = trace.human_names[i]
    steps = trace.executed(i, node) | trace.fired(i, node)
    label = node
    if exp.message is not None:
        shown = trace.human_gesture[:, i] == exp.message
        steps = steps | shown if node in trace.node_names else shown
        label = f"{node}({HUMAN_GESTURES.get(exp.message, exp.message)})"
    elif node == "MakeGesture":  # a card asking for "a gesture": MakeGesture(0) (stop gesturing) does not count
        steps = trace.human_gesture[:, i] != 0
        label = "MakeGesture(any gesture)"
    dist = _robot_human_distance(trace, i)
    if exp.kind == "gives_way_while_passing":
        passing = exp.within if exp.within is not None else settings.passing
        close = steps & (dist <= passing)
        if close.any():
            k = int(np.argmax(close))
            return _finding(exp, True, f"{name} ran {label} on {int(steps.sum())} steps; first with the robot "
                                       f"{dist[k]:.2f} m away at t={trace.t[k]:.1f} s", time=trace.t[k],
                            distance=dist[k], human=name)
        if steps.any():
            k = int(np.argmin(np.where(steps, dist, np.inf)))
            return _finding(exp, False, f"{name} ran {label} on {int(steps.sum())} steps but never with the robot "
                                        f"within {passing:g} m (closest {dist[k]:.2f} m at t={trace.t[k]:.1f} s)",
                            time=trace.t[k], distance=dist[k], human=name)
        return _finding(exp, False, _never(trace, i, node, label), human=name)
    if steps.any():
        k = int(np.argmax(steps))
        return _finding(exp, True, f"{name}: {label} first at t={trace.t[k]:.1f} s (robot {dist[k]:.2f} m away), "
                                   f"{int(steps.sum())} steps", time=trace.t[k], distance=dist[k], human=name)
    return _finding(exp, False, _never(trace, i, node, label), human=name)


def _never(trace: Trace, i: int, node: str, label: str) -> str:
    name = trace.human_names[i]
    spec = LIBRARY.get(node)
    verb = "never succeeded" if spec is not None and spec.kind == "condition" else "never ran"
    text = f"{name}: {label} {verb}"
    if node not in trace.node_names:
        text += " (the simulator recorded no such node)"
    if node == "RobotSays":
        said = sorted({int(g) for g in np.unique(trace.robot_gesture) if g != 0})
        text += f"; the robot's gestures were {said or 'none'}"
    acts = trace.action[:, i]
    if (acts >= 0).any():
        counts = np.bincount(acts[acts >= 0], minlength=len(trace.node_names))
        top = trace.node_names[int(np.argmax(counts))]
        text += f"; it mostly ran {top}"
    return text


def check_executes(exp: Expectation, trace: Trace, settings: VerifySettings) -> Finding:
    if not exp.node:
        return _finding(exp, False, f"cannot check: {exp.detail or 'no node given'}")
    cands = _candidates(exp, trace)
    if isinstance(cands, str) or not cands:
        return _finding(exp, False, cands or "the trace has no humans")
    results = [_executes_one(exp, trace, i, settings) for i in cands]
    return next((r for r in results if r.passed), results[0]).model_copy(update={"name": exp.name})


def check_group_together(exp: Expectation, trace: Trace, settings: VerifySettings) -> Finding:
    names = [n for n in (exp.human or "").split(",") if n]
    idx = [_human_index(trace, n) for n in names]
    if len(names) < 2 or any(i is None for i in idx):
        return _finding(exp, False, f"cannot check: group members {names or 'unknown'} not all in the trace")
    spread = exp.within if exp.within is not None else settings.group_spread
    pair_dist = np.stack([np.linalg.norm(trace.humans[:, a, :2] - trace.humans[:, b, :2], axis=1)
                          for a, b in itertools.combinations(idx, 2)], axis=1)
    widest = pair_dist.max(axis=1)
    share = float(np.mean(widest <= spread)) if trace.steps else 0.0
    k = int(np.argmax(widest))
    text = (f"{', '.join(names)} within {spread:g} m of each other {share:.0%} of the time "
            f"(needs {settings.group_fraction:.0%}); widest {widest[k]:.2f} m at t={trace.t[k]:.1f} s")
    return _finding(exp, share >= settings.group_fraction, text, time=trace.t[k], distance=widest[k],
                    human=",".join(names))


def check_robot_reaches_goal(exp: Expectation, trace: Trace, settings: VerifySettings) -> Finding:
    goal = exp.point if exp.point is not None else trace.robot_goal
    if goal is None:
        return _finding(exp, False, "no robot goal is known (paths.json and trace have none)")
    radius = exp.within or settings.goal_radius or float(trace.meta.get("robot_goal_radius", DEFAULT_GOAL_RADIUS))
    to_goal = np.linalg.norm(trace.robot[:, :2] - np.asarray(goal), axis=1)
    reached = to_goal <= radius
    if reached.any():
        k = int(np.argmax(reached))
        return _finding(exp, True, f"reached at t={trace.t[k]:.1f} s ({to_goal[k]:.2f} m from the goal)",
                        time=trace.t[k], distance=to_goal[k])
    return _finding(exp, False, _why_not_reached(trace, to_goal, radius), time=trace.t[-1], distance=to_goal[-1])


def _why_not_reached(trace: Trace, to_goal: np.ndarray, radius: float) -> str:
    text = f"ended {to_goal[-1]:.2f} m from the goal (radius {radius:g} m; closest {to_goal.min():.2f} m)"
    if trace.end_reason:
        text += f"; simulation ended by {trace.end_reason}"
    speed = np.linalg.norm(trace.robot[:, VX:VY + 1], axis=1)
    moving = np.nonzero(speed >= STOPPED_SPEED)[0]
    stalled_from = int(moving[-1]) + 1 if len(moving) else 0
    if stalled_from < trace.steps - 1:
        k = stalled_from
        stalled = float(trace.t[-1] - trace.t[k])
        if trace.humans.shape[1]:
            dist = np.linalg.norm(trace.humans[k, :, :2] - trace.robot[k, :2], axis=1)
            j = int(np.argmin(dist))
            text += (f"; the robot stood still for the last {stalled:.1f} s, from t={trace.t[k]:.1f} s, "
                     f"{dist[j]:.2f} m from {trace.human_names[j]}")
            if dist[j] < 2.0:
                text += " (blocked)"
        else:
            text += f"; the robot stood still for the last {stalled:.1f} s"
    return text


def check_no_collision(exp: Expectation, trace: Trace, settings: VerifySettings) -> Finding:
    """Discs overlapping by more than `overlap` metres: the robot ran into a person (or was run into)."""
    if not trace.humans.shape[1]:
        return _finding(exp, True, "no humans in the scenario")
    centre = np.linalg.norm(trace.humans[:, :, :2] - trace.robot[:, None, :2], axis=2)
    gap = centre - trace.robot_radius - np.asarray(trace.human_radii)[None, :]
    hits = gap < -settings.overlap
    if not hits.any():
        k, j = np.unravel_index(int(np.argmin(gap)), gap.shape)
        return _finding(exp, True, f"closest gap {gap[k, j]:.2f} m to {trace.human_names[j]} at t={trace.t[k]:.1f} s",
                        time=trace.t[k], distance=float(gap[k, j]), human=trace.human_names[j])
    k = int(np.argmax(hits.any(axis=1)))
    j = int(np.argmin(gap[k]))
    steps = int(hits.any(axis=1).sum())
    finding = _finding(exp, False, f"robot and {trace.human_names[j]} overlap by {-gap[k, j]:.2f} m at t={trace.t[k]:.1f} s "
                    f"({steps} steps with a collision, {steps * trace.dt:.1f} s)", time=trace.t[k],
                    distance=float(gap[k, j]), human=trace.human_names[j])
    finding.required = settings.collisions_fail
    return finding


CHECKS = {
    "meets_human": check_meets_human,
    "executes": check_executes,
    "gives_way_while_passing": check_executes,
    "group_together": check_group_together,
    "robot_reaches_goal": check_robot_reaches_goal,
    "no_collision": check_no_collision,
}


def evaluate(expectations: list[Expectation], trace: Trace, settings: VerifySettings | None = None) -> list[Finding]:
    settings = settings or VerifySettings()
    if trace.steps == 0:
        return [_finding(e, False, "the trace is empty") for e in expectations]
    return [CHECKS[e.kind](e, trace, settings) for e in expectations]
