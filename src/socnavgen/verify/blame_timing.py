"""Blame rules for failures whose timing the spec sets (verify/blame.py applies them; docs/verify.md's table):
asking a person's tree to fix them asks the impossible, whatever the tree does.

- a block that ends as it begins: the person blocks `until` a robot phrase, and the robot says it on a `blocked`
  cue reaching where a blocker stands (sim/people/leaves.BLOCK_AHEAD)                                -> spec
- an encounter's window that closes before the robot comes near the person: the robot was within reach of them
  only after the window (the next encounter began: its node close to this one, or its `within` wide)   -> spec
- a stop seen only before the approach: the person stood in front of the robot while it was near, but never once
  the two had come APPROACH closer than at the start (they stood from t = 0 while the robot drove away; round 38's
  scene A): no tree makes a stop happen after an approach the scenario never has                       -> spec"""

from __future__ import annotations

import numpy as np

from socnavgen.run.spec import ScenarioSpec
from socnavgen.sim.people.leaves import BLOCK_AHEAD
from socnavgen.verify.criteria import Compiled
from socnavgen.verify.evidence import in_window
from socnavgen.verify.models import Verdict
from socnavgen.verify.signals import Signals, phrase_id
from socnavgen.verify.thresholds import APPROACH, STOP_SPEED


def ended_at_once(cc: Compiled, s: Signals, spec: ScenarioSpec, h: str) -> Verdict | None:
    """h's block ends (`until`) on a phrase a `blocked` cue says from as far as a blocker stands."""
    if cc.criterion.kind != "blocks_robot":
        return None
    for enc, part in spec.parts_of(h):
        if part.reaction != "block" or not part.until or (cc.encounter is not None and enc.id != cc.encounter.id):
            continue
        said = (s.get(f"robot_says_{phrase_id(part.until)}") > 0.5).any()
        for n, cue in enumerate(spec.script.cues, 1):
            if said and cue.say == part.until and cue.trigger.when == "blocked" and cue.trigger.distance >= BLOCK_AHEAD:
                return "spec", None, (f"cue {n} says {part.until} when someone is within {cue.trigger.distance:g} m "
                                      f"ahead, and a blocker stands {BLOCK_AHEAD:g} m ahead: {h}'s block ends "
                                      "(`until`) as it begins; give the block `lasts`, or say the phrase later (an "
                                      "`after` cue)")
    return None


def window_closed_early(cc: Compiled, s: Signals, h: str, reach: float) -> Verdict | None:
    """The robot came within `reach` of h, but only after the criterion's encounter window had closed."""
    if not cc.window or cc.encounter is None:
        return None
    win, near = in_window(cc, s), s.get(f"dist_{h}") <= reach
    if not win.any() or (near & win).any() or not near.any():
        return None
    end, first = float(s.t[np.flatnonzero(win)[-1]]), float(s.t[int(np.argmax(near))])
    return "spec", None, (f"{cc.encounter.id}'s window ended at t={end:.1f} s, before the robot first came within "
                          f"{reach:g} m of {h} (t={first:.1f} s): the next encounter began too early; give it a "
                          f"smaller `within`, or a place farther on from {cc.encounter.node or cc.encounter.id}")


def stood_before_approach(cc: Compiled, s: Signals, h: str) -> Verdict | None:
    """stops_near_robot: h stood still within the criterion's distance of the robot only before the two had come
    APPROACH closer than at the start (the stop the criterion asks for comes after an approach)."""
    if cc.criterion.kind != "stops_near_robot" or cc.distance is None:
        return None
    near = s.get(f"dist_{h}") <= cc.distance
    stood = near & (s.get(f"speed_{h}") <= STOP_SPEED)
    approached = s.get(f"closer_{h}") >= APPROACH
    if not stood.any() or (stood & np.maximum.accumulate(approached)).any():
        return None
    t = s.t[stood]
    after = (f"first at t={float(s.t[int(np.argmax(approached))]):.1f} s, when {h} no longer stood"
             if approached.any() else "never")
    return "spec", None, (f"{h} stood still within {cc.distance:g} m of the robot (t={float(t[0]):.1f}-"
                          f"{float(t[-1]):.1f} s) only before the two had come {APPROACH:g} m closer than at the start "
                          f"({after}): a stop counts after an approach; have the robot come towards {h} while they "
                          f"wait, or state a wait from the start by an stl on moved_{h} (always (moved_{h} < 0.5) "
                          "until ...)")
