"""Giving way: the step aside (`aside`: out of the robot's way, having moved off its route by itself; moved here
from verify/signals.py, which re-exports it) and letting the robot through: a step aside counts only if the person
stays out of the robot's way until the robot has got past them (issue 25, hospital_08 of the new-request suite: three nurses stepped aside after
EXCUSE ME and closed up again round the robot while it was still in the gap; it had to back out and go round
them, and every give-way criterion passed on the step aside).

- back in the way: the person is again on the robot's route just ahead of it, in the corridor its body sweeps
  (route.ahead_on_route, within proxemics.HELD_UP_DISTANCE along it); without a route, ahead along its heading
  within that distance. The robot turning toward someone standing aside does not put them back in its way;
- past: the robot has come at least as far along its route as the person (without a route: the person is no
  longer ahead of the robot along its heading).

A step aside at step k is kept when, after k, the robot gets past the person before the person is back in its
way (or the person is never back in its way).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from socnavgen import proxemics
from socnavgen.sim import contact
from socnavgen.sim.people.give_way import PASSED_MARGIN
from socnavgen.sim.trace import YAW
from socnavgen.verify.route import ahead_on_route, route_offset, route_progress
from socnavgen.verify.thresholds import ASIDE_DISTANCE

CLOSING_STEP = 1e-3  # m per step: two people whose distance shrinks by more than this are closing up
REGROUP_PAUSE = 1.0  # s: two who parted for the robot may stand this long before they start closing up again

Signals = Any  # a verify.signals.Signals (which calls in here: importing it back would make a cycle)


def aside(s: Signals, human: str) -> np.ndarray:
    """1 where the human is out of the robot's way having moved ASIDE_DISTANCE from where it last stood in it
    (0 before it was ever in the way): evidence that the person made way, not that the robot went around.

    With a route (two or more waypoints), "in the way" is ahead along the robot's heading, or on the route (within
    the corridor its body sweeps: robot + person radius + WAY_MARGIN_VERIFY) ahead of the robot along it, round bends
    too, within proxemics.HELD_UP_DISTANCE along it (the one notion of someone holding the robot up: a visitor who
    starts on the route 5 m ahead round a bend and walks off it to wait by a door stepped aside from nothing,
    hospital_01); where it stood is where it last stood so ON the route (a robot turning toward someone who already
    stepped off does not undo the step). Stepping aside: gaining ASIDE_DISTANCE from the route since that stand
    began."""
    i = s.human(human)
    way = s.in_way(i)
    p = s.pos(human)
    points = list(s.trace.robot_waypoints)
    steps = np.arange(s.trace.steps)
    if len(points) < 2:
        last = np.maximum.accumulate(np.where(way, steps, -1)) if len(steps) else steps
        moved_off = contact.lengths(p - p[np.maximum(last, 0)]) >= ASIDE_DISTANCE
        return ~way & (last >= 0) & moved_off
    half = float(s.trace.robot_radius) + float(np.asarray(s.trace.human_radii, dtype=float)[i]) \
        + proxemics.WAY_MARGIN_VERIFY
    off = route_offset(p, points)
    ahead = route_progress(p, points, near=s.route()[0])[0] - s.route()[0]
    corridor = off < half
    way = way | (corridor & (ahead > 0.0) & (ahead <= proxemics.HELD_UP_DISTANCE))
    stood = way & corridor
    last = np.maximum.accumulate(np.where(stood, steps, -1))
    ref = np.maximum(last, 0)
    closest = off.copy()  # per step of a stand: the nearest to the route it came during that stand
    edges = np.flatnonzero(np.diff(np.concatenate([[0], stood.astype(np.int8), [0]])))
    for a, b in zip(edges[::2], edges[1::2], strict=True):
        closest[a:b] = off[a:b].min()
    gained = off - closest[ref]
    moved_off = gained >= ASIDE_DISTANCE  # the route stays put: only the person's own steps change `off`
    return ~way & (last >= 0) & moved_off


def _next(mask: np.ndarray) -> np.ndarray:
    """(T,) for each step the first step at or after it where `mask` holds (T when none)."""
    n = len(mask)
    idx = np.where(mask, np.arange(n), n)
    return np.minimum.accumulate(idx[::-1])[::-1] if n else idx


def got_past(s: Signals, human: str) -> np.ndarray:
    """(T,) bool: the robot is level with or past `human` (along its route; else along its heading)."""
    p = s.pos(human)
    points = list(s.trace.robot_waypoints)
    if len(points) >= 2:
        return route_progress(p, points, near=s.route()[0])[0] <= s.route()[0]
    rel = p - s.pos("robot")
    yaw = s.trace.robot[:, YAW]
    return rel[:, 0] * np.cos(yaw) + rel[:, 1] * np.sin(yaw) <= 0.0


def gone_by(s: Signals, human: str) -> np.ndarray:
    """(T,) bool: the robot has gone by `human` as the simulator's giver-way judges it (sim/people/give_way
    .robot_has_passed): beyond their spot along its route (else its heading) by both radii + PASSED_MARGIN, and
    that far from them. Until then a person standing aside is still letting it by."""
    i = s.human(human)
    clear = float(s.trace.robot_radius) + float(np.asarray(s.trace.human_radii, dtype=float)[i]) + PASSED_MARGIN
    p = s.pos(human)
    points = list(s.trace.robot_waypoints)
    if len(points) >= 2:
        beyond = s.route()[0] - route_progress(p, points, near=s.route()[0])[0]
    else:
        rel = p - s.pos("robot")
        yaw = s.trace.robot[:, YAW]
        beyond = -(rel[:, 0] * np.cos(yaw) + rel[:, 1] * np.sin(yaw))
    return (beyond > clear) & (s.distances()[:, i] > clear)


def back_in_way(s: Signals, human: str) -> np.ndarray:
    """(T,) bool: `human` is on the robot's route just ahead of it (module doc)."""
    i = s.human(human)
    points = list(s.trace.robot_waypoints)
    if len(points) < 2:
        return s.in_way(i) & (s.distances()[:, i] <= proxemics.HELD_UP_DISTANCE)
    half = float(s.trace.robot_radius) + float(np.asarray(s.trace.human_radii, dtype=float)[i]) \
        + proxemics.WAY_MARGIN_VERIFY
    return ahead_on_route(s.route()[0], s.pos(human), points, half, proxemics.HELD_UP_DISTANCE,
                          float(s.trace.robot_radius))


def kept_aside(s: Signals, human: str, stepped: np.ndarray) -> np.ndarray:
    """`stepped` (`aside`) on the steps after which the person stays out of the robot's way until it has got
    past them (module doc); and from such a step on while the robot is past them and they are not back in its
    way: the person let it through, walking back behind it (to the spot or the group they left) undoes nothing
    (warehouse_08, first answer: a packer who parted for the robot and closed up with the others once it was past
    her failed gives_way when another packer came into its way as it turned on at the corner)."""
    stepped = np.asarray(stepped, dtype=bool)
    if not stepped.any():
        return stepped
    back = back_in_way(s, human)
    n = len(stepped)
    after = np.minimum(np.arange(n) + 1, n - 1)
    past = got_past(s, human)
    next_back, next_past = _next(back)[after], _next(past)[after]
    last = np.arange(n) == n - 1
    kept = stepped & (last | (next_back >= n) | (next_past < next_back))
    through = (past & ~back).tolist()
    out = kept.tolist()
    for k in range(1, n):  # a let-through lasts while the robot stays past them and they stay out of its way
        out[k] = out[k] or (out[k - 1] and through[k])
    return np.asarray(out, dtype=bool)


def undone(s: Signals, human: str, stepped: np.ndarray) -> tuple[float, float] | None:
    """(when it first stepped aside, when it was back in the robot's way before it got past) for a person whose
    every step aside was undone, else None."""
    stepped = np.asarray(stepped, dtype=bool)
    if not stepped.any() or kept_aside(s, human, stepped).any():
        return None
    k = int(np.flatnonzero(stepped)[0])
    back = np.flatnonzero(back_in_way(s, human)[k:])
    return float(s.t[k]), float(s.t[k + int(back[0])]) if len(back) else float(s.t[-1])


def short_step(s: Signals, human: str, start: int, stop: int) -> tuple[float, float, float, float] | None:
    """(when, how far it moved off the route, how far from the route it then stood, the corridor's half width) for
    a person who, between steps `start` and `stop`, moved ASIDE_DISTANCE or more off the robot's route but stayed
    inside the corridor its body sweeps (the half width `aside` uses); None otherwise or without a route
    (warehouse_07 of round 14: a prompt 0.46 m step to 0.77 m from the route's corner, the corridor 0.85 m)."""
    points = list(s.trace.robot_waypoints)
    if len(points) < 2 or stop <= start:
        return None
    i = s.human(human)
    half = float(s.trace.robot_radius) + float(np.asarray(s.trace.human_radii, dtype=float)[i]) \
        + proxemics.WAY_MARGIN_VERIFY
    off = route_offset(s.pos(human)[start:stop + 1], points)
    k = int(np.argmax(off))
    if off[k] - off[0] < ASIDE_DISTANCE or off[k] >= half:
        return None
    return float(s.t[start + k]), float(off[k] - off[0]), float(off[k]), half


def parted_for_robot(s: Signals, a: int, b: int) -> np.ndarray:
    """(T,) bool: two people (human indices a, b) are apart to let the robot through: the robot's centre is
    between them (its projection inside the segment joining them, within its radius + GIVE_WAY_CLEARANCE of
    it), or its heading crosses that segment within proxemics.HELD_UP_DISTANCE ahead (it is about to pass
    between them), or either executes GiveWaytoRobot with the robot within HELD_UP_DISTANCE of them, or either
    stands aside (`aside`) for the robot within that distance and not yet gone by them (`gone_by`, the simulator's
    own 'passed': warehouse_08, a packer waiting beside the robot's next leg until it has gone by her;
    warehouse_05, a worker at the aisle edge until the sweeping robot is a body length past); and for REGROUP_PAUSE after such a step
    whatever they do (the robot's heading swinging off the gap, or onto the one aside, for a moment: warehouse_08),
    and on while they are closing up again (their distance shrinking step by step). A group's cohesion (`spread`) is judged outside these steps: a group that parts for
    the robot and closes again is a group, one whose member leaves is not (hospital_08)."""
    pos = s.trace.humans[:, :, :2]
    robot = s.trace.robot[:, :2]
    seg = pos[:, b] - pos[:, a]
    rel = robot - pos[:, a]
    u = np.einsum("ij,ij->i", rel, seg) / (np.einsum("ij,ij->i", seg, seg) + 1e-12)
    off = contact.lengths(rel - u[:, None] * seg)
    between = (u > 0.0) & (u < 1.0) & (off <= float(s.trace.robot_radius) + proxemics.GIVE_WAY_CLEARANCE)
    hx, hy = np.cos(s.trace.robot[:, YAW]), np.sin(s.trace.robot[:, YAW])
    cross = seg[:, 0] * hy - seg[:, 1] * hx  # where robot + k * heading meets a + j * seg: j, k below
    safe = np.where(np.abs(cross) > 1e-9, cross, np.inf)
    j = (rel[:, 0] * hy - rel[:, 1] * hx) / safe
    k = (rel[:, 0] * seg[:, 1] - rel[:, 1] * seg[:, 0]) / safe
    between |= (j > 0.0) & (j < 1.0) & (k >= 0.0) & (k <= proxemics.HELD_UP_DISTANCE)
    near = [contact.lengths(robot - pos[:, i]) <= proxemics.HELD_UP_DISTANCE for i in (a, b)]
    parted = between | (s.trace.executed(a, "GiveWaytoRobot") & near[0]) | (s.trace.executed(b, "GiveWaytoRobot") & near[1])
    for i, close in zip((a, b), near, strict=True):  # one still standing aside for a robot not yet gone by them
        name = s.trace.human_names[i]
        parted |= (s.get(f"aside_{name}") > 0.5) & ~gone_by(s, name) & close
    change = np.diff(contact.lengths(seg), prepend=np.inf)
    t = np.asarray(s.trace.t, dtype=float)
    out, ended = parted.copy(), -np.inf
    for k in range(1, len(parted)):  # the closing-up after a parting continues it
        if parted[k]:
            ended = t[k]
            continue
        out[k] = out[k - 1] and (change[k] < -CLOSING_STEP or t[k] - ended <= REGROUP_PAUSE)
    return out
