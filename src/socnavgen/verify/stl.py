"""Signal temporal logic on a trace with rtamt's discrete-time semantics (seconds as the time unit), giving
the robustness of a formula: how far from passing, in the unit of the signals that decide it (> 0 passes,
< 0 fails). rtamt parses and defines the semantics; verify/stl_numpy.py evaluates every operator over the
whole trace in linear time and memory, whatever the formula's bounds.

A formula names signals of verify/signals.py and uses rtamt's operators (always, eventually,
historically, once, until, since, implies, and, or, not; bounds in seconds: eventually[0:5]).
Formulas from spec.json are untrusted: length-limited, one expression only (no declarations or
assignments), every identifier a known signal of the run, and at most MAX_STL_CELLS of work; stage 1
refuses intervals no episode can hold (formula_problems).
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
from socnavgen.limits import MAX_SIM_SECONDS
from socnavgen.verify import stl_numpy
from socnavgen.verify.signals import Signals, UnknownSignal

MAX_FORMULA_CHARS = 1000  # an authored (`stl`) formula
MAX_NESTING = 24  # parentheses or temporal operators: rtamt's parser recurses on each level
# a criterion kind's formula, written here, grows with the people it names (a `meets` of a team of four came to
# 1001 characters and 12 temporal operators): its length is bounded by the spec's people, its nesting by the kind,
# so only the parentheses' depth and MAX_STL_CELLS guard it
MAX_COMPILED_CHARS = 20_000
MAX_STL_CELLS = 40_000_000  # operators x trace steps: one float series per operator (at most ~320 MB)
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


def check_formula(formula: str, signals: Signals, *, authored: bool = True) -> list[str]:
    """Raise FormulaError unless the formula is short, a single expression and names only known signals;
    return the signal names it uses. `authored` False: a criterion kind's own formula (MAX_COMPILED_CHARS)."""
    names = list(_checked_text(formula, authored))
    for name in names:
        try:
            signals.get(name)
        except UnknownSignal as exc:
            raise FormulaError(str(exc)) from None
    return names


@lru_cache(maxsize=1024)
def _checked_text(formula: str, authored: bool = True) -> tuple[str, ...]:
    """The checks of check_formula that read the text alone, kept per formula (a campaign checks the same
    few on every episode; a refused formula is not kept and is refused again, with the same message)."""
    if not formula or not formula.strip():
        raise FormulaError("the formula is empty")
    most = MAX_FORMULA_CHARS if authored else MAX_COMPILED_CHARS
    if len(formula) > most:
        raise FormulaError(f"the formula has {len(formula)} characters (at most {most}); split it into "
                           "several criteria")
    depth = max(_nesting(formula), len(_TEMPORAL.findall(formula)) if authored else 0)
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


def monitor(formula: str, signals: Signals, *, authored: bool = True) -> Verdict:
    """Robustness of `formula` over the whole trace (FormulaError for bad formulas). Work and memory are linear
    in the trace whatever the formula's bounds (verify/stl_numpy.py); a formula too large for the trace is
    refused before any work (MAX_STL_CELLS). `authored` False: a criterion kind's own formula."""
    rtamt = _rtamt()
    names = check_formula(formula, signals, authored=authored)
    t = signals.t
    if len(t) == 0:
        raise FormulaError("the trace is empty")
    dt = _period(signals)
    try:
        spec = _parsed(formula, tuple(names), dt)
        nodes = stl_numpy.count_nodes(spec)
        if nodes * len(t) > MAX_STL_CELLS:
            raise FormulaError(f"the formula has {nodes} operators and signals: too many to monitor on a trace of "
                               f"{len(t)} steps (at most {MAX_STL_CELLS // len(t)}); split it into several criteria")
        series = stl_numpy.evaluate(spec, {name: signals.get(name) for name in names})
    except stl_numpy.NotSupported as exc:
        raise FormulaError(_not_supported(str(exc))) from None
    except rtamt.RTAMTException as exc:
        raise FormulaError(_readable(str(exc))) from None
    except (ValueError, ArithmeticError) as exc:  # x / 0, sqrt(-1), exp(1000) in the formula's arithmetic
        raise FormulaError(f"the formula cannot be evaluated on this trace ({exc}); check that nothing is divided "
                           "by zero and that sqrt / exp / pow get values they accept") from None
    except RecursionError:  # pragma: no cover - MAX_NESTING keeps formulas far from this
        raise FormulaError(f"the formula is too deeply nested (at most {MAX_NESTING} levels)") from None
    return Verdict(robustness=float(series[0]) if len(series) else float("-inf"), series=series)


def _period(signals: Signals) -> float:
    t = signals.t
    return float(signals.trace.dt) if signals.trace.dt > 0 else float(np.median(np.diff(t))) if len(t) > 1 else 1.0


def _not_supported(what: str) -> str:
    if what.startswith("bounds"):
        return f"an interval {what[7:]} (in samples) ends before it begins; write every interval [a:b] with a <= b"
    if "NaN" in what:
        return ("the formula is undefined on this trace: it subtracts or compares infinities (e.g. arithmetic on "
                "a bounded operator near the end of the trace); compare each part with a number instead")
    return f"the formula uses {what}, which the verifier cannot monitor"


def formula_bounds(formula: str, dt: float) -> list[float]:
    """The end of every interval of the formula's timed operators, in seconds (after rtamt's conversion at
    period `dt`). FormulaError when the formula does not parse or a bound is not a multiple of `dt`."""
    rtamt = _rtamt()
    try:
        spec = _parsed(formula, tuple(formula_signals(formula)), dt)
        if not spec.set_ast_flag:
            spec.offline_interpreter.set_ast(spec.ast)
            spec.set_ast_flag = True
        convert = spec.offline_interpreter.time_unit_transformer
        stack, out = [spec.ast.specs[-1]], []
        while stack:
            node = stack.pop()
            if hasattr(node, "begin") and hasattr(node, "end"):
                out.append(convert(node)[1] * dt)
            stack.extend(getattr(node, "children", []) or [])
    except rtamt.RTAMTException as exc:
        raise FormulaError(_readable(str(exc))) from None
    return out


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
    if "multiple of the sampling period" in message:
        return "every interval bound must be a multiple of the simulation step (e.g. [0:0.5] at 0.05 s steps)"

    def shift(m: re.Match) -> str:
        return f"column {max(1, int(m[2]) - len(_PREFIX) + 1)}"

    return "STL syntax: " + re.sub(r"(\d+):(\d+):", lambda m: shift(m) + ":", message, count=1)


def formula_problems(formula: str, humans: list[str], places: list[str], *, dt: float | None = None,
                     horizon: float = MAX_SIM_SECONDS) -> list[str]:
    """Problems of a formula before any simulation (for stage-1 checks of spec.json): syntax, length, signal
    names against the run's humans and places (encounter ids, goal, node_<id>), and intervals that no episode
    can hold (longer than `horizon` seconds) or that the simulator's step `dt` (its default when None) cannot
    sample. [] when fine."""
    from socnavgen.sim import empty_room
    from socnavgen.sim.trace import Trace

    if dt is None:
        from socnavgen.sim import SimConfig

        dt = SimConfig().dt
    n = len(humans)
    trace = Trace(dt=dt, t=np.array([0.0, dt]), robot=np.zeros((2, 6)), humans=np.ones((2, n, 6)),
                  human_names=list(humans), group_ids=[-1] * n, human_radii=np.full(n, PERSON_RADIUS), robot_radius=ROBOT_RADIUS,
                  node_names=[], action=np.full((2, n), -1, np.int16), succeeded=np.zeros((2, n), np.int64),
                  human_gesture=np.zeros((2, n), np.int8), robot_gesture=np.zeros(2, np.int8),
                  behavior_state=np.zeros((2, n), np.int8), robot_goal=(0.0, 0.0))
    signals = Signals(trace, world=empty_room(4.0, 4.0, 0.1), places=dict.fromkeys(places, (0.0, 0.0)))
    try:
        monitor(formula, signals)
        longest = max(formula_bounds(formula, dt), default=0.0)
    except FormulaError as exc:
        return [str(exc)]
    if longest > horizon:
        return [f"the formula waits up to {longest:g} s, longer than any episode can last (at most {horizon:g} s); "
                f"bound its intervals by the scenario's length"]
    return []
