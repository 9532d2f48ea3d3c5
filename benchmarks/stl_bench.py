"""STL monitoring cost per formula: rtamt's offline interpreter vs the numpy evaluator (verify/stl_numpy.py)
on the criteria's formulas, over a 1,200-sample trace (60 s at 0.05 s).

    PYTHONPATH=src:. python benchmarks/stl_bench.py
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT / "src"), str(ROOT)]

import numpy as np  # noqa: E402
from tests.verify.test_stl_numpy import CRITERIA, DT, signals  # noqa: E402

from socnavgen.verify import stl_numpy  # noqa: E402
from socnavgen.verify.stl import _parsed, formula_signals  # noqa: E402


def best_ms(fn, repeats: int = 5) -> float:  # noqa: ANN001
    best = float("inf")
    for _ in range(repeats):
        start = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - start)
    return best * 1000


def main() -> None:
    n = 1200
    data = signals("walk", n, np.random.default_rng(0))
    rows = []
    for formula in CRITERIA:
        names = tuple(formula_signals(formula))
        spec = _parsed(formula, names, DT)
        dataset = {"time": [k * DT for k in range(n)]} | {k: [float(v) for v in data[k]] for k in names}
        slow = best_ms(lambda spec=spec, dataset=dataset: spec.evaluate(dataset))
        fast = best_ms(lambda spec=spec, names=names: stl_numpy.evaluate(spec, {k: data[k] for k in names}))
        rows.append((formula if len(formula) < 60 else formula[:57] + "...", slow, fast))
    print(f"{'formula':<60} | rtamt ms | numpy ms | speed-up")
    print(f"{'-' * 60}-+----------+----------+---------")
    for formula, slow, fast in rows:
        print(f"{formula:<60} | {slow:8.2f} | {fast:8.3f} | {slow / fast:7.0f}x")
    total_slow, total_fast = sum(r[1] for r in rows), sum(r[2] for r in rows)
    print(f"{'all ' + str(len(rows)) + ' criteria':<60} | {total_slow:8.2f} | {total_fast:8.3f} | "
          f"{total_slow / total_fast:7.0f}x")


if __name__ == "__main__":
    main()
