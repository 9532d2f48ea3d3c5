"""The robot's body: how a velocity command becomes motion (compiled `drive`), within the body's limits.

* `diff_drive` (default): a unicycle, as most service robots (a differential-drive base): it moves only
  along its heading, turns at most `max_omega`, speeds up at most `max_accel`, brakes at most `max_decel`
  and changes its turn rate at most `max_alpha`. A world-frame velocity asked by a policy is tracked:
  the robot turns toward it (proportional to the heading error, TURN_GAIN) and drives forward at the asked
  speed times the cosine of the heading error (it turns on the spot when the error is over 90 degrees);
  a slow velocity asked straight behind it (at most REVERSE_SPEED) is driven backwards. A policy may also
  command the unicycle directly (forward speed, turn rate: RobotAction.unicycle, DWA).
* `holonomic`: the velocity asked is followed in any direction, within `max_speed` and `max_accel` /
  `max_decel`; the robot faces where it moves (or the heading the policy gives).

Whatever the body, a move whose path comes closer than half the robot's radius to a wall is refused (the
robot stands that step, still turning), and a non-finite command counts as standing still.

A differential-drive robot goes where it faces, not where its policy's velocity points, so a policy that keeps
a gap to people by choosing its velocity (robot.polite.keep_clear) cannot promise it alone: the body has a
protective field (`guard`, a gap in metres; NaN: none), as a safety laser scanner has: a forward step that
would take it closer than `guard` (surface to surface) to someone it is approaching is not made (the robot
stops at once, an emergency stop; it may still turn).
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass
from typing import Literal

from socnavgen.bodies import ROBOT_MAX_SPEED
from socnavgen.errors import ValidationFailed
from socnavgen.sim.jit import jit
from socnavgen.sim.world.queries import swept_clear

HOLONOMIC, DIFF_DRIVE = 0, 1
KINEMATICS = {"holonomic": HOLONOMIC, "diff_drive": DIFF_DRIVE}
TURN_GAIN = 3.0  # 1/s: turn rate asked per radian of heading error
REVERSE_SPEED = 0.35  # m/s: a velocity at most this fast, more than REVERSE_ANGLE off the heading, is driven backwards
REVERSE_ANGLE = 2.4  # rad
TURNING_SPEED = 0.05  # m/s: a holonomic robot slower than this keeps its yaw


@dataclass(frozen=True)
class RobotBody:
    """The robot's kinematics and limits (defaults: a small differential-drive service robot such as a
    TIAGo or Pioneer base). Part of every trace's meta (`robot_body`) and campaign row."""

    kinematics: Literal["diff_drive", "holonomic"] = "diff_drive"
    max_speed: float = 1.0  # m/s
    max_accel: float = 1.0  # m/s^2 speeding up
    max_decel: float = 2.0  # m/s^2 braking
    max_omega: float = 2.0  # rad/s
    max_alpha: float = 4.0  # rad/s^2

    def __post_init__(self) -> None:
        if self.kinematics not in KINEMATICS:
            raise ValidationFailed(f"robot body kinematics {self.kinematics!r}: use one of {', '.join(KINEMATICS)}")
        for name in ("max_speed", "max_accel", "max_decel", "max_omega", "max_alpha"):
            value = getattr(self, name)
            if not (isinstance(value, int | float) and math.isfinite(value) and value > 0):
                raise ValidationFailed(f"robot body {name} = {value!r}: it must be a positive number")
        if self.max_speed > ROBOT_MAX_SPEED:
            raise ValidationFailed(f"robot body max_speed {self.max_speed:g} m/s: at most {ROBOT_MAX_SPEED:g} m/s")

    def meta(self) -> dict:
        return asdict(self)

    def columns(self) -> dict:
        """The limits as they are stored in a campaign row (`robot_kinematics`, `robot_max_speed`, ...)."""
        return {f"robot_{k}": v for k, v in asdict(self).items()}


@jit(inline=True)
def _toward(value, target, step):  # noqa: ANN001, ANN201
    """`value` moved toward `target` by at most `step`."""
    return min(target, value + step) if target >= value else max(target, value - step)


@jit(inline=True)
def _wrap(angle):  # noqa: ANN001, ANN201
    return (angle + math.pi) % (2 * math.pi) - math.pi


@jit(inline=True)
def intrudes(s, old, new, guard):  # noqa: ANN001, ANN201
    """Whether moving from `old` to `new` takes the robot closer than `guard` to someone it approaches."""
    people, radius = s.people, s.robot[0].radius
    for k in range(people.shape[0]):
        d_new = abs(people[k].pos - new)
        if d_new < people[k].radius + radius + guard and d_new < abs(people[k].pos - old):
            return True
    return False


@jit(inline=True)
def drive(s, v, heading, has_heading, unicycle, forward, turn, guard, decel):  # noqa: ANN001, ANN201
    """Move the robot for one step: a world velocity `v` (facing `heading` when given), or with `unicycle` a
    forward speed and a turn rate; within the body's limits, braking at most `decel` (m/s2; NaN: the body's
    max_decel; robot.brake), never across or into a wall, and (a differential-drive body) never closer than
    `guard` to someone it approaches (NaN: no protective field)."""
    robot, dt = s.robot[0], s.clock[0].dt
    brake = decel if decel < robot.max_decel else robot.max_decel  # NaN: the body's own limit
    if not (math.isfinite(v.real) and math.isfinite(v.imag)):
        v = 0j
    if not (math.isfinite(forward) and math.isfinite(turn)):
        unicycle, forward, turn = True, 0.0, 0.0
    old = robot.yaw
    if robot.kinematics == DIFF_DRIVE:
        speed = abs(v)
        if unicycle:
            want_u, want_w = forward, turn
        elif speed < 1e-6:
            want_u = 0.0
            want_w = TURN_GAIN * _wrap(math.atan2(heading.imag, heading.real) - robot.yaw) if has_heading and \
                abs(heading) > 0 else 0.0
        else:
            error = _wrap(math.atan2(v.imag, v.real) - robot.yaw)
            if abs(error) > REVERSE_ANGLE and speed <= REVERSE_SPEED:  # backing up slowly
                error = _wrap(error + math.pi)
                want_u = -speed * math.cos(error)
            else:
                want_u = speed * max(0.0, math.cos(error))
            want_w = TURN_GAIN * error
        want_u = min(max(want_u, -robot.max_speed), robot.max_speed)
        want_w = min(max(want_w, -robot.max_omega), robot.max_omega)
        u = robot.speed
        rate = robot.max_accel if abs(want_u) > abs(u) and want_u * u >= 0 else brake
        u = _toward(u, want_u, rate * dt)
        w = _toward(robot.omega, want_w, robot.max_alpha * dt)
        yaw = _wrap(robot.yaw + w * dt)
        mid = robot.yaw + 0.5 * w * dt
        step = u * complex(math.cos(mid), math.sin(mid))
        new = robot.pos + step * dt
        if u != 0 and (not swept_clear(s.world, robot.pos, new, 0.5 * robot.radius)
                       or (not math.isnan(guard) and intrudes(s, robot.pos, new, guard))):
            u, step, new = 0.0, 0j, robot.pos
        robot.yaw, robot.speed, robot.omega = yaw, u, w
        robot.heading = complex(math.cos(yaw), math.sin(yaw))
        robot.pos, robot.vel = new, step
        return
    if unicycle:  # a unicycle command on a holonomic body: along the heading, turning as asked
        robot.yaw = _wrap(robot.yaw + min(max(turn, -robot.max_omega), robot.max_omega) * dt)
        v = forward * complex(math.cos(robot.yaw), math.sin(robot.yaw))
        has_heading, heading = True, complex(math.cos(robot.yaw), math.sin(robot.yaw))
    if abs(v) > robot.max_speed:
        v = v * (robot.max_speed / abs(v))
    change = v - robot.vel
    rate = robot.max_accel if abs(v) > abs(robot.vel) else brake
    if abs(change) > rate * dt:
        v = robot.vel + change * (rate * dt / abs(change))
    new = robot.pos + v * dt
    if v != 0 and not swept_clear(s.world, robot.pos, new, 0.5 * robot.radius):
        v, new = 0j, robot.pos
    if abs(v) > TURNING_SPEED:
        facing = heading if has_heading and abs(heading) > 0 else v
        robot.yaw = math.atan2(facing.imag, facing.real)
        robot.heading = facing / abs(facing)
    robot.omega = _wrap(robot.yaw - old) / dt
    robot.pos, robot.vel, robot.speed = new, v, abs(v)
