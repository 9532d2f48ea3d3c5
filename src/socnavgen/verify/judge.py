"""Judge one trace: monitor every criterion (STL robustness + evidence), run the tree checks, blame every
failure, and assemble the VerifyReport. Pure: everything comes in as objects, nothing is read or written."""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import partial
from typing import Any

import numpy as np

from socnavgen.run.models import PathPlan
from socnavgen.run.spec import Criterion, ScenarioSpec
from socnavgen.sim.trace import Trace
from socnavgen.verify.blame import blame_criterion, spec_problem
from socnavgen.verify.blame_tree import blame_tree_check
from socnavgen.verify.criteria import Compiled, compile_criterion
from socnavgen.verify.derive import derive_spec, encounter_places, with_implied
from socnavgen.verify.evaluate import evaluate, node_steps
from socnavgen.verify.evidence import evidence
from socnavgen.verify.expectations import tree_checks
from socnavgen.verify.models import Expectation, Finding, Source, VerifyReport, VerifySettings
from socnavgen.verify.signals import Signals
from socnavgen.verify.stl import FormulaError, monitor
from socnavgen.verify.thresholds import DEFAULT_GOAL_RADIUS, MIN_RUN_SECONDS
from socnavgen.verify.way_end import RoomEnd, room_end_findings, room_ends
from socnavgen.verify.way_in import WayIn, way_in_findings, ways_in
from socnavgen.verify.windows import encounter_window
from socnavgen.verify.witness import held_at_the_start


def _title(c: Criterion) -> str:
    if c.text:
        return c.text
    who = c.human or ", ".join(c.humans) or "robot"
    return f"{c.id}: {c.kind.replace('_', ' ')} ({who}{', ' + c.encounter if c.encounter else ''})"


def _with_blame(finding: Finding, blame: str, human: str | None, reason: str) -> Finding:
    return finding.model_copy(update={"blame": blame, "blame_human": human, "blame_reason": reason,
                                      "stage": blame if blame in ("paths", "behaviors") else None})


@dataclass
class Prepared:
    """What judging needs from the run alone (plan, location, spec, trees, card, settings), worked out once
    per run: a campaign keeps it with the LoadedRun and judges every episode's trace with it."""

    used: ScenarioSpec  # spec.json, else the spec derived from paths and card
    judged: list[tuple[Criterion, Source]]
    places: dict[str, tuple[float, float]]  # encounter places
    node_points: dict[str, tuple[float, float]]
    expectations: list[Expectation]
    plan: PathPlan
    location: Any
    derived: bool = False  # no spec.json: criteria derived from the paths and the card
    ways: list[WayIn] = field(default_factory=list)  # each person's planned way into their encounter (verify/way_in.py)
    ends: list[RoomEnd] = field(default_factory=list)  # people whose way ends in a room (verify/way_end.py)
    _compiled: dict[tuple[int, float, float | None], Compiled | FormulaError] = field(default_factory=dict)
    _problems: dict[int, str | None] = field(default_factory=dict)
    _goal: tuple[float, float] | None = None

    def compiled(self, k: int, settings: VerifySettings, goal_radius: float, dt: float | None = None) -> Compiled:
        """compile_criterion of the k-th judged criterion for a trace of step `dt` (FormulaError when it cannot be
        compiled)."""
        key = (k, goal_radius, dt)
        if key not in self._compiled:
            try:
                self._compiled[key] = compile_criterion(self.judged[k][0], self.used, settings, goal_radius, dt)
            except FormulaError as exc:
                self._compiled[key] = exc
        found = self._compiled[key]
        if isinstance(found, FormulaError):
            raise FormulaError(str(found))
        return found

    def problem(self, k: int) -> str | None:
        """spec_problem of the k-th judged criterion (for a spec derived from the paths, about the paths' humans)."""
        if k not in self._problems:
            roster = {h.name for h in self.plan.humans} if self.derived else None
            self._problems[k] = spec_problem(self.judged[k][0], self.used, roster)
        return self._problems[k]

    def plan_goal(self) -> tuple[float, float]:
        """World point of the robot path's last node (the goal of a trace that records none)."""
        if self._goal is None:
            self._goal = tuple(self.location.node_world(self.plan.robot[-1]))
        return self._goal


def prepare(plan: PathPlan, location: Any, spec: ScenarioSpec | None, trees: dict[str, str],
            card_criteria: list[dict] | None, settings: VerifySettings) -> Prepared:
    """The run-only part of `judge`: criteria (spec.json's and the implied ones, else derived), places,
    the location's node points and the tree checks."""
    if spec is None:
        used, judged = derive_spec(plan, location, card_criteria, settings)
    else:
        used, judged = spec, with_implied(spec, settings, len(plan.humans), plan)
    node_points: dict[str, tuple[float, float]] = {}
    ways: list[WayIn] = []
    ends: list[RoomEnd] = []
    if location is not None:
        from socnavgen.location.places import PlaceFinder

        node_points = {n: tuple(location.node_world(n)) for n in location.scene_graph.node_ids()}
        finder = PlaceFinder(location)
        clearance = {n: finder.clearance_m(n) for n in {n for h in plan.humans for n in h.path if n in node_points}}
        ways = ways_in(plan, used, node_points, clearance, authored=spec is not None)
        graph = location.graph
        ends = room_ends(plan, used, graph, lambda n: str(graph.nodes[n].get("type", "")),
                         edge_type=lambda u, v: str(graph.edges[u, v].get("type", "")))
    return Prepared(used=used, judged=judged, places=encounter_places(used, plan, location), node_points=node_points,
                    expectations=tree_checks(plan, trees, card_criteria), plan=plan, location=location,
                    derived=spec is None, ways=ways, ends=ends)


def judge_criterion(c: Criterion, source: Source, spec: ScenarioSpec, plan: PathPlan | None, signals: Signals,
                    settings: VerifySettings, goal_radius: float, *, prepared: Prepared | None = None,
                    index: int = 0) -> Finding:
    """One criterion: compiled, monitored with rtamt, explained, and blamed when it fails. `prepared` (with
    the criterion's `index` in it) keeps the compiled formula and the spec check across traces."""
    base = Finding(name=_title(c), kind=c.kind, passed=False, evidence="", human=c.human, source=source,
                   criterion=c.id, required=not (c.kind == "no_collision" and not settings.collisions_fail))
    try:
        dt = signals.trace.dt
        cc: Compiled = prepared.compiled(index, settings, goal_radius, dt) if prepared is not None else \
            compile_criterion(c, spec, settings, goal_radius, dt)
        base.formula = cc.formula
        verdict = monitor(cc.formula, signals, authored=c.kind == "stl")
    except FormulaError as exc:
        text = f"cannot be monitored: {exc}"
        failed = base.model_copy(update={"evidence": text})
        if "unknown place" in str(exc):
            return _with_blame(failed, "paths", None, "ground the encounter on a scene-graph node")
        return _with_blame(failed, "spec", None, str(exc))
    text, time, distance = evidence(cc, signals)
    problem = prepared.problem(index) if prepared is not None else spec_problem(c, spec)
    robustness = None if problem else round(verdict.robustness, 3)  # a contradictory criterion has no margin
    passed = problem is None and verdict.robustness >= 0
    shown = text if problem is None else f"{text}; {problem}"
    finding = base.model_copy(update={
        "passed": passed, "evidence": shown, "robustness": robustness,
        "time": None if time is None else round(float(time), 3),
        "distance": None if distance is None else round(float(distance), 2)})
    started = held_at_the_start(cc.formula, signals) if passed and c.kind == "stl" and source == "spec" else None
    if started:  # an authored order witnessed by the start positions alone (verify/witness.py)
        return _with_blame(finding.model_copy(update={"passed": False, "evidence": f"{text}; {started}",
                                                      "robustness": None}),
                           "spec", None, "write the order so that it happens during the run: its later event must "
                                         "not already hold where people start (a tighter distance, or a person "
                                         "first away from the place and then at it)")
    if passed:
        return finding
    if problem:
        return _with_blame(finding, "spec", None, problem)
    location, authored = (prepared.location, not prepared.derived) if prepared is not None else (None, True)
    return _with_blame(finding, *blame_criterion(cc, signals, spec, plan, settings.deadlock_seconds, location,
                                                 authored))


def ended_early(trace: Trace, goal: tuple[float, float] | None, goal_radius: float) -> str | None:
    """Why the run ended before anything could happen (shorter than MIN_RUN_SECONDS, e.g. a robot whose goal is
    its start), or None."""
    seconds = float(trace.t[-1] - trace.t[0])
    if seconds >= MIN_RUN_SECONDS:
        return None
    why = f"the run ended after {seconds:.2f} s ({trace.end_reason or 'no reason given'})"
    if goal is not None:
        off = float(((trace.robot[0, 0] - goal[0]) ** 2 + (trace.robot[0, 1] - goal[1]) ** 2) ** 0.5)
        if off <= goal_radius:
            return f"{why}: the robot's goal is where it starts ({off:.2f} m away), so nothing could happen"
    return f"{why}, before anything could happen"


def judge(trace: Trace, *, plan: PathPlan, location: Any, spec: ScenarioSpec | None, trees: dict[str, str],
          card_criteria: list[dict] | None, settings: VerifySettings, run_name: str = "",
          prepared: Prepared | None = None) -> VerifyReport:
    """The whole verdict on a trace. With `spec` its criteria decide and the tree checks are diagnostics;
    without, criteria are derived from the paths and card and the tree checks are required too. `prepared`:
    `prepare` of these very arguments, kept from an earlier trace of the same run."""
    if prepared is None:
        prepared = prepare(plan, location, spec, trees, card_criteria, settings)
    used, judged = prepared.used, prepared.judged
    goal_radius = settings.goal_radius or float((trace.meta or {}).get("robot_goal_radius", DEFAULT_GOAL_RADIUS))
    world_factory = None
    if location is not None:
        from socnavgen.sim import World

        def world_factory() -> World:
            return World.from_location(location)

    places = dict(prepared.places)
    if trace.robot_goal is None and plan.robot and location is not None:
        places["goal"] = prepared.plan_goal()
    signals = Signals(trace, world_factory=world_factory, places=places, node_points=prepared.node_points,
                      goal_radius=goal_radius, windows=partial(encounter_window, spec=used, settings=settings))
    findings: list[Finding] = []
    early = "the trace is empty" if trace.steps == 0 else ended_early(trace, signals.places.get("goal"), goal_radius)
    expectations = prepared.expectations
    if early:  # no verdict about a run in which nothing could happen, only that
        fix = ("give the robot a path whose goal is not its start" if "goal is where it starts" in early
               else "simulate long enough for the scenario to happen")
        findings = [Finding(name=_title(c), kind=c.kind, passed=False, evidence=early, source=src, criterion=c.id,
                            human=c.human, blame="paths", blame_reason=fix, stage="paths") for c, src in judged]
        findings += [Finding(name=e.name, kind=e.kind, passed=False, evidence=early, source=e.source, human=e.human,
                             node=e.node, blame="paths", blame_reason=fix, stage="paths", required=spec is None)
                     for e in expectations]
        expectations = []
    else:
        findings = [judge_criterion(c, src, used, plan, signals, settings, goal_radius, prepared=prepared, index=k)
                    for k, (c, src) in enumerate(judged)]
        findings += way_in_findings(prepared.ways, trace, settings)
        goal = signals.places.get("goal")
        there = trace.end_reason == "robot_goal" or (goal is not None and float(
            np.hypot(trace.robot[-1, 0] - goal[0], trace.robot[-1, 1] - goal[1])) <= goal_radius)
        findings += room_end_findings(prepared.ends, trace, prepared.node_points, there,
                                      world_factory() if prepared.ends and world_factory is not None else None)
    for exp, (finding, before_cause) in zip(expectations, evaluate(expectations, trace, settings), strict=True):
        finding.required = spec is None
        if not finding.passed:
            node, message = _first_missing_cause(trace, exp.node, exp.message, exp.caused_by, finding.human,
                                                 before_cause)
            ran = exp.kind == "gives_way_while_passing" and node == exp.node and not before_cause  # ran, no effect
            finding = _with_blame(finding, *blame_tree_check(node, message, finding.human,
                                                             signals if trace.steps else None, before_cause,
                                                             finding.time if ran else None))
        findings.append(finding)
    findings = _held_up_by_an_unsaid_phrase(findings)
    seconds = float(trace.t[-1] - trace.t[0]) if trace.steps else 0.0
    return VerifyReport(run=run_name, passed=all(f.passed or not f.required for f in findings), findings=findings,
                        settings=settings, spec=spec is not None, trace_steps=trace.steps,
                        trace_seconds=round(seconds, 3), end_reason=trace.end_reason)


def _first_missing_cause(trace: Trace, node: str | None, message: int | None, caused_by: list, human: str | None,
                         before_cause: bool) -> tuple[str | None, int | None]:
    """A node that never ran because a condition gating it never held is blamed like that condition."""
    if before_cause or human not in trace.human_names or not trace.steps:
        return node, message
    i = trace.human_names.index(human)
    for gate, gate_message in caused_by:
        if not node_steps(trace, i, gate, gate_message).any():
            return gate, gate_message
    return node, message


def _held_up_by_an_unsaid_phrase(findings: list[Finding]) -> list[Finding]:
    """A robot held up by someone whose tree waits for a phrase the script never said (its tree check is blamed on
    the robot's script) is the script's to fix, also where no spec names the phrase (rules D1 and R4 with a spec)."""
    waiting = {f.human: f for f in findings if not f.passed and f.node and f.blame == "robot_script" and f.human}
    out = []
    for f in findings:
        cause = waiting.get(f.blame_human) if f.blame_human else None
        if (not f.passed and cause is not None and f.blame == "behaviors"
                and f.kind in ("robot_reaches_goal", "no_deadlock")):
            f = _with_blame(f, "robot_script", None, f"{f.blame_human} waits for the robot's phrase, which it never "
                                                      f"said ({cause.name}): {cause.blame_reason}")
        out.append(f)
    return out
