"""The numpy STL evaluator gives rtamt's robustness series, sample for sample, on every operator the
criteria use (and the others it covers), on realistic and adversarial signals; what it does not cover
falls back to rtamt."""

from __future__ import annotations

import itertools
import warnings

import numpy as np
import pytest

from socnavgen.verify import stl_numpy
from socnavgen.verify.stl import _parsed, formula_signals

DT = 0.05

with warnings.catch_warnings():  # rtamt's antlr runtime imports the deprecated typing.io
    warnings.simplefilter("ignore", DeprecationWarning)
    import rtamt  # noqa: F401

# the criteria's formulas (verify/criteria.py, one per kind), as they are generated
CRITERIA = [
    "eventually ((dist_a <= 2) and (mid_a <= 1))",
    "eventually (always[0:1] ((dist_a <= 1.5) and (ahead_a >= 0.5) and (speed_a <= 0.1)))",
    "((not (react_a >= 0.5)) until (says_p >= 0.5)) and (eventually ((says_p >= 0.5) and "
    "(eventually[0:3] (react_a >= 0.5))))",
    "(eventually (dist_a <= 2)) and (always (((dist_a <= 2) and (inway_a >= 0.5)) implies "
    "(eventually[0:2] (not (inway_a >= 0.5)))))",
    "eventually ((says_p >= 0.5) and (eventually[0:2] (always (dist_a <= 2))))",
    "eventually (always (dist_a <= 2))",
    "(not (los_a >= 0.5)) until (dist_a <= 3)",
    "always (spread_a_b <= 1.5)",
    "(eventually (react_a >= 0.5)) and (always ((once (react_a >= 0.5)) implies (dist_a >= 2)))",
    "eventually (robot_to_goal <= 0.5)",
    "always (gap_min >= -0.01)",
    "always (deadlock < 10)",
]
# every other node the evaluator covers, alone and nested
OTHERS = [
    "historically (dist_a <= 2)", "(dist_a <= 2) since (react_a >= 0.5)", "once[0:0.5] (dist_a > 1)",
    "historically[0.1:0.4] (dist_a < 3)", "always[0.2:0.6] (dist_a >= 1)", "eventually[0:0] (dist_a == 2)",
    "eventually[0.05:0.25] (dist_a !== 2)", "(dist_a <= 2) iff (react_a >= 0.5)", "(dist_a <= 2) xor (mid_a <= 1)",
    "(dist_a <= 2) or (not (mid_a >= 1))", "rise (react_a >= 0.5)", "fall (react_a >= 0.5)",
    "prev (dist_a <= 2)", "next (dist_a <= 2)", "abs(dist_a - mid_a) <= 1", "dist_a + mid_a * 2 >= 3",
    "always (eventually[0:0.5] ((dist_a <= 2) until (mid_a <= 1)))",
    "eventually[0:100] (dist_a <= 0)",  # a bound past any trace here: all padding
    "always[0:1] (once (react_a >= 0.5))",
    # bounded until / since (rtamt's are cubic in the bound; ours linear), inside the trace and past its ends
    "(dist_a <= 2) until[0:0.5] (mid_a <= 1)", "(dist_a <= 2) until[0.1:0.3] (mid_a <= 1)",
    "(dist_a <= 2) until[0.2:0.2] (mid_a <= 1)", "(dist_a <= 2) until[0.5:1] (mid_a <= 1)",
    "(dist_a <= 2) since[0:0.4] (mid_a <= 1)", "(dist_a <= 2) since[0.15:0.35] (mid_a <= 1)",
    "(dist_a <= 2) since[0.5:1] (mid_a <= 1)", "eventually[0.3:100] (dist_a < 1)", "once[0.2:50] (dist_a > 1)",
    "sqrt(abs(dist_a)) + exp(mid_a / 10) - pow(dist_a, 2) <= 3", "dist_a / (mid_a + 10) >= 0.1",
]


def signals(kind: str, n: int, rng: np.random.Generator) -> dict[str, np.ndarray]:
    names = ["dist_a", "mid_a", "ahead_a", "speed_a", "react_a", "says_p", "inway_a", "los_a", "spread_a_b",
             "robot_to_goal", "gap_min", "deadlock"]
    out = {}
    for name in names:
        if kind == "walk":
            out[name] = np.abs(np.cumsum(rng.normal(0, 0.3, n)) + rng.uniform(0, 4))
        elif kind == "steps":
            out[name] = np.repeat(rng.integers(0, 2, max(1, n // 7 + 1)).astype(float), 7)[:n]
        elif kind == "ties":  # values exactly on the thresholds
            out[name] = rng.choice([0.0, 0.5, 1.0, 1.5, 2.0, 3.0, -0.01, 10.0], n)
        else:  # constant
            out[name] = np.full(n, 2.0)
    return out


class TraceSignals:
    """What monitor() reads of verify.signals.Signals: the sample times, the trace's dt, named signals."""

    def __init__(self, data: dict[str, np.ndarray]) -> None:
        self.data = data
        self.t = np.arange(len(next(iter(data.values())))) * DT
        self.trace = type("Trace", (), {"dt": DT})()

    def get(self, name: str) -> np.ndarray:
        return self.data[name]


def rtamt_series(formula: str, data: dict[str, np.ndarray]) -> np.ndarray:
    names = tuple(formula_signals(formula))
    spec = _parsed(formula, names, DT)
    n = len(next(iter(data.values())))
    dataset = {"time": [k * DT for k in range(n)]}
    dataset.update({name: [float(v) for v in data[name]] for name in names})
    return np.array([float(v) for _, v in spec.evaluate(dataset)])


def numpy_series(formula: str, data: dict[str, np.ndarray]) -> np.ndarray:
    names = tuple(formula_signals(formula))
    return stl_numpy.evaluate(_parsed(formula, names, DT), {name: data[name] for name in names})


def same(a: np.ndarray, b: np.ndarray) -> bool:
    return a.shape == b.shape and bool(np.all((a == b) | np.isclose(a, b, rtol=0, atol=1e-9)))


@pytest.mark.parametrize("formula", CRITERIA + OTHERS)
def test_numpy_matches_rtamt_sample_for_sample(formula: str) -> None:
    rng = np.random.default_rng(abs(hash(formula)) % 2**32)
    for kind, n in itertools.product(("walk", "steps", "ties", "constant"), (2, 3, 17, 400)):
        data = signals(kind, n, rng)
        reference, fast = rtamt_series(formula, data), numpy_series(formula, data)
        assert same(reference, fast), (kind, n, reference[:12], fast[:12])


def test_a_bounded_eventually_by_hand() -> None:
    """eventually[0:0.1] at 0.05 s looks at this sample and the next two; past the end there is nothing."""
    x = np.array([-1.0, -1.0, 2.0, -1.0, -1.0])
    got = numpy_series("eventually[0:0.1] (dist_a > 0)", {"dist_a": x})
    assert got.tolist() == [2.0, 2.0, 2.0, -1.0, -1.0]
    got = numpy_series("once[0.05:0.1] (dist_a > 0)", {"dist_a": x})  # the two samples before
    assert got.tolist() == [-np.inf, -1.0, -1.0, 2.0, 2.0]


def test_until_by_hand() -> None:
    """(a until b): b now, or a now and (a until b) from the next sample on; never b: -inf at the end."""
    a, b = np.array([0.2, 1.0, 2.0, 5.0]), np.array([-2.0, -1.0, 0.5, -4.0])
    got = numpy_series("(dist_a >= 0) until (mid_a >= 0)", {"dist_a": a, "mid_a": b})
    assert got.tolist() == [0.2, 0.5, 0.5, -4.0]


def test_a_one_sample_trace_is_monitored() -> None:
    """rtamt's offline evaluate fails on one sample (it measures the sampling period between samples);
    the numpy evaluator answers: always and eventually of one sample are that sample."""
    got = numpy_series("(always (dist_a <= 2)) and (eventually[0:1] (dist_a <= 3))", {"dist_a": np.array([1.5])})
    assert got.tolist() == [0.5]


def test_arithmetic_that_can_fail_is_rtamts() -> None:
    """Division, sqrt, exp and pow are computed sample by sample with Python's operators, as rtamt does: the
    same values, and the same errors (a division by zero is a formula error, not inf)."""
    from socnavgen.verify.stl import FormulaError, monitor

    data = {"dist_a": np.array([1.0, 2.0, 3.0]), "mid_a": np.array([2.0, 2.0, 2.0])}
    for formula in ("(dist_a / mid_a) <= 1", "sqrt(dist_a) + exp(mid_a) - pow(dist_a, 2) <= 3"):
        assert numpy_series(formula, data).tolist() == rtamt_series(formula, data).tolist()
    assert monitor("(dist_a / mid_a) <= 1", TraceSignals(data)).series.tolist() == [0.5, 0.0, -0.5]
    with pytest.raises(FormulaError, match="divided by zero"):
        monitor("(dist_a / (mid_a - 2)) <= 1", TraceSignals(data))


def test_infinite_differences_are_refused_instead_of_guessed() -> None:
    """inf - inf is NaN, and rtamt's min / max of NaN depend on argument order: not reproduced, refused."""
    from socnavgen.verify.stl import FormulaError, monitor

    data = {"dist_a": np.array([np.inf, 1.0]), "mid_a": np.array([np.inf, 0.0])}
    with pytest.raises(stl_numpy.NotSupported):
        numpy_series("(dist_a - mid_a) >= 0", data)
    with pytest.raises(FormulaError, match="undefined on this trace"):
        monitor("((eventually[0.1:0.1] dist_a) - (eventually[0.1:0.1] mid_a)) >= 0",
                TraceSignals({"dist_a": np.array([1.0, 2.0]), "mid_a": np.array([0.0, 1.0])}))


def test_a_reversed_interval_is_a_formula_error_not_a_crash() -> None:
    """eventually[1:0.5] is an empty window: rtamt's evaluate fails with a bare ValueError (the numpy path
    leaves such bounds to it); monitor says what to change instead."""
    from socnavgen.verify.stl import FormulaError, monitor

    signals = TraceSignals({"dist_a": np.linspace(0.0, 3.0, 20)})
    with pytest.raises(FormulaError, match=r"a <= b"):
        monitor("eventually[1:0.5] (dist_a > 1)", signals)
    # the window at t = 0 ends at sample 10 of 20 evenly spread over 0..3
    assert monitor("eventually[0:0.5] (dist_a > 1)", signals).robustness == pytest.approx(3.0 * 10 / 19 - 1.0)
