"""Rule N3 for an encounter's cue on where the robot is (robot_visible / robot_near / robot_blocking): the person's
part reacts to the robot's place and that never held in the run, so the tree had nothing to react to.

Who can fix it depends on how far off the trigger was (issue 25: a capable model's triggers missed by a hair):

- a wall always between them while within the distance (robot_visible, robot_blocking), or the robot never
  within the distance by more than NEAR_MISS: where they meet is the paths' to change            -> paths
- the robot came within the distance, in sight, but never in front of them (robot_blocking: IsRobotBlocking's
  cone, bt.library.BLOCKING_CONE; a robot letting them pass stands beside their way), or missed the distance by
  NEAR_MISS or less (it stood where its own cue stopped it, 2.77 m from a 2.7 m trigger): the trigger itself,
  with the trigger and distance the run shows would have held                                     -> spec

The message always says how close the robot came (and, for robot_blocking, how far off the person's heading).
"""

from __future__ import annotations

import math

import numpy as np

from socnavgen.bt.library import BLOCKING_CONE
from socnavgen.run.spec import Blame, ScenarioSpec
from socnavgen.verify.criteria import Compiled
from socnavgen.verify.signals import Signals, runlength
from socnavgen.verify.windows import off_heading, triggered

Verdict = tuple[Blame, str | None, str]

NEAR_MISS = 1.0  # m: a trigger distance the robot missed by this much or less is the trigger's (spec), not the place's
MARGIN = 0.5  # m: a trigger distance advised is the closest the robot came plus this, rounded up to STEP
STEP = 0.5  # m
SEEN_CUES = {"robot_visible": "in sight of", "robot_near": "near", "robot_blocking": "in front of"}


def advised(closest: float, distance: float) -> float:
    """A trigger distance that holds where the robot came: its closest plus MARGIN, rounded up, at least `distance`."""
    return max(distance, math.ceil((closest + MARGIN) / STEP - 1e-9) * STEP)


def cue_never_held(cc: Compiled, s: Signals, h: str, spec: ScenarioSpec | None = None) -> Verdict | None:
    """The verdict when h's encounter cue never held (None when it held, or cannot be told from the trace)."""
    part = cc.part
    if part is None or part.trigger not in SEEN_CUES or part.distance is None:
        return None
    held = triggered(s, h, part)
    if held is None or held.any():
        return None
    d, dist, los = part.distance, s.get(f"dist_{h}"), s.get(f"los_{h}") > 0.5
    k = int(np.argmin(dist))
    still = " (the robot standing still there)" if s.get("robot_still")[k] > 0.5 else ""
    fact = f"closest {dist[k]:.2f} m at t={s.t[k]:.1f} s{still}"
    node = cc.encounter.node or cc.encounter.id if cc.encounter is not None else "its place"
    head = f"the robot was never {SEEN_CUES[part.trigger]} {h} within {d:g} m"
    within = dist <= d
    seen = within & los
    if part.trigger != "robot_near" and within.any() and not seen.any():
        return "paths", None, (f"{head} ({fact}, always with a wall between them while within it): {h}'s cue never "
                               f"held; make the robot's path end or pass where {h} at {node} sees it")
    if part.trigger == "robot_blocking" and seen.any():
        off = np.degrees(off_heading(s, h))
        j = int(np.argmin(np.where(seen, off, np.inf)))
        aside = _let_pass(spec, h)
        fix = (f"robot_visible {d:g} m (in sight within it from t={s.t[int(np.argmax(seen))]:.1f} s) or robot_near "
               f"(both hold whichever way {h} faces)")
        return "spec", None, (f"{head} ({fact}; in sight within {d:g} m it was at best {off[j]:.1f} degrees off the way "
                              f"{h} faced, at t={s.t[j]:.1f} s, {dist[j]:.2f} m away, where robot_blocking needs "
                              f"{math.degrees(BLOCKING_CONE):.1f}{aside}): {h}'s trigger never held, so the reaction "
                              f"never ran; give {h} a trigger that holds where the robot comes: {fix}")
    miss = float(dist[k]) - d
    if 0.0 < miss <= NEAR_MISS:
        more = advised(float(dist[k]), d)
        return "spec", None, (f"{head} ({fact}: missed by {miss:.2f} m): {h}'s trigger never held, so the reaction "
                              f"never ran; a trigger distance the robot reaches only by a hair fails on any change of "
                              f"its approach: give it {more:g} m or more (where the robot stands for its cues, plus a "
                              f"margin), or meet where the robot comes nearer")
    return "paths", None, (f"{head} ({fact}): {h}'s cue never held; make the robot's path end or pass where {h} at "
                           f"{node} sees it")


def _let_pass(spec: ScenarioSpec | None, h: str) -> str:
    """Why the robot stands off h's way: a let_pass cue for h (it waits beside their way)."""
    if spec is not None and any(cue.let_pass == h for cue in spec.script.cues):
        return f"; a robot letting {h} pass waits beside {h}'s way, never in front of {h}"
    return ""


def stop_not_held(cc: Compiled, s: Signals) -> Verdict:
    """robot_stops failed. A robot that stood at the place long enough in all, but never the criterion's seconds at
    once, had its stand broken (it steps aside for someone who must get past it while it waits): saying "a cue
    there must stop it" then misleads the model, whose wait cue is already there (round 24's player)."""
    enc = cc.encounter
    near = s.get(f"robot_to_{enc.id}") <= (cc.distance or 0) if enc is not None else np.ones(len(s.t), bool)
    still = (s.get("robot_still") > 0.5) & near
    runs = runlength(still, s.trace.dt)
    total, longest, needs = float(still.sum() * s.trace.dt), float(runs.max(initial=0.0)), cc.seconds or 0.0
    if needs > 0 and total >= needs:
        return ("robot_script", None,
                f"the robot stood still at the place {total:.1f} s in all but at most {longest:.1f} s at once (needs "
                f"{needs:g} s at once): something moved it during its wait (it steps aside for someone who must get "
                f"past it); ask for no longer a stop than it holds at once, or keep the others' ways off its spot")
    return "robot_script", None, "the robot did not stand still at the place: a cue there must stop it (wait)"
