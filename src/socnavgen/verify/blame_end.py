"""Blame rules for a robot that did not get to its goal when no tree is to blame (verify/blame.py applies them;
docs/verify.md's table):

- D5 the robot held up by someone who walked to its own goal, at or next to the robot's goal: the plan ends a
  person where the robot must arrive; no tree can fix that                                          -> paths
- R3 the robot ended standing still with nobody in its way, a cue of its script holding it then (a timed
  `wait` not over, `wait_until_clear` with someone ahead within its distance, a cue that set its speed to 0
  and none that set it going again): the trace's cue log (meta `script_cues_fired`) says which  -> robot_script
- R5 ... with no cue holding it (the log says so): the robot failed to progress on its own, the simulator's
  navigation; no stage can fix it (report it)                                                       -> simulator
- R2's reason when the run timed out with the robot moving but getting nowhere (no_progress_at_end): it was not
  "still on its way" (hospital_10 of round 14: 100 s edging about 0.4 m from a junction with a family of four
  round it was told "its route takes longer than the run")
"""

from __future__ import annotations

import numpy as np

from socnavgen import proxemics
from socnavgen.run.models import PathPlan
from socnavgen.run.spec import RobotCue, ScenarioSpec
from socnavgen.sim.people.spots import REACH, RING_STEP, RINGS
from socnavgen.sim.robot.script import describe
from socnavgen.verify.criteria import Compiled
from socnavgen.verify.models import Verdict
from socnavgen.verify.signals import Signals
from socnavgen.verify.thresholds import HELD_ON, PROGRESS_STEP, STILL_SPEED

GOAL_AREA = RINGS * RING_STEP + REACH  # m: how far round its goal point a person who walked there stands (sim spots)
WALKING_NODES = ("RegularNav", "UpdateGoal", "IsGoalReached")  # the tree just walks the person its path (to its goal)
SIMULATOR_NOTE = ("the robot's own navigation failed (the simulator's, not the scenario's): no stage of the model can "
                  "fix it; report it")


def _node(s: Signals, name: str) -> str:
    return name[5:] if name.startswith("node_") else name


def goal_taken(s: Signals, plan: PathPlan | None, who: str, k: int) -> Verdict | None:
    """Rule D5: `who` holds the robot up at step k standing round its own goal (its last path node, within
    GOAL_AREA: on it or on a spot round it, sim/people/spots; not with the robot between it and that goal: held up on
    its way there), its tree only walking it there (WALKING_NODES),
    and that goal is at or next to the robot's goal (within GOAL_AREA of it): the plan ends `who` where the robot
    must arrive. A person at its own goal there is never its tree's fault."""
    mine = next((h.path for h in (plan.humans if plan is not None else []) if h.name == who and h.path), None)
    goal = s.places.get(f"node_{mine[-1]}") if mine else None
    robot_goal = s.places.get("goal")
    if mine is None or goal is None or robot_goal is None or not 0 <= k < s.trace.steps:
        return None
    if float(np.hypot(*(s.pos(who)[k] - np.asarray(goal)))) > GOAL_AREA:
        return None
    began = max(0, k - int(round(float(s.get("deadlock")[k]) / s.trace.dt)) + 1)  # where the hold began
    here = s.pos(who)[began]
    to_goal, to_robot = np.asarray(goal) - here, s.pos("robot")[began] - here
    if float(np.dot(to_goal, to_robot)) > 0 and float(np.hypot(*to_robot)) < float(np.hypot(*to_goal)):
        return None  # the robot stood between them and their goal: held up on their way, not arrived (D2, D4)
    apart = float(np.hypot(*(np.asarray(goal) - np.asarray(robot_goal))))
    if apart > GOAL_AREA:
        return None
    i = s.human(who)
    window = s.trace.action[max(0, k - int(round(1.0 / s.trace.dt))):k + 1, i]
    names = {s.trace.node_names[a] for a in window if a >= 0}
    if names - set(WALKING_NODES):
        return None  # a node of its tree keeps it there (a stop, a look, a block...): its tree's (D2, D4)
    robot_node = plan.robot[-1] if plan is not None and plan.robot else "its last node"
    where = "on the robot's goal" if apart < 0.05 else f"{apart:.1f} m from the robot's goal {robot_node}"
    dead = float(s.get("deadlock")[k])
    when = f"{dead:.0f} s from t={s.t[k] - dead + s.trace.dt:.1f} s" if dead > 0 else f"at t={s.t[k]:.1f} s"
    return ("paths", None, f"{who}'s path ends at {mine[-1]}, {where}, and {who} stood there, at its own goal, in the "
                           f"robot's way ({float(s.gaps()[k, i]):.2f} m gap, {when}): the plan ends a person "
                           "where the robot must arrive, which no tree can change; end that person's path elsewhere "
                           "(a node off the robot's goal and out of its way in), or end the robot's route elsewhere")


def _cue_events(s: Signals, cues: list[RobotCue]) -> list[tuple[float, str, list[int]]] | None:
    """(t, event text, indices of the cues it may be) of the trace's cue log, None when the trace has no log."""
    log = (s.trace.meta or {}).get("script_cues_fired")
    if not isinstance(log, list):
        return None
    texts = [describe(c) for c in cues]
    out = []
    for entry in log:
        if isinstance(entry, (list, tuple)) and len(entry) == 2 and isinstance(entry[1], str):
            out.append((float(entry[0]), entry[1], [n for n, text in enumerate(texts) if text == entry[1]]))
    return out


def _holding(s: Signals, spec: ScenarioSpec, settings_deadlock: float,
             events: list[tuple[float, str, list[int]]]) -> str | None:
    """What of the script held the robot standing at the end of the run, from its cue log, or None."""
    cues, end = spec.script.cues, float(s.t[-1])
    speed, speed_by = spec.script.speed, None
    held = []
    for n, (t, text, which) in enumerate(events):
        for c in which:
            cue = cues[c]
            if cue.speed is not None:
                speed, speed_by = cue.speed, (c, t)
            if cue.wait and t + cue.wait > end - settings_deadlock:
                held.append(f"cue {c + 1} ({text}, at t={t:.1f} s) waits until t={t + cue.wait:.1f} s")
            gave_up = any(e[0] >= t and e[1].endswith("go around") for e in events[n + 1:])
            if cue.wait_until_clear and not gave_up:
                reach = max(cue.trigger.distance, proxemics.HELD_UP_DISTANCE)
                ahead = [h for i, h in enumerate(s.trace.human_names)
                         if s.in_way(i)[-1] and s.distances()[-1, i] <= reach]
                if ahead:
                    held.append(f"cue {c + 1} ({text}, at t={t:.1f} s) waits until nobody is within {reach:g} m "
                                f"ahead ({', '.join(ahead)} is)")
    if speed < STILL_SPEED:
        by = f"cue {speed_by[0] + 1} set its speed to {speed:g} at t={speed_by[1]:.1f} s" if speed_by else \
            f"its script's speed is {speed:g}"
        go = [n + 1 for n, c in enumerate(cues) if c.speed is not None and c.speed >= STILL_SPEED
              and not any(n in e[2] for e in events)]
        held.append(by + (f" and cue {', '.join(map(str, go))} that would set it going never fired" if go else ""))
    return "; ".join(held) or None


def standing_at_end(s: Signals, spec: ScenarioSpec, settings_deadlock: float) -> Verdict | None:
    """Rules R3 and R5: the robot ended standing still for longer than the deadlock limit with nobody in its way.
    With the trace's cue log: the script when a cue of it held the robot then, else the simulator. Without a log
    (a trace from elsewhere): the script when it has cues that can make the robot stand."""
    stalled, in_way = s.get("stalled"), s.blocked()
    if not s.trace.steps or stalled[-1] < settings_deadlock or in_way[-1]:
        return None
    still = f"the robot stood still for its last {stalled[-1]:.0f} s with nobody in its way"
    events = _cue_events(s, spec.script.cues)
    if events is None:
        waits = [c for c in spec.script.cues if c.wait or c.wait_until_clear or c.trigger.when == "human_says"
                 or (c.speed is not None and c.speed < STILL_SPEED)]
        if not waits and spec.script.speed >= STILL_SPEED:
            return None
        return ("robot_script", None, f"{still}: a cue of its script may keep it waiting (wait, wait_until_clear, a "
                                      "speed of 0 or a phrase that never comes); shorten the wait or change its trigger")
    holding = _holding(s, spec, settings_deadlock, events)
    if holding:
        return "robot_script", None, f"{still}, its script holding it: {holding}; shorten the wait or change its trigger"
    fired = "; ".join(f"t={t:.1f} s {text}" for t, text, _ in events) or "none fired"
    return ("simulator", None, f"{still} ({_where(s)}) and no cue of its script holding it (its cues: {fired}): "
                               f"{SIMULATOR_NOTE}")


def _where(s: Signals) -> str:
    left = float(s.get("robot_to_goal")[-1]) if "goal" in s.places else None
    nodes = [(float(np.hypot(*(s.pos("robot")[-1] - np.asarray(p)))), _node(s, n)) for n, p in s.places.items()
             if n.startswith("node_")]
    parts = [f"{left:.1f} m from its goal" if left is not None else "", f"nearest node {min(nodes)[1]}" if nodes else ""]
    return ", ".join(p for p in parts if p) or "short of its goal"


STUCK_AT_END = 10.0  # s without PROGRESS_STEP of progress along its route: a robot at the timeout was stuck, not slow


def no_progress_at_end(s: Signals, where: str) -> str | None:
    """Rule R2's reason for a robot that timed out getting nowhere for its last STUCK_AT_END s or more: how long,
    and who stood within proxemics.HELD_UP_DISTANCE of it then (not in its way by the verifier's notion: round it,
    where it must pass)."""
    progress = s.get("progress")
    if s.trace.end_reason != "timeout" or progress.size == 0:
        return None
    since = int(np.argmax(progress >= progress[-1] - PROGRESS_STEP))
    idle = float(s.t[-1] - s.t[since])
    if idle < STUCK_AT_END:
        return None
    near = near_at_end(s)
    fact = f"the robot made no progress along its route for its last {idle:.0f} s ({where})"
    if near:
        return f"{fact}, {near}"
    return f"{fact}, nobody near it: its route does not get it through there (check the route's nodes)"


def near_at_end(s: Signals) -> str:
    """'' or what to say of the people within proxemics.HELD_UP_DISTANCE of the robot at the run's end (nearest
    first): not in its way by the swept-width rule, yet where it must pass."""
    gaps = s.gaps()[-1]
    near = [s.trace.human_names[i] for i in np.argsort(gaps) if s.distances()[-1, i] <= proxemics.HELD_UP_DISTANCE]
    if not near:
        return ""
    return (f"with {', '.join(near)} within {proxemics.HELD_UP_DISTANCE:g} m of it, beside its way: people stand "
            "where it must pass (it keeps a margin from people and does not squeeze past them); have them step "
            "aside to a wider place, or end their reaction or their path farther from the robot's route, or route "
            "the robot round them")


def never_released(cc: Compiled, s: Signals) -> Verdict:
    """Rule W1: the stop's distance still covered the robot where the run ended (the implied walks_on failed): where
    the two end is stage 2's (the --verify loop sends it to stage 1, the stop's distance, when it fails again after
    the paths changed)."""
    h, near = (cc.part.human, cc.part.distance) if cc.part is not None else ("", None)
    gap = float(s.get(f"dist_{h}")[-1])
    return ("paths", None, f"{h} still stood at the end of the run with the robot {gap:.1f} m away, inside the "
                           f"{near:g} m its stop lasts for (robot_near, no `lasts`), for the run's last "
                           f"{HELD_ON:g} s: it never walks on along its path; the robot must end farther from where "
                           f"{h} stops than that (or the stop needs a shorter distance, or `lasts` seconds)")


def short_of_goal(s: Signals) -> str:
    """Rule R2's reason, with what the robot did: still on its way when the run ended, or standing short of it."""
    points = np.asarray(s.trace.robot_waypoints, dtype=float).reshape(-1, 2)
    total = float(np.hypot(*np.diff(points, axis=0).T).sum()) if len(points) > 1 else 0.0
    left = max(total - float(s.route()[0][-1]), 0.0) if total else float(s.get("robot_to_goal")[-1])
    stalled = float(s.get("stalled")[-1])
    where = f"{left:.1f} m of its route left{where_robot(s)}"
    stuck = no_progress_at_end(s, where)
    if stuck:
        return stuck
    if stalled < 1.0 and s.trace.end_reason == "timeout":
        return (f"the robot was still on its way when the simulation ended at t={s.t[-1]:.0f} s ({where}), nobody "
                "holding it up: its route takes longer than the run; make it shorter (or the robot faster)")
    near = near_at_end(s)
    if near:  # not in its way by the swept-width rule, yet where it must pass (round 30: a child 1.1 m off it)
        return f"the robot ended standing still for its last {stalled:.0f} s with {where}, {near}"
    return (f"the robot ended standing still for its last {stalled:.0f} s with {where} and nobody near it: its "
            "route does not bring it to its goal (check the route's last nodes)")


def where_robot(s: Signals) -> str:
    """', nearest node N' of where the robot ended (or '' without node places), for the reasons above."""
    nodes = [(float(np.hypot(*(s.pos("robot")[-1] - np.asarray(p)))), n[5:]) for n, p in s.places.items()
             if n.startswith("node_")]
    return f", nearest node {min(nodes)[1]}" if nodes else ""
