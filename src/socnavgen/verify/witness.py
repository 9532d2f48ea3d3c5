"""The moment that decides an STL formula, and what its signals were then: the evidence of an `stl` criterion.

Per-signal minima mislead (round 13, warehouse_10: `always (dist < 2.5 implies speed > 0.3)` failed with the
evidence "speed_human1 min 0.00 m/s at t=0.0 s", a moment the implication held vacuously). The robustness
semantics says which step decides each operator (verify/stl_numpy.py evaluates the same series); this module
walks down the formula from t = 0 to that step:

- always: its first failing step (passing: its tightest one); eventually: its first holding step (failing: the
  step it came closest);
- `a implies b` failing: a held there and b did not (then on into b); `and` failing: into the part that failed;
  `or` holding: into the part that held;
- `a until b`: holding, the first step b held; failing, the first step a stopped holding before b held (or b's
  nearest, never holding);
- anything else (since, timed until, comparisons) ends the walk at the step reached.

The evidence names the step and the values of the signals of the part it ended at ("at t=12.3 s, where
dist_human1 < 2.5 held (dist_human1 1.80 m) and speed_human1 > 0.3 did not (speed_human1 0.05 m/s)")."""

from __future__ import annotations

import re
from typing import Any

import numpy as np

from socnavgen.verify import stl_numpy
from socnavgen.verify.signals import Signals, _kind_of
from socnavgen.verify.stl import _parsed, _period, formula_signals

_MAX_SIGNALS = 4  # values shown per part


def _values(names: list[str], s: Signals, k: int) -> str:
    """'dist_human1 1.80 m, speed_human1 0.05 m/s' at step k (0/1 signals as yes / no)."""
    out = []
    for name in names[:_MAX_SIGNALS]:
        found = _kind_of(name)
        unit = found[0].unit if found else ""
        value = float(s.get(name)[k])
        out.append(f"{name} {'yes' if value > 0.5 else 'no'}" if unit == "0/1" else f"{name} {value:.2f} {unit}".rstrip())
    return ", ".join(out)


def _text(node: Any) -> str:
    """The part's formula text as rtamt prints it, without its parentheses round names and numbers, spaced."""
    bare = re.sub(r"\(([\w.]+)\)", r"\1", str(getattr(node, "name", "")))
    return re.sub(r"\s*(<=|>=|==|!=|<|>|->)\s*", r" \1 ", bare)


def _walker(formula: str, s: Signals) -> tuple[Any, Any]:
    """The formula's top node as rtamt parsed it, and the walker that evaluates its parts on this trace."""
    names = formula_signals(formula)
    spec = _parsed(formula, tuple(names), _period(s))
    if not spec.set_ast_flag:
        spec.offline_interpreter.set_ast(spec.ast)
        spec.set_ast_flag = True
    return spec.ast.specs[-1], stl_numpy._Walker({n: s.get(n) for n in names}, len(s.t),
                                                 spec.offline_interpreter.time_unit_transformer)


def decisive(formula: str, s: Signals) -> tuple[float, str] | None:
    """(time, text) of the step that decides `formula` on this trace and what its signals were then; None when
    the formula cannot be walked (it is then shown per signal)."""
    try:
        root, walker = _walker(formula, s)
        with np.errstate(invalid="ignore", over="ignore"):
            k, why, node = _walk(root, 0, walker, [])
    except Exception:  # noqa: BLE001 - evidence only: the verdict itself comes from stl.monitor
        return None
    if k is None or not why:  # no temporal operator walked (a since at the top): the per-signal view says more
        return None
    t = float(s.t[k])
    if isinstance(node, tuple):  # an implication that failed: its two sides
        left, right = node
        what = (f"where {_text(left)} held ({_values(formula_signals(_text(left)), s, k)}) and {_text(right)} did "
                f"not ({_values(formula_signals(_text(right)), s, k)})")
    else:
        what = _values(formula_signals(_text(node)), s, k)
    return t, f"at t={t:.1f} s ({'; '.join(why)}): {what}"


def held_at_the_start(formula: str, s: Signals) -> str | None:
    """Why an order the formula claims was witnessed only by where people start, else None: an `a until b` (the
    whole formula, or a part of a top-level `and`) whose b already held at t = 0 orders nothing that happened in
    the run (hospital_04: "the doctor goes through the door first" held at t = 0, his spawn spot within the
    formula's 0.8 m of the door). Only authored claims are asked (judge.py): an implied "e1 before e2" may start
    met, a guide beside the person it guides."""
    try:
        root, walker = _walker(formula, s)
        parts, found = [root], []
        with np.errstate(invalid="ignore", over="ignore"):
            while parts:
                node = parts.pop()
                kind = type(node).__name__
                if kind == "Conjunction":
                    parts.extend(node.children[:2])
                elif kind == "Until" and len(s.t) and walker.visit(node.children[1])[0] > 0:
                    found.append(node.children[1])
    except Exception:  # noqa: BLE001 - a formula the walker cannot read is judged by its verdict alone
        return None
    if not found:
        return None
    right = found[-1]
    return (f"held only where people start: {_text(right)} already held at t=0.0 s "
            f"({_values(formula_signals(_text(right)), s, 0)}), so nothing in the run came first: an order is "
            "witnessed by something that happens during the run")


def _until(node: Any, k: int, w: Any, why: list[str]) -> tuple[int | None, list[str], Any]:
    """`a until b` from step k: held - the first step b held (a held up to it); failed - the first step a failed
    before b held, or b never holding (the nearest it came)."""
    left, right = node.children[:2]
    a, b = w.visit(left)[k:], w.visit(right)[k:]
    held, failed = np.flatnonzero(b > 0), np.flatnonzero(a <= 0)
    if len(held) and (not len(failed) or held[0] <= failed[0]):
        return k + int(held[0]), [*why, f"the first moment {_text(right)} held, {_text(left)} having held till then"], node
    if len(failed):
        return k + int(failed[0]), [*why, f"{_text(left)} stopped holding before {_text(right)} ever held"], node
    return k + int(np.argmax(b)), [*why, f"{_text(right)} never held: the nearest it came"], node


_FUTURE = {"Always": False, "Eventually": True, "TimedAlways": False, "TimedEventually": True}


def _walk(node: Any, k: int, w: Any, why: list[str]) -> tuple[int | None, list[str], Any]:
    """Down from `node` at step k to the step and part that decide it (module doc)."""
    kind = type(node).__name__
    if kind in _FUTURE:
        child = node.children[0]
        series = w.visit(child)
        begin, end = w.window(node) if kind.startswith("Timed") else (0, len(series))
        lo, hi = min(k + begin, len(series)), min(k + end + 1, len(series))
        if lo >= hi:
            return k, why, node
        part = series[lo:hi]
        word = "eventually" if _FUTURE[kind] else "always"
        if _FUTURE[kind]:
            held = np.flatnonzero(part > 0)
            j, note = (int(held[0]), f"the first moment the `{word}` part held") if len(held) else \
                (int(np.argmax(part)), f"the nearest the `{word}` part came to holding")
        else:
            failed = np.flatnonzero(part < 0)
            j, note = (int(failed[0]), f"the first moment the `{word}` part failed") if len(failed) else \
                (int(np.argmin(part)), f"the tightest moment of the `{word}` part")
        return _walk(child, lo + j, w, [*why, note])
    if kind == "Implies":
        left, right = node.children[:2]
        if w.visit(left)[k] > 0 and w.visit(right)[k] < 0:
            if type(right).__name__ in _FUTURE:
                return _walk(right, k, w, [*why, f"{_text(left)} held, so {_text(right)} was due"])
            return k, why, (left, right)
        return k, why, node
    if kind == "Until":
        return _until(node, k, w, why)
    if kind in ("Conjunction", "Disjunction"):
        a, b = node.children[:2]
        va, vb = w.visit(a)[k], w.visit(b)[k]
        if kind == "Conjunction" and min(va, vb) < 0:
            return _walk(a if va <= vb else b, k, w, why)
        if kind == "Disjunction" and max(va, vb) > 0:
            return _walk(a if va >= vb else b, k, w, why)
        return k, why, node
    return k, why, node

