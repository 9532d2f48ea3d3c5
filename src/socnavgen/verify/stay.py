"""A stop that must last while the robot is near (a `stop` part on robot_near with no `lasts`): where the person
stood and when they walked off with the robot still there - stops_near_robot's evidence and blame of such a walk.

Why it matters: people standing in the way of a robot that waits for them make room (sim.people.make_room). A
person whose text and tree say they stay while the robot goes round them, who then steps away because the robot
waited in front of them, did not stay (home_10: two chatting friends who "stay where they are" stood 1 s, walked
1-1.5 m away, and the robot drove through where the group stood). When the simulator's make-room moved them, the
tree is not at fault: the robot found no way round them, which the spec decides (who gives way, where they stand).
"""

from __future__ import annotations

import numpy as np

from socnavgen.sim.trace import GIVE_WAY_BEHAVIOR
from socnavgen.verify.criteria import Compiled, stay_reach, stays_while_near
from socnavgen.verify.models import Verdict
from socnavgen.verify.perceived import seen_hold
from socnavgen.verify.runs import lasting
from socnavgen.verify.signals import Signals
from socnavgen.verify.thresholds import STOP_HOLD, STOP_SPEED, WALK_SPEED


def walked_off(cc: Compiled, s: Signals) -> tuple[int, int, float] | None:
    """(step of their first stand within the criterion's distance, first step after it they walked with the robot
    still within the stop's distance, that distance) for a stops_near_robot whose stop lasts while the robot is
    near; None when it is no such stop, they never stood, or never walked off meanwhile."""
    near = stays_while_near(cc.part) if cc.criterion.kind == "stops_near_robot" else None
    h = cc.human
    if near is None or not h or cc.distance is None:
        return None
    dist, speed, dt = s.get(f"dist_{h}"), s.get(f"speed_{h}"), s.trace.dt
    stood = lasting((dist <= cc.distance) & (speed <= STOP_SPEED), seen_hold(STOP_HOLD, dt), dt)
    if not stood.any():
        return None
    first, stay = int(np.argmax(stood)), stay_reach(cc.distance, near)
    walks = (speed > WALK_SPEED) & (dist <= stay) & (np.arange(len(dist)) > first)
    return (first, int(np.argmax(walks)), stay) if walks.any() else None


def walk_off_text(cc: Compiled, s: Signals) -> str:
    """'; stood from t=16.9 s, then walked off at t=24.5 s (0.45 m/s) with the robot still 1.9 m away' or ''."""
    found = walked_off(cc, s)
    if found is None:
        return ""
    first, k, stay = found
    h = cc.human
    return (f"; stood from t={s.t[first]:.1f} s, then walked off at t={s.t[k]:.1f} s "
            f"({s.get(f'speed_{h}')[k]:.2f} m/s) with the robot still {s.get(f'dist_{h}')[k]:.1f} m away (within "
            f"{stay:g} m: the stop lasts while it is near)")


def stay_broken(cc: Compiled, s: Signals) -> Verdict | None:
    """Rule R8: the person stood, then walked off while the robot was still near. Made room for the robot waiting
    in front of them (the simulator's make-room, their tree still standing them) -> spec; their own tree walked
    them -> behaviors(h)."""
    found = walked_off(cc, s)
    h = cc.human
    if found is None or not h:
        return None
    first, k, stay = found
    i = s.trace.human_names.index(h)
    when = f"stood from t={s.t[first]:.1f} s and walked off at t={s.t[k]:.1f} s with the robot {s.get(f'dist_{h}')[k]:.1f} m away"
    soon = k + int(round(STOP_HOLD / s.trace.dt)) + 1  # the walk is seen from speeds averaged round each step
    if (s.trace.behavior_state[k:soon, i] == GIVE_WAY_BEHAVIOR).any():
        return ("spec", None,
                f"{h} {when}, making room for the robot that waited in front of them (people standing in the way of "
                f"a waiting robot step aside): the robot found no way round {h}, who is to stay while it passes; "
                f"let {h} give way instead (reaction give_way), or place the meeting where the robot has room to go "
                f"round {h}")
    return ("behaviors", h, f"{h} {when}: the stop lasts while the robot is within {stay:g} m (no `lasts`); keep "
                            f"{h} standing while IsRobotNearby holds")
