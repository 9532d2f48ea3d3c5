"""Runs of True over a trace's steps: how long each has lasted, which last long enough, and latching (the
signals' and the blame rules' one home for run lengths)."""

from __future__ import annotations

import numpy as np


def runlength(flags: np.ndarray, dt: float) -> np.ndarray:
    """Seconds each step has been inside a continuous run of True (0 where False): dt added once per step of the
    run, the j-th step of every run reading the j-th partial sum of one cumsum."""
    flags = np.asarray(flags, dtype=bool)
    n = len(flags)
    if not n:
        return np.zeros(0)
    sums = np.cumsum(np.full(n, float(dt)))  # sequential: sums[j] = sums[j - 1] + dt, as a running total
    steps = np.arange(n)
    run_start = np.maximum.accumulate(np.where(flags, -1, steps))  # last False at or before each step
    return np.where(flags, sums[np.maximum(steps - run_start - 1, 0)], 0.0)


def lasting(flags: np.ndarray, seconds: float, dt: float) -> np.ndarray:
    """(T,) bool: the steps from which `flags` stays true for at least `seconds` (this step included, dt each)."""
    flags = np.asarray(flags, dtype=bool)
    return runlength(flags[::-1], dt)[::-1] >= seconds - 1e-9


def latched(flags: np.ndarray) -> np.ndarray:
    """(T,) 1 from the first True step on (a `said` phrase, a `moved` person: once so, so for good)."""
    return np.maximum.accumulate(np.asarray(flags, dtype=float)) if len(flags) else np.zeros(0)
