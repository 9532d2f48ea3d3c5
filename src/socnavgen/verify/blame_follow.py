"""Blame rule F1 (verify/blame.py applies it; docs/verify.md's table): a follows_human criterion failed, its
cause having held. The follower is measured against whom it follows, never against the robot (warehouse_10 of
round 13: a worker filing behind another was blamed for not reacting to the robot).

- the person followed never walked while the follower could follow: nobody to follow   -> behaviors(followed)
- otherwise the follower fell behind (or never walked with them)                           -> behaviors(follower)

Rule N3 for any follower (never_near_start): it was never near its encounter's place within S s after the phrase
(or at all, with no phrase), so the following could not start there                      -> paths"""

from __future__ import annotations

import numpy as np

from socnavgen.verify.criteria import Compiled
from socnavgen.verify.models import Verdict
from socnavgen.verify.signals import Signals
from socnavgen.verify.thresholds import WALK_SPEED
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
