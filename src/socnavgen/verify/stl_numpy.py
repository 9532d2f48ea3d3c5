"""rtamt's discrete-time offline STL semantics, evaluated with numpy over the whole trace at once.

rtamt parses the formula (its AST is walked here) and stays the reference: its interpreter runs
per-sample Python loops, ~8 ms per formula on a 1,000-step trace, a third of a campaign episode.
Each supported node gives the same robustness series as rtamt's visitor of that node (cross-checked
in tests/verify/test_stl_numpy.py); anything else raises NotSupported and the caller falls back to
rtamt, so no formula loses support. Bounds of timed operators are converted to samples by rtamt's
own interpreter (same rounding, same error for a bound that is not a multiple of the period).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.lib.stride_tricks import sliding_window_view

INF = float("inf")


class NotSupported(Exception):
    """A node (or input) this evaluator does not reproduce exactly: use rtamt."""


def evaluate(spec: Any, data: dict[str, np.ndarray]) -> np.ndarray:
    """Robustness series of a parsed rtamt specification over `data` (signal name -> float array, all of
    one length). Raises NotSupported where rtamt must be used instead."""
    arrays = {name: np.asarray(values, dtype=float) for name, values in data.items()}
    lengths = {len(a) for a in arrays.values()}
    if len(lengths) != 1 or any(np.isnan(a).any() for a in arrays.values()):
        raise NotSupported("signals of different lengths or with NaN (Python's min/max order matters)")
    (n,) = lengths
    if not spec.set_ast_flag:  # what rtamt's own evaluate does first: its interpreter converts the bounds
        spec.offline_interpreter.set_ast(spec.ast)
        spec.set_ast_flag = True
    walker = _Walker(arrays, n, spec.offline_interpreter.time_unit_transformer)
    return walker.visit(spec.ast.specs[-1])


def _future_window(x: np.ndarray, begin: int, end: int, fill: float, reduce: Any) -> np.ndarray:
    """out[i] = reduce(x[i+begin .. i+end]), samples past the end counting as `fill` (rtamt's padding)."""
    n = len(x)
    padded = np.concatenate([x, np.full(end + 1, fill)])
    return reduce(sliding_window_view(padded, end - begin + 1)[begin:begin + n], axis=1)


def _past_window(x: np.ndarray, begin: int, end: int, fill: float, reduce: Any) -> np.ndarray:
    """out[i] = reduce(x[i-end .. i-begin]), samples before the start counting as `fill`."""
    n = len(x)
    padded = np.concatenate([np.full(end, fill), x])
    return reduce(sliding_window_view(padded, end - begin + 1)[:n], axis=1)


class _Walker:
    def __init__(self, data: dict[str, np.ndarray], n: int, bounds: Any) -> None:
        self.data, self.n, self.bounds = data, n, bounds

    def window(self, node: Any) -> tuple[int, int]:
        """The bounds in samples, as rtamt converts them; anything but 0 <= begin <= end is left to rtamt."""
        begin, end = self.bounds(node)
        if not 0 <= begin <= end:
            raise NotSupported(f"bounds [{begin}:{end}]")
        return begin, end

    def visit(self, node: Any) -> np.ndarray:
        method = getattr(self, "_" + type(node).__name__, None)
        if method is None:
            raise NotSupported(type(node).__name__)
        out = method(node)
        if np.isnan(out).any():  # inf - inf: rtamt's min / max then depend on argument order
            raise NotSupported("NaN")
        return out

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
        op = node.operator.value
        from rtamt.semantics.enumerations.comp_oper import StlComparisonOperator as Op

        if op == Op.EQ.value:
            return -np.abs(left - right)
        if op == Op.NEQ.value:
            return np.abs(left - right)
        if op in (Op.LEQ.value, Op.LESS.value):
            return right - left
        if op in (Op.GEQ.value, Op.GREATER.value):
            return left - right
        raise NotSupported(f"comparison {op}")

    def _Abs(self, node: Any) -> np.ndarray:
        return np.abs(self._children(node)[0])

    def _Addition(self, node: Any) -> np.ndarray:
        left, right = self._children(node)
        return left + right

    def _Subtraction(self, node: Any) -> np.ndarray:
        left, right = self._children(node)
        return left - right

    def _Multiplication(self, node: Any) -> np.ndarray:
        left, right = self._children(node)
        return left * right

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
        return self._chain(node, range(self.n - 1, -1, -1))

    def _Since(self, node: Any) -> np.ndarray:
        """The same recurrence from the start: out[i] = max(right[i], min(left[i], out[i-1]))."""
        return self._chain(node, range(self.n))

    def _chain(self, node: Any, order: range) -> np.ndarray:
        left, right = (a.tolist() for a in self._children(node))
        out, carried = [0.0] * self.n, -INF
        for i in order:
            carried = max(min(left[i], carried), right[i])
            out[i] = carried
        return np.array(out)

    # -- timed operators (bounds in samples from rtamt's interpreter): window side, padding, reduction
    TIMED = {"TimedEventually": (True, -INF, np.max), "TimedAlways": (True, INF, np.min),
             "TimedOnce": (False, -INF, np.max), "TimedHistorically": (False, INF, np.min)}

    def _timed(self, node: Any) -> np.ndarray:
        future, fill, reduce = self.TIMED[type(node).__name__]
        begin, end = self.window(node)
        return (_future_window if future else _past_window)(self._children(node)[0], begin, end, fill, reduce)

    _TimedEventually = _TimedAlways = _TimedOnce = _TimedHistorically = _timed

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
