"""Where the robot is along its route: progress (metres of the route covered) and the route's direction, per
step, from the trace's waypoints. A robot that jitters in place, backs up or turns on the spot makes no
progress; the deadlock signal counts time without progress, not time standing still."""

from __future__ import annotations

import bisect

import numpy as np

from socnavgen.sim import contact

TIE = 1e-6  # m: segments this equally near a point are the same place on a route that comes back over itself
#              (exact overlaps only: near a joint the first nearest wins as before, to the bit)
HEADING_RUN = 0.3  # m: on a shared stretch the robot drives the leg it has moved along over its last this many metres


def route_progress(robot_xy: np.ndarray, waypoints: list[tuple[float, float]],
                   near: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """(progress (T,), tangent (T, 2)): the arc length along the waypoint polyline of the point nearest each
    position, and that segment's unit direction. Without a polyline (fewer than two distinct waypoints) progress
    is the distance driven and the tangent zero.

    A route that comes back over itself (a patrol there and back, ef ... 8r ... ef) has two equally near
    segments (within TIE) at every point of the shared stretch: the one whose progress is nearest a reference
    wins (ties: the later one). The reference is `near` (T,) when given (a person's place judged against the
    robot's progress: ahead of it on the leg it drives now). For the robot itself it is the leg it moves along:
    the one whose direction its last HEADING_RUN metres of travel follow (a robot backing off a little stays on
    its leg); standing or crossing it, the one nearest its progress the step before (at the start, the first leg).
    Without that, the way back read as the way out driven backwards: no progress, and a follower behind the robot
    "in its way" (hospital_06, first answer: a 36 s deadlock while it led the patient home; hospital_07: a robot
    turning 0.3 m short of its turning point stayed on the way out for the whole way back)."""
    pts = np.asarray(waypoints, dtype=float).reshape(-1, 2)
    seg = np.diff(pts, axis=0)
    lens = contact.lengths(seg)
    keep = lens > 1e-9
    robot_xy = np.asarray(robot_xy, dtype=float).reshape(-1, 2)
    t = len(robot_xy)
    if not keep.any():
        driven = np.concatenate([[0.0], np.cumsum(contact.lengths(np.diff(robot_xy, axis=0)))]) if t else np.zeros(0)
        return driven, np.zeros((t, 2))
    start, seg, lens = pts[:-1][keep], seg[keep], lens[keep]
    before = np.concatenate([[0.0], np.cumsum(lens)[:-1]])
    unit = seg / lens[:, None]
    rel_x = robot_xy[:, 0:1] - start[:, 0]  # (T, S): the robot from each segment's start
    rel_y = robot_xy[:, 1:2] - start[:, 1]
    along = np.clip(rel_x * unit[:, 0] + rel_y * unit[:, 1], 0.0, lens)  # metres along each segment
    off = np.hypot(rel_x - along * unit[:, 0], rel_y - along * unit[:, 1])
    nearest = np.argmin(off, axis=1)
    every = before + along  # (T, S) progress on each segment
    tied = off <= off.min(axis=1, keepdims=True) + TIE if t else np.zeros((0, len(lens)), dtype=bool)
    rows = np.flatnonzero(tied.sum(axis=1) > 1)
    if len(rows) and near is not None:
        gap = np.abs(every[rows] - np.asarray(near, dtype=float)[rows, None]) - 1e-9 * every[rows]
        nearest[rows] = np.argmin(np.where(tied[rows], gap, np.inf), axis=1)
    elif len(rows):
        progress = every[np.arange(t), nearest]
        driven = np.concatenate([[0.0], np.cumsum(contact.lengths(np.diff(robot_xy, axis=0)))])
        back = np.searchsorted(driven, driven - HEADING_RUN, side="right") - 1  # where it was HEADING_RUN m ago
        for k in rows[rows > 0]:  # in order: the step before is final when this one is judged
            gap = np.abs(every[k] - progress[k - 1]) - 1e-9 * every[k]
            if driven[k] >= HEADING_RUN:
                moved = robot_xy[k] - robot_xy[max(back[k], 0)]
                along = unit[:, 0] * moved[0] + unit[:, 1] * moved[1]
                ahead = tied[k] & (along > 0.5 * HEADING_RUN)  # legs it drives forward along (not across them)
                if ahead.any():
                    gap = np.where(ahead, gap, np.inf)
            nearest[k] = int(np.argmin(np.where(tied[k], gap, np.inf)))
            progress[k] = every[k, nearest[k]]
    return every[np.arange(t), nearest], unit[nearest]


def leg_left(progress: np.ndarray, waypoints: list[tuple[float, float]]) -> np.ndarray:
    """(T,) metres from each progress to the end of the route segment it is on (at a waypoint: the segment that
    ends there, as route_progress's tangent); inf on the last segment (no turn after it) and without a route."""
    pts = np.asarray(waypoints, dtype=float).reshape(-1, 2)
    lens = contact.lengths(np.diff(pts, axis=0)) if len(pts) >= 2 else np.zeros(0)
    lens = lens[lens > 1e-9]
    progress = np.asarray(progress, dtype=float)
    if len(lens) < 2:
        return np.full(len(progress), np.inf)
    ends = np.cumsum(lens)
    at = np.searchsorted(ends, progress - 1e-9, side="left")
    return np.where(at < len(ends) - 1, ends[np.minimum(at, len(ends) - 1)] - progress, np.inf)


def progress_events(progress: np.ndarray, step: float) -> np.ndarray:
    """(T,) bool: the steps on which the robot's best progress so far first exceeds the previous event's by
    `step` metres (a ratchet: going back and forth never makes new progress)."""
    best = np.maximum.accumulate(progress) if len(progress) else progress
    events = np.zeros(len(best), dtype=bool)
    if not len(best):
        return events
    values = best.tolist()  # monotone: each next event is one bisection away (a route of L m has L / step events)
    k = bisect.bisect_left(values, values[0] + step)
    while k < len(values):
        events[k] = True
        k = bisect.bisect_left(values, values[k] + step, k)
    return events


def route_offset(xy: np.ndarray, waypoints: list[tuple[float, float]]) -> np.ndarray:
    """(T,) distance from each point to the waypoint polyline (how far off the route it is)."""
    pts = np.asarray(waypoints, dtype=float).reshape(-1, 2)
    xy = np.asarray(xy, dtype=float).reshape(-1, 2)
    if len(pts) < 2 or not len(xy):
        return np.full(len(xy), np.inf)
    a, seg = pts[:-1], np.diff(pts, axis=0)
    lens2 = np.maximum((seg * seg).sum(axis=1), 1e-18)
    rel_x, rel_y = xy[:, 0:1] - a[:, 0], xy[:, 1:2] - a[:, 1]  # (T, S)
    t = np.clip((rel_x * seg[:, 0] + rel_y * seg[:, 1]) / lens2, 0.0, 1.0)
    dx, dy = rel_x - t * seg[:, 0], rel_y - t * seg[:, 1]
    return np.sqrt(dx * dx + dy * dy).min(axis=1)


def ahead_on_route(progress: np.ndarray, xy: np.ndarray, waypoints: list[tuple[float, float]], half: np.ndarray | float,
                   reach: float, front: float) -> np.ndarray:
    """(N,) bool: each point within `half` of the route polyline and `front` to `reach` m farther along it than
    the robot's `progress` there: on the robot's route just ahead of it, round bends too (a person standing in a
    doorway just past the route's turn holds up a robot still on the leg before it), beyond the robot's front
    (`front`: its radius; someone level with it at the corridor's edge is beside it). False without a route."""
    xy = np.asarray(xy, dtype=float).reshape(-1, 2)
    if len(np.asarray(waypoints, dtype=float).reshape(-1, 2)) < 2 or not len(xy):
        return np.zeros(len(xy), dtype=bool)
    ahead = route_progress(xy, waypoints, near=progress)[0] - np.asarray(progress, dtype=float)
    return (route_offset(xy, waypoints) < half) & (ahead > front) & (ahead <= reach)



def lag_along(robot_xy: np.ndarray, xy: np.ndarray, tangent: np.ndarray) -> np.ndarray:
    """(T,) metres each point is behind the robot along the way it drives (its route's direction there, `tangent`
    from route_progress; negative: ahead of it); zeros without a route. Local, so a point past the route's end or
    round its last bend is not read as level with the robot."""
    rel = np.asarray(robot_xy, dtype=float).reshape(-1, 2) - np.asarray(xy, dtype=float).reshape(-1, 2)
    return (rel * np.asarray(tangent, dtype=float).reshape(-1, 2)).sum(axis=1)
