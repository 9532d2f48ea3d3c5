"""The evidence shown beside each verdict: what happened, when, how far (text, time, distance), one function
per criterion kind of verify/criteria.py's registry (kinds without their own use the per-human one)."""

from __future__ import annotations

import re
from collections.abc import Callable
from itertools import combinations

import numpy as np

from socnavgen.sim import contact
from socnavgen.verify.criteria import Compiled, notice_range
from socnavgen.verify.idle import idle_fact
from socnavgen.verify.passing import back_in_way, short_step, undone
from socnavgen.verify.people import people_evidence
from socnavgen.verify.signals import Signals, aside
from socnavgen.verify.stay import walk_off_text
from socnavgen.verify.thresholds import (
    APPROACH,
    DEADLOCK_SECONDS,
    PROGRESS_STEP,
    STOP_HOLD,
    STOP_SPEED,
    WALK_SPEED,
)
from socnavgen.verify.windows import triggered, window_text

Evidence = tuple[str, float | None, float | None]  # text, time, distance


def _closest(s: Signals, h: str) -> tuple[int, float]:
    dist = s.get(f"dist_{h}")
    k = int(np.argmin(dist))
    return k, float(dist[k])


def _first(mask: np.ndarray) -> int | None:
    idx = np.flatnonzero(mask)
    return int(idx[0]) if len(idx) else None


def words(phrase: str | None) -> str:
    """'excuse_me' -> 'EXCUSE ME' (as the spec and the node library write phrases)."""
    return (phrase or "").replace("_", " ").upper()


def met_mask(s: Signals, h: str, enc, distance: float) -> np.ndarray:  # noqa: ANN001 - Encounter | None
    """(T,) bool: the steps on which met(h, e) holds (criteria.met_expression, evaluated with numpy)."""
    ok = (s.get(f"dist_{h}") <= distance) & (s.get(f"closer_{h}") >= APPROACH)
    if enc is None:
        return ok
    e, w = enc.id, enc.within
    return ok & (s.get(f"mid_{h}_to_{e}") <= w) & came_to(s, "robot", e, w) & came_to(s, h, e, w)


def came_to(s: Signals, who: str, place: str, within: float) -> np.ndarray:
    """criteria.came_to with numpy: came APPROACH closer to the place, or started within `within` of it."""
    to = s.get(f"{who}_to_{place}")
    return (s.get(f"closer_{who}_to_{place}") >= APPROACH) | (to[:1] <= within)


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
    t, d = s.t, cc.distance or 0.0
    dist = s.get(f"dist_{h}")
    k, closest = _closest(s, h)
    text = f"closest {closest:.2f} m at t={t[k]:.1f} s" + (" (the start)" if k == 0 else "")
    met = met_mask(s, h, cc.encounter, d)
    if cc.previous is not None:  # its own meeting: after the earlier encounter's one, apart in between
        before = met_mask(s, h, cc.previous, d)
        apart_after = np.maximum.accumulate((dist > d) & (np.cumsum(before) > 0))
        met = met & (np.concatenate([[False], apart_after[:-1]]) if len(met) else met)
    j = _first(met)
    if j is not None:
        where = "" if cc.encounter is None else \
            f", {s.get(f'mid_{h}_to_{cc.encounter.id}')[j]:.2f} m from {cc.encounter.node or cc.encounter.id}"
        return f"{h} met at t={t[j]:.1f} s, {dist[j]:.2f} m apart{where}; " + text, float(t[j]), float(dist[j])
    near = dist <= d
    if cc.encounter is not None:
        near &= s.get(f"mid_{h}_to_{cc.encounter.id}") <= cc.encounter.within
    if near.any() and not met.any():
        j = int(np.flatnonzero(near)[0])
        why = _no_approach(cc, s, h, j)
        if why:
            return f"within {d:g} m at the place only without an approach ({why}); " + text, float(t[j]), float(dist[j])
    if cc.previous is not None and near.any():
        return (f"{h} was met only once, at {cc.previous.node or cc.previous.id} ({cc.previous.id}): this encounter "
                f"needs its own meeting; " + text), float(t[k]), closest
    if cc.encounter is None:
        return text, float(t[k]), closest
    e = cc.encounter.id
    robot_to, human_to = s.get(f"robot_to_{e}"), s.get(f"{h}_to_{e}")
    kr, kh = int(np.argmin(robot_to)), int(np.argmin(human_to))
    text += (f", {s.get(f'mid_{h}_to_{e}')[k]:.2f} m from {cc.encounter.node or e}; the robot was nearest the node "
             f"at t={t[kr]:.1f} s ({robot_to[kr]:.2f} m), {h} at t={t[kh]:.1f} s ({human_to[kh]:.2f} m)")
    return text, float(t[k]), closest


def _no_approach(cc: Compiled, s: Signals, h: str, j: int) -> str:
    """Why the first step within the distance at the place is no meeting ('' when it is one)."""
    if s.get(f"closer_{h}")[j] < APPROACH:
        start = float(s.get(f"closer_{h}")[j] + s.get(f"dist_{h}")[j])  # apart at the start (verify/ways.py)
        return (f"at t={s.t[j]:.1f} s they were no closer than at the start ({start:.2f} m apart)" if j == 0 else
                f"at t={s.t[j]:.1f} s they were less than {APPROACH:g} m closer than at the start ({start:.2f} m)")
    if cc.encounter is None:
        return ""
    e, w = cc.encounter.id, cc.encounter.within
    if not came_to(s, "robot", e, w)[j]:
        return "the robot had not come toward the place"
    if not came_to(s, h, e, w)[j]:
        return f"{h} had not come toward the place, nor waited at it"
    return ""


def stayed_off_place(cc: Compiled, s: Signals, h: str, near: np.ndarray) -> str | None:
    """The repair (blame rule N3) for a meeting that failed only because the robot or `h` neither came toward the
    encounter's place nor started within its `within` (a wife cooking at the stove 2.1 m from the kitchen node of
    a `within` 1.5 encounter, home_08), over the steps `near` (within the distance at the place): who, and how far
    from the place it stayed; None when they did not come closer to each other either, or no party is to blame so."""
    if cc.encounter is None:
        return None
    e, w, node = cc.encounter.id, cc.encounter.within, cc.encounter.node or cc.encounter.id
    approached = near & (s.get(f"closer_{h}") >= APPROACH)
    if not approached.any():
        return None
    for who in ("robot", h):
        if not came_to(s, who, e, w)[approached].any():
            return (f"{who} stayed {float(s.get(f'{who}_to_{e}')[0]):.1f} m from {node}, beyond the `within` "
                    f"({w:g} m), never coming toward it: let it wait at {node} or come to it, or set the encounter there")
    return None


def way_cause(cc: Compiled, s: Signals, asked: bool = True) -> np.ndarray:
    """(T,) bool: the cause of a gives_way criterion holds - its human, or one of those giving way together with
    it, in the robot's way within the criterion's distance, in its window, and (`asked`) once the human's own
    trigger held: the clock of criteria._gives_way's formula starts there, not at the first moment in the way."""
    d = cc.distance or 0.0
    out = np.zeros(s.trace.steps, dtype=bool)
    for who in (cc.human, *cc.together):
        out |= (s.get(f"inway_{who}") > 0.5) & (s.get(f"dist_{who}") <= d)
    if asked and cc.asked and cc.part is not None and cc.human:
        trig = triggered(s, cc.human, cc.part)
        if trig is not None:
            out &= np.maximum.accumulate(trig)
    return out & in_window(cc, s)


def in_window(cc: Compiled, s: Signals, after: float = 0.0) -> np.ndarray:
    """(T,) bool: the steps of the criterion's encounter window and `after` s past its end (every step without
    one): a cause inside it may have its reaction that much later."""
    if not cc.window:
        return np.ones(s.trace.steps, dtype=bool)
    win = s.get(cc.window) > 0.5
    idx = np.flatnonzero(win)
    if len(idx) and after > 0:
        win[idx[-1]:idx[-1] + int(round(after / max(s.trace.dt, 1e-9))) + 1] = True
    return win


def _phrase_evidence(cc: Compiled, s: Signals) -> Evidence:
    h, t = cc.human or "", s.t
    says = s.get(f"robot_says_{cc.phrase}") > 0.5
    first_say = _first(says)
    react = s.get(f"react_{h}_{cc.reaction}") if cc.reaction else np.zeros(len(t))
    first_react = _first(react > 0.5)
    parts = [f"the robot said {words(cc.phrase)} first at t={t[first_say]:.1f} s" if first_say is not None
             else f"the robot never said {words(cc.phrase)}"]
    if cc.reaction:
        reacting = react > 0.5
        hold = int(round(STOP_HOLD / max(s.trace.dt, 1e-9)))
        window = int(round((cc.seconds or 0.0) / max(s.trace.dt, 1e-9)))
        n = len(t)
        win = in_window(cc, s)
        calm = np.array([not says[k] and says[k:k + hold + 1].any() and not reacting[k:k + hold + 1].any()
                         and win[k:k + hold + 1].any() for k in range(n)], dtype=bool)  # quiet; the phrase starts
        start = _first(says)
        if start is not None and start <= hold and not reacting[:start + 1].any() and win[0]:
            calm[max(start - 1, 0)] = True  # said at the run's start, nobody reacting before it
        after = None
        for k0 in np.flatnonzero(calm):
            hit = _first(reacting[k0:k0 + hold + window + 1])
            if hit is not None:
                after = int(k0) + hit
                break
        if first_react is None:
            parts.append(f"{h} never showed {cc.reaction}" + _undone_text(s, h, cc.reaction))
        elif after is not None:
            parts.append(f"{h} showed {cc.reaction} at t={t[after]:.1f} s, after the phrase")
        elif first_say is not None and not calm.any():
            parts.append(f"{h} was showing {cc.reaction} within {STOP_HOLD:g} s of every moment the phrase started "
                         f"(first at t={t[first_react]:.1f} s, BEFORE it): no reaction to it")
        else:
            short = short_step(s, h, first_say, min(first_say + hold + window, n - 1)) \
                if cc.reaction == "give_way" and first_say is not None else None
            parts.append(f"{h} first showed {cc.reaction} at t={t[first_react]:.1f} s, not within "
                         f"{cc.seconds or 0:g} s of the phrase" + (
                             f" (it moved {short[1]:.2f} m off the robot's route by t={short[0]:.1f} s, but to "
                             f"{short[2]:.2f} m from it, inside the {short[3]:.2f} m its body sweeps: a step too short "
                             "to let it pass)" if short else ""))
        first_react = after if after is not None else first_react
    k = first_react if first_react is not None else first_say
    d = float(s.get(f"dist_{h}")[k]) if k is not None and h else None
    return "; ".join(parts) + window_text(s, cc.window), (float(t[k]) if k is not None else None), d


def _late_text(cc: Compiled, s: Signals, h: str, way: np.ndarray) -> str:
    """Why a gives_way whose person did step aside fails: the first moment in the robot's way (its cause) with
    no step aside within S s (home_10 of round 13 read "stepped aside at t=14.7 s" next to FAIL, the person back
    in the way at 19.2 s for 5.3 s); '' when there is none."""
    kept, t = s.get(f"aside_{h}") > 0.5, s.t
    n = int(round((cc.seconds or 0.0) / max(s.trace.dt, 1e-9)))
    done = np.concatenate([[0], np.cumsum(kept)])
    steps = np.arange(len(t))
    k = _first(way & (done[np.minimum(steps + n + 1, len(t))] - done[steps] == 0))
    if k is None:
        return ""
    again = " again" if kept[:k].any() else ""
    undone_at = ""  # a step aside within S s that did not count: back in the robot's way before it got past
    r = _first(aside(s, h)[k:k + n + 1])
    back = _first(back_in_way(s, h)[k + r:]) if r is not None else None
    if r is not None and back is not None:
        undone_at = (f" stepped aside at t={t[k + r]:.1f} s but was back in its way at t={t[k + r + back]:.1f} s "
                     "before it got past;")
    short = short_step(s, h, k, k + n) if r is None else None
    why = undone_at
    if short is not None:
        why = (f" moved {short[1]:.2f} m off its route by t={short[0]:.1f} s but stood {short[2]:.2f} m from it, "
               f"inside the {short[3]:.2f} m its body sweeps (a step too short to let it pass);")
    j = _first(kept[k:])
    then = (f"out of it{' for good' if undone_at else ''} only at t={t[k + j]:.1f} s, {t[k + j] - t[k]:.1f} s later"
            if j is not None else "never out of it again by itself")
    return (f"; but in its way{again} at t={t[k]:.1f} s ({s.get(f'dist_{h}')[k]:.2f} m):{why} {then} (more "
            f"than {cc.seconds or 0:g} s): not giving way")


def _undone_text(s: Signals, h: str, reaction: str | None) -> str:
    """' (stepped aside at t=20.0 s, back in the robot's way at t=27.1 s before it got past)' when that is why."""
    found = undone(s, h, aside(s, h)) if reaction == "give_way" else None
    return "" if found is None else (f" (stepped aside at t={found[0]:.1f} s, but was back in the robot's way at "
                                     f"t={found[1]:.1f} s before it got past)")


def _human_evidence(cc: Compiled, s: Signals) -> Evidence:
    h, t = cc.human or "", s.t
    k, closest = _closest(s, h)
    text = f"closest {closest:.2f} m at t={t[k]:.1f} s"
    kind = cc.criterion.kind
    if kind in ("stops_near_robot", "blocks_robot"):
        speed = s.get(f"speed_{h}")
        near = (s.get(f"dist_{h}") <= (cc.distance or 0)) & in_window(cc, s, cc.seconds or 0.0)
        text += f"; slowest while within {cc.distance:g} m: {speed[near].min():.2f} m/s" if near.any() else \
            f"; never within {cc.distance:g} m"
        if kind == "stops_near_robot" and not (s.get(f"closer_{h}") >= APPROACH).any():
            text += "; the robot never came any closer than at the start"
        text += walk_off_text(cc, s)
    elif kind == "hidden_until":
        reach = notice_range(cc.distance or 0.0)
        seen = _first((s.get(f"los_{h}") > 0.5) & (s.get(f"dist_{h}") <= reach))
        if seen is not None:
            text += (f"; first in sight within {reach:g} m at t={t[seen]:.1f} s, "
                     f"{s.get(f'dist_{h}')[seen]:.2f} m apart")
            return text, float(t[seen]), float(s.get(f"dist_{h}")[seen])
        text += f"; never in sight within {reach:g} m"
    elif kind == "gives_way":
        way = way_cause(cc, s)
        text += (f"; in the robot's way within {cc.distance:g} m for {way.sum() * s.trace.dt:.1f} s"
                 + (f" ({' or '.join((h, *cc.together))}, giving way together)" if cc.together else ""))
        first = _first(way)
        if first is not None:
            aside = _first((s.get(f"aside_{h}") > 0.5) & (np.arange(len(t)) >= first))
            text += (f", first at t={t[first]:.1f} s; " + (f"stepped aside at t={t[aside]:.1f} s" if aside is not None
                                                          else f"{h} never stepped out of it itself"
                                                          + _undone_text(s, h, "give_way")))
            text += _late_text(cc, s, h, way) if aside is not None else ""
        elif way_cause(cc, s, asked=False).any():
            text += f"; in its way only before {h} was asked to move (its trigger never held while in the way)"
    elif kind == "says" and cc.phrase:
        first = _first(s.get(f"{h}_says_{cc.phrase}") > 0.5)
        text += f"; {h} said {words(cc.phrase)} first at t={t[first]:.1f} s" if first is not None else \
            f"; {h} never said {words(cc.phrase)}"
    elif kind == "follows_robot":
        text += _follow_text(cc, s, h)
    return text + window_text(s, cc.window), float(t[k]), closest


def _follow_text(cc: Compiled, s: Signals, h: str) -> str:
    """How far the follower fell behind whom it follows (the robot, or the person of follows_human)."""
    o, t = cc.leader, s.t
    way = s.get(f"way_{h}" if o == "robot" else f"way_{h}_{o}")
    first = 0
    if cc.phrase:
        said = _first(s.get(f"robot_says_{cc.phrase}") > 0.5)
        if said is None:
            return f"; the robot never said {words(cc.phrase)}"
        first = said
    k = first + int(np.argmax(way[first:]))
    straight = float(contact.lengths(s.pos(h)[k] - s.pos(o)[k]))
    text = (f"; the robot said {words(cc.phrase)} at t={t[first]:.1f} s" if cc.phrase else "") + \
        (f"; farthest {'after it ' if cc.phrase else ''}{way[k]:.2f} m from {'the robot' if o == 'robot' else o} "
         f"along the walkable way at t={t[k]:.1f} s")
    if way[k] > straight + 0.5:
        text += f" ({straight:.2f} m straight, through a wall)"
    if not (s.get(f"speed_{h}")[first:] > WALK_SPEED).any():
        text += f"; {h} never walked after it"
    elif o != "robot" and not ((s.get(f"speed_{h}") > WALK_SPEED) & (s.get(f"speed_{o}") > WALK_SPEED))[first:].any():
        text += f"; {h} and {o} never walked at the same time"
    return text


def _follower_evidence(cc: Compiled, s: Signals) -> Evidence:
    """follows_human: about the follower and whom it follows; how close the robot came says nothing of it."""
    h = cc.human or ""
    way = s.get(f"way_{h}_{cc.leader}")
    said = _first(s.get(f"robot_says_{cc.phrase}") > 0.5) if cc.phrase else 0
    k = (said or 0) + int(np.argmax(way[said or 0:]))  # the farthest after the cause, as the text says
    return _follow_text(cc, s, h)[2:] + window_text(s, cc.window), float(s.t[k]), float(way[k])


def _group_evidence(cc: Compiled, s: Signals) -> Evidence:
    name = cc.formula.split("(")[1].split()[0]
    spread = s.get(name)
    k = int(np.argmax(spread))
    return f"widest {spread[k]:.2f} m at t={s.t[k]:.1f} s (needs <= {cc.distance:g} m)", float(s.t[k]), float(spread[k])


def _goal_evidence(cc: Compiled, s: Signals) -> Evidence:
    to_goal = s.get("robot_to_goal")
    short = s.get("short_of_goal") > 0.5
    reached = _first(((to_goal <= (cc.distance or 0)) | short) & (s.get("route_done") > 0.5))
    if reached is not None:
        how = f", {to_goal[reached]:.2f} m short of it at a social distance from someone standing there" \
            if to_goal[reached] > (cc.distance or 0) else ""
        return f"reached at t={s.t[reached]:.1f} s{how}", float(s.t[reached]), float(to_goal[reached])
    text = f"ended {to_goal[-1]:.2f} m from the goal (closest {to_goal.min():.2f} m, radius {cc.distance:g} m)"
    if not s.get("route_done")[-1]:
        text += "; it never came near every waypoint of its route before the goal"
    if s.trace.end_reason:
        text += f"; simulation ended by {s.trace.end_reason}"
        meta = s.trace.meta if isinstance(s.trace.meta, dict) else {}
        if s.trace.end_reason == "timeout" and isinstance(meta.get("timeout"), int | float):
            why = meta.get("timeout_why")
            text += f" (its limit {meta['timeout']:g} s" + (f": {why})" if isinstance(why, str) and why else ")")
    stalled = s.get("stalled")
    if stalled[-1] > 0:
        text += f"; the robot stood still for the last {stalled[-1]:.1f} s"
    return text, float(s.t[-1]), float(to_goal[-1])


def _people_evidence(cc: Compiled, s: Signals) -> Evidence:
    return people_evidence(cc.human, s)


def _collision_evidence(cc: Compiled, s: Signals) -> Evidence:
    summary = s.contacts()
    return summary.describe(), summary.min_gap_time, summary.min_gap


def deadlock_culprit(s: Signals) -> tuple[int, str | None]:
    """Step of the longest deadlock and the human holding the robot up then (the one with the smallest gap)."""
    dead = s.get("deadlock")
    k = int(np.argmax(dead))
    best, who = np.inf, None
    holding = s.holding_up()
    for i, name in enumerate(s.trace.human_names):
        if holding[k, i]:
            gap = float(s.gaps()[k, i])
            if gap < best:
                best, who = gap, name
    return k, who


def _deadlock_evidence(cc: Compiled, s: Signals) -> Evidence:
    dead = s.get("deadlock")
    k, who = deadlock_culprit(s)
    idle = idle_fact(s) if dead[k] < (cc.seconds or DEADLOCK_SECONDS) else None
    if idle:  # no_deadlock's other half: idle with its way clear (verify/idle.py)
        return idle, float(s.t[int(np.argmax(s.get("idle")))] - float(np.max(s.get("idle"))) + s.trace.dt), None
    if dead[k] <= 0:
        return "the robot was never stuck behind someone", None, None
    start = s.t[k] - dead[k] + s.trace.dt
    gap = float(s.gaps()[k, s.human(who)]) if who else None
    first = max(0, k - int(round(dead[k] / s.trace.dt)) + 1)
    driven = float(contact.lengths(np.diff(s.pos("robot")[first:k + 1], axis=0)).sum())
    how = "stood still" if driven < 2 * PROGRESS_STEP else \
        f"moved {driven:.1f} m without progress along its route (back and forth in place)"
    text = f"the robot {how} {dead[k]:.1f} s from t={start:.1f} s with {who or 'someone'} in its way"
    if gap is not None:
        text += f" ({gap:.2f} m gap)"
    return text, float(start), gap


def _stl_evidence(cc: Compiled, s: Signals) -> Evidence:
    """The step that decides the formula and its signals' values then (verify/witness.py); failing that, what
    the formula's signals did: each distance's minimum and when, each 0/1 signal's first true step."""
    from socnavgen.verify.witness import decisive

    found = decisive(cc.formula, s)
    if found is not None:
        return found[1], found[0], None
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


def _robot_stop_evidence(cc: Compiled, s: Signals) -> Evidence:
    """How slow the robot was at the place: home_03's robot crept through its greeting stop at 0.25 m/s."""
    enc = cc.encounter
    near = s.get(f"robot_to_{enc.id}") <= (cc.distance or 0) if enc is not None else np.ones(len(s.t), bool)
    if not near.any():
        return f"the robot never came within {cc.distance:g} m of {enc.id if enc else 'the place'}", None, None
    speed = s.get("speed_robot")
    k = int(np.flatnonzero(near)[np.argmin(speed[near])])
    still = (s.get("robot_still") > 0.5) & near
    return (f"slowest within {cc.distance:g} m of {enc.node if enc else 'the place'}: {speed[k]:.2f} m/s at "
            f"t={s.t[k]:.1f} s; stood still there {still.sum() * s.trace.dt:.1f} s in all (needs {cc.seconds:g} s at "
            f"once)"), float(s.t[k]), None


def _stop_together_evidence(cc: Compiled, s: Signals) -> Evidence:
    """The closest the named people came while all of them stood still."""
    names = list(dict.fromkeys(cc.criterion.humans or [cc.human or ""]))
    still = np.all([s.get(f"speed_{h}") <= STOP_SPEED for h in names], axis=0)
    widest = np.max([s.get(f"way_{a}_{b}") for a, b in combinations(names, 2)], axis=0)
    if not still.any():
        k = int(np.argmin(widest))
        return (f"{' and '.join(names)} never stood still at the same time (closest together {widest[k]:.2f} m at "
                f"t={s.t[k]:.1f} s)"), float(s.t[k]), float(widest[k])
    k = int(np.flatnonzero(still)[np.argmin(widest[still])])
    return (f"while all stood still, closest together {widest[k]:.2f} m at t={s.t[k]:.1f} s (needs <= "
            f"{cc.distance:g} m for {cc.seconds:g} s)"), float(s.t[k]), float(widest[k])


EVIDENCE: dict[str, Callable[[Compiled, Signals], Evidence]] = {
    "robot_stops": _robot_stop_evidence, "stop_together": _stop_together_evidence,
    "meets": _meets_evidence, "reacts_after_phrase": _phrase_evidence, "group_together": _group_evidence,
    "robot_reaches_goal": _goal_evidence, "no_collision": _collision_evidence, "no_deadlock": _deadlock_evidence,
    "people_apart": _people_evidence, "stl": _stl_evidence, "follows_human": _follower_evidence,
}  # every other kind of criteria.CRITERION_KINDS: _human_evidence


def evidence(cc: Compiled, s: Signals) -> Evidence:
    fn = EVIDENCE.get(cc.criterion.kind, _human_evidence)
    text, time, dist = fn(cc, s)
    if cc.notes:
        text += " (" + "; ".join(cc.notes) + ")"
    return text, time, dist
