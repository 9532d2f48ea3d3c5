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

from socnavgen.bodies import COMFORT_DECELERATION, INTIMATE_SPACE, PERSONAL_SPACE, SOCIAL_SPACE
from socnavgen.bodies import STANDING as STANDING_SPEED  # slower than this the robot stands
from socnavgen.sim.trace import VX, VY, Trace, X, Y

DECELERATION_WINDOW = 0.25  # s: speed changes are measured over this window (one step alone is noise)
# "Approaches slowly" / "slows down": over its approach to the place, a mean speed of at most two thirds of the
# robot's own cruise speed (its top speed away from the place), or a crawl whatever its cruise: SLOW_SPEED is the corner speed the default robot is suggested
# (robot.polite.CORNER_SPEED), from which a comfortable brake (COMFORT_DECELERATION) stops it within 3 cm.
SLOW_SHARE = 2 / 3
SLOW_SPEED = 0.3  # m/s
# "Crosses first without hesitation": standing (slower than STANDING_SPEED) more than HESITATION s on its approach
# to the place, within HESITATION_REACH m (the cards' meeting distance), is hesitating.
HESITATION = 1.0  # s
HESITATION_REACH = 3.0  # m
SPEED_NOISE = 0.01  # m/s: speeds this close to a limit are at it (a robot driving at exactly 0.3 m/s reads 0.3 + 1e-9)
DECEL_NOISE = 1e-6  # m/s2: a deceleration this close to the comfort limit is at it (braking at exactly 1.5 m/s2 reads
# 1.5000000000000004 over a window)


CheckName = Literal["slow_near_place", "keeps_right", "stops_when_close", "keeps_distance", "smooth_braking",
                    "keeps_line", "lets_person_pass_first", "goes_first", "follow_distance"]


class ExpectedCheck(BaseModel):
    """One checkable part of a card's expected robot behaviour (cards.yaml `expected_checks`)."""

    model_config = ConfigDict(extra="forbid")
    check: CheckName
    within: float | None = Field(None, gt=0, le=20, description="m: distance to the place (or person) it is judged in")
    speed: float | None = Field(None, ge=0, le=2, description="m/s: slow whatever the cruise (slow_near_place), "
                                "the most the robot may close in (stops_when_close)")
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

    def each_gap(self) -> np.ndarray:
        """(T, H') robot-person gap (surface to surface) per person of the check."""
        radii = np.asarray(self.trace.human_radii, dtype=float)
        radii = radii[[self.human]] if self.human is not None else radii
        return np.abs(self.people() - self.robot[:, None]) - radii[None, :] - float(self.trace.robot_radius)

    def gaps(self) -> np.ndarray:
        """(T,) smallest robot-person gap over the check's people (inf when none)."""
        gaps = self.each_gap()
        return gaps.min(axis=1) if gaps.shape[1] else np.full(self.trace.steps, math.inf)

    def toward(self) -> np.ndarray:
        """(T, H') the robot's own speed toward each person of the check (m/s, negative: away from them)."""
        v = self.trace.robot[:, VX] + 1j * self.trace.robot[:, VY]
        to = self.people() - self.robot[:, None]
        return (v[:, None] * (to / np.maximum(np.abs(to), 1e-9)).conjugate()).real

    def closing(self) -> np.ndarray:
        """(T, H') how fast the robot itself closes in on each person (m/s, 0 when it does not): its velocity
        along the line to them, counted only while the gap shrinks. A person walking into a robot that stands
        or drives away, or walking away from one that follows, is no closing in by the robot."""
        own = self.toward()
        if self.trace.steps < 2:
            return np.maximum(own, 0.0)
        shrinks = -np.gradient(self.each_gap(), np.asarray(self.trace.t, dtype=float), axis=0)
        return np.maximum(np.minimum(own, shrinks), 0.0)

    def lateral(self, points: np.ndarray | None = None) -> np.ndarray:
        """Signed offset from the robot's route (right of the direction of travel positive) of the robot, (T,), or
        of `points` ((T,) or (T, H') complex: the people)."""
        p = self.robot if points is None else points
        route = np.array([complex(*w) for w in self.trace.robot_waypoints], dtype=complex)
        if len(route) < 2:
            return np.zeros(p.shape)
        flat = p.reshape(-1)[:, None]
        a, b = route[:-1], route[1:]
        d = b - a
        length2 = np.maximum(np.abs(d) ** 2, 1e-12)
        s = np.clip(((flat - a) * d.conjugate()).real / length2, 0, 1)
        foot = a + s * d
        nearest = np.abs(flat - foot).argmin(axis=1)
        rows = np.arange(len(flat))
        rel = (flat[:, 0] - foot[rows, nearest]) * d[nearest].conjugate() / np.abs(d[nearest])
        return (-rel.imag).reshape(p.shape)  # left of the direction of travel is +imag: right is positive

    def retreating(self) -> np.ndarray:
        """(T, H') bool: the robot stands, or moves away from that person (its speed toward them below
        -STANDING_SPEED): a gap it keeps then is the person's doing, not its own."""
        own = self.toward()
        return (self.speed[:, None] <= STANDING_SPEED) | (own < -STANDING_SPEED)


@dataclass(frozen=True)
class Outcome:
    value: float | None  # the measured number (None: the check did not apply)
    passed: bool | None  # None: did not apply


NOT_APPLIED = Outcome(None, None)


def approach(s: Situation, within: float) -> np.ndarray | None:
    """(T,) bool: the robot's approach to the place - the steps within `within` m of it up to the robot's closest
    point to it (leaving the place is no approach); None when it never came that near (or no place)."""
    if s.place is None:
        return None
    distance = np.abs(s.robot - s.place)
    near = distance <= within
    if not near.any():
        return None
    return near & (np.arange(len(near)) <= int(np.argmin(distance)))


def slow_near_place(s: Situation, c: ExpectedCheck) -> Outcome:
    window = approach(s, c.within or 2.0)
    if window is None:
        return NOT_APPLIED
    moving = s.speed > STANDING_SPEED
    window = window & (np.arange(len(window)) >= int(np.argmax(moving)))  # not the wait before it first moved
    if not window.any():
        return NOT_APPLIED
    mean = float(s.speed[window].mean())
    cruise = float(s.speed[~window].max()) if (~window).any() else float(s.speed.max())
    slow = max(c.speed if c.speed is not None else SLOW_SPEED, SLOW_SHARE * cruise)
    return Outcome(mean, mean <= slow + SPEED_NOISE)


def keeps_right(s: Situation, c: ExpectedCheck) -> Outcome:
    where = np.abs(s.robot - s.place) <= (c.within or 3.0) if s.place is not None else np.ones(s.trace.steps, bool)
    if not where.any():
        return NOT_APPLIED
    mean = float(s.lateral()[where].mean())
    return Outcome(mean, mean >= (c.offset if c.offset is not None else 0.1))


def stops_when_close(s: Situation, c: ExpectedCheck) -> Outcome:
    close = s.each_gap() < (c.gap if c.gap is not None else INTIMATE_SPACE)
    if not close.any():
        return NOT_APPLIED
    top = float(max(0.0, s.closing()[close].max()))
    return Outcome(top, top <= (c.speed if c.speed is not None else STANDING_SPEED))


def keeps_distance(s: Situation, c: ExpectedCheck) -> Outcome:
    gaps = s.each_gap()
    if not gaps.shape[1]:
        return NOT_APPLIED
    low = float(np.where(s.retreating(), math.inf, gaps).min())
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
    return Outcome(top, top <= COMFORT_DECELERATION + DECEL_NOISE)


def keeps_line(s: Situation, c: ExpectedCheck) -> Outcome:
    """No swerve toward anyone within reach: judged only toward people within `within` (personal space, 1.2 m),
    so moving aside for an overtaker on one side is no swerve toward someone walking 3 m ahead on the other."""
    gaps = s.each_gap()
    near = gaps < (c.within or PERSONAL_SPACE)
    if not near.any():
        return NOT_APPLIED
    robot, people = s.lateral(), s.lateral(s.people())
    toward = np.where(people > robot[:, None], robot[:, None], -robot[:, None])  # off its route to their side
    top = float(np.where(near, toward, -math.inf).max())
    return Outcome(top, top <= (c.offset if c.offset is not None else 0.3))


def _passing(distance: np.ndarray, t: np.ndarray, within: float) -> float | None:
    """When something passes the place: the time of its closest approach to it, if that is within `within` m
    (a robot that stops short of a crossing and then drives over it passes it when it drives over)."""
    near = distance <= within
    return float(t[int(np.argmin(np.where(near, distance, math.inf)))]) if near.any() else None


def _order_at_place(s: Situation, c: ExpectedCheck) -> float | None:
    """Seconds between the robot's and the person's passing of the place (positive: the person passed first;
    +-inf: only one of them passed - it was first); None when neither came within `within` m of it."""
    if s.place is None:
        return None
    t = np.asarray(s.trace.t, dtype=float)
    radius = c.within or 1.0
    robot = _passing(np.abs(s.robot - s.place), t, radius)
    people = np.abs(s.people() - s.place)
    person = _passing(people.min(axis=1), t, radius) if people.shape[1] else None
    if robot is None and person is None:
        return None
    return math.inf if robot is None else -math.inf if person is None else robot - person


def lets_person_pass_first(s: Situation, c: ExpectedCheck) -> Outcome:
    lead = _order_at_place(s, c)
    return NOT_APPLIED if lead is None else Outcome(lead, lead > 0)


def goes_first(s: Situation, c: ExpectedCheck) -> Outcome:
    """Crosses first without hesitation: it reaches the place before the person, stood on its approach to it
    (within HESITATION_REACH m) at most HESITATION s, and did not force its way: its own driving never took it
    within `gap` (intimate space) of them - brushing past the person who waved it on is no going first."""
    lead = _order_at_place(s, c)
    if lead is None:
        return NOT_APPLIED
    window = approach(s, HESITATION_REACH)
    stood = float(np.sum(window & (s.speed < STANDING_SPEED)) * s.trace.dt) if window is not None else 0.0
    gaps = s.each_gap()
    forced = bool(gaps.shape[1]) and float(np.where(s.retreating(), math.inf, gaps).min()) < (
        c.gap if c.gap is not None else INTIMATE_SPACE)
    return Outcome(-lead, lead < 0 and stood <= HESITATION and not forced)


def follow_distance(s: Situation, c: ExpectedCheck) -> Outcome:
    """Neither too close (the robot never drives into intimate space: no tailgating) nor losing the person (the
    gap stays within `high` 80 % of the time from the first time it was)."""
    gaps = s.gaps()
    low, high = (c.low if c.low is not None else INTIMATE_SPACE), (c.high if c.high is not None else SOCIAL_SPACE)
    started = np.flatnonzero(gaps <= high)
    if not len(started):
        return NOT_APPLIED
    share = float((gaps[started[0]:] <= high).mean())
    tailgates = bool((np.where(s.retreating(), math.inf, s.each_gap()) < low).any())
    return Outcome(share, share >= 0.8 and not tailgates)


# name -> (function, definition): the definition is what the report's glossary shows
CHECKS: dict[str, tuple[Callable[[Situation, ExpectedCheck], Outcome], str]] = {
    "slow_near_place": (slow_near_place, "on its approach to the place (within `within` m, 2, up to its closest "
                        "point to it, from when it first moved) the robot's mean speed is at most two thirds of its "
                        "top speed elsewhere, or at most `speed` (0.3 m/s): it takes at least 1.5 times as long as "
                        "at cruise; value: that mean speed (m/s)"),
    "keeps_right": (keeps_right, "mean signed offset from the route (right of travel positive) within `within` m (3) "
                    "of the place is at least `offset` (0.1 m); value: the mean offset"),
    "stops_when_close": (stops_when_close, "whenever a person is closer than `gap` (0.45 m), the robot's own speed "
                         "toward them is at most `speed` (0.1 m/s): it does not close in (a person walking into it "
                         "does not count); applies only if someone came that close; value: that top speed (m/s)"),
    "keeps_distance": (keeps_distance, "the smallest gap to the person while the robot drives and not away from "
                       "them is at least `gap` (0.45 m, outside intimate space): someone walking up to a robot that "
                       "stands or backs off is not its doing; value: that gap (m)"),
    "smooth_braking": (smooth_braking, f"no deceleration above {COMFORT_DECELERATION} m/s^2 (0.15 g, the comfort "
                       f"limit of Hoberock 1977) over {DECELERATION_WINDOW} s; value: the strongest"),
    "keeps_line": (keeps_line, "while a person is within `within` m (1.2, personal space) the robot keeps within "
                   "`offset` (0.3 m) of its route on that person's side: it does not swerve toward anyone within "
                   "reach (making room on the other side is allowed); value: its largest offset toward them (m)"),
    "lets_person_pass_first": (lets_person_pass_first, "the person passes the place (their closest approach to it, "
                               "within `within` m, 1) before the robot does; value: the robot's passing minus the "
                               "person's (s)"),
    "goes_first": (goes_first, f"the robot passes the place (its closest approach, within `within` m, 1) before the "
                   f"person, stands at most {HESITATION:g} s on its approach to it (within {HESITATION_REACH:g} m): "
                   "without hesitation, and its own driving never takes it within `gap` (0.45 m, intimate space) of "
                   "them: it does not force its way; value: the person's passing minus the robot's (s)"),
    "follow_distance": (follow_distance, "from the first time within `high` m (3.6, social space) the gap stays "
                        "within it at least 80 % of the time (not losing the person), and the robot never drives "
                        "within `low` (0.45 m, intimate space: no tailgating); value: that share"),
}


# name -> the readable title a report shows
TITLES: dict[str, str] = {
    "slow_near_place": "Slow on its approach to the place", "keeps_right": "Keeps right",
    "stops_when_close": "Does not close in on a person within reach", "keeps_distance": "Keeps out of intimate space",
    "smooth_braking": "Brakes smoothly", "keeps_line": "Keeps its line, no swerve toward people",
    "lets_person_pass_first": "Lets the person through first", "goes_first": "Goes first without hesitating",
    "follow_distance": "Keeps a steady following distance",
}


def check_title(name: str) -> str:
    """The check's readable title (its name when it has none)."""
    return TITLES.get(name, name.replace("_", " ").capitalize())


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
