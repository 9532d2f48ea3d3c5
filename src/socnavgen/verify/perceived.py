"""Speeds as a person watching sees them: the one definition of moving, walking, stopping and standing still that
every judgement of the verifier reads (signals.Signals.speed: speed_<who>, robot_still, stalled, the stop and
walking reactions, the stop and standoff criteria, blame's "who was moving").

A person watching sees how far a body gets over about a step, not its speed at one 0.05 s sample: the speed seen
at a step is the mean speed over the thresholds.PERCEIVED_SECONDS centred on it (the ends of the trace: over the
part of that window inside it). So a slow step while bending round someone is no stop (warehouse_10 of the
new-request suite: slowing from 0.75 m/s to 0.09 m/s and back, under 0.2 m/s for 0.25 s, is seen at 0.27 m/s at
least; "the file walks past without stopping"), a robot edging forward in short bursts between pauses is seen creeping, nearly standing, as the eyes
saw it (warehouse_09), and a robot that stops for half a second is seen standing (warehouse_08). A standstill of
a second is seen as one: it fails "keeps walking" whatever the speed around it, and it is seen standing for its
length less the window (the walk before and after it shows at its ends): `seen_hold`, what the stop criteria and
the stop reaction hold for. A trace whose step is as long as half the window is read as it is (and held for whole).
"""

from __future__ import annotations

import numpy as np

from socnavgen.verify.thresholds import PERCEIVED_SECONDS


def half_window(dt: float) -> int:
    """Steps of `dt` on each side of a step that its seen speed averages over (0: a coarse trace, whose one step
    already spans the window, is read as it is)."""
    return int(np.floor(PERCEIVED_SECONDS / float(dt) / 2.0 + 1e-9)) if dt > 0 else 0


def perceived(speed: np.ndarray, dt: float) -> np.ndarray:
    """(T,) the speed as seen: the mean over the centred window of PERCEIVED_SECONDS (truncated at the ends). A
    standstill inside the window adds exact zeros, so a long one reads exactly 0."""
    values = np.asarray(speed, dtype=float)
    h, n = half_window(dt), len(values)
    if h == 0 or n < 2:
        return values.copy()
    sums = np.concatenate([[0.0], np.cumsum(values)])
    steps = np.arange(n)
    lo, hi = np.maximum(steps - h, 0), np.minimum(steps + h + 1, n)
    return (sums[hi] - sums[lo]) / (hi - lo)


def seen_hold(seconds: float, dt: float | None) -> float:
    """How long a standstill of `seconds` is seen standing on a trace of step `dt`: less the window the speed is
    averaged over (None: the trace is not known, the standstill's own length)."""
    return seconds - (2 * half_window(dt) * dt if dt else 0.0)
