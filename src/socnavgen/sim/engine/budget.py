"""The run's time limit when nobody sets one: the ONE rule (simulate, verify, generate --verify and the
prompts that tell a model how long its scenario may take all follow it).

    limit = max(FLOOR, SLACK x (route length / cruise speed + the script's waits) + MARGIN)

The route length is the robot's waypoint polyline; its cruise speed the script's (the slowest a `speed` cue
sets), else the policy's max_speed; the waits are every `wait` cue once, CLEAR_PATIENCE x (CLEAR_REPEATS + 1)
for each `wait_until_clear` cue (the longest it stands before going around) and the robot's start delay.
SLACK leaves time for slowing near people, waiting behind them and making way; MARGIN for the encounters.
A fixed limit (the CLI's --timeout, SimConfig.timeout) overrides it.
"""

from __future__ import annotations

import math
from typing import Any, NamedTuple

import numpy as np

from socnavgen.limits import MAX_SIM_SECONDS, MAX_SIM_STEPS
from socnavgen.run.spec import RobotScript
from socnavgen.sim.robot.script import CLEAR_PATIENCE, CLEAR_REPEATS

FLOOR = 120.0  # s: no run gets less (every run had this limit before it followed the route)
SLACK = 2.0  # x the time the route takes at its cruise speed
MARGIN = 30.0  # s on top
DEFAULT_SPEED = 0.6  # m/s: the cruise speed of a robot that states none (the script's default)
RULE_TEXT = (f"the run's time limit is twice the time the robot's route takes at its cruise speed, plus its "
             f"script's waits, plus {MARGIN:g} s, and never less than {FLOOR:g} s")


class TimeLimit(NamedTuple):
    seconds: float
    why: str  # how it was set, in words (the trace's meta `timeout_why`; the verifier quotes it)


def time_limit(waypoints: Any, speed: float | None, script: RobotScript | None = None,
               start_delay: float = 0.0, dt: float = 0.05) -> TimeLimit:
    """The limit for a robot driving `waypoints` (complex or (x, y) points) at `speed` m/s (None: the script's
    cruise speed, else DEFAULT_SPEED) playing `script` (see the module's docstring)."""
    points = np.array([complex(*p) if not isinstance(p, complex) else p for p in waypoints], dtype=complex)
    length = float(np.abs(np.diff(points)).sum()) if len(points) > 1 else 0.0
    cruise = script.speed if script is not None else (speed or DEFAULT_SPEED)
    if script is not None:
        cruise = min([cruise, *(c.speed for c in script.cues if c.speed is not None and c.speed > 0)])
    if speed:
        cruise = min(cruise, speed)
    cruise = max(cruise, 0.05)
    waits = max(start_delay, 0.0)
    if script is not None:
        waits += sum(c.wait + (CLEAR_PATIENCE * (CLEAR_REPEATS + 1) if c.wait_until_clear else 0.0)
                     for c in script.cues)
    drive = length / cruise
    wanted = SLACK * (drive + waits) + MARGIN
    cap = min(MAX_SIM_SECONDS, MAX_SIM_STEPS * dt)
    seconds = min(max(FLOOR, math.ceil(wanted)), cap)
    why = (f"{length:.1f} m of route at {cruise:g} m/s = {drive:.0f} s" + (f", {waits:.0f} s of waits" if waits
           else "") + f": {SLACK:g} x that + {MARGIN:g} s = {wanted:.0f} s")
    why += f", at least {FLOOR:g} s" if wanted < FLOOR else f", at most {cap:g} s" if wanted > cap else ""
    return TimeLimit(float(seconds), why)
