"""Bootstrap confidence intervals and paired comparisons (numpy, vectorised, seeded: same table, same CIs)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

LEVEL = 0.95


@dataclass(frozen=True)
class Estimate:
    mean: float
    low: float
    high: float
    n: int

    def overlaps(self, other: Estimate) -> bool:
        return not (self.high < other.low or other.high < self.low)

    def text(self, digits: int = 3) -> str:
        if self.n == 0 or not np.isfinite(self.mean):
            return "–"
        return f"{self.mean:.{digits}g} [{self.low:.{digits}g}, {self.high:.{digits}g}]"


def bootstrap_mean(values: np.ndarray, resamples: int = 2000, seed: int = 0, level: float = LEVEL) -> Estimate:
    """Mean with a percentile-bootstrap CI; NaN (undefined values) are left out."""
    x = np.asarray(values, dtype=float)
    x = x[np.isfinite(x)]
    n = len(x)
    if n == 0:
        return Estimate(float("nan"), float("nan"), float("nan"), 0)
    if np.all(x == x[0]):  # one value (a deterministic policy): exactly it, not a mean off by 1e-16
        return Estimate(float(x[0]), float(x[0]), float(x[0]), n)
    rng = np.random.default_rng(seed)
    means = np.empty(resamples)
    chunk = max(1, 2_000_000 // n)  # bound memory: resamples x n indices at most ~2M at a time
    for start in range(0, resamples, chunk):
        stop = min(resamples, start + chunk)
        means[start:stop] = x[rng.integers(0, n, size=(stop - start, n))].mean(axis=1)
    alpha = (1 - level) / 2
    low, high = np.quantile(means, [alpha, 1 - alpha])
    return Estimate(float(x.mean()), float(low), float(high), n)


@dataclass(frozen=True)
class Paired:
    """policy - baseline on the same (scenario, seed) pairs."""

    difference: Estimate
    wins: int  # pairs where the policy is better (by the metric's direction)
    ties: int
    losses: int


def paired_difference(policy: np.ndarray, baseline: np.ndarray, better: str | None, resamples: int = 2000,
                      seed: int = 0) -> Paired:
    a, b = np.asarray(policy, dtype=float), np.asarray(baseline, dtype=float)
    keep = np.isfinite(a) & np.isfinite(b)
    d = a[keep] - b[keep]
    sign = -1.0 if better == "lower" else 1.0
    wins = int(np.count_nonzero(sign * d > 1e-12)) if better else 0
    losses = int(np.count_nonzero(sign * d < -1e-12)) if better else 0
    return Paired(bootstrap_mean(d, resamples, seed), wins, len(d) - wins - losses if better else len(d), losses)
