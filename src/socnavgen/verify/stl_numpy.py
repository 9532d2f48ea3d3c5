"""rtamt's discrete-time offline STL semantics, evaluated with numpy over the whole trace at once.

rtamt parses the formula (its AST is walked here) and stays the reference: its interpreter runs
per-sample Python loops (~8 ms per formula on a 1,000-step trace, and a bounded `until` is cubic in its
bound), so every node is evaluated here instead, giving the same robustness series as rtamt's visitor
of that node (cross-checked sample for sample in tests/verify/test_stl_numpy.py). Work and memory are
linear in the trace, whatever the bounds:

- bounds of timed operators are converted to samples by rtamt's own interpreter (same rounding, same
  error for a bound that is not a multiple of the period), then clipped to the trace's length: past its
  last sample everything is padding, so a longer window changes nothing;
- sliding minima / maxima use the van Herk / Gil-Werman blocks (two cumulative passes, O(n) for any
  window);
- a bounded until / since is the unbounded one cut by a window: (a U[a,b] b)(i) =
  min(always[0,a-1] a, (a U b) and eventually[0,b-a] b, both from i + a), exact for min / max semantics;
- arithmetic that can fail (division, sqrt, exp, pow) is computed per sample with Python's own operators
  and math functions, as rtamt does, so the same inputs raise the same errors.

What has no exact numpy equivalent raises NotSupported (a NaN from inf - inf, whose min / max in rtamt
depend on argument order; bounds with begin > end): the caller reports the formula as not monitorable.
"""

from __future__ import annotations

import math
from functools import lru_cache
from typing import Any

import numpy as np

from socnavgen.memo import kept

INF = float("inf")


class NotSupported(Exception):
    """A node (or input) this evaluator does not reproduce exactly."""


def evaluate(spec: Any, data: dict[str, np.ndarray]) -> np.ndarray:
    """Robustness series of a parsed rtamt specification over `data` (signal name -> float array, all of
    one length). Raises NotSupported where the semantics cannot be reproduced exactly."""
    arrays = {name: np.asarray(values, dtype=float) for name, values in data.items()}
    lengths = {len(a) for a in arrays.values()}
    if len(lengths) != 1 or any(np.isnan(a).any() for a in arrays.values()):
        raise NotSupported("signals of different lengths or with NaN (Python's min/max order matters)")
    (n,) = lengths
    if not spec.set_ast_flag:  # what rtamt's own evaluate does first: its interpreter converts the bounds
        spec.offline_interpreter.set_ast(spec.ast)
        spec.set_ast_flag = True
    walker = _Walker(arrays, n, spec.offline_interpreter.time_unit_transformer)
    with np.errstate(invalid="ignore", over="ignore"):  # inf - inf: every node's result is checked for NaN
        return walker.visit(spec.ast.specs[-1])


def count_nodes(spec: Any) -> int:
    """How many nodes the parsed formula has (each holds one series while it is evaluated); kept on the spec."""
    def count() -> int:
        stack, found = [spec.ast.specs[-1]], 0
        while stack:
            node = stack.pop()
            found += 1
            stack.extend(getattr(node, "children", []) or [])
        return found

    return kept(spec, "nodes", count)


def sliding(x: np.ndarray, width: int, reduce: Any) -> np.ndarray:
    """out[k] = reduce(x[k : k + width]) for k = 0 .. len(x) - width, with `reduce` np.maximum or np.minimum:
    van Herk / Gil-Werman, O(len(x)) for any width (exact: only min / max are taken)."""
    n = len(x)
    if width <= 1:
        return x.copy()
    fill = -INF if reduce is np.maximum else INF  # neutral: padding never wins
    blocks = -(-n // width)
    padded = np.full(blocks * width, fill)
    padded[:n] = x
    rows = padded.reshape(blocks, width)
    prefix = reduce.accumulate(rows, axis=1).ravel()
    suffix = reduce.accumulate(rows[:, ::-1], axis=1)[:, ::-1].ravel()
    return reduce(suffix[: n - width + 1], prefix[width - 1: n])


def _future_window(x: np.ndarray, begin: int, end: int, fill: float, reduce: Any) -> np.ndarray:
    """out[i] = reduce(x[i+begin .. i+end]), samples past the end counting as `fill` (rtamt's padding)."""
    n = len(x)
    padded = np.concatenate([x, np.full(end + 1, fill)])
    return sliding(padded, end - begin + 1, reduce)[begin:begin + n]


def _past_window(x: np.ndarray, begin: int, end: int, fill: float, reduce: Any) -> np.ndarray:
    """out[i] = reduce(x[i-end .. i-begin]), samples before the start counting as `fill`."""
    n = len(x)
    padded = np.concatenate([np.full(end, fill), x])
    return sliding(padded, end - begin + 1, reduce)[:n]


def _until(left: np.ndarray, right: np.ndarray) -> np.ndarray:
    """out[i] = max(right[i], min(left[i], out[i+1])), out[n] = -inf: one pass from the end."""
    out, carried = [0.0] * len(left), -INF
    lt, rt = left.tolist(), right.tolist()
    for i in range(len(lt) - 1, -1, -1):
        carried = max(min(lt[i], carried), rt[i])
        out[i] = carried
    return np.array(out, dtype=float)


def _timed_until(left: np.ndarray, right: np.ndarray, begin: int, end: int) -> np.ndarray:
    """rtamt's out[i] = max over d in [begin, end] of min(right[i+d], min(left[i .. i+d-1])), right padded
    with -inf and left with +inf past the end, as min(always[0:begin-1] left, (left until right) from
    i + begin, eventually[0:end-begin] right from i + begin)."""
    n = len(left)
    shifted_until = np.concatenate([_until(left, right), np.full(begin, -INF)])[begin:begin + n]
    window = _future_window(right, begin, end, -INF, np.maximum)
    out = np.minimum(shifted_until, window)
    if begin > 0:
        out = np.minimum(out, _future_window(left, 0, begin - 1, INF, np.minimum))
    return out


def _per_sample(fn: Any, *columns: np.ndarray) -> np.ndarray:
    """fn applied sample by sample on Python floats (rtamt's arithmetic: same results, same errors)."""
    return np.array([fn(*values) for values in zip(*(c.tolist() for c in columns), strict=True)], dtype=float)


def _no_nan(x: np.ndarray) -> np.ndarray:
    if np.isnan(x).any():
        raise NotSupported("NaN")
    return x


@lru_cache(maxsize=1)
def _comparisons() -> dict[Any, Any]:
    """rtamt's comparison operators -> their robustness (left, right): the same expressions as its visitor."""
    from rtamt.semantics.enumerations.comp_oper import StlComparisonOperator as Op

    return {Op.EQ.value: lambda a, b: -np.abs(a - b), Op.NEQ.value: lambda a, b: np.abs(a - b),
            Op.LEQ.value: lambda a, b: b - a, Op.LESS.value: lambda a, b: b - a,
            Op.GEQ.value: lambda a, b: a - b, Op.GREATER.value: lambda a, b: a - b}


_DISPATCH: dict[type, Any] = {}  # rtamt node class -> the _Walker method evaluating it


class _Walker:
    def __init__(self, data: dict[str, np.ndarray], n: int, bounds: Any) -> None:
        self.data, self.n, self.bounds = data, n, bounds

    def window(self, node: Any) -> tuple[int, int]:
        """The bounds in samples, as rtamt converts them, clipped to the trace's length (past the last sample
        there is only padding, so nothing changes); begin > end is refused."""
        begin, end = self.bounds(node)
        if not 0 <= begin <= end:
            raise NotSupported(f"bounds [{begin}:{end}]")
        return min(begin, self.n), min(end, self.n)

    def visit(self, node: Any) -> np.ndarray:
        kind = type(node)
        method = _DISPATCH.get(kind)
        if method is None:
            method = _DISPATCH[kind] = getattr(_Walker, "_" + kind.__name__, None)
            if method is None:
                raise NotSupported(kind.__name__)
        return method(self, node)

    def _children(self, node: Any) -> list[np.ndarray]:
        """The operands as rtamt reads them: its first two children (its parser may repeat some)."""
        return [self.visit(child) for child in node.children[:2]]

    # -- leaves and arithmetic
    def _Variable(self, node: Any) -> np.ndarray:
        if node.field or node.var not in self.data:
            raise NotSupported(f"variable {node.var}.{node.field}")
        return self.data[node.var]

    def _Constant(self, node: Any) -> np.ndarray:
        return np.full(self.n, float(node.val))

    def _Predicate(self, node: Any) -> np.ndarray:
        left, right = self._children(node)
        rule = _comparisons().get(node.operator.value)
        if rule is None:
            raise NotSupported(f"comparison {node.operator.value}")
        return _no_nan(rule(left, right))

    def _Abs(self, node: Any) -> np.ndarray:
        return np.abs(self._children(node)[0])

    # inf - inf, 0 * inf: NaN, whose min / max in rtamt depend on argument order (checked where it can arise)
    def _Addition(self, node: Any) -> np.ndarray:
        left, right = self._children(node)
        return _no_nan(left + right)

    def _Subtraction(self, node: Any) -> np.ndarray:
        left, right = self._children(node)
        return _no_nan(left - right)

    def _Multiplication(self, node: Any) -> np.ndarray:
        left, right = self._children(node)
        return _no_nan(left * right)

    def _Division(self, node: Any) -> np.ndarray:  # Python's / raises on zero, as in rtamt
        return _no_nan(_per_sample(lambda a, b: a / b, *self._children(node)))

    def _Sqrt(self, node: Any) -> np.ndarray:
        return _no_nan(_per_sample(math.sqrt, self._children(node)[0]))

    def _Exp(self, node: Any) -> np.ndarray:
        return _no_nan(_per_sample(math.exp, self._children(node)[0]))

    def _Pow(self, node: Any) -> np.ndarray:
        return _no_nan(_per_sample(math.pow, *self._children(node)))

    # -- Boolean connectives
    def _Neg(self, node: Any) -> np.ndarray:
        return -self._children(node)[0]

    def _Conjunction(self, node: Any) -> np.ndarray:
        return np.minimum(*self._children(node))

    def _Disjunction(self, node: Any) -> np.ndarray:
        return np.maximum(*self._children(node))

    def _Implies(self, node: Any) -> np.ndarray:
        left, right = self._children(node)
        return np.maximum(-left, right)

    def _Iff(self, node: Any) -> np.ndarray:
        left, right = self._children(node)
        return -np.abs(left - right)

    def _Xor(self, node: Any) -> np.ndarray:
        left, right = self._children(node)
        return np.abs(left - right)

    # -- temporal operators without bounds
    def _Eventually(self, node: Any) -> np.ndarray:
        return np.maximum.accumulate(self._children(node)[0][::-1])[::-1]

    def _Always(self, node: Any) -> np.ndarray:
        return np.minimum.accumulate(self._children(node)[0][::-1])[::-1]

    def _Once(self, node: Any) -> np.ndarray:
        return np.maximum.accumulate(self._children(node)[0])

    def _Historically(self, node: Any) -> np.ndarray:
        return np.minimum.accumulate(self._children(node)[0])

    def _Until(self, node: Any) -> np.ndarray:
        """out[i] = max(right[i], min(left[i], out[i+1])), out[n] = -inf: one pass from the end."""
        return _until(*self._children(node))

    def _Since(self, node: Any) -> np.ndarray:
        """The same recurrence from the start: out[i] = max(right[i], min(left[i], out[i-1]))."""
        left, right = self._children(node)
        return _until(left[::-1], right[::-1])[::-1]

    # -- timed operators (bounds in samples from rtamt's interpreter): window side, padding, reduction
    TIMED = {"TimedEventually": (True, -INF, np.maximum), "TimedAlways": (True, INF, np.minimum),
             "TimedOnce": (False, -INF, np.maximum), "TimedHistorically": (False, INF, np.minimum)}

    def _timed(self, node: Any) -> np.ndarray:
        future, fill, reduce = self.TIMED[type(node).__name__]
        begin, end = self.window(node)
        return (_future_window if future else _past_window)(self._children(node)[0], begin, end, fill, reduce)

    _TimedEventually = _TimedAlways = _TimedOnce = _TimedHistorically = _timed

    def _TimedUntil(self, node: Any) -> np.ndarray:
        begin, end = self.window(node)
        return _timed_until(*self._children(node), begin, end)

    def _TimedSince(self, node: Any) -> np.ndarray:
        """The past mirror of until: the same computation on the reversed series."""
        begin, end = self.window(node)
        left, right = self._children(node)
        return _timed_until(left[::-1], right[::-1], begin, end)[::-1]

    # -- one-step operators
    def _Previous(self, node: Any) -> np.ndarray:
        return np.concatenate([[INF], self._children(node)[0][:-1]])

    def _StrongPrevious(self, node: Any) -> np.ndarray:
        return np.concatenate([[-INF], self._children(node)[0][:-1]])

    def _Next(self, node: Any) -> np.ndarray:
        return np.concatenate([self._children(node)[0][1:], [INF]])

    def _StrongNext(self, node: Any) -> np.ndarray:
        return np.concatenate([self._children(node)[0][1:], [-INF]])

    def _Rise(self, node: Any) -> np.ndarray:
        x = self._children(node)[0]
        return np.minimum(-np.concatenate([[-INF], x[:-1]]), x)

    def _Fall(self, node: Any) -> np.ndarray:
        x = self._children(node)[0]
        return np.minimum(np.concatenate([[INF], x[:-1]]), -x)
