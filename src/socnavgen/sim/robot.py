"""The robot as a plugin: what it observes, what it answers, and the built-in policies.

A policy is any class with `act(observation) -> RobotAction` (and optionally `reset(observation)`),
loadable from the command line as `--robot module:Class` or `--robot path/to/file.py:Class`.
Scripted robot speech (spec.json's script cues, then PathPlan.robot_gestures) is applied by the engine
unless the policy returns its own gesture; every policy sees the script's cues as `obs.cues`.
"""

from __future__ import annotations

import importlib
import importlib.util
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Protocol, runtime_checkable

import numpy as np

from socnavgen.bodies import ROBOT_GOAL_TOLERANCE, ROBOT_RADIUS
from socnavgen.errors import InputFileError
from socnavgen.sim.sfm import SFMParams, _pair_force

SWEPT_MARGIN = 0.05  # m beyond the two radii: a person this close to the robot's path line blocks it
NUDGE_BAND = 0.35  # m beyond the radii: the robot edges sideways away from a person this close to its path
NUDGE_SPEED = 0.25  # m/s
NUDGE_ROOM = 0.3  # m: edging sideways only where this much room is left beside the robot (not into a jamb)
CLOSE_REACH = 0.15  # m: a waypoint this close is reached whatever the walls
WALL_MARGIN = 0.05  # m: closer than radius + this to a wall, the robot slides along it instead of into it
LOOK_WALL = 0.3  # s of motion looked ahead for walls
WALL_PUSH = 0.15  # m/s at most, back out of a wall the robot grazes
AROUND_LOOK = 1.0  # m: room looked for on either side before going around someone
AROUND_BIAS = 0.1  # m/s sideways while going around (a person dead ahead pushes straight back otherwise)
GOAL_DECEL = 0.8  # m/s2: the social-force and the straight robots slow down for their goal at this rate
OCCUPIED_REACH = 2.0  # m: an intermediate waypoint someone stands on is skipped once the robot is this close


class Observation:
    """What the robot knows at time t. Vectors as numpy (x, y) arrays; `*_c` are the same as complex."""

    def __init__(self, sim: Any) -> None:
        self._sim = sim

    @property
    def t(self) -> float:
        return self._sim.t

    @property
    def dt(self) -> float:
        return self._sim.dt

    @property
    def position(self) -> np.ndarray:
        return np.array([self._sim.robot_pos.real, self._sim.robot_pos.imag])

    @property
    def velocity(self) -> np.ndarray:
        return np.array([self._sim.robot_vel.real, self._sim.robot_vel.imag])

    @property
    def yaw(self) -> float:
        return self._sim.robot_yaw

    @property
    def radius(self) -> float:
        return self._sim.robot_radius

    @property
    def waypoints(self) -> np.ndarray:
        """(K, 2) the robot's path in world coordinates; the last one is the goal."""
        w = self._sim.robot_waypoints
        return np.column_stack([w.real, w.imag])

    @property
    def human_positions(self) -> np.ndarray:
        p = self._sim.crowd.pos
        return np.column_stack([p.real, p.imag])

    @property
    def human_count(self) -> int:
        return self._sim.crowd.n

    @property
    def human_velocities(self) -> np.ndarray:
        v = self._sim.crowd.vel
        return np.column_stack([v.real, v.imag])

    @property
    def human_radii(self) -> np.ndarray:
        return self._sim.crowd.radius

    @property
    def human_gestures(self) -> list[int]:
        return list(self._sim.crowd.gesture)

    @property
    def cues(self) -> Any:
        """What the scenario's robot script asks now (sim.gestures.CueState): `say` (gesture code, 0 none),
        `wait` (stand still), `speed` (cruise m/s), `misbehave`, `fired` [(t, cue)]."""
        return self._sim.cues

    @property
    def robot_said(self) -> set[int]:
        """Every gesture code the robot has shown so far."""
        return set(self._sim.robot_said)

    @property
    def world(self) -> Any:
        """The World: `clearance` (metres to walls per cell), `clearance_at`, `line_of_sight`."""
        return self._sim.world

    # complex views for fast policies
    @property
    def position_c(self) -> complex:
        return self._sim.robot_pos

    @property
    def velocity_c(self) -> complex:
        return self._sim.robot_vel

    @property
    def waypoints_c(self) -> np.ndarray:
        return self._sim.robot_waypoints

    @property
    def human_positions_c(self) -> np.ndarray:
        return self._sim.crowd.pos

    @property
    def human_velocities_c(self) -> np.ndarray:
        return self._sim.crowd.vel


@dataclass
class RobotAction:
    vx: float
    vy: float
    gesture: int | None = None  # None: keep the scenario's scripted gestures


@runtime_checkable
class RobotPolicy(Protocol):
    """act() is called once per step. Optionally: reset(obs) once at the start, and an attribute
    `heading` (unit complex) when the robot's facing differs from its velocity (e.g. while edging aside)."""

    def act(self, obs: Observation) -> RobotAction: ...


class _WaypointTracker:
    """The current waypoint. With `line_clearance`, a waypoint counts as reached within `tolerance` only
    when the straight line on to the next one keeps that clearance from walls (else the robot drives on to
    within CLOSE_REACH of it): cutting a doorway's corner would put the robot into the jamb."""

    def __init__(self, tolerance: float, line_clearance: float | None = None) -> None:
        self.index = 1
        self.tolerance = tolerance
        self.line_clearance = line_clearance
        self._source: np.ndarray | None = None
        self._points: list[complex] = []  # the waypoints as Python complex (read every step)

    def target(self, obs: Observation) -> tuple[complex, bool]:
        """Current waypoint and whether it is the last; advances past waypoints reached."""
        wps = obs.waypoints_c
        if wps is not self._source:
            self._source, self._points = wps, [complex(w) for w in wps.tolist()]
        pts = self._points
        last = len(pts) - 1
        if last < 0:
            return obs.position_c, True
        self.index = min(self.index, last)
        p = obs.position_c
        while self.index < last and self._reached(obs, p, pts[self.index], pts[self.index + 1]):
            self.index += 1
        return pts[self.index], self.index == last

    def _reached(self, obs: Observation, p: complex, wp: complex, following: complex) -> bool:
        d = abs(wp - p)
        if d > self.tolerance:
            return False
        if self.line_clearance is None or d <= CLOSE_REACH:
            return True
        return _segment_clear(obs.world, p, following, self.line_clearance)


def slide_along_walls(obs: Observation, v: complex, margin: float = WALL_MARGIN) -> complex:
    """`v` without its into-the-wall part when the robot is within `margin` of touching a wall, plus a
    gentle push back out: a robot pressed against a corner slides along it instead of stopping for good."""
    world, p, r = obs.world, obs.position_c, obs.radius
    if world.clearance_at_point(p + v * LOOK_WALL) >= r + margin:
        return v
    clearance = world.clearance_at_point(p)
    points, valid = world.nearest_obstacles(np.array([p]))
    away = p - complex(points[0])
    if not valid[0] or abs(away) < 1e-9:
        return v
    n = away / abs(away)
    into = (v * n.conjugate()).real
    if into < 0:
        v -= into * n
    if clearance < r:
        v += n * min(WALL_PUSH, (r - clearance) * 2.0)
    return v


class WaypointsPolicy:
    """Follows its waypoints in straight lines like the teleoperated robot of the paper: slows down when a
    person is in its way and stops short of them; slides along walls it grazes; edges sideways past someone
    standing close beside its path; and after waiting `patience` seconds behind someone who does not make
    way, it drives around them slowly where there is room (as the operator would), skipping a waypoint a
    person stands on and stopping at the far edge of a goal someone stands next to."""

    def __init__(self, max_speed: float = 0.6, accel: float = 0.8, brake: float = 3.0,
                 waypoint_tolerance: float = 0.4, slow_gap: float = 2.0, stop_gap: float = 0.5,
                 patience: float = 2.0, detour_speed: float = 0.3) -> None:
        self.max_speed, self.accel, self.brake = max_speed, accel, brake
        self.slow_gap, self.stop_gap = slow_gap, stop_gap
        self.patience, self.detour_speed = patience, detour_speed
        self.tracker = _WaypointTracker(waypoint_tolerance, line_clearance=ROBOT_RADIUS)
        self.speed = 0.0
        self.waited = 0.0  # seconds spent blocked by someone in the way
        self.heading: complex | None = None  # where the robot means to go (its yaw), whatever the nudge
        self._around = SFMPolicy(max_speed=detour_speed)  # how it steers around people once patience ran out
        self.around_side = 0.0  # +1 left / -1 right: the side it goes around on (kept while blocked)

    def look_ahead(self, obs: Observation, direction: complex, reach: float = math.inf) -> tuple[float, float]:
        """(free distance to the nearest person in the swept path ahead, sideways nudge -1/0/+1).

        The nudge moves the robot away from the nearest person standing close beside its path, as a
        teleoperator squeezes past someone who stepped aside in a narrow corridor. `reach`: where the robot
        will stop (its goal); someone beyond it is in the way only if they stand too close to that point."""
        p, back, rr = obs.position_c, direction.conjugate(), obs.radius
        people = obs.human_positions_c
        radii = obs.human_radii
        if len(people) > 32:  # keep only those within reach before the Python loop
            near = np.abs(people - p) < self.slow_gap + 2.0
            people, radii = people[near], radii[near]
        gap, nudge_at, nudge = math.inf, math.inf, 0.0
        for q, r in zip(people.tolist(), radii.tolist(), strict=True):
            rel = (q - p) * back
            if rel.real <= 0:
                continue
            ahead = rel.real - r - rr
            # someone already beside the robot blocks only if the bodies would touch: it is passing them
            margin = SWEPT_MARGIN if ahead > 0 else 0.0
            across = abs(rel.imag) if rel.real <= reach else abs(rel - reach)
            if across < r + rr + margin and ahead < gap:
                gap = ahead
            if r + rr + margin <= abs(rel.imag) < r + rr + NUDGE_BAND and ahead < self.slow_gap and ahead < nudge_at:
                nudge_at, nudge = ahead, (-1.0 if rel.imag > 0 else 1.0)
        return gap, nudge

    def gap_ahead(self, obs: Observation, direction: complex) -> float:
        return self.look_ahead(obs, direction)[0]

    def act(self, obs: Observation) -> RobotAction:
        target, last = self.tracker.target(obs)
        p = obs.position_c
        arrive = ROBOT_GOAL_TOLERANCE * 0.5
        if last and abs(target - p) < self.slow_gap + 1.0:
            target, arrive = self._reachable_goal(obs, target)
        to = target - p
        dist = abs(to)
        if last and dist <= arrive:
            self.speed = 0.0
            return RobotAction(0.0, 0.0)
        direction = to / dist if dist > 1e-9 else complex(math.cos(obs.yaw), math.sin(obs.yaw))
        self.heading = direction
        gap, nudge = self.look_ahead(obs, direction, dist if last else math.inf)
        want = self.max_speed * min(1.0, max(0.0, (gap - self.stop_gap) / (self.slow_gap - self.stop_gap)))
        if last:
            want = min(want, math.sqrt(2 * self.accel * dist))
        blocked = gap - self.stop_gap < 0.1 and (not last or dist > gap + 0.5)
        self.waited = self.waited + obs.dt if blocked else 0.0
        if not blocked:
            self.around_side = 0.0
        if blocked and self.waited >= self.patience:
            if self._skip_occupied_waypoint(obs):
                self.waited = 0.0  # next step heads for the following waypoint
            else:
                if not self.around_side:  # the side with more room (keep right on a tie): breaks the symmetry
                    left, right = (obs.world.clearance_at_point(p + direction * 1j * k * AROUND_LOOK) for k in (1, -1))
                    self.around_side = 1.0 if left > right + 0.05 else -1.0
                action = self._around.toward(obs, target)
                v = complex(action.vx, action.vy)
                if abs(v) < AROUND_BIAS:  # pushed straight back by someone dead ahead: sidestep
                    v += direction * 1j * self.around_side * AROUND_BIAS
                v = slide_along_walls(obs, v)
                self.speed = abs(v)
                if self.speed > 0.05:
                    self.heading = v / self.speed
                return RobotAction(v.real, v.imag)
        self.speed = min(want, self.speed + self.accel * obs.dt) if want >= self.speed else \
            max(want, self.speed - self.brake * obs.dt)
        v = direction * self.speed
        if nudge:
            side = direction * 1j * nudge
            if obs.world.clearance_at_point(p + side * NUDGE_ROOM) >= obs.radius + 0.1:
                v += side * NUDGE_SPEED
        v = slide_along_walls(obs, v)
        return RobotAction(v.real, v.imag)

    def _skip_occupied_waypoint(self, obs: Observation) -> bool:
        """Someone standing on an intermediate waypoint: head for the next one if it is in sight."""
        wps, k, p = obs.waypoints_c, self.tracker.index, obs.position_c
        if k >= len(wps) - 1 or abs(wps[k] - p) > OCCUPIED_REACH or len(obs.human_positions_c) == 0:
            return False
        occupied = np.abs(obs.human_positions_c - wps[k]) < obs.human_radii + obs.radius + SWEPT_MARGIN
        if occupied.any() and _segment_clear(obs.world, p, complex(wps[k + 1]), 0.5 * obs.radius + 0.05):
            self.tracker.index = k + 1
            return True
        return False

    def _reachable_goal(self, obs: Observation, goal: complex) -> tuple[complex, float]:
        """(where to stop, how close): someone standing right next to the goal leaves the far edge of the
        goal's circle, which still counts as arrived."""
        people, radii = obs.human_positions_c, obs.human_radii
        if len(people) == 0:
            return goal, ROBOT_GOAL_TOLERANCE * 0.5
        d = np.abs(people - goal)
        k = int(np.argmin(d - radii))
        if d[k] >= radii[k] + obs.radius + SWEPT_MARGIN + 0.1 or d[k] < 1e-6:
            return goal, ROBOT_GOAL_TOLERANCE * 0.5
        away = (goal - complex(people[k])) / d[k]
        return goal + away * ROBOT_GOAL_TOLERANCE * 0.75, ROBOT_GOAL_TOLERANCE * 0.15


def _segment_clear(world: Any, a: complex, b: complex, clearance: float) -> bool:
    n = max(2, int(abs(b - a) / 0.1) + 1)
    pts = a + (b - a) * np.linspace(0.0, 1.0, n)
    return bool((world.clearance_at(pts) >= clearance).all())


class SFMPolicy:
    """The robot as one more social-force agent heading for its waypoints (it does not wait: it
    negotiates its way around people), with the same safety layer as the default robot (keep_clear: the
    social force alone lets it brush into people that stand still)."""

    def __init__(self, max_speed: float = 0.6, waypoint_tolerance: float = 0.5,
                 params: SFMParams | None = None) -> None:
        self.max_speed = max_speed
        self.params = params or SFMParams()
        self.tracker = _WaypointTracker(waypoint_tolerance)

    def act(self, obs: Observation) -> RobotAction:
        target, last = self.tracker.target(obs)
        action = self.toward(obs, target, last)
        v = keep_clear(obs, complex(action.vx, action.vy))  # a social robot: negotiates, never pushes into people
        return RobotAction(v.real, v.imag)

    def toward(self, obs: Observation, target: complex, last: bool = False) -> RobotAction:
        """One social-force step toward `target` (slowing down for it when it is the last waypoint)."""
        p, v, prm = obs.position_c, obs.velocity_c, self.params
        to = target - p
        dist = abs(to)
        if last and dist <= ROBOT_GOAL_TOLERANCE * 0.5:
            return RobotAction(0.0, 0.0)
        v0 = min(self.max_speed, math.sqrt(2 * GOAL_DECEL * dist)) if last else self.max_speed
        force = prm.k_des * (v0 * to / max(dist, 1e-9) - v) / prm.tau
        hp = obs.human_positions_c
        if len(hp):
            d = hp - p
            near = np.abs(d) <= (prm.cutoff or np.inf)
            if near.any():
                force += complex(_pair_force(d[near], v - obs.human_velocities_c[near], prm).sum())
        obs_pt, valid = obs.world.nearest_obstacles(np.array([p]))
        if valid[0]:
            dd = p - obs_pt[0]
            r = abs(dd)
            if r > 1e-9:
                force += prm.k_obs * math.exp(-(r - obs.radius) / prm.sigma_obs) * dd / r
        v = v + force * obs.dt
        if abs(v) > v0:
            v = v * (v0 / abs(v))
        return RobotAction(v.real, v.imag)


KEEP_CLEAR = 0.03  # m: the scripted robot never moves closer than this gap to anyone


def keep_clear(obs: Observation, v: complex, margin: float = KEEP_CLEAR) -> complex:
    """`v` without the part that would take the robot closer than `margin` (surface gap) to a person:
    the robot may slide past or back off, never push into someone."""
    if v == 0 or obs.human_count == 0:
        return v
    people = obs.human_positions_c.tolist()  # a handful of people: scalar arithmetic beats numpy calls
    p, dt, rr = obs.position_c, obs.dt, obs.radius
    reach = [r + rr + margin for r in obs.human_radii.tolist()]
    for _ in range(3):  # a second person may be met after sliding along the first
        nxt = p + v * dt
        close = [k for k, q in enumerate(people) if abs(q - nxt) < reach[k]]
        if not close:
            return v
        for k in close:
            d = people[k] - p
            if abs(d) < 1e-9:
                continue
            n = d / abs(d)
            toward = (v * n.conjugate()).real
            if toward > 0:
                v -= toward * n
    nxt = p + v * dt
    return v if all(abs(q - nxt) >= min(reach[k], abs(q - p)) for k, q in enumerate(people)) else 0j


class ScriptedPolicy(WaypointsPolicy):
    """The default robot: plays the scenario's robot script (spec.json; obs.cues): cruises at the script's
    speed, stands still while a cue says wait (or until its way is clear), and says what the cues say (the
    engine shows `cues.say`). Otherwise it drives like the waypoints robot, and it never moves into a
    person (keep_clear) unless the script says the robot misbehaves on purpose."""

    def __init__(self, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self._rude = StraightPolicy()

    def act(self, obs: Observation) -> RobotAction:
        cues = obs.cues
        if cues.misbehave:
            return self._rude.act(obs)
        self.max_speed = cues.speed
        if cues.wait:
            self.speed = 0.0
            return RobotAction(0.0, 0.0)
        action = super().act(obs)
        v = complex(action.vx, action.vy)
        target, _ = self.tracker.target(obs)
        ahead = target - obs.position_c
        if abs(ahead) > 1e-9 and (v * (ahead / abs(ahead)).conjugate()).real < 0:
            v -= (v * (ahead / abs(ahead)).conjugate()).real * ahead / abs(ahead)  # never retreat: a crowd
            # pushing it back would drive it the wrong way for good; it sidesteps or waits instead
        v = keep_clear(obs, v)
        if abs(v) < abs(complex(action.vx, action.vy)) - 1e-9:
            self.speed = min(self.speed, abs(v))
        return RobotAction(v.real, v.imag, action.gesture)


class StraightPolicy:
    """A deliberately bad robot: straight at each waypoint at cruise speed, through people (for campaigns
    that must catch a rude robot). It only slides along walls and slows down for its goal."""

    def __init__(self, max_speed: float = 0.6) -> None:
        self.max_speed = max_speed
        self.tracker = _WaypointTracker(ROBOT_GOAL_TOLERANCE * 2)

    def act(self, obs: Observation) -> RobotAction:
        target, last = self.tracker.target(obs)
        to = target - obs.position_c
        dist = abs(to)
        if last and dist <= ROBOT_GOAL_TOLERANCE * 0.5:
            return RobotAction(0.0, 0.0)
        speed = min(self.max_speed, math.sqrt(2 * GOAL_DECEL * dist)) if last else self.max_speed
        v = slide_along_walls(obs, to / max(dist, 1e-9) * speed)
        return RobotAction(v.real, v.imag)


# the registry of built-in robots (`--robot NAME`); `scripted` is the default
BUILTIN: dict[str, type] = {"scripted": ScriptedPolicy, "waypoints": WaypointsPolicy, "sfm": SFMPolicy,
                            "straight": StraightPolicy}
DEFAULT_ROBOT = "scripted"


def load_policy(spec: str) -> RobotPolicy:
    """`scripted`, `waypoints`, `sfm`, `straight`, `package.module:Class` or `path/to/file.py:Class` -> a policy
    instance."""
    if spec in BUILTIN:
        return BUILTIN[spec]()
    if ":" not in spec:
        raise InputFileError(f"unknown robot {spec!r}", hint="use " + ", ".join(BUILTIN) + ", module:Class or file.py:Class")
    module_name, _, class_name = spec.rpartition(":")
    try:
        if module_name.endswith(".py"):
            path = Path(module_name)
            if not path.is_file():
                raise InputFileError("robot policy file not found", file=path)
            mod_spec = importlib.util.spec_from_file_location(f"socnavgen_user_policy_{path.stem}", path)
            module = importlib.util.module_from_spec(mod_spec)
            mod_spec.loader.exec_module(module)
        else:
            module = importlib.import_module(module_name)
        cls = getattr(module, class_name)
    except InputFileError:
        raise
    except Exception as exc:  # noqa: BLE001 - anything user code raises on import
        raise InputFileError(f"cannot load robot policy {spec!r}: {type(exc).__name__}: {exc}",
                             hint="the class must be importable and take no constructor arguments") from exc
    if not isinstance(cls, type):
        raise InputFileError(f"{spec} is not a robot policy class", hint="see RobotPolicy in docs/simulator.md")
    try:
        policy = cls()
    except Exception as exc:  # noqa: BLE001 - a user constructor's failure is the user's to fix
        raise InputFileError(f"robot policy {spec} could not be created: {type(exc).__name__}: {exc}",
                             hint="its constructor must run without arguments") from exc
    if not callable(getattr(policy, "act", None)):
        raise InputFileError(f"{spec} has no act(observation) method", hint="see RobotPolicy in docs/simulator.md")
    return policy
