"""Each acceptance-criterion kind of spec.json compiled to ONE STL formula over the named signals
(verify/signals.py), made non-vacuous (a check about the robot being near also requires that it came
near), and the evidence shown beside its verdict.

The formulas, with h = the criterion's human, e = its encounter, D = distance, S = seconds, W = the
encounter's `within` (docs/verify.md has the same table):

  meets               eventually (dist_h <= D and mid_h_to_e <= W)
  stops_near_robot    eventually always[0:1] (dist_h <= D and ahead_h and speed_h <= 0.1)
  reacts_after_phrase (not react_h_R) until robot_says_P  and  eventually (robot_says_P and eventually[0:S] react_h_R)
  gives_way           eventually (dist_h <= D)  and  always ((dist_h <= D and inway_h) implies eventually[0:S] not inway_h)
  follows_robot       eventually (robot_says_P and eventually[0:S] always (dist_h <= D))   (without P: eventually always)
  hidden_until        (not los_h) until (dist_h <= D)
  group_together      always (spread_h1_h2_... <= D)
  says                eventually (h_says_P and dist_h <= D)          (without D: eventually h_says_P)
  keeps_away          eventually noticed  and  always (once noticed implies dist_h >= D),
                      noticed = los_h and dist_h <= max(5, D + 2)
  blocks_robot        eventually always[0:1] (inway_h and dist_h <= D and speed_h <= 0.1 and robot_still)
  robot_reaches_goal  eventually (robot_to_goal <= D)
  no_collision        always (gap_min >= -0.01)                        (sim/contact.py)
  no_deadlock         always (deadlock < S)
  stl                 the criterion's own formula
"""

from __future__ import annotations

import re
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from socnavgen.run.spec import Criterion, Encounter, HumanPart, ScenarioSpec
from socnavgen.sim import contact
from socnavgen.verify.models import VerifySettings
from socnavgen.verify.signals import STOP_SPEED, Signals, phrase_id
from socnavgen.verify.stl import FormulaError

DEFAULTS = {"stops_near_robot": 1.5, "gives_way": 2.0, "follows_robot": 2.0, "hidden_until": 3.0,
            "keeps_away": 1.5, "blocks_robot": 1.5}  # metres, when the criterion gives no distance
NOTICE_RANGE = 5.0  # m: a human notices a visible robot this close (keeps_away)


@dataclass
class Compiled:
    """A criterion ready to monitor: its formula, the facts it needs, and its evidence."""

    criterion: Criterion
    formula: str
    human: str | None = None
    encounter: Encounter | None = None
    part: HumanPart | None = None
    distance: float | None = None
    seconds: float | None = None
    phrase: str | None = None  # robot phrase identifier (excuse_me) the criterion waits for
    reaction: str | None = None
    notes: list[str] = field(default_factory=list)


def _b(name: str) -> str:
    return f"({name} > 0.5)"


def _not(name: str) -> str:
    return f"({name} < 0.5)"


def encounter_of(c: Criterion, spec: ScenarioSpec) -> tuple[Encounter | None, HumanPart | None]:
    """The criterion's encounter (named, else the first one its human takes part in) and the human's part."""
    enc = spec.encounter(c.encounter) if c.encounter else None
    if c.encounter and enc is None:
        raise FormulaError(f"criterion {c.id}: no encounter {c.encounter!r} in the spec")
    if enc is None and c.human:
        parts = spec.parts_of(c.human)
        enc = parts[0][0] if parts else None
    part = next((p for p in enc.humans if p.human == c.human), None) if enc is not None and c.human else None
    return enc, part


def _need_human(c: Criterion) -> str:
    if not c.human:
        raise FormulaError(f"criterion {c.id} ({c.kind}) names no `human`")
    return c.human


def _phrase(c: Criterion, part: HumanPart | None) -> str | None:
    word = c.phrase or (part.phrase if part is not None and part.trigger == "robot_says" else None)
    return phrase_id(word) if word else None


def compile_criterion(c: Criterion, spec: ScenarioSpec, settings: VerifySettings,
                      goal_radius: float) -> Compiled:
    """The STL formula of one criterion (FormulaError when the criterion is incomplete)."""
    enc, part = encounter_of(c, spec)
    out = Compiled(criterion=c, formula="", human=c.human, encounter=enc, part=part)
    k = c.kind
    if k == "meets":  # `human`, or a group (`humans`): the robot meets the group where it meets any member
        members = [c.human] if c.human else list(c.humans)
        if not members:
            raise FormulaError(f"criterion {c.id} (meets) names no `human` (or `humans` of a group)")
        d = out.distance = c.distance or settings.distance
        if enc is not None:
            w = enc.within
            met = [f"((dist_{h} <= {d:g}) and (mid_{h}_to_{enc.id} <= {w:g}))" for h in members]
        else:
            out.notes.append("no encounter place: only the distance is checked")
            met = [f"(dist_{h} <= {d:g})" for h in members]
        out.formula = f"eventually ({' or '.join(met)})" if len(met) > 1 else f"eventually {met[0]}"
    elif k == "stops_near_robot":
        h = _need_human(c)
        d = out.distance = c.distance or DEFAULTS[k]
        out.formula = (f"eventually (always[0:1] ((dist_{h} <= {d:g}) and {_b(f'ahead_{h}')} and "
                       f"(speed_{h} <= {STOP_SPEED:g})))")
    elif k == "reacts_after_phrase":
        h = _need_human(c)
        p = out.phrase = _phrase(c, part)
        r = out.reaction = c.reaction or (part.reaction if part is not None else None)
        if not p or not r:
            raise FormulaError(f"criterion {c.id}: reacts_after_phrase needs the robot's `phrase` and the `reaction`")
        s = out.seconds = c.seconds or settings.reaction_seconds
        react, says = f"react_{h}_{r}", f"robot_says_{p}"
        out.formula = (f"({_not(react)} until {_b(says)}) and "
                       f"(eventually ({_b(says)} and (eventually[0:{s:g}] {_b(react)})))")
    elif k == "gives_way":
        h = _need_human(c)
        d = out.distance = c.distance or DEFAULTS[k]
        s = out.seconds = c.seconds or settings.reaction_seconds
        out.formula = (f"(eventually (dist_{h} <= {d:g})) and (always (((dist_{h} <= {d:g}) and "
                       f"{_b(f'inway_{h}')}) implies (eventually[0:{s:g}] {_not(f'inway_{h}')})))")
    elif k == "follows_robot":
        h = _need_human(c)
        d = out.distance = c.distance or DEFAULTS[k]
        p = out.phrase = _phrase(c, part)
        s = out.seconds = c.seconds or settings.reaction_seconds
        if p:
            out.formula = (f"eventually ({_b(f'robot_says_{p}')} and (eventually[0:{s:g}] "
                           f"(always (dist_{h} <= {d:g}))))")
        else:
            out.formula = f"eventually (always (dist_{h} <= {d:g}))"
    elif k == "hidden_until":
        h = _need_human(c)
        d = out.distance = c.distance or DEFAULTS[k]
        out.formula = f"{_not(f'los_{h}')} until (dist_{h} <= {d:g})"
    elif k == "group_together":
        names = list(c.humans) or ([p.human for p in enc.humans] if enc is not None else [])
        if len(names) < 2:
            raise FormulaError(f"criterion {c.id}: group_together needs at least two `humans`")
        names = sorted(set(names), key=lambda n: int(n[5:]))
        d = out.distance = c.distance or settings.group_spread
        out.formula = f"always (spread_{'_'.join(names)} <= {d:g})"
    elif k == "says":
        h = _need_human(c)
        if not c.phrase:
            raise FormulaError(f"criterion {c.id}: says needs the `phrase`")
        p = out.phrase = phrase_id(c.phrase)
        out.distance = c.distance
        out.formula = (f"eventually ({_b(f'{h}_says_{p}')} and (dist_{h} <= {c.distance:g}))" if c.distance
                       else f"eventually {_b(f'{h}_says_{p}')}")
    elif k == "keeps_away":
        h = _need_human(c)
        d = out.distance = c.distance or DEFAULTS[k]
        noticed = f"({_b(f'los_{h}')} and (dist_{h} <= {max(NOTICE_RANGE, d + 2):g}))"
        out.formula = f"(eventually {noticed}) and (always ((once {noticed}) implies (dist_{h} >= {d:g})))"
    elif k == "blocks_robot":
        h = _need_human(c)
        d = out.distance = c.distance or DEFAULTS[k]
        out.formula = (f"eventually (always[0:1] ({_b(f'inway_{h}')} and (dist_{h} <= {d:g}) and "
                       f"(speed_{h} <= {STOP_SPEED:g}) and {_b('robot_still')}))")
    elif k == "robot_reaches_goal":
        d = out.distance = c.distance or goal_radius
        out.formula = f"eventually (robot_to_goal <= {d:g})"
    elif k == "no_collision":
        if c.human:
            out.formula = f"always (gap_{c.human} >= {-contact.OVERLAP_TOLERANCE:g})"
        else:
            out.formula = f"always (gap_min >= {-contact.OVERLAP_TOLERANCE:g})"
    elif k == "no_deadlock":
        s = out.seconds = c.seconds or settings.deadlock_seconds
        out.formula = f"always (deadlock < {s:g})"
    elif k == "stl":
        if not c.formula:
            raise FormulaError(f"criterion {c.id}: kind stl needs a `formula`")
        out.formula = c.formula
    else:  # pragma: no cover - the Literal of spec.py lists every kind
        raise FormulaError(f"criterion {c.id}: unknown kind {k!r}")
    return out


# ---- evidence ------------------------------------------------------------------------------------
Evidence = tuple[str, float | None, float | None]  # text, time, distance


def _closest(s: Signals, h: str) -> tuple[int, float]:
    dist = s.get(f"dist_{h}")
    k = int(np.argmin(dist))
    return k, float(dist[k])


def _first(mask: np.ndarray) -> int | None:
    idx = np.flatnonzero(mask)
    return int(idx[0]) if len(idx) else None


def _meets_evidence(cc: Compiled, s: Signals) -> Evidence:
    members = [cc.human] if cc.human else list(cc.criterion.humans)
    if len(members) > 1:  # a group: the evidence of the member met first, else of the closest one
        each = [(_meets_evidence_of(cc, s, h), h) for h in members]
        met = [(ev, h) for ev, h in each if f"{h} met at " in ev[0]]
        if met:
            return min(met, key=lambda eh: eh[0][1] or 0.0)[0]
        return min(each, key=lambda eh: eh[0][2] if eh[0][2] is not None else float("inf"))[0]
    return _meets_evidence_of(cc, s, members[0] if members else "")


def _meets_evidence_of(cc: Compiled, s: Signals, h: str) -> Evidence:
    t = s.t
    dist = s.get(f"dist_{h}")
    k, closest = _closest(s, h)
    text = f"closest {closest:.2f} m at t={t[k]:.1f} s"
    if cc.encounter is None:
        return text, float(t[k]), closest
    e = cc.encounter.id
    mid = s.get(f"mid_{h}_to_{e}")
    ok = (dist <= (cc.distance or 0)) & (mid <= cc.encounter.within)
    if ok.any():
        j = _first(ok)
        return (f"{h} met at t={t[j]:.1f} s, {dist[j]:.2f} m apart, {mid[j]:.2f} m from {cc.encounter.node or e}; "
                + text), float(t[j]), float(dist[j])
    robot_to, human_to = s.get(f"robot_to_{e}"), s.get(f"{h}_to_{e}")
    kr, kh = int(np.argmin(robot_to)), int(np.argmin(human_to))
    text += (f", {mid[k]:.2f} m from {cc.encounter.node or e}; the robot was nearest the node at t={t[kr]:.1f} s "
             f"({robot_to[kr]:.2f} m), {h} at t={t[kh]:.1f} s ({human_to[kh]:.2f} m)")
    return text, float(t[k]), closest


def words(phrase: str | None) -> str:
    """'excuse_me' -> 'EXCUSE ME' (as the spec and the node library write phrases)."""
    return (phrase or "").replace("_", " ").upper()


def _phrase_evidence(cc: Compiled, s: Signals) -> Evidence:
    h, t = cc.human or "", s.t
    says = s.get(f"robot_says_{cc.phrase}") > 0.5
    first_say = _first(says)
    react = s.get(f"react_{h}_{cc.reaction}") if cc.reaction else np.zeros(len(t))
    first_react = _first(react > 0.5)
    parts = [f"the robot said {words(cc.phrase)} first at t={t[first_say]:.1f} s" if first_say is not None
             else f"the robot never said {words(cc.phrase)}"]
    if cc.reaction:
        if first_react is None:
            parts.append(f"{h} never showed {cc.reaction}")
        else:
            when = "BEFORE the phrase" if first_say is None or first_react < first_say else "after it"
            parts.append(f"{h} first showed {cc.reaction} at t={t[first_react]:.1f} s ({when})")
    k = first_react if first_react is not None else first_say
    d = float(s.get(f"dist_{h}")[k]) if k is not None and h else None
    return "; ".join(parts), (float(t[k]) if k is not None else None), d


def _human_evidence(cc: Compiled, s: Signals) -> Evidence:
    h, t = cc.human or "", s.t
    k, closest = _closest(s, h)
    text = f"closest {closest:.2f} m at t={t[k]:.1f} s"
    if cc.criterion.kind in ("stops_near_robot", "blocks_robot"):
        speed = s.get(f"speed_{h}")
        near = s.get(f"dist_{h}") <= (cc.distance or 0)
        if near.any():
            text += f"; slowest while within {cc.distance:g} m: {speed[near].min():.2f} m/s"
        else:
            text += f"; never within {cc.distance:g} m"
    elif cc.criterion.kind == "hidden_until":
        seen = _first(s.get(f"los_{h}") > 0.5)
        if seen is not None:
            text += f"; first in sight at t={t[seen]:.1f} s, {s.get(f'dist_{h}')[seen]:.2f} m apart"
            return text, float(t[seen]), float(s.get(f"dist_{h}")[seen])
        text += "; never in sight"
    elif cc.criterion.kind == "gives_way":
        way = (s.get(f"inway_{h}") > 0.5) & (s.get(f"dist_{h}") <= (cc.distance or 0))
        text += f"; in the robot's way within {cc.distance:g} m for {way.sum() * s.trace.dt:.1f} s"
    elif cc.criterion.kind == "says" and cc.phrase:
        first = _first(s.get(f"{h}_says_{cc.phrase}") > 0.5)
        text += f"; {h} said {words(cc.phrase)} first at t={t[first]:.1f} s" if first is not None else \
            f"; {h} never said {words(cc.phrase)}"
    elif cc.criterion.kind == "follows_robot" and cc.phrase:
        first = _first(s.get(f"robot_says_{cc.phrase}") > 0.5)
        far = s.get(f"dist_{h}")
        if first is not None:
            text += (f"; the robot said {words(cc.phrase)} at t={t[first]:.1f} s; farthest after it "
                     f"{far[first:].max():.2f} m")
        else:
            text += f"; the robot never said {words(cc.phrase)}"
    return text, float(t[k]), closest


def _group_evidence(cc: Compiled, s: Signals) -> Evidence:
    name = cc.formula.split("(")[1].split()[0]
    spread = s.get(name)
    k = int(np.argmax(spread))
    return f"widest {spread[k]:.2f} m at t={s.t[k]:.1f} s (needs <= {cc.distance:g} m)", float(s.t[k]), float(spread[k])


def _goal_evidence(cc: Compiled, s: Signals) -> Evidence:
    to_goal = s.get("robot_to_goal")
    reached = _first(to_goal <= (cc.distance or 0))
    if reached is not None:
        return f"reached at t={s.t[reached]:.1f} s", float(s.t[reached]), float(to_goal[reached])
    text = f"ended {to_goal[-1]:.2f} m from the goal (closest {to_goal.min():.2f} m, radius {cc.distance:g} m)"
    if s.trace.end_reason:
        text += f"; simulation ended by {s.trace.end_reason}"
    stalled = s.get("stalled")
    if stalled[-1] > 0:
        text += f"; the robot stood still for the last {stalled[-1]:.1f} s"
    return text, float(s.t[-1]), float(to_goal[-1])


def _collision_evidence(cc: Compiled, s: Signals) -> Evidence:
    summary = s.contacts()
    return summary.describe(), summary.min_gap_time, summary.min_gap


def deadlock_culprit(s: Signals) -> tuple[int, str | None]:
    """Step of the longest deadlock and the human most in the robot's way then."""
    dead = s.get("deadlock")
    k = int(np.argmax(dead))
    best, who = np.inf, None
    for i, name in enumerate(s.trace.human_names):
        if s.in_way(i)[k]:
            gap = float(s.gaps()[k, i])
            if gap < best:
                best, who = gap, name
    return k, who


def _deadlock_evidence(cc: Compiled, s: Signals) -> Evidence:
    dead = s.get("deadlock")
    k, who = deadlock_culprit(s)
    if dead[k] <= 0:
        return "the robot was never stuck behind someone", None, None
    start = s.t[k] - dead[k] + s.trace.dt
    gap = float(s.gaps()[k, s.human(who)]) if who else None
    text = f"the robot stood still {dead[k]:.1f} s from t={start:.1f} s with {who or 'someone'} in its way"
    if gap is not None:
        text += f" ({gap:.2f} m gap)"
    return text, float(start), gap


def _stl_evidence(cc: Compiled, s: Signals) -> Evidence:
    """What the formula's signals did: each distance's minimum and when, each 0/1 signal's first true step."""
    from socnavgen.verify.signals import SIGNAL_KINDS
    from socnavgen.verify.stl import formula_signals

    units = {}
    for name in formula_signals(cc.formula):
        kind = next((k for k in SIGNAL_KINDS if re.fullmatch(k.pattern, name)), None)
        units[name] = kind.unit if kind else ""
    parts = []
    for name, unit in list(units.items())[:4]:
        values = s.get(name)
        if unit == "0/1":
            first = _first(values > 0.5)
            parts.append(f"{name} first at t={s.t[first]:.1f} s" if first is not None else f"{name} never")
        else:
            k = int(np.argmin(values))
            parts.append(f"{name} min {values[k]:.2f} {unit} at t={s.t[k]:.1f} s")
    return "; ".join(parts) or "formula", None, None


EVIDENCE: dict[str, Callable[[Compiled, Signals], Evidence]] = {
    "meets": _meets_evidence, "reacts_after_phrase": _phrase_evidence, "group_together": _group_evidence,
    "robot_reaches_goal": _goal_evidence, "no_collision": _collision_evidence, "no_deadlock": _deadlock_evidence,
    "stl": _stl_evidence,
}


def evidence(cc: Compiled, s: Signals) -> Evidence:
    fn = EVIDENCE.get(cc.criterion.kind, _human_evidence)
    text, time, dist = fn(cc, s)
    if cc.notes:
        text += " (" + "; ".join(cc.notes) + ")"
    return text, time, dist
