"""Each acceptance-criterion kind of spec.json compiled to ONE STL formula over the named signals
(verify/signals.py): a registry (CRITERION_KINDS, like signals.SIGNAL_KINDS), one entry per kind with its
formula, why it cannot pass vacuously, how it is compiled and how its evidence is shown (verify/evidence.py).

h = the criterion's human, e = its encounter (named, else the first one h takes part in), D = distance,
S = seconds, W = the encounter's `within`, P = the robot phrase, A = thresholds.APPROACH. A meeting
`met(h, e)` is an approach, at the place:

  (dist_h <= D) and (mid_h_to_e <= W) and (closer_h >= A) and came(robot, e) and came(h, e),
  came(x, e) = (closer_x_to_e >= A) or (x_to_e + closer_x_to_e <= W)

(they came A closer to each other than at the start; each came A closer to the place, or waited at it from
the start: x_to_e + closer_x_to_e is x's distance to the place at the start), so a meeting at t = 0, or
between two bodies that never moved, is none. docs/verify.md shows the same table.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from itertools import combinations

from socnavgen.bodies import CONTACT_MARGIN
from socnavgen.run.spec import Criterion, Encounter, HumanPart, ScenarioSpec
from socnavgen.verify.models import VerifySettings
from socnavgen.verify.perceived import seen_hold
from socnavgen.verify.signals import phrase_id
from socnavgen.verify.stl import FormulaError
from socnavgen.verify.thresholds import (
    APPROACH,
    FOLLOW_AHEAD,
    FOLLOW_SEEN,
    IDLE_SECONDS,
    KIND_DISTANCE,
    NOTICE_RANGE,
    REACTION_SLACK,
    ROBOT_STOP_SECONDS,
    STOP_HOLD,
    STOP_NOTICE_RANGE,
    STOP_SPEED,
    WALK_SPEED,
)
from socnavgen.verify.windows import WINDOWED, encounters_of, window_name


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
    previous: Encounter | None = None  # meets: the earlier encounter of the same human, met before this one
    window: str | None = None  # during_<human>_<encounter>: judged in this encounter's window (verify/windows.py)
    together: tuple[str, ...] = ()  # gives_way: the others giving way with the human (giving_way_together)
    asked: bool = False  # gives_way: its clock starts once the human's own trigger held (_trigger_formula)
    leader: str = "robot"  # follows_robot / follows_human: whom the human follows (leader_of)
    notes: list[str] = field(default_factory=list)


@dataclass(frozen=True)
class Context:
    """What compiling a criterion needs besides the criterion."""

    spec: ScenarioSpec
    settings: VerifySettings
    goal_radius: float
    dt: float | None = None  # the trace's step: how long a stop is seen standing on it (perceived.seen_hold)


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


def came_to(who: str, place: str, within: float) -> str:
    """`who` came APPROACH closer to the place than at the start, or started within `within` of it (waiting
    there): x_to_p + closer_x_to_p is x's distance to the place at the start."""
    return f"((closer_{who}_to_{place} >= {APPROACH:g}) or (({who}_to_{place} + closer_{who}_to_{place}) <= {within:g}))"


def met_expression(h: str, enc: Encounter | None, distance: float) -> str:
    """The STL of "the robot meets h at e": within `distance`, at the place, after an approach (module doc)."""
    near = f"(dist_{h} <= {distance:g}) and (closer_{h} >= {APPROACH:g})"
    if enc is None:
        return f"({near})"
    return (f"({near} and (mid_{h}_to_{enc.id} <= {enc.within:g}) and {came_to('robot', enc.id, enc.within)} and "
            f"{came_to(h, enc.id, enc.within)})")


def previous_encounter(spec: ScenarioSpec, enc: Encounter, human: str) -> Encounter | None:
    """The encounter of `human` just before `enc` (by order, then as listed) where it is to be met (not one
    it avoids): two encounters never share one meeting."""
    order = encounters_of(spec, human)
    at = next((k for k, e in enumerate(order) if e.id == enc.id), None)
    return order[at - 1] if at else None


def _in_window(out: Compiled) -> str:
    """'(during_h_e > 0.5) and ' for a criterion judged in its encounter's window, else ''."""
    return f"{_b(out.window)} and " if out.window else ""


def _need_human(c: Criterion) -> str:
    if not c.human:
        raise FormulaError(f"criterion {c.id} ({c.kind}) names no `human`")
    return c.human


def _phrase(c: Criterion, part: HumanPart | None) -> str | None:
    word = c.phrase or (part.phrase if part is not None and part.trigger == "robot_says" else None)
    return phrase_id(word) if word else None


# ---- one compile function per kind: fills `out` (its formula and the facts its evidence needs) --------
def _meets(c: Criterion, ctx: Context, out: Compiled) -> None:
    members = [c.human] if c.human else list(c.humans)
    if not members:
        raise FormulaError(f"criterion {c.id} (meets) names no `human` (or `humans` of a group)")
    d = out.distance = c.distance or ctx.settings.distance
    enc = out.encounter
    if enc is None:
        out.notes.append("no encounter place: only the distance and the approach are checked")
    met = [met_expression(h, enc, d) for h in members]
    if len(members) == 1 and enc is not None:
        prev = out.previous = previous_encounter(ctx.spec, enc, members[0])
        if prev is not None:  # its own meeting: apart again after the one of the earlier encounter
            h = members[0]
            out.formula = (f"eventually ({met[0]} and (once ((dist_{h} > {d:g}) and (once "
                           f"{met_expression(h, prev, d)}))))")
            return
    out.formula = f"eventually ({' or '.join(met)})" if len(met) > 1 else f"eventually {met[0]}"


def _stops_near_robot(c: Criterion, ctx: Context, out: Compiled) -> None:
    h = _need_human(c)
    d = out.distance = c.distance or KIND_DISTANCE[c.kind]
    s = out.seconds = c.seconds or ctx.settings.reaction_seconds
    notice = max(d + 1.0, STOP_NOTICE_RANGE)  # the cause: the robot comes near (an approach, not where it started)
    # "in front of" either way round: the robot ahead of h (h faces it), or h ahead of the robot in its way (a
    # picker with its back to the robot that drove up behind it and stopped: warehouse_02). Beside or behind the
    # robot with h facing away is neither.
    front = f"({_b(f'ahead_{h}')} or {_b(f'inway_{h}')})"
    stand = (f"(always[0:{seen_hold(STOP_HOLD, ctx.dt):g}] ((dist_{h} <= {d:g}) and {front} and "
             f"(speed_{h} <= {STOP_SPEED:g})))")
    out.formula = (f"eventually ({_in_window(out)}(dist_{h} <= {notice:g}) and (closer_{h} >= {APPROACH:g}) and "
                   f"(eventually[0:{s:g}] {stand}))")
    near = stays_while_near(out.part)
    if near is not None:  # ... and once they stood, they do not walk off while the robot is still there (a later
        # stand somewhere else, where they went, is no stay)
        out.formula = (f"({out.formula}) and (always ((once ({_in_window(out)}{stand})) implies "
                       f"((speed_{h} <= {WALK_SPEED:g}) or (dist_{h} > {stay_reach(d, near):g}))))")


def stay_reach(distance: float, near: float) -> float:
    """While the robot is within this (m) a stop that lasts while it is near keeps the person standing: the
    criterion's distance, or the stop's less REACTION_SLACK where that is nearer (the stop ends as the robot crosses
    its distance and the person sets off then: round 32's home_26 walked at 0.35 m/s with the robot 2.45 m off a
    2.5 m stop)."""
    return max(min(distance, near - REACTION_SLACK), 0.0)


def stays_while_near(part: HumanPart | None) -> float | None:
    """The distance within which a stop part keeps the person standing while the robot is there (a stop on
    robot_near with no `lasts`: it lasts while the robot is near), else None (a timed stop, one on another
    trigger, or no such part). stops_near_robot then also needs them not to walk off after their stand while the
    robot is still within it (home_10: two friends who 'stay where they are' stood 1 s, then walked 1-1.5 m away
    from the robot waiting in front of them, and the robot drove through where the group stood)."""
    if part is None or part.reaction != "stop" or part.trigger != "robot_near" or part.lasts is not None:
        return None
    return part.distance if part.distance is not None else float("inf")


def _reacts_after_phrase(c: Criterion, ctx: Context, out: Compiled) -> None:
    h = _need_human(c)
    p = out.phrase = _phrase(c, out.part)
    r = out.reaction = c.reaction or (out.part.reaction if out.part is not None else None)
    if not p or not r:
        raise FormulaError(f"criterion {c.id}: reacts_after_phrase needs the robot's `phrase` and the `reaction`")
    s = out.seconds = c.seconds or ctx.settings.reaction_seconds
    react, says = f"react_{h}_{r}", f"robot_says_{p}"
    # caused by the phrase: for STOP_HOLD s around the moment it starts being said the person does not show the
    # reaction, and shows it within S s after. Walking before (a person who ran in, then stood in the robot's way) is no
    # reaction to it; one going on while the robot speaks (started before, without the cause) does not count.
    # A phrase said in the run's first STOP_HOLD s (a cue at the start) has no such moment before it: there the
    # person shows no reaction from the start until it is said.
    # Judged in the encounter's window (verify/windows.py) for a person met more than once: the phrase starts in it.
    w, inside = STOP_HOLD, _in_window(out)
    soon = f"(eventually[0:{w:g}] {_b(out.window)}) and " if out.window else ""
    out.formula = (f"(eventually ({soon}{_not(says)} and (always[0:{w:g}] {_not(react)}) and (eventually[0:{w:g}] "
                   f"{_b(says)}) and (eventually[0:{w + s:g}] {_b(react)}))) or ({inside}(eventually[0:{w:g}] "
                   f"{_b(says)}) and ({_not(react)} until ({_b(says)} and (eventually[0:{s:g}] {_b(react)}))))")


def reaction_reach(spec: ScenarioSpec, part: HumanPart | None) -> float | None:
    """How far from the robot a part's reaction can begin: its trigger's distance, or for a robot phrase the
    largest distance at which a cue of the script says it (None when the spec does not tell)."""
    if part is None:
        return None
    if part.trigger == "robot_says" and part.phrase:
        reach = [cue.trigger.distance for cue in spec.script.cues
                 if cue.say == part.phrase and cue.trigger.when in ("blocked", "human_within")
                 and cue.trigger.human in (None, part.human)]
        return max(reach, default=None)
    if part.trigger in ("robot_near", "robot_visible", "robot_blocking"):
        return part.distance
    return None


def giving_way_together(enc: Encounter | None, human: str) -> tuple[str, ...]:
    """The others who give way in the same encounter, on the same trigger: one of them in the robot's way is
    the cause for all (a group parting for the robot: one member stands in its way, the others beside)."""
    if enc is None:
        return ()
    mine = next((p for p in enc.humans if p.human == human), None)
    if mine is None or mine.reaction != "give_way":
        return ()
    return tuple(p.human for p in enc.humans if p.human != human and p.reaction == "give_way"
                 and (p.trigger, p.phrase) == (mine.trigger, mine.phrase))


def _trigger_formula(part: HumanPart | None, h: str) -> str | None:
    """The part's trigger as a formula over the signals (windows.triggered's rule), None when it has none the
    trace shows as such (always, time, another's phrase: the window and the cause time those)."""
    if part is None:
        return None
    if part.trigger == "robot_says" and part.phrase:
        return _b(f"robot_says_{phrase_id(part.phrase)}")
    if part.distance is None:
        return None
    near = f"(dist_{h} <= {part.distance:g})"
    return {"robot_near": near, "robot_visible": f"({near} and {_b(f'los_{h}')})",
            "robot_blocking": f"({near} and {_b(f'ahead_{h}')})"}.get(part.trigger)


def _gives_way(c: Criterion, ctx: Context, out: Compiled) -> None:
    h = _need_human(c)
    reach = reaction_reach(ctx.spec, out.part)  # in the way when the reaction was asked for counts, however far
    d = out.distance = max(c.distance or KIND_DISTANCE[c.kind], reach + REACTION_SLACK if reach else 0.0)
    s = out.seconds = c.seconds or ctx.settings.reaction_seconds
    out.together = giving_way_together(out.encounter, h)

    def cause(who: str) -> str:
        return f"((dist_{who} <= {d:g}) and {_b(f'inway_{who}')})"

    anyone = " or ".join(cause(who) for who in (h, *out.together))
    # h's clock starts once h's own trigger held (the phrase that asks them, the robot come near): in the way
    # before it, nobody had asked h to move yet (hospital_13's family, in the trailing robot's way from 2 s, asked
    # at 37 s); with others, another in the way is not h's cue to move either
    asked = _trigger_formula(out.part, h)
    out.asked = asked is not None
    cause_h = f"({_in_window(out)}({anyone}){f' and (once {asked})' if asked else ''})"
    react = _b(f"aside_{h}")
    if out.together:  # a member never in the way itself has made way by standing aside
        react = f"({react} or (not (once {cause(h)})))"
    out.formula = f"(eventually {cause_h}) and (always ({cause_h} implies (eventually[0:{s:g}] {react})))"


def leader_of(c: Criterion, part: HumanPart | None) -> str:
    """Whom a follows_* criterion measures its human against: the robot (follows_robot), or the person its
    follow_human reaction follows (follows_human: that reaction's `other`, never the robot)."""
    if c.kind != "follows_human":
        return "robot"
    if part is None or part.reaction != "follow_human" or not part.other:
        raise FormulaError(f"criterion {c.id}: follows_human needs a human whose encounter has the reaction "
                           "follow_human, naming whom they follow in `other`")
    return part.other


def follow_span(part: HumanPart | None, reaction_seconds: float) -> float | None:
    """How long a follow that ends by itself (its part has `lasts`: a toddler trails the robot 16 s, then goes back to
    the sofa) is judged: its `lasts` less the reaction's seconds to fall in (at least half of it). None: a follow to
    the end of the run (latched, or while its trigger holds), judged to the end (home_19's player swapped
    follows_robot for stops_near_robot because the follow was judged to the end of the run, where the toddlers had
    gone back as the text says, and stops_near_robot passed toddlers who never trailed the robot)."""
    if part is None or part.reaction not in ("follow", "follow_human") or part.lasts is None:
        return None
    return max(part.lasts - reaction_seconds, part.lasts / 2)


def _follows(c: Criterion, ctx: Context, out: Compiled) -> None:
    h = _need_human(c)
    d = out.distance = c.distance or KIND_DISTANCE[c.kind]
    p = out.phrase = _phrase(c, out.part)
    s = out.seconds = c.seconds or ctx.settings.reaction_seconds
    o = out.leader = leader_of(c, out.part)
    way = f"way_{h}" if o == "robot" else f"way_{h}_{o}"
    # following a person: both walk at once (two standing side by side follow no one); the robot drives anyway
    walks = f"(speed_{h} > {WALK_SPEED:g})" if o == "robot" else f"((speed_{h} > {WALK_SPEED:g}) and (speed_{o} > {WALK_SPEED:g}))"
    enc = out.encounter
    # following starts at its place: h is near it when it begins to follow (after the phrase: within S s of it,
    # so a group called from across the room walks up and falls in; the robot's phrase is heard anywhere)
    there = f"({h}_to_{enc.id} <= {enc.within + d:g}) and " if enc is not None else ""
    span = follow_span(out.part, s)
    keep, walk = (f"always[0:{span:g}]", f"eventually[0:{span:g}]") if span is not None else ("always", "eventually")
    # following the robot: walking after it while it drives, not ahead of it along its way, FOLLOW_SEEN s at least (one
    # who only walks up to it from in front, or stays ahead of it, never trails it: home_19's toddlers)
    if o == "robot":
        walks = f"always[0:{FOLLOW_SEEN:g}] ({walks} and (not {_b('robot_still')}) and (lag_{h} >= {-FOLLOW_AHEAD:g}))"
    follow = f"({there}({keep} ({way} <= {d:g})) and ({walk} {walks}))"
    out.formula = (f"eventually ({_b(f'robot_says_{p}')} and (eventually[0:{s:g}] {follow}))" if p
                   else f"eventually {follow}")


def notice_range(distance: float) -> float:
    """How close a visible robot is noticed (keeps_away's cause, hidden_until's sight): NOTICE_RANGE, or 2 m
    beyond the criterion's distance when that is larger. One notion of "seeing the robot": a robot in sight at the
    far end of a warehouse 50 s before the approach is not the one that appears round the rack."""
    return max(NOTICE_RANGE, distance + 2)


def noticed(h: str, distance: float) -> str:
    return f"({_b(f'los_{h}')} and (dist_{h} <= {notice_range(distance):g}))"


def _hidden_until(c: Criterion, ctx: Context, out: Compiled) -> None:
    h = _need_human(c)
    d = out.distance = c.distance or KIND_DISTANCE[c.kind]
    out.formula = f"(not {noticed(h, d)}) until ((dist_{h} <= {d:g}) and (closer_{h} >= {APPROACH:g}))"


def _group_together(c: Criterion, ctx: Context, out: Compiled) -> None:
    enc = out.encounter
    names = list(c.humans) or ([p.human for p in enc.humans] if enc is not None else [])
    if len(names) < 2:
        raise FormulaError(f"criterion {c.id}: group_together needs at least two `humans`")
    names = sorted(set(names), key=lambda n: int(n[5:]))
    d = out.distance = c.distance or ctx.settings.group_spread
    out.formula = f"always (spread_{'_'.join(names)} <= {d:g})"


def _says(c: Criterion, ctx: Context, out: Compiled) -> None:
    h = _need_human(c)
    if not c.phrase:
        raise FormulaError(f"criterion {c.id}: says needs the `phrase`")
    p = out.phrase = phrase_id(c.phrase)
    out.distance = c.distance
    out.formula = (f"eventually ({_b(f'{h}_says_{p}')} and (dist_{h} <= {c.distance:g}))" if c.distance
                   else f"eventually {_b(f'{h}_says_{p}')}")


def _keeps_away(c: Criterion, ctx: Context, out: Compiled) -> None:
    h = _need_human(c)
    d = out.distance = c.distance or KIND_DISTANCE[c.kind]
    seen = noticed(h, d)
    out.formula = f"(eventually {seen}) and (always ((once {seen}) implies (dist_{h} >= {d:g})))"


def _blocks_robot(c: Criterion, ctx: Context, out: Compiled) -> None:
    h = _need_human(c)
    d = out.distance = c.distance or KIND_DISTANCE[c.kind]
    out.formula = (f"eventually (always[0:{seen_hold(STOP_HOLD, ctx.dt):g}] ({_b(f'inway_{h}')} and (dist_{h} <= {d:g}) and "
                   f"(speed_{h} <= {STOP_SPEED:g}) and {_b('robot_still')}))")


def _robot_stops(c: Criterion, ctx: Context, out: Compiled) -> None:
    enc = out.encounter
    if enc is None:
        raise FormulaError(f"criterion {c.id}: robot_stops names the `encounter` at whose place the robot stands")
    w = out.distance = c.distance or enc.within
    s = out.seconds = c.seconds or ROBOT_STOP_SECONDS
    # a robot that only slows down there (home_03: 0.25 m/s through the greeting) or stands elsewhere does not
    # holding its place: standing, or stepping aside for someone coming past in the wait (not advancing)
    out.formula = (f"eventually ({came_to('robot', enc.id, w)} and (always[0:{s:g}] ({_b('robot_holds')} and "
                   f"(robot_to_{enc.id} <= {w:g}))))")


def _stop_together(c: Criterion, ctx: Context, out: Compiled) -> None:
    names = list(dict.fromkeys(c.humans or ([c.human] if c.human else [])))
    if len(names) < 2:
        raise FormulaError(f"criterion {c.id}: stop_together needs at least two `humans`")
    d = out.distance = c.distance or KIND_DISTANCE[c.kind]
    out.seconds = c.seconds or STOP_HOLD
    # each has walked (a stop, not two who stood there from the start), all stand at once, each within D of each
    # along the walkable way (never through a wall), for S s as seen; at the encounter's place when it names one
    parts = [f"{_b(f'moved_{h}')} and (speed_{h} <= {STOP_SPEED:g})" for h in names]
    parts += [f"(way_{a}_{b} <= {d:g})" for a, b in combinations(names, 2)]
    enc = out.encounter if c.encounter else None
    if enc is not None:
        parts += [f"({h}_to_{enc.id} <= {enc.within + d:g})" for h in names]
    out.formula = f"eventually (always[0:{seen_hold(out.seconds, ctx.dt):g}] ({' and '.join(parts)}))"


def _robot_reaches_goal(c: Criterion, ctx: Context, out: Compiled) -> None:
    d = out.distance = c.distance or ctx.goal_radius
    out.formula = f"eventually (((robot_to_goal <= {d:g}) or {_b('short_of_goal')}) and {_b('route_done')})"


def _no_collision(c: Criterion, ctx: Context, out: Compiled) -> None:
    gap = f"gap_{c.human}" if c.human else "gap_min"
    out.formula = f"always ({gap} > {CONTACT_MARGIN:g})"


def _people_apart(c: Criterion, ctx: Context, out: Compiled) -> None:
    gap = f"pgap_{c.human}" if c.human else "pgap_min"
    out.formula = f"always ({gap} > {CONTACT_MARGIN:g})"


def _no_deadlock(c: Criterion, ctx: Context, out: Compiled) -> None:
    s = out.seconds = c.seconds or ctx.settings.deadlock_seconds
    out.formula = f"always (deadlock < {s:g}) and always (idle < {IDLE_SECONDS:g})"  # nor idle with its way clear


def _stl(c: Criterion, ctx: Context, out: Compiled) -> None:
    if not c.formula:
        raise FormulaError(f"criterion {c.id}: kind stl needs a `formula`")
    out.formula = c.formula


@dataclass(frozen=True)
class CriterionKind:
    """One kind of acceptance criterion: its formula as documented, why it cannot pass vacuously, how it is
    compiled (`build`) and how its evidence is shown (verify/evidence.py, by the same name)."""

    name: str
    formula: str
    because: str
    build: Callable[[Criterion, Context, Compiled], None]


_IN_WINDOW = "; for a person met more than once, the cause inside its encounter's window (during_h_e)"
CRITERION_KINDS: dict[str, CriterionKind] = {k.name: k for k in (
    CriterionKind("meets", "eventually met(h, e)  (a second encounter of h: eventually (met(h, e) and once "
                  "((dist_h > D) and once met(h, e_before))))", "an approach at the place, its own meeting",
                  _meets),
    CriterionKind("stops_near_robot", "eventually ((dist_h <= max(D + 1, 3)) and (closer_h >= A) and "
                  "eventually[0:S] always[0:0.5] (dist_h <= D and (ahead_h or inway_h) and speed_h <= 0.1))  (a "
                  "stop on robot_near without `lasts`, within N of its trigger: and always ((once stood) implies "
                  "(speed_h <= 0.3 or dist_h > min(D, N - 0.5))))",
                  "the robot came near (they approached), then h stood still 1 s in front of it (seen standing 0.5 s: "
                  "speeds are as seen, verify/perceived.py; facing it, or in "
                  "its way); a stop lasting while the robot is near: from that stand on, h does not walk off while "
                  "it is still within the stop's distance (verify/stay.py)" + _IN_WINDOW,
                  _stops_near_robot),
    CriterionKind("reacts_after_phrase", "eventually (not robot_says_P and always[0:H] not react_h_R and "
                  "eventually[0:H] robot_says_P and eventually[0:H+S] react_h_R)", "h shows no reaction for H s "
                  "around the moment the phrase starts, then reacts within S s" + _IN_WINDOW,
                  _reacts_after_phrase),
    CriterionKind("gives_way", "eventually (dist_h <= D and inway_h)  and  always ((dist_h <= D and inway_h) "
                  "implies eventually[0:S] aside_h)  (D at least the reaction's trigger distance + 0.5; with others giving "
                  "way on the same trigger: any of them in the way is the cause, one never in it counts as aside)",
                  "h (or one giving way together with h) was in the robot's way and h moved out of it itself"
                  + _IN_WINDOW,
                  _gives_way),
    CriterionKind("follows_robot", "eventually (robot_says_P and eventually[0:S] (h_to_e <= W + D and (always "
                  "way_h <= D) and eventually always[0:2] (speed_h > 0.3 and not robot_still and lag_h >= -0.75)))  "
                  "(no P: eventually (h_to_e <= W + D and ...))",
                  "within S s after the phrase, from near its place on, within D along the walkable way to the "
                  f"end, walking after the driving robot {FOLLOW_SEEN:g} s at least, not ahead of it (lag_h >= "
                  f"-{FOLLOW_AHEAD:g}) (a follow whose part `lasts` L s: for max(L - S, L/2) s, not to the end)",
                  _follows),
    CriterionKind("follows_human", "follows_robot's formula with way_h_o (o: whom h's follow_human reaction "
                  "follows, its `other`) for way_h, and eventually (speed_h > 0.3 and speed_o > 0.3)",
                  "after its cause, near its place, within D of o along the walkable way to the end, both walking "
                  "at once (never measured against the robot)",
                  _follows),
    CriterionKind("hidden_until", "(not noticed) until (dist_h <= D and closer_h >= A), noticed = los_h and "
                  "dist_h <= max(5, D + 2)", "they must approach and come within D, unseen within the noticing range",
                  _hidden_until),
    CriterionKind("group_together", "always (spread_h1_h2... <= D)", "the whole run", _group_together),
    CriterionKind("says", "eventually (h_says_P and dist_h <= D)  (no D: eventually h_says_P)",
                  "the phrase shown", _says),
    CriterionKind("keeps_away", "eventually noticed and always (once noticed implies dist_h >= D), noticed = "
                  "los_h and dist_h <= max(5, D + 2)", "h must have seen the robot first", _keeps_away),
    CriterionKind("blocks_robot", "eventually always[0:0.5] (inway_h and dist_h <= D and speed_h <= 0.1 and "
                  "robot_still)", "a real 1 s standoff", _blocks_robot),
    CriterionKind("robot_stops", "eventually (came(robot, e) and always[0:S] (robot_holds and robot_to_e <= W))  "
                  "(W: its distance, else e's within; S: 2 s unless given)", "the robot came to the place and held it "
                  "S s: stood, or stepped aside for someone in its wait, never advancing (slowing down is no stop)",
                  _robot_stops),
    CriterionKind("stop_together", "eventually always[0:S] (each h: moved_h and speed_h <= 0.1; each pair: way_a_b "
                  "<= D; with an encounter: each h_to_e <= W + D)", "people who had walked stand still at once, "
                  "within D of each other along the walkable way, S s as seen (a greeting: nobody stands alone)",
                  _stop_together),
    CriterionKind("robot_reaches_goal", "eventually ((robot_to_goal <= D or short_of_goal) and route_done)",
                  "always judged; a round trip's goal counts on the way back", _robot_reaches_goal),
    CriterionKind("no_collision", "always (gap_min > 0.05)  (gap_h with a human)", "contact = gap <= 0.05 m",
                  _no_collision),
    CriterionKind("people_apart", "always (pgap_min > 0.05)  (pgap_h with a human)", "two people touching = their "
                  "gap <= 0.05 m (the robot's contact), from t = 0", _people_apart),
    CriterionKind("no_deadlock", f"always (deadlock < S) and always (idle < {IDLE_SECONDS:g})", "no progress along "
                  "the route counts, not standing; idle: none with its way clear and no cue asking it to wait",
                  _no_deadlock),
    CriterionKind("stl", "the criterion's own formula", "up to the author", _stl),
)}


def compile_criterion(c: Criterion, spec: ScenarioSpec, settings: VerifySettings,
                      goal_radius: float, dt: float | None = None) -> Compiled:
    """The STL formula of one criterion (FormulaError when the criterion is incomplete), for a trace of step `dt`."""
    enc, part = encounter_of(c, spec)
    out = Compiled(criterion=c, formula="", human=c.human, encounter=enc, part=part,
                   window=window_name(spec, c.human, enc) if c.kind in WINDOWED else None)
    kind = CRITERION_KINDS.get(c.kind)
    if kind is None:  # pragma: no cover - the Literal of spec.py lists every kind (tested against the registry)
        raise FormulaError(f"criterion {c.id}: unknown kind {c.kind!r}")
    kind.build(c, Context(spec=spec, settings=settings, goal_radius=goal_radius, dt=dt), out)
    return out
