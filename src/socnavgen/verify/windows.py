"""The window of each encounter of a person met more than once: the stretch of the run in which the criteria of
that encounter (gives_way, stops_near_robot, reacts_after_phrase) are judged, so that a later encounter's
reaction is never timed from an earlier meeting (issue 25: a picker met at the aisle's south end, then at its
north end, "in the robot's way first at t = 10 s" at the first meeting, could never give way in time at the
second).

A person's encounters are taken in their `order` (then as listed), those it avoids left out
(criteria.previous_encounter ranks them the same way). "Together at e" means the robot and the person within
the encounter's reach (the meeting distance, or the largest distance a criterion of that encounter gives) with
their midpoint within the encounter's `within` of its node.

- the first encounter's window opens at the start of the run;
- a later one opens at the first step, after the previous one began, on which the person's part in it is
  triggered (the simulated person switches to a later part as soon as its trigger holds: "e1 block the robot,
  e2 give way once it says EXCUSE ME" is one meeting), or the two are together at its place after the previous
  encounter ended (the first step, after they were first together there, on which they no longer are); after a
  LATCHED part, whose tree holds the later parts inside its latch (proposal/tree_needs.py), a later trigger
  counts only once the latched part's own trigger has held (warehouse_02: the robot within 4 m of the picker,
  e2's trigger, before it says EXCUSE ME, e1's, opens no e2 window);
- each window closes when the person's next encounter opens (the last one at the end of the run).

A window that never opens is empty: its criteria have no cause in it and fail, blamed on the paths.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from socnavgen.bt.library import BLOCKING_CONE
from socnavgen.run.spec import Encounter, HumanPart, ScenarioSpec
from socnavgen.sim.trace import YAW
from socnavgen.verify.models import VerifySettings

if TYPE_CHECKING:  # pragma: no cover - signals imports nothing from here at run time
    from socnavgen.verify.signals import Signals

WINDOWED = ("gives_way", "stops_near_robot", "reacts_after_phrase")  # criterion kinds judged in their window


def held_within(flags: np.ndarray, steps: int, *, ahead: bool = False) -> np.ndarray:
    """(T,) bool: `flags` held at some step of the last `steps` steps (this one included), or of the next ones with
    `ahead`: "said within S s before" (a follower's cue) and "out of the way within S s after" (a give-way)."""
    flags = np.asarray(flags, dtype=float)
    if ahead:
        return held_within(flags[::-1], steps)[::-1]
    return np.convolve(flags, np.ones(max(steps, 0) + 1), mode="full")[: flags.size] > 0


def encounters_of(spec: ScenarioSpec, human: str) -> list[Encounter]:
    """The encounters `human` is met in (not those it avoids), in the order they happen."""
    mine = [e for e in spec.encounters if any(p.human == human and p.reaction != "avoid" for p in e.humans)]
    ranked = sorted(range(len(mine)), key=lambda k: (mine[k].order, k))
    return [mine[k] for k in ranked]


def window_name(spec: ScenarioSpec, human: str | None, enc: Encounter | None) -> str | None:
    """The signal `during_<human>_<encounter>` of a criterion about `human` at `enc`, or None when the person has
    one encounter only (its window is the whole run)."""
    if human is None or enc is None:
        return None
    order = encounters_of(spec, human)
    return f"during_{human}_{enc.id}" if len(order) > 1 and any(e.id == enc.id for e in order) else None


def reach(spec: ScenarioSpec, enc: Encounter, human: str, settings: VerifySettings) -> float:
    """How close the robot and `human` count as together at `enc`: the meeting distance, or the largest distance
    a criterion of that encounter about that person gives."""
    own = [c.distance for c in spec.criteria if c.encounter == enc.id and human in [c.human, *c.humans]
           and c.distance and c.kind in (*WINDOWED, "meets")]
    return max([settings.distance, *own])


def together(s: Signals, human: str, enc: Encounter, distance: float) -> np.ndarray:
    """(T,) bool: the robot and `human` within `distance`, their midpoint within `within` of the encounter's place
    (distance alone when the encounter has no place on the map)."""
    near = s.get(f"dist_{human}") <= distance
    if enc.id not in s.places:
        return near
    return near & (s.get(f"mid_{human}_to_{enc.id}") <= enc.within)


def _first(mask: np.ndarray, start: int) -> int | None:
    idx = np.flatnonzero(mask[start:])
    return start + int(idx[0]) if len(idx) else None


def off_heading(s: Signals, human: str) -> np.ndarray:
    """(T,) radians between the way `human` faces and the robot, seen from them: IsRobotBlocking's test (the
    simulator's leaf) holds within bt.library.BLOCKING_CONE, so the verifier's robot_blocking is the same cone (its
    looser ahead_<human> of stops_near_robot said "triggered" where the tree's condition never held: warehouse_04)."""
    i = s.human(human)
    rel = s.trace.robot[:, :2] - s.trace.humans[:, i, :2]
    bearing = np.arctan2(rel[:, 1], rel[:, 0]) - s.trace.humans[:, i, YAW]
    return np.abs((bearing + np.pi) % (2 * np.pi) - np.pi)


def triggered(s: Signals, human: str, part: HumanPart) -> np.ndarray | None:
    """(T,) bool: the steps on which the person's part is triggered (run.spec.HumanPart.trigger, as the verifier's
    signals see it), None when the trigger cannot be told from the trace (a distance it does not give)."""
    from socnavgen.verify.signals import UnknownSignal, phrase_id

    d, dist = part.distance, s.get(f"dist_{human}")
    try:
        if part.trigger == "always":
            return np.ones(s.trace.steps, dtype=bool)
        if part.trigger == "robot_says" and part.phrase:
            return s.get(f"robot_says_{phrase_id(part.phrase)}") > 0.5
        if part.trigger == "human_says" and part.phrase and part.other:
            return s.get(f"{part.other}_says_{phrase_id(part.phrase)}") > 0.5
        if part.trigger == "robot_moving":
            return s.get("robot_still") < 0.5
        if part.trigger == "time" and part.seconds is not None:
            return s.t >= part.seconds
        if d is None:
            return None
        if part.trigger == "robot_near":
            return dist <= d
        if part.trigger == "robot_far":
            return dist > d
        if part.trigger not in ("robot_visible", "robot_blocking"):
            return None
        near = (dist <= d) & (s.get(f"los_{human}") > 0.5)
        return near & (off_heading(s, human) <= BLOCKING_CONE) if part.trigger == "robot_blocking" else near
    except UnknownSignal:
        return None


def opening_steps(s: Signals, spec: ScenarioSpec, human: str, settings: VerifySettings) -> list[int | None]:
    """The step each encounter of `human` (encounters_of order) opens at, None for one that never does."""
    steps = s.trace.steps
    opens: list[int | None] = []
    ended, began = 0, 0  # the step the previous encounter ended, and began
    held: int | None = 0  # the step from which a later part may take over (a latched earlier part: once triggered)
    for k, enc in enumerate(encounters_of(spec, human)):
        at = together(s, human, enc, reach(spec, enc, human, settings))
        first = _first(at, ended)
        part = next(p for p in enc.humans if p.human == human)
        cue = triggered(s, human, part) if k else None
        by_cue = _first(cue, min(max(began + 1, held), steps)) if cue is not None and steps and held is not None \
            else None
        if part.latch:  # the later parts live inside its latch (proposal/tree_needs.py): not before its trigger
            gate = triggered(s, human, part)
            held = held if gate is None else _first(gate, 0)
        start = min((x for x in (first, by_cue) if x is not None), default=None)
        opens.append(0 if k == 0 else start)
        if first is not None:
            gone = _first(~at, first)
            ended = steps if gone is None else gone
        if k == 0:
            began = first if first is not None else 0
        elif start is not None:
            began = start
    return opens


def encounter_window(s: Signals, human: str, encounter: str, *, spec: ScenarioSpec,
                     settings: VerifySettings) -> np.ndarray:
    """(T,) bool: the steps inside the window of `encounter` for `human` (module doc)."""
    order = [e.id for e in encounters_of(spec, human)]
    if encounter not in order:
        from socnavgen.verify.signals import UnknownSignal

        raise UnknownSignal(f"{human} takes part in no encounter {encounter!r} (its encounters: "
                            f"{', '.join(order) or 'none'})")
    opens = opening_steps(s, spec, human, settings)
    k = order.index(encounter)
    out = np.zeros(s.trace.steps, dtype=bool)
    start = opens[k]
    if start is None:
        return out
    stop = next((o for o in opens[k + 1:] if o is not None), s.trace.steps)
    out[start:max(stop, start)] = True
    return out


def window_text(s: Signals, name: str | None) -> str:
    """'in e2's window (from t=33.1 s, when the robot and human1 came together at its place)', '' for no window."""
    if name is None:
        return ""
    mask = s.get(name) > 0.5
    human, enc = name.split("_", 2)[1:]
    if not mask.any():
        return f"; {human} and the robot were never together at {enc}'s place after the encounter before it"
    idx = np.flatnonzero(mask)
    a, b = int(idx[0]), int(idx[-1])
    return f" (judged in {enc}'s window, t={s.t[a]:.1f}-{s.t[b]:.1f} s)"
