"""A decoded HuNavSim recording -> socnavgen's Trace, so that the verifier and the metrics judge a Gazebo run
with the same code as a headless one: agents mapped to the run's humans (by name, else by id as the export
numbered them), the recording checked against the run (humans, groups, where everyone starts, the clock),
and the states resampled onto a fixed time step."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from socnavgen.bag.reader import (
    AgentState,
    BagError,
    ReadTopics,
    Recording,
    bt_series,
    gesture_series,
    read_recording,
)
from socnavgen.bodies import PERSON_RADIUS, ROBOT_RADIUS
from socnavgen.limits import MAX_SIM_STEPS
from socnavgen.sim.trace import Trace

if TYPE_CHECKING:
    from socnavgen.location import Location
    from socnavgen.run import PathPlan

DEFAULT_DT = 0.05  # s, the simulator's default step
SAME_TIME = 1e-6  # s: a grid time this close to a sample is that sample (no interpolation)
CLOCK_BACK_TOLERANCE = 1_000_000  # ns: stamps may wobble by a millisecond; a larger step back is a jump


@dataclass
class BagReadOptions:
    topics: ReadTopics = field(default_factory=ReadTopics)
    dt: float | None = None  # resampling step; None = the bag's own (socnavgen bags) or DEFAULT_DT
    first_agent_id: int | None = None  # id of human1 (0 socrates export, 1 hunav2/hunav1); None = detect
    agent_map: dict[int, str] | None = None  # explicit agent id -> human name
    hunav_msgs: str = "auto"  # auto | socrates | hunav
    max_gap: float = 2.0  # s without a human state that counts as a broken recording
    start_tolerance: float = 3.0  # m between where someone starts and the first node of their path


@dataclass
class BagTrace:
    trace: Trace
    notes: list[str]
    agent_ids: dict[str, int]  # human name -> agent id in the bag


def bag_to_trace(path: Path | str, plan: PathPlan, location: Location,
                 options: BagReadOptions | None = None) -> BagTrace:
    """Read the bag at `path` and turn it into a Trace of the run whose paths.json is `plan`."""
    options = options or BagReadOptions()
    rec = read_recording(path, options.topics, hunav_msgs=options.hunav_msgs)
    return recording_to_trace(rec, plan, location, options)


def _mapping(rec: Recording, plan: PathPlan, options: BagReadOptions, notes: list[str]) -> dict[int, str]:
    """agent id -> human name, or one BagError naming the agents that do not fit."""
    humans = sorted(plan.humans, key=lambda h: h.agent_id)
    names = [h.name for h in humans]
    seen: dict[int, str] = {}
    for msg in rec.humans:
        for a in msg:
            seen.setdefault(a.ident, a.name)
    topic = rec.topics["humans"]
    ids_text = (f"ids {', '.join(str(h.agent_id) for h in humans)} in a socrates export, "
                f"{', '.join(str(h.agent_id + 1) for h in humans)} in a hunav2 / hunav1 export")
    hint = "pass --agent-ids socrates|hunav, or --agent-map ID=NAME,... (e.g. --agent-map 7=human1)"
    if options.agent_map is not None:
        bad = sorted(n for n in options.agent_map.values() if n not in names)
        if bad:
            raise BagError(f"--agent-map names {', '.join(bad)}, not humans of this run ({', '.join(names)})",
                           file=rec.path)
        mapping = dict(options.agent_map)
        notes.append("agents mapped by --agent-map")
    elif len(seen) == len(names) and sorted(seen.values()) == sorted(names):
        mapping = {i: n for i, n in seen.items()}
        notes.append("agents mapped by name")
    else:
        base = options.first_agent_id
        if base is None and isinstance(rec.meta, dict) and isinstance(rec.meta.get("first_agent_id"), int):
            base = rec.meta["first_agent_id"]
        if base is None:
            base = next((b for b in (0, 1) if set(seen) == {h.agent_id + b for h in humans}), None)
        if base is None:
            base = 0 if 0 in seen else 1
        mapping = {h.agent_id + base: h.name for h in humans}
        notes.append(f"agents mapped by id (human1 = id {base}, as the {'socrates' if base == 0 else 'hunav'} "
                     "export numbers them)")
    unknown = sorted(i for i in seen if i not in mapping)
    if unknown:
        who = ", ".join(f"id {i} ({seen[i]!r})" for i in unknown[:8])
        raise BagError(f"agent(s) {who} on {topic} are not humans of this run: its humans are "
                       f"{', '.join(names)} = {ids_text}", file=rec.path, hint=hint)
    missing = [n for i, n in mapping.items() if i not in seen]
    if missing:
        raise BagError(f"{', '.join(missing)} of this run never appear(s) on {topic} (agents seen: "
                       f"{', '.join(f'{i} {n!r}' for i, n in sorted(seen.items())) or 'none'})", file=rec.path,
                       hint=hint)
    return mapping


def _samples(rec: Recording, options: BagReadOptions, notes: list[str]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(indices of the human messages kept, their times (ns), index of the robot message paired with each)."""
    log = np.asarray(rec.human_log, dtype=np.int64)
    stamp = np.asarray(rec.human_stamp, dtype=np.int64)
    order = np.argsort(log, kind="stable")
    robot_log = np.asarray(rec.robot_log, dtype=np.int64)
    robot_order = np.argsort(robot_log, kind="stable")
    paired = np.searchsorted(robot_log[robot_order], log[order], side="right") - 1
    keep = paired >= 0
    if not keep.all():
        notes.append(f"{int((~keep).sum())} human state(s) before the first robot state skipped")
    order, paired = order[keep], robot_order[paired[keep]]
    if len(order) == 0:
        raise BagError(f"no robot state on {rec.topics['robot']} comes before or with the last human state",
                       file=rec.path, hint="record both topics during the whole run")
    kept = stamp[order]
    use_stamps = bool((kept[1:] > 0).all() and kept[-1] > kept[0])  # a sim-time clock may start at 0
    times = stamp[order] if use_stamps else log[order]
    source = "header stamps" if use_stamps else "recording times"
    back = np.flatnonzero(np.diff(times) < -CLOCK_BACK_TOLERANCE)
    if len(back):
        k = int(back[0])
        raise BagError(f"the clock jumps back by {(times[k] - times[k + 1]) / 1e9:.3f} s at "
                       f"t = {(times[k] - times[0]) / 1e9:.3f} s on {rec.topics['humans']} ({source}, message "
                       f"{k + 2}): the recording holds more than one episode (a simulator reset?)", file=rec.path,
                       hint="record one episode per bag, or cut one out (ros2 bag convert / mcap filter)")
    increasing = np.concatenate([[True], times[1:] > np.maximum.accumulate(times)[:-1]])
    if not increasing.all():
        notes.append(f"{int((~increasing).sum())} human state(s) with a repeated time stamp dropped")
    order, times, paired = order[increasing], times[increasing], paired[increasing]
    gaps = np.flatnonzero(np.diff(times) > options.max_gap * 1e9)
    if len(gaps):
        k = int(gaps[0])
        raise BagError(f"no state on {rec.topics['humans']} for {(times[k + 1] - times[k]) / 1e9:.2f} s (from "
                       f"t = {(times[k] - times[0]) / 1e9:.2f} s, {source}): the clock jumps or the recording "
                       "paused", file=rec.path,
                       hint=f"allow longer gaps with --max-gap (now {options.max_gap:g} s) if the simulator was "
                            "only slow")
    if len(order) < 2:
        raise BagError("the recording holds a single state of the humans and the robot", file=rec.path,
                       hint="record the whole run")
    notes.append(f"{len(order)} states, time from the {source}")
    return order, times, paired


def _check_against_run(states: np.ndarray, robot: np.ndarray, groups: list[int], plan: PathPlan,
                       location: Location, names: list[str], options: BagReadOptions, path: Path) -> None:
    for i, human in enumerate(sorted(plan.humans, key=lambda h: h.agent_id)):
        if groups[i] != human.group_id:
            raise BagError(f"{names[i]} is in group {groups[i]} in the recording but in group {human.group_id} in "
                           "paths.json: the recording does not match this run", file=path,
                           hint="was the bag recorded from another scenario's export?")
        node = human.path[0]
        nx, ny = location.node_world(node)
        gap = math.hypot(states[0, i, 0] - nx, states[0, i, 1] - ny)
        if gap > options.start_tolerance:
            raise BagError(f"{names[i]} starts at ({states[0, i, 0]:.2f}, {states[0, i, 1]:.2f}), {gap:.1f} m from "
                           f"the first node of its path ({node} at ({nx:.2f}, {ny:.2f})): the recording does not "
                           "match this run", file=path,
                           hint="was it recorded from another scenario or location? (--start-tolerance to allow "
                                "more)")
    rx, ry = location.node_world(plan.robot[0])
    gap = math.hypot(robot[0, 0] - rx, robot[0, 1] - ry)
    if gap > options.start_tolerance:
        raise BagError(f"the robot starts at ({robot[0, 0]:.2f}, {robot[0, 1]:.2f}), {gap:.1f} m from the first node "
                       f"of its path ({plan.robot[0]} at ({rx:.2f}, {ry:.2f})): the recording does not match this run",
                       file=path, hint="was it recorded from another scenario or location?")


def _resample(r: np.ndarray, dt: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Grid times and, per grid time, the sample at or before it, the one after, and the weight of the latter."""
    steps = int(math.floor(r[-1] / dt + 1e-9)) + 1
    grid = np.arange(steps) * dt
    i = np.clip(np.searchsorted(r, grid + SAME_TIME, side="right") - 1, 0, len(r) - 1)
    j = np.minimum(i + 1, len(r) - 1)
    span = r[j] - r[i]
    offset = grid - r[i]
    w = np.where((span > 0) & (offset > SAME_TIME), offset / np.where(span > 0, span, 1.0), 0.0)
    return grid, i, j, w


def _point(value: Any, what: str, path: Path) -> tuple[float, float]:
    """(x, y) of a point in the run's metadata the bag carries; one message when it is not two numbers."""
    try:
        x, y = (float(v) for v in value)
    except (TypeError, ValueError):
        raise BagError(f"the bag's run metadata gives the {what} as {str(value)[:40]}, not two numbers (x, y)",
                       file=path, hint="record the run again with the exported metadata topic intact") from None
    return x, y


def _interp(a: np.ndarray, i: np.ndarray, j: np.ndarray, w: np.ndarray) -> np.ndarray:
    """Columns x, y, yaw, vx, vy, omega of (N, ..., 6) states at the grid: linear, yaw along the short way;
    a grid time on a sample gives that sample exactly."""
    ww = w.reshape((-1,) + (1,) * (a.ndim - 1))
    out = a[i] + ww * (a[j] - a[i])
    turn = np.angle(np.exp(1j * (a[j][..., 2] - a[i][..., 2])))
    yaw = np.angle(np.exp(1j * (a[i][..., 2] + ww[..., 0] * turn)))
    out[..., 2] = np.where(ww[..., 0] == 0, a[i][..., 2], yaw)
    return out


def recording_to_trace(rec: Recording, plan: PathPlan, location: Location,
                       options: BagReadOptions | None = None) -> BagTrace:
    options = options or BagReadOptions()
    notes = [f"hunav_msgs: {rec.flavour}"]
    mapping = _mapping(rec, plan, options, notes)
    humans = sorted(plan.humans, key=lambda h: h.agent_id)
    names = [h.name for h in humans]
    index = {name: k for k, name in enumerate(names)}
    order, times, paired = _samples(rec, options, notes)
    n, h = len(order), len(names)
    states = np.full((n, h, 6), np.nan)
    bstate = np.zeros((n, h), dtype=np.int8)
    gesture = np.zeros((n, h), dtype=np.int8)
    groups: list[int | None] = [None] * h
    radii = np.zeros(h)
    for row, m in enumerate(order):
        for a in rec.humans[int(m)]:
            k = index[mapping[a.ident]]
            states[row, k] = a.state
            bstate[row, k] = np.clip(a.behavior_state, -128, 127)
            gesture[row, k] = np.clip(a.gesture, -128, 127)
            if groups[k] is None:
                groups[k], radii[k] = a.group, a.radius
    absent = [names[k] for k in range(h) if np.isnan(states[0, k, 0])]
    if absent:
        raise BagError(f"{', '.join(absent)} missing from the first state on {rec.topics['humans']}: HuNavSim "
                       "publishes every agent in every message", file=rec.path, hint="record from the start of the run")
    filled = int(np.isnan(states[:, :, 0]).sum())
    if filled:
        notes.append(f"{filled} missing agent state(s) held from the previous message")
        for row in range(1, n):
            gap = np.isnan(states[row, :, 0])
            states[row, gap] = states[row - 1, gap]
    group_ids = [int(g) if g is not None else -1 for g in groups]  # all set: everybody is in the first state
    robots: list[AgentState] = [rec.robots[int(p)] for p in paired]
    robot = np.asarray([r.state for r in robots], dtype=float)
    _check_against_run(states, robot, group_ids, plan, location, names, options, rec.path)
    meta_in = rec.meta if isinstance(rec.meta, dict) and rec.meta.get("human_names") == names else {}
    dt = options.dt or (float(meta_in["dt"]) if isinstance(meta_in.get("dt"), (int, float)) else DEFAULT_DT)
    if not (math.isfinite(dt) and 0.001 <= dt <= 1.0):
        raise BagError(f"resampling step {dt!r} s is outside 0.001..1 s", file=rec.path, hint="pass --dt 0.05")
    r = (times - times[0]) / 1e9
    if r[-1] / dt + 1 > MAX_SIM_STEPS:
        raise BagError(f"{r[-1]:.0f} s at dt {dt:g} s is more than {MAX_SIM_STEPS} steps", file=rec.path,
                       hint="raise --dt")
    grid, i, j, w = _resample(r, dt)
    log_at = np.asarray(rec.human_log, dtype=np.int64)[order][i]
    if rec.gestures:
        robot_gesture = gesture_series(rec.gestures, rec.gesture_log, log_at)
    else:
        robot_gesture = np.asarray([r.gesture for r in robots], dtype=np.int64)[i]
    node_names = [str(x) for x in meta_in.get("node_names", [])] if isinstance(meta_in.get("node_names"), list) else []
    activity = bt_series(rec, log_at, h) if node_names else None
    if activity is None:
        node_names = []
        action, succeeded = np.full((len(grid), h), -1, np.int16), np.zeros((len(grid), h), np.int64)
        notes.append("no behavior-tree activity in the recording: tree checks cannot see which node ran")
    else:
        action, succeeded = activity
    waypoints = [_point(p, "robot waypoint", rec.path) for p in meta_in.get("robot_waypoints", [])] if meta_in else \
        [location.node_world(node) for node in plan.robot]
    goal_in = meta_in.get("robot_goal") if meta_in else None
    goal = _point(goal_in, "robot goal", rec.path) if goal_in else (rec.goal or (waypoints[-1] if waypoints else None))
    robot_radius = robots[0].radius if robots[0].radius > 0 else ROBOT_RADIUS  # the wrapper's, when it says 0
    meta = dict(meta_in.get("meta") or {}) if isinstance(meta_in.get("meta"), dict) else {}
    agent_ids = {name: ident for ident, name in mapping.items()}
    meta["bag"] = {"file": str(rec.path), "hunav_msgs": rec.flavour, "topics": rec.topics, "agent_ids": agent_ids,
                   "states": int(n), "recorded_seconds": float(r[-1]), "dt": dt}
    trace = Trace(
        dt=dt, t=grid, robot=_interp(robot, i, j, w), humans=_interp(states, i, j, w), human_names=names,
        group_ids=group_ids, human_radii=np.where(radii > 0, radii, PERSON_RADIUS),
        robot_radius=float(robot_radius), node_names=node_names, action=action, succeeded=succeeded,
        human_gesture=gesture[i], robot_gesture=np.clip(robot_gesture, -128, 127).astype(np.int8),
        behavior_state=bstate[i], robot_goal=goal, robot_waypoints=waypoints,
        end_reason=str(meta_in.get("end_reason", "end of recording")) if meta_in else "end of recording", meta=meta)
    notes.append(f"resampled to {len(grid)} steps of {dt:g} s ({r[-1]:.1f} s recorded)")
    return BagTrace(trace=trace, notes=notes, agent_ids=agent_ids)
