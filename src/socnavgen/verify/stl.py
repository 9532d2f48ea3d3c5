"""Signal temporal logic on a trace, monitored offline with rtamt (discrete time, seconds as the time
unit), giving the robustness of a formula: how far from passing, in the unit of the signals that
decide it (> 0 passes, < 0 fails).

A formula names signals of verify/signals.py and uses rtamt's operators (always, eventually,
historically, once, until, since, implies, and, or, not; bounds in seconds: eventually[0:5]).
Formulas from spec.json are untrusted: length-limited, one expression only (no declarations or
assignments), and every identifier must be a known signal of the run.
"""

from __future__ import annotations

import logging
import re
import warnings
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from functools import lru_cache
from typing import Any

import numpy as np

from socnavgen.bodies import PERSON_RADIUS, ROBOT_RADIUS
from socnavgen.verify import stl_numpy
from socnavgen.verify.signals import Signals, UnknownSignal

MAX_FORMULA_CHARS = 1000
MAX_NESTING = 24  # parentheses or temporal operators: rtamt's parser recurses on each level
_TEMPORAL = re.compile(r"\b(?:always|eventually|historically|once|until|since|unless|next|prev|not)\b")
OPERATORS = frozenset({
    "not", "or", "and", "iff", "implies", "xor", "rise", "fall", "always", "eventually", "until", "unless",
    "historically", "once", "since", "next", "prev", "true", "false", "abs", "sqrt", "exp", "pow",
    "s", "ms", "us", "ns", "ps"})
_IDENT = re.compile(r"(?<![\w.])[A-Za-z_][A-Za-z0-9_]*")
_FORBIDDEN = re.compile(r"[;@{}]|(?<![<>=!])=(?!=)")
_OUT = "rob"  # the monitored output variable
_PREFIX = f"{_OUT} = "


class FormulaError(ValueError):
    """A formula that cannot be monitored, with a message saying what to change."""


@dataclass(frozen=True)
class Verdict:
    robustness: float  # at t = 0: > 0 satisfied, < 0 violated
    series: np.ndarray  # robustness of the formula evaluated from each step on

    @property
    def passed(self) -> bool:
        return self.robustness > 0


def formula_signals(formula: str) -> list[str]:
    """The signal names a formula uses, in order of first appearance."""
    seen: dict[str, None] = {}
    for name in _IDENT.findall(formula):
        if name not in OPERATORS:
            seen.setdefault(name, None)
    return list(seen)


def _nesting(formula: str) -> int:
    depth = deepest = 0
    for ch in formula:
        if ch == "(":
            depth += 1
            deepest = max(deepest, depth)
        elif ch == ")":
            depth -= 1
    return deepest


def check_formula(formula: str, signals: Signals) -> list[str]:
    """Raise FormulaError unless the formula is short, a single expression and names only known signals;
    return the signal names it uses."""
    names = list(_checked_text(formula))
    for name in names:
        try:
            signals.get(name)
        except UnknownSignal as exc:
            raise FormulaError(str(exc)) from None
    return names


@lru_cache(maxsize=1024)
def _checked_text(formula: str) -> tuple[str, ...]:
    """The checks of check_formula that read the text alone, kept per formula (a campaign checks the same
    few on every episode; a refused formula is not kept and is refused again, with the same message)."""
    if not formula or not formula.strip():
        raise FormulaError("the formula is empty")
    if len(formula) > MAX_FORMULA_CHARS:
        raise FormulaError(f"the formula has {len(formula)} characters (at most {MAX_FORMULA_CHARS}); split it into "
                           "several criteria")
    depth = max(_nesting(formula), len(_TEMPORAL.findall(formula)))
    if depth > MAX_NESTING:
        raise FormulaError(f"the formula nests {depth} levels deep or has as many temporal operators (at most "
                           f"{MAX_NESTING}); split it into several "
                           "criteria")
    if _FORBIDDEN.search(formula):
        raise FormulaError("a formula is one expression: no ';', '=', '@', '{' or '}' (compare with ==, <=, >=)")
    names = formula_signals(formula)
    if not names:
        raise FormulaError("the formula names no signal")
    return tuple(names)


@lru_cache(maxsize=1)
def _rtamt() -> Any:
    """The rtamt module, imported once (its antlr runtime imports the deprecated typing.io)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        import rtamt

    return rtamt


@contextmanager
def _quiet_root_logger() -> Iterator[None]:
    """rtamt warns on the root logger (implicit declarations): silenced around what calls into it."""
    root = logging.getLogger()
    level = root.level
    root.setLevel(logging.ERROR)
    try:
        yield
    finally:
        root.setLevel(level)


def monitor(formula: str, signals: Signals) -> Verdict:
    """Robustness of `formula` over the whole trace (FormulaError for bad formulas)."""
    rtamt = _rtamt()
    names = check_formula(formula, signals)
    t = signals.t
    if len(t) == 0:
        raise FormulaError("the trace is empty")
    dt = float(signals.trace.dt) if signals.trace.dt > 0 else float(np.median(np.diff(t))) if len(t) > 1 else 1.0
    try:
        spec = _parsed(formula, tuple(names), dt)
        try:  # rtamt's semantics with numpy, whole trace at once; rtamt itself for what it does not cover
            series = stl_numpy.evaluate(spec, {name: signals.get(name) for name in names})
        except stl_numpy.NotSupported:
            data = {"time": [float(x) for x in t]}
            data.update({name: [float(v) for v in signals.get(name)] for name in names})
            with _quiet_root_logger():
                series = np.array([float(v) for _, v in spec.evaluate(data)], dtype=float)
    except rtamt.RTAMTException as exc:
        raise FormulaError(_readable(str(exc))) from None
    except (ValueError, ArithmeticError) as exc:  # rtamt on e.g. eventually[2:1] (an empty window), x / 0
        raise FormulaError(f"the formula cannot be evaluated on this trace ({exc}); check that every "
                           "interval [a:b] has a <= b and that nothing is divided by zero") from None
    except RecursionError:  # pragma: no cover - MAX_NESTING keeps formulas far from this
        raise FormulaError(f"the formula is too deeply nested (at most {MAX_NESTING} levels)") from None
    return Verdict(robustness=float(series[0]) if len(series) else float("-inf"), series=series)


@lru_cache(maxsize=256)
def _parsed(formula: str, names: tuple[str, ...], dt: float) -> Any:
    """A parsed rtamt specification, kept per formula: parsing costs about as much as evaluating, and a
    campaign checks the same few formulas on every episode (offline `evaluate` keeps no state between
    calls: the same data gives the same robustness)."""
    rtamt = _rtamt()
    with _quiet_root_logger():
        spec = rtamt.StlDiscreteTimeSpecification()
        for name in names:
            spec.declare_var(name, "float")
        spec.declare_var(_OUT, "float")
        spec.set_sampling_period(dt, "s", 0.1)
        spec.spec = _PREFIX + formula
        spec.parse()
    return spec


def _readable(message: str) -> str:
    """rtamt's error, with the column counted in the user's formula (we prefix `rob = `)."""
    message = message.replace("RTAMT Exception: ", "").strip()

    def shift(m: re.Match) -> str:
        return f"column {max(1, int(m[2]) - len(_PREFIX) + 1)}"

    return "STL syntax: " + re.sub(r"(\d+):(\d+):", lambda m: shift(m) + ":", message, count=1)


def formula_problems(formula: str, humans: list[str], places: list[str]) -> list[str]:
    """Problems of a formula before any simulation (for stage-1 checks of spec.json): syntax, length, and
    signal names against the run's humans and places (encounter ids, goal, node_<id>). [] when fine."""
    from socnavgen.sim.trace import Trace
    from socnavgen.sim.world import empty_room

    n = len(humans)
    trace = Trace(dt=1.0, t=np.array([0.0, 1.0]), robot=np.zeros((2, 6)), humans=np.ones((2, n, 6)),
                  human_names=list(humans), group_ids=[-1] * n, human_radii=np.full(n, PERSON_RADIUS), robot_radius=ROBOT_RADIUS,
                  node_names=[], action=np.full((2, n), -1, np.int16), succeeded=np.zeros((2, n), np.int64),
                  human_gesture=np.zeros((2, n), np.int8), robot_gesture=np.zeros(2, np.int8),
                  behavior_state=np.zeros((2, n), np.int8), robot_goal=(0.0, 0.0))
    signals = Signals(trace, world=empty_room(4.0, 4.0, 0.1), places=dict.fromkeys(places, (0.0, 0.0)))
    try:
        monitor(formula, signals)
    except FormulaError as exc:
        return [str(exc)]
    return []
