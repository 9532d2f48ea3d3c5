"""The card's expected robot behaviour, measured: each checkable part of a card's `expected_robot_behavior`
("approaches the corner slowly, keeps right, stops if the person is too close") is one check of this registry,
named with its parameters in cards.yaml (`expected_checks`). A check measures one number on the trace, passes
or fails against its threshold, and says when it does not apply (the situation never arose: nobody came that
close, the robot never got near the place). The episode's `expected_behaviour` score is the share of the checks
that applied and passed.

Every check reads the place of the card's encounter (its scene-graph node, `place`), the encounter's person
(`human`, or everyone when None) and the robot's route (trace.robot_waypoints). Thresholds are parameters with
documented defaults; the registry (CHECKS) holds each check's function and definition text.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np
from pydantic import BaseModel, ConfigDict, Field

from socnavgen.bodies import INTIMATE_SPACE
from socnavgen.sim.trace import VX, VY, Trace, X, Y

# A comfortable deceleration for people near or on a moving vehicle: 0.11-0.15 g is the limit ground-transport
# comfort studies find acceptable (Hoberock 1977, "A survey of longitudinal acceleration comfort studies in
# ground transportation vehicles", J. Dyn. Sys. Meas. Control 99(2)); 0.15 g = 1.5 m/s^2.
COMFORT_DECELERATION = 1.5  # m/s^2
DECELERATION_WINDOW = 0.25  # s: speed changes are measured over this window (one step alone is noise)
STANDING_SPEED = 0.1  # m/s: slower than this the robot stands


CheckName = Literal["slow_near_place", "keeps_right", "stops_when_close", "keeps_distance", "smooth_braking",
                    "keeps_line", "lets_person_pass_first", "goes_first", "follow_distance"]


class ExpectedCheck(BaseModel):
    """One checkable part of a card's expected robot behaviour (cards.yaml `expected_checks`)."""

    model_config = ConfigDict(extra="forbid")
    check: CheckName
    within: float | None = Field(None, gt=0, le=20, description="m: distance to the place (or person) it is judged in")
    speed: float | None = Field(None, ge=0, le=2, description="m/s: the most the robot may drive there")
    gap: float | None = Field(None, ge=0, le=5, description="m: robot-person gap (surface to surface)")
    offset: float | None = Field(None, ge=0, le=2, description="m: lateral offset from the route")
    low: float | None = Field(None, ge=0, le=20, description="m: smallest gap kept (follow_distance)")
    high: float | None = Field(None, ge=0, le=20, description="m: largest gap kept (follow_distance)")


@dataclass(frozen=True)
class Situation:
    """What a check looks at: the trace, the encounter's place (world point), its person (index or None for
    everyone) and derived per-step arrays, computed once."""

    trace: Trace
    place: complex | None
    human: int | None

    @property
    def robot(self) -> np.ndarray:
        return self.trace.robot[:, X] + 1j * self.trace.robot[:, Y]

    @property
    def speed(self) -> np.ndarray:
        return np.hypot(self.trace.robot[:, VX], self.trace.robot[:, VY])

    def people(self) -> np.ndarray:
        """(T, H') complex positions of the people the check is about."""
        h = self.trace.humans
        cols = [self.human] if self.human is not None else list(range(h.shape[1]))
        return h[:, cols, X] + 1j * h[:, cols, Y]

    def gaps(self) -> np.ndarray:
        """(T,) smallest robot-person gap over the check's people (inf when none)."""
        people = self.people()
        if not people.shape[1]:
            return np.full(self.trace.steps, math.inf)
        radii = np.asarray(self.trace.human_radii, dtype=float)
        radii = radii[[self.human]] if self.human is not None else radii
        return (np.abs(people - self.robot[:, None]) - radii[None, :] - float(self.trace.robot_radius)).min(axis=1)

    def lateral(self) -> np.ndarray:
        """(T,) signed offset of the robot from its route (right of the direction of travel positive)."""
        route = np.array([complex(*w) for w in self.trace.robot_waypoints], dtype=complex)
        if len(route) < 2:
            return np.zeros(self.trace.steps)
        a, b = route[:-1], route[1:]
        d = b - a
        length2 = np.maximum(np.abs(d) ** 2, 1e-12)
        p = self.robot[:, None]
        s = np.clip(((p - a) * d.conjugate()).real / length2, 0, 1)
        foot = a + s * d
        nearest = np.abs(p - foot).argmin(axis=1)
        rows = np.arange(len(p))
        rel = (p[:, 0] - foot[rows, nearest]) * d[nearest].conjugate() / np.abs(d[nearest])
        return -rel.imag  # left of the direction of travel is +imag: right is positive


@dataclass(frozen=True)
class Outcome:
    value: float | None  # the measured number (None: the check did not apply)
    passed: bool | None  # None: did not apply


NOT_APPLIED = Outcome(None, None)


def _first_time(mask: np.ndarray, t: np.ndarray) -> float | None:
    return float(t[int(np.argmax(mask))]) if mask.any() else None


def slow_near_place(s: Situation, c: ExpectedCheck) -> Outcome:
    if s.place is None:
        return NOT_APPLIED
    near = np.abs(s.robot - s.place) <= (c.within or 2.0)
    if not near.any():
        return NOT_APPLIED
    top = float(s.speed[near].max())
    return Outcome(top, top <= (c.speed if c.speed is not None else 0.4))


def keeps_right(s: Situation, c: ExpectedCheck) -> Outcome:
    where = np.abs(s.robot - s.place) <= (c.within or 3.0) if s.place is not None else np.ones(s.trace.steps, bool)
    if not where.any():
        return NOT_APPLIED
    mean = float(s.lateral()[where].mean())
    return Outcome(mean, mean >= (c.offset if c.offset is not None else 0.1))


def stops_when_close(s: Situation, c: ExpectedCheck) -> Outcome:
    close = s.gaps() < (c.gap if c.gap is not None else INTIMATE_SPACE)
    if not close.any():
        return NOT_APPLIED
    top = float(s.speed[close].max())
    return Outcome(top, top <= (c.speed if c.speed is not None else STANDING_SPEED))


def keeps_distance(s: Situation, c: ExpectedCheck) -> Outcome:
    gaps = s.gaps()
    if not np.isfinite(gaps).any():
        return NOT_APPLIED
    low = float(gaps.min())
    return Outcome(low, low >= (c.gap if c.gap is not None else INTIMATE_SPACE))


def smooth_braking(s: Situation, c: ExpectedCheck) -> Outcome:  # noqa: ARG001 - every check takes its parameters
    t = np.asarray(s.trace.t, dtype=float)
    if len(t) < 2:
        return NOT_APPLIED
    lag = max(1, int(round(DECELERATION_WINDOW / max(s.trace.dt, 1e-9))))
    if len(t) <= lag:
        return NOT_APPLIED
    drop = (s.speed[:-lag] - s.speed[lag:]) / (t[lag:] - t[:-lag])
    top = float(max(0.0, drop.max()))
    return Outcome(top, top <= COMFORT_DECELERATION)


def keeps_line(s: Situation, c: ExpectedCheck) -> Outcome:
    gaps = s.gaps()
    near = gaps < (c.within or 3.0)
    if not near.any():
        return NOT_APPLIED
    top = float(np.abs(s.lateral()[near]).max())
    return Outcome(top, top <= (c.offset if c.offset is not None else 0.3))


def _order_at_place(s: Situation, c: ExpectedCheck) -> float | None:
    """Seconds between the person's and the robot's first arrival within `within` of the place (positive: the
    person came first); None when one of them never got there."""
    if s.place is None:
        return None
    t = np.asarray(s.trace.t, dtype=float)
    radius = c.within or 1.0
    robot = _first_time(np.abs(s.robot - s.place) <= radius, t)
    people = np.asarray((np.abs(s.people() - s.place) <= radius).any(axis=1))
    person = _first_time(people, t)
    return None if robot is None or person is None else robot - person


def lets_person_pass_first(s: Situation, c: ExpectedCheck) -> Outcome:
    lead = _order_at_place(s, c)
    return NOT_APPLIED if lead is None else Outcome(lead, lead > 0)


def goes_first(s: Situation, c: ExpectedCheck) -> Outcome:
    lead = _order_at_place(s, c)
    return NOT_APPLIED if lead is None else Outcome(-lead, lead < 0)


def follow_distance(s: Situation, c: ExpectedCheck) -> Outcome:
    gaps = s.gaps()
    low, high = (c.low if c.low is not None else INTIMATE_SPACE), (c.high if c.high is not None else 3.6)
    started = np.flatnonzero(gaps <= high)
    if not len(started):
        return NOT_APPLIED
    after = gaps[started[0]:]
    share = float(((after >= low) & (after <= high)).mean())
    return Outcome(share, share >= 0.8)


# name -> (function, definition): the definition is what the report's glossary shows
CHECKS: dict[str, tuple[Callable[[Situation, ExpectedCheck], Outcome], str]] = {
    "slow_near_place": (slow_near_place, "the robot's top speed within `within` m (2) of the place is at most "
                        "`speed` (0.4 m/s); value: that top speed"),
    "keeps_right": (keeps_right, "mean signed offset from the route (right of travel positive) within `within` m (3) "
                    "of the place is at least `offset` (0.1 m); value: the mean offset"),
    "stops_when_close": (stops_when_close, "whenever the person is closer than `gap` (0.45 m), the robot drives at "
                         "most `speed` (0.1 m/s); applies only if that happened; value: its top speed then"),
    "keeps_distance": (keeps_distance, "the smallest gap to the person stays at least `gap` (0.45 m, outside intimate "
                       "space); value: that gap"),
    "smooth_braking": (smooth_braking, f"no deceleration above {COMFORT_DECELERATION} m/s^2 (0.15 g, the comfort "
                       f"limit of Hoberock 1977) over {DECELERATION_WINDOW} s; value: the strongest"),
    "keeps_line": (keeps_line, "while the person is within `within` m (3) the robot stays within `offset` (0.3 m) of "
                   "its route; value: the largest offset"),
    "lets_person_pass_first": (lets_person_pass_first, "the person reaches the place (within `within` m, 1) before "
                               "the robot; value: robot's arrival minus the person's (s)"),
    "goes_first": (goes_first, "the robot reaches the place (within `within` m, 1) before the person; value: the "
                   "person's arrival minus the robot's (s)"),
    "follow_distance": (follow_distance, "from the first time within `high` m (3.6), the gap stays between `low` "
                        "(0.45) and `high` m at least 80 % of the time; value: that share"),
}


def check_behaviour(trace: Trace, checks: list[ExpectedCheck], place: complex | None,
                    human: int | None) -> tuple[float | None, list[dict[str, Any]]]:
    """(score, details): the share of the checks that applied and passed (None when none applied), and per
    check {check, value, passed} (passed None: did not apply)."""
    situation = Situation(trace, place, human)
    details: list[dict[str, Any]] = []
    for c in checks:
        outcome = CHECKS[c.check][0](situation, c)
        value = None if outcome.value is None or not math.isfinite(outcome.value) else round(outcome.value, 4)
        details.append({"check": c.check, "value": value, "passed": outcome.passed})
    applied = [d["passed"] for d in details if d["passed"] is not None]
    return (sum(applied) / len(applied) if applied else None), details
