"""Blame rule F1 (verify/blame.py applies it; docs/verify.md's table): a follows_human criterion failed, its
cause having held. The follower is measured against whom it follows, never against the robot (warehouse_10 of
round 13: a worker filing behind another was blamed for not reacting to the robot).

- the person followed never walked while the follower could follow: nobody to follow   -> behaviors(followed)
- otherwise the follower fell behind (or never walked with them)                           -> behaviors(follower)

Rule F2 for follows_robot (ahead_of_robot): when the robot set off after the phrase that starts the follow, the
follower stood ahead of it along its way (where it was going): there was nothing to follow from there -> paths

Rule N3 for any follower (never_near_start): it was never near its encounter's place within S s after the phrase
(or at all, with no phrase), so the following could not start there                      -> paths"""

from __future__ import annotations

import numpy as np

from socnavgen.verify.criteria import Compiled
from socnavgen.verify.models import Verdict
from socnavgen.verify.signals import Signals
from socnavgen.verify.thresholds import FOLLOW_AHEAD, WALK_SPEED
from socnavgen.verify.windows import held_within


def blame_follower(cc: Compiled, s: Signals, h: str) -> Verdict:
    """Rule F1 for h following cc.leader (a person)."""
    o, d = cc.leader, cc.distance or 0.0
    if not (s.get(f"speed_{o}") > WALK_SPEED).any():
        return "behaviors", o, (f"{o} never walked, so {h} had nobody to follow (follows_human): {o}'s tree must "
                                f"walk its path")
    way = s.get(f"way_{h}_{o}")
    k = int(np.argmax(way))
    return "behaviors", h, (f"{h} did not keep within {d:g} m of {o}, whom it follows (follows_human): "
                            f"{way[k]:.2f} m behind at t={s.t[k]:.1f} s; its tree must follow {o} (FollowHuman) "
                            "for good once its cue held")


def never_near_start(cc: Compiled, s: Signals, h: str) -> Verdict | None:
    """Rule N3 for follows_robot / follows_human: h never came near its place (W + D of the encounter's node)
    within S s after the robot said the phrase (the phrase is heard anywhere: a group called from across the room
    walks up and falls in), or never at all without a phrase."""
    if cc.encounter is None:
        return None
    there = s.get(f"{h}_to_{cc.encounter.id}") <= cc.encounter.within + (cc.distance or 0.0)
    if cc.phrase:
        said = s.get(f"robot_says_{cc.phrase}") > 0.5
        there &= held_within(said, int(round((cc.seconds or 0.0) / s.trace.dt)))  # said in the last S s
    if there.any():
        return None
    node = cc.encounter.node or cc.encounter.id
    heard = (f" within {cc.seconds or 0.0:g} s after the robot said {cc.phrase.replace('_', ' ').upper()}"
             if cc.phrase else "")
    return "paths", None, f"{h} was never near {node}{heard}: the following must start there"


def ahead_of_robot(cc: Compiled, s: Signals, h: str) -> Verdict | None:
    """Rule F2: when the robot set off after the phrase that starts the follow, h stood ahead of it along
    the way it drives (lag below -FOLLOW_AHEAD): a follower placed on the robot's route ahead of it, with nothing to
    follow from there (round 35's home_27: the guest started at the robot's goal; the player read "did not react as
    asked" and loosened the criteria instead of moving her)."""
    if not cc.phrase:  # a follow the robot's coming starts (robot_near, robot_visible): someone waiting on its route
        return None  # who falls in behind once it has passed is no follower placed ahead (round 29's hospital_19)
    said = np.flatnonzero(s.get(f"robot_says_{cc.phrase}") > 0.5)
    if not said.size:
        return None
    lag, start = s.get(f"lag_{h}"), int(said[0])
    driving = np.flatnonzero(s.get("speed_robot")[start:] > WALK_SPEED)
    if not driving.size:
        return None
    k = start + int(driving[0])
    if lag[k] >= -FOLLOW_AHEAD:
        return None
    return "paths", None, (f"{h} stood {-lag[k]:.1f} m ahead of the robot along its way when it set off at "
                           f"t={s.t[k]:.1f} s after its cause: a follower on the robot's route ahead of it has "
                           "nothing to follow; start them behind or beside the robot's start, not on its route ahead")
