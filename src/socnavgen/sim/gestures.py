"""Scripted robot speech: PathPlan.robot_gestures rules (e.g. say EXCUSE ME (4) while someone blocks the way)
and the cues of spec.json's robot script (say, wait, change speed), executed by RobotScriptRunner.

Rules are checked in order every step; the first one whose condition held within its last `duration`
seconds sets the gesture (HuNavSim keeps the last /robot_gesture value, so a gesture persists while held).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from socnavgen.bt.library import HUMAN_GESTURES, ROBOT_GESTURES
from socnavgen.run.models import RobotGestureRule
from socnavgen.run.spec import RobotCue, RobotScript

FRONT_CONE = 0.6  # rad: "in front of the robot" for the `blocked` condition


class ScriptedGestures:
    def __init__(self, rules: list[RobotGestureRule], node_points: dict[str, complex]) -> None:
        self.rules = list(rules)
        self.node_points = node_points
        self.last_true = [-math.inf] * len(self.rules)

    def condition(self, rule: RobotGestureRule, sim: Any) -> bool:
        if rule.when == "always":
            return True
        if rule.when == "at_node":
            point = self.node_points.get(rule.node or "")
            return point is not None and abs(point - sim.robot_pos) <= 1.0
        if sim.crowd.n == 0:
            return False
        if rule.when == "near_human":
            return bool((np.abs(sim.crowd.pos - sim.robot_pos) <= rule.distance).any())
        return person_in_way(sim, rule.distance)

    def gesture(self, sim: Any) -> int:
        for k, rule in enumerate(self.rules):
            if self.condition(rule, sim):
                self.last_true[k] = sim.t
            if sim.t - self.last_true[k] <= rule.duration:
                return rule.gesture
        return 0


# ---- the robot's script of spec.json (run/spec.py RobotScript) -----------------------------------
ROBOT_PHRASE_CODE = {name: code for code, name in ROBOT_GESTURES.items() if code}
HUMAN_PHRASE_CODE = {name: code for code, name in HUMAN_GESTURES.items() if code}
CLEAR_DISTANCE = 1.5  # m: `wait_until_clear` waits until nobody is in the robot's way this close


@dataclass
class CueState:
    """What the script asks of the robot now; every policy sees it as `obs.cues`."""

    say: int = 0  # robot gesture code the script makes now (0: none)
    wait: bool = False  # stand still now (a scripted wait, or waiting until the way is clear)
    speed: float = 0.6  # cruise speed (m/s) the script sets
    misbehave: bool = False  # the scenario wants a rude robot (no stopping for people)
    fired: list[tuple[float, str]] = field(default_factory=list)  # (t, cue) of every cue fired so far


def person_in_way(sim: Any, distance: float) -> bool:
    """Someone within `distance` (centres) ahead of the robot's direction of travel, in its way."""
    if sim.crowd.n == 0:
        return False
    rel = sim.crowd.pos - sim.robot_pos
    near = np.abs(rel) <= distance
    local = rel * sim.robot_direction().conjugate()
    ahead = (np.abs(np.angle(local)) <= FRONT_CONE) | ((local.real > 0) & (np.abs(local.imag) <
                                                                            sim.crowd.radius + sim.robot_radius))
    return bool((near & ahead).any())


class RobotScriptRunner:
    """Executes the cues of a RobotScript: each step, which cues fire (a `once` cue fires the first time its
    trigger holds, the others each time it becomes true), and from that what the robot says, whether it
    stands still and at what speed it cruises."""

    def __init__(self, script: RobotScript, encounter_points: dict[str, complex]) -> None:
        self.script = script
        self.points = encounter_points
        n = len(script.cues)
        self.fired = [0] * n
        self.was_true = [False] * n
        self.say_until = [-math.inf] * n
        self.wait_until = [-math.inf] * n
        self.until_clear = [False] * n
        self.state = CueState(speed=script.speed, misbehave=script.misbehave)

    def _holds(self, cue: RobotCue, sim: Any) -> bool:
        trig = cue.trigger
        if trig.when == "start":
            return True
        if trig.when == "after":
            return sim.t >= trig.seconds
        if trig.when == "at_encounter":
            point = self.points.get(trig.encounter or "")
            return point is not None and abs(point - sim.robot_pos) <= trig.distance
        if trig.when == "blocked":
            return person_in_way(sim, trig.distance)
        who = _human_index(trig.human, sim.crowd.n)
        if trig.when == "human_within":
            d = np.abs(sim.crowd.pos - sim.robot_pos)
            return bool(d.size and (d[who] <= trig.distance if who is not None else (d <= trig.distance).any()))
        code = HUMAN_PHRASE_CODE.get(trig.phrase or "", -1)  # human_says
        shown = np.asarray(sim.crowd.gesture) == code
        return bool(shown.size and (shown[who] if who is not None else shown.any()))

    def update(self, sim: Any) -> CueState:
        t, state = sim.t, self.state
        for k, cue in enumerate(self.script.cues):
            now = self._holds(cue, sim)
            rising = now and not self.was_true[k]
            self.was_true[k] = now
            if not rising or (cue.once and self.fired[k]):
                continue
            self.fired[k] += 1
            if cue.say:
                self.say_until[k] = t + cue.hold
            if cue.wait:
                self.wait_until[k] = t + cue.wait
            self.until_clear[k] = cue.wait_until_clear
            if cue.speed is not None:
                state.speed = cue.speed
            state.fired.append((round(t, 3), _describe(cue)))
        say, wait = 0, False
        for k, cue in enumerate(self.script.cues):
            if cue.say and t < self.say_until[k]:
                say = ROBOT_PHRASE_CODE[cue.say]  # the latest cue in script order wins
            if t < self.wait_until[k]:
                wait = True
            elif self.until_clear[k]:
                self.until_clear[k] = person_in_way(sim, max(cue.trigger.distance, CLEAR_DISTANCE))
                wait = wait or self.until_clear[k]
        state.say, state.wait = say, wait
        return state


def _human_index(name: str | None, n: int) -> int | None:
    """humanK -> agent id K-1 (None: any human, or a name beyond the crowd)."""
    if not name:
        return None
    k = int(name[5:]) - 1
    return k if 0 <= k < n else None


def _describe(cue: RobotCue) -> str:
    trig = cue.trigger
    what = [f"say {cue.say}" if cue.say else "", f"wait {cue.wait:g} s" if cue.wait else "",
            "wait until clear" if cue.wait_until_clear else "", f"speed {cue.speed:g}" if cue.speed is not None else ""]
    return f"{trig.when}: " + ", ".join(w for w in what if w)
