"""The robot idling: standing, creeping or edging about (within IDLE_REACH) with no progress along its route while its way is clear
(nobody holds it up: Signals.holding_up) and no cue of its script asks it to stand (a timed `wait`, `let_pass`
until its person went by as a viewer sees it, `wait_until_clear`, a speed of 0), short of its goal. Nobody watching can see why it
does not go on (issue 25: home_16's robot stood 12 s in a doorway after both children had run by, then looped back
away from its goal; a robot inching at 5 mm/s 1.07 m from someone beyond its goal until the run timed out).

The signal `idle` (s) is how long that has lasted, continuously; the always-on `no_deadlock` criterion also holds
`idle < IDLE_SECONDS` (verify/criteria.py). What the cues asked is read from the trace's cue log (meta
`script_cues_fired`, the texts sim.robot.script.fired writes); a trace without a log counts no cue waits as known:
then every step after the first waiting cue could be one, and none counts as idle.
"""

from __future__ import annotations

import re
from typing import Protocol

import numpy as np

from socnavgen import proxemics
from socnavgen.sim import contact
from socnavgen.sim.robot.script import (
    CLEAR_PATIENCE,
    CLEAR_REPEATS,
    LET_PASS_AWAY,
    LET_PASS_PATIENCE,
    LET_PASS_STILL,
    LET_PASS_STILL_REACH,
    LET_PASS_WALKED,
)
from socnavgen.sim.social_metrics import arrival_row
from socnavgen.sim.trace import Trace
from socnavgen.verify.route import progress_events
from socnavgen.verify.thresholds import IDLE_SECONDS, PROGRESS_STEP, STILL_SPEED

IDLE_REACH = 1.0  # m: idling is staying this near where it began (standing, creeping, edging about); a robot driving
# farther is going somewhere: on a route that comes back over itself its progress is not always followed (hospital_18's
# trip into a room and back read as 8 s without progress)
CLEAR_LONGEST = CLEAR_PATIENCE * (CLEAR_REPEATS + 1)  # s: the longest a wait_until_clear cue stands the robot
_WAIT = re.compile(r"(?:^|: |, )wait ([0-9.]+) s(?:,|$)")
_LET = re.compile(r"(?:^|: |, )let (\S+) pass(?:,|$)")
_SPEED = re.compile(r"(?:^|: |, )speed ([0-9.eE+-]+)(?:,|$)")
_CLEAR = "wait until clear"
_FIRED = re.compile(r"^[a-z_]+: ")  # "at_encounter: wait 15 s, let human2 pass" (script.describe)


class _Signals(Protocol):  # what of verify.signals.Signals this reads (it imports this module)
    trace: Trace
    places: dict[str, tuple[float, float]]
    goal_radius: float

    @property
    def t(self) -> np.ndarray: ...
    def pos(self, who: str) -> np.ndarray: ...
    def blocked(self) -> np.ndarray: ...
    def route(self) -> tuple[np.ndarray, np.ndarray]: ...
    def get(self, name: str) -> np.ndarray: ...
    def human(self, name: str) -> int: ...
    def distances(self) -> np.ndarray: ...
    def holding_up(self) -> np.ndarray: ...


def cue_log(trace: Trace) -> list[tuple[float, str]] | None:
    """(t, text) of the trace's cue log, None when the trace has none."""
    log = (trace.meta or {}).get("script_cues_fired") if isinstance(trace.meta, dict) else None
    if not isinstance(log, list):
        return None
    return [(float(e[0]), e[1]) for e in log if isinstance(e, list | tuple) and len(e) == 2 and isinstance(e[1], str)]


def _end_of(log: list[tuple[float, str]], n: int, prefixes: tuple[str, ...]) -> float:
    """Time of the first event after log[n] starting with one of `prefixes` (inf: none)."""
    return next((t for t, text in log[n + 1:] if text.startswith(prefixes)), float("inf"))


def gone_by(s: _Signals, who: str, fired: float) -> float:
    """When the person a `let_pass` cue fired at `fired` waits for has gone by as a viewer sees it (inf: never),
    the script's rule (sim.robot.script.gone_by) on the trace: having come within HELD_UP_DISTANCE of the robot or
    into its way, out of its way and LET_PASS_AWAY farther than their closest, or stopped there (LET_PASS_STILL s
    within LET_PASS_STILL_REACH, having walked LET_PASS_WALKED): a wait for them after that has no visible cause."""
    try:
        i = s.human(who)
    except (KeyError, ValueError):
        return float("inf")
    t, xy = s.t, s.trace.humans[:, i, :2]
    d, way = s.distances()[:, i], s.holding_up()[:, i]
    k0 = int(np.searchsorted(t, fired - 1e-9))
    near, closest, still_at, still_since = False, np.inf, xy[min(k0, len(t) - 1)], fired
    for k in range(k0, len(t)):
        near = near or d[k] <= proxemics.HELD_UP_DISTANCE or bool(way[k])
        closest = min(closest, float(d[k]))
        if float(np.hypot(*(xy[k] - still_at))) > LET_PASS_STILL_REACH:
            still_at, still_since = xy[k], float(t[k])
        stopped = float(np.hypot(*(xy[k] - xy[k0]))) >= LET_PASS_WALKED and t[k] - still_since >= LET_PASS_STILL
        if near and not way[k] and (d[k] >= closest + LET_PASS_AWAY or stopped):
            return float(t[k])
    return float("inf")


def cue_waits(s: _Signals) -> np.ndarray:
    """(T,) bool: the steps on which a cue of the robot's script asked it to stand (from the cue log), a `let_pass`
    only until its person has gone by (gone_by)."""
    trace = s.trace
    t = np.asarray(trace.t, dtype=float)
    out = np.zeros(len(t), dtype=bool)
    log = cue_log(trace)
    if log is None:
        return np.ones(len(t), dtype=bool)  # unknown: any step may be a wait
    stopped_at = None  # a cue's speed below STILL_SPEED, until one sets it going
    for n, (when, text) in enumerate(log):
        if not _FIRED.match(text):
            continue
        speed = _SPEED.search(text)
        if speed:
            if float(speed[1]) < STILL_SPEED:
                stopped_at = when if stopped_at is None else stopped_at
            elif stopped_at is not None:
                out |= (t >= stopped_at) & (t < when)
                stopped_at = None
        wait, let = _WAIT.search(text), _LET.search(text)
        if let:
            most = float(wait[1]) if wait else LET_PASS_PATIENCE
            end = min(when + most, _end_of(log, n, (f"{let[1]} has gone by", f"{let[1]} did not go by")),
                      gone_by(s, let[1], when))
        elif wait:
            end = when + float(wait[1])
        else:
            end = when
        if _CLEAR in text:
            end = max(end, min(when + CLEAR_LONGEST, _end_of(log, n, ("still blocked: stop waiting",))))
        out |= (t >= when) & (t <= end)
    if stopped_at is not None:
        out |= t >= stopped_at
    return out


def idle_seconds(s: _Signals) -> np.ndarray:
    """(T,) s: how long the robot has made no progress along its route (less than PROGRESS_STEP, a ratchet: going
    back and forth is none) within IDLE_REACH of where that began, continuously, with its way clear, no cue asking it to stand and short of its goal
    (arrived: within its goal radius, stopped short of someone at it, or going on for its followers)."""
    steps = s.trace.steps
    if steps == 0 or not len(s.trace.robot_waypoints):
        return np.zeros(steps)
    done = np.zeros(steps, dtype=bool)
    if "goal" in s.places:
        done = contact.lengths(s.pos("robot") - np.asarray(s.places["goal"])) <= s.goal_radius
    done = np.maximum.accumulate(done | (s.get("short_of_goal") > 0.5))
    done[arrival_row(s.trace):] = True
    idle = ~progress_events(s.route()[0], PROGRESS_STEP) & ~s.blocked() & ~cue_waits(s) & ~done
    dt, xy = s.trace.dt, s.pos("robot")
    out = np.zeros(steps)
    run, began = 0.0, xy[0]
    for k in range(steps):
        if not idle[k] or float(np.hypot(*(xy[k] - began))) > IDLE_REACH:
            run, began = 0.0, xy[k]  # on its way, or driving somewhere: a leg the route's progress may not follow
        run = run + dt if idle[k] else 0.0
        out[k] = run
    return out


def idle_fact(s: _Signals) -> str | None:
    """What the longest idling was, for a finding (None: never IDLE_SECONDS long): how long, from when, where,
    whether it stood or moved about, who was nearest."""
    idle = s.get("idle")
    k = int(np.argmax(idle)) if len(idle) else 0
    if not len(idle) or idle[k] < IDLE_SECONDS:
        return None
    first = max(0, k - int(round(idle[k] / s.trace.dt)) + 1)
    xy = s.pos("robot")
    driven = float(contact.lengths(np.diff(xy[first:k + 1], axis=0)).sum())
    how = "stood still" if driven < 2 * PROGRESS_STEP else f"moved {driven:.1f} m about without getting on along its route"
    names = s.trace.human_names
    near = ""
    if names:
        d = contact.lengths(s.trace.humans[k, :, :2] - xy[k])
        i = int(np.argmin(d))
        near = f"; nearest person {names[i]} {float(d[i]):.1f} m away, not in its way"
    return (f"the robot {how} for {idle[k]:.1f} s from t={float(s.t[first]):.1f} s at ({xy[first][0]:.1f}, "
            f"{xy[first][1]:.1f}) with its way clear and no cue of its script asking it to wait{near}")
