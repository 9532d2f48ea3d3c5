"""DWA, the Dynamic Window Approach (Fox, Burgard, Thrun, "The dynamic window approach to collision
avoidance", IEEE Robotics & Automation Magazine 4(1), 1997): `--robot dwa`.

Our own implementation of the paper's section 3, written for this simulator. The robot answers a unicycle
command (v, omega) (RobotAction.unicycle), searched over

    V_r = V_s  intersect  V_a  intersect  V_d                                              (paper, section 3)

* V_s, the possible velocities: |v| <= max speed, |omega| <= max turn rate (the body's limits, obs.limits);
* V_d, the dynamic window: v in [v_a - vdot_b h, v_a + vdot_a h], omega in [omega_a - omegadot h,
  omega_a + omegadot h], the velocities reachable within the window `h` (s) from the current ones (v_a,
  omega_a: obs.speed, obs.omega) under the body's accelerations; sampled on a grid of `v_samples` x
  `w_samples`, with v >= 0 (the paper's robot drives forward);
* V_a, the admissible velocities: v <= sqrt(2 dist(v, omega) vdot_b) and |omega| <= sqrt(2
  dist(v, omega) omegadot_b), dist being the distance travelled along the circular arc of (v, omega) before
  the robot's disc would touch a wall or come within HARD of a person (the paper's obstacles are static; here the people move on at their
  current velocity, a usual extension, and walls come from the occupancy map); standing still is always
  admissible.

Among V_r it maximises the objective (section 3)

    G(v, omega) = sigma(alpha heading(v, omega) + beta dist(v, omega) + gamma velocity(v, omega))

with heading = 1 - |theta| / pi, theta the angle between the robot's heading at the end of the predicted
arc and the direction to the route's target (robot.route: the waypoint, or the global planner's carrot where
the line to it is blocked), dist the free distance capped at `dist_cap` and divided by it, velocity v / max
speed, and sigma the smoothing of the paper taken as each term's normalisation to [0, 1] over the window (the
weights `alpha`, `beta`, `gamma` are ours, tuned on the classic cases of tests/sim/test_baselines.py).
The robot slows down for its goal (v <= sqrt(2 vdot_b d_goal)) and turns on the spot toward its target when
it faces more than `turn_in_place` rad away from it, until it faces within TURNED (the paper's robot starts
pointing along its way). Not in the paper (a recovery behaviour, as navigation stacks add one): after choosing
to stand for `patience` s away from its goal (someone stands against it), it backs away for ESCAPE s at up to
REVERSE_SPEED along the arc that frees the most room, then searches again.
"""

from __future__ import annotations

import math

import numpy as np

from socnavgen.sim.robot.api import RobotAction
from socnavgen.sim.robot.route import Route, RouteFollower

HARD = 0.06  # m: an arc coming closer than this to a person is not admissible (contact is 0.05 m)
CELL_SLACK = 0.01  # m: already closer to a wall than the margin, an arc counts as hitting it only this much closer
TURNED = 0.4  # rad: turning on the spot ends facing this close to the way
TURN_GAIN = 2.0  # 1/s: turn rate on the spot per radian still to turn
STUCK_SPEED = 0.02  # m/s: choosing slower than this counts as standing (stuck)
REVERSE_SPEED = 0.15  # m/s: backing away when stuck
ESCAPE = 1.5  # s backing away


class DWAPolicy(RouteFollower):
    """`--robot dwa` (see the module's docstring). Parameters (a campaign's `params:`): max_speed (m/s),
    window (s: h), horizon (s of predicted motion), step (s between predicted points), v_samples, w_samples,
    alpha, beta, gamma (weights of heading, clearance and speed), dist_cap (m), safety (m added to the
    radii), turn_in_place (rad), patience (s standing before it backs away)."""

    def __init__(self, max_speed: float = 0.6, window: float = 0.25, horizon: float = 3.0, step: float = 0.1,
                 v_samples: int = 9, w_samples: int = 21, alpha: float = 0.8, beta: float = 1.0,
                 gamma: float = 0.3, dist_cap: float = 1.5, safety: float = 0.1, turn_in_place: float = 1.2,
                 goal_decel: float = 0.8, patience: float = 3.0) -> None:
        self.max_speed, self.window, self.horizon, self.step = float(max_speed), float(window), float(horizon), float(step)
        self.v_samples, self.w_samples = max(2, int(v_samples)), max(3, int(w_samples))
        self.alpha, self.beta, self.gamma = float(alpha), float(beta), float(gamma)
        self.dist_cap, self.safety, self.turn_in_place = float(dist_cap), float(safety), float(turn_in_place)
        self.goal_decel, self.patience = float(goal_decel), float(patience)
        self.route: Route | None = None
        self._turning, self._stuck = False, 0.0  # turning on the spot; s it has chosen to stand
        self._times = np.arange(1, int(round(self.horizon / self.step)) + 1) * self.step

    def act(self, obs) -> RobotAction:  # noqa: ANN001 - an Observation
        way = self.way(obs)
        if way is None:
            return RobotAction.unicycle(0.0, 0.0)
        route, p, yaw, to, top, lim = self.route, obs.position_c, obs.yaw, way.to, way.top, obs.limits
        error = _wrap(math.atan2(to.imag, to.real) - yaw)
        v_now, w_now = max(obs.speed, 0.0), obs.omega
        if abs(error) > (TURNED if self._turning else self.turn_in_place):  # facing away: turn on the spot first
            self._turning = True  # until it faces within TURNED of its way, at a turn rate it can stop from
            rate = min(lim["max_omega"], math.sqrt(2.0 * lim["max_alpha"] * abs(error)), TURN_GAIN * abs(error))
            return RobotAction.unicycle(0.0, math.copysign(rate, error))
        self._turning = False
        escaping = self._stuck >= self.patience
        if escaping:  # stuck: back away slowly along the arc that frees the most room, for ESCAPE s
            vs = np.linspace(-REVERSE_SPEED, 0.0, 4)
        else:
            vs = np.linspace(max(0.0, v_now - lim["max_decel"] * self.window),
                             min(top, v_now + lim["max_accel"] * self.window), self.v_samples)
        ws = np.linspace(max(-lim["max_omega"], w_now - lim["max_alpha"] * self.window),
                         min(lim["max_omega"], w_now + lim["max_alpha"] * self.window), self.w_samples)
        v, w = (a.ravel() for a in np.meshgrid(vs, ws))
        arcs = _arcs(p, yaw, v, w, self._times)  # (candidates, T) predicted positions
        free, stop = self._free_distance(obs, route, arcs, np.abs(v))
        admissible = (np.abs(v) <= np.sqrt(2.0 * stop * lim["max_decel"]) + 1e-9) & \
                     (np.abs(w) <= np.sqrt(2.0 * stop * lim["max_alpha"]) + 1e-9) | (v == 0.0)
        end_yaw = yaw + w * self._times[-1]
        goal_heading = math.atan2(to.imag, to.real)
        heading = 1.0 - np.abs(_wrap(goal_heading - end_yaw)) / math.pi
        room = _norm(np.minimum(free, self.dist_cap) / self.dist_cap)
        score = room + _norm(-v) if escaping else \
            self.alpha * _norm(heading) + self.beta * room + self.gamma * _norm(v / max(top, 1e-9))
        score = np.where(admissible, score, -np.inf)
        best = int(np.argmax(score))
        chosen = (float(v[best]), float(w[best])) if np.isfinite(score[best]) else (0.0, 0.0)
        if escaping:
            self._stuck = self._stuck + obs.dt if self._stuck < self.patience + ESCAPE else 0.0
        else:
            self._stuck = self._stuck + obs.dt if abs(chosen[0]) < STUCK_SPEED and abs(route.goal - p) > 0.3 else 0.0
        return RobotAction.unicycle(*chosen)

    def _free_distance(self, obs, route: Route, arcs: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:  # noqa: ANN001
        """(dist(v, omega) of the objective, the distance of the admissibility test): metres along each arc
        before the robot's disc comes within `safety` of a person (people moving on at their velocity) or
        safety / 2 of a wall, and before it comes within HARD of a person or touches a wall; the whole arc's
        length when nothing is hit. Already closer than a margin, only closing in further counts."""
        radius, p = obs.radius, obs.position_c
        clear_now = route.world.clearance_at_point(p)
        clear = route.clearance(arcs) - radius
        soft = clear < min(0.5 * self.safety, clear_now - radius - CELL_SLACK)
        hard = clear < min(0.0, clear_now - radius - CELL_SLACK)
        people = obs.human_positions_c
        if len(people):
            near = np.abs(people - p) < self.horizon * (self.max_speed + 2.0) + 1.0
            if near.any():
                radii = radius + obs.human_radii[near]
                gap_now = np.abs(people[near] - p) - radii
                q = people[near][:, None] + obs.human_velocities_c[near][:, None] * self._times[None, :]  # (n, T)
                gap = np.abs(arcs[:, None, :] - q[None]) - radii[None, :, None]
                soft |= (gap < np.minimum(self.safety, gap_now - 1e-6)[None, :, None]).any(axis=1)
                hard |= (gap < np.minimum(HARD, gap_now - 1e-6)[None, :, None]).any(axis=1)
        travelled = np.concatenate([[0.0], self._times])
        free = [v * travelled[np.where(hit.any(axis=1), hit.argmax(axis=1), len(self._times))] for hit in (soft, hard)]
        return free[0], free[1]


def _wrap(angle):  # noqa: ANN001, ANN202 - a float or an array
    return (angle + np.pi) % (2 * np.pi) - np.pi


def _norm(values: np.ndarray) -> np.ndarray:
    """values scaled to [0, 1] over the admissible window (all equal: zeros)."""
    finite = values[np.isfinite(values)]
    if finite.size == 0:
        return np.zeros_like(values)
    low, high = finite.min(), finite.max()
    return (values - low) / (high - low) if high - low > 1e-12 else np.zeros_like(values)


def _arcs(p: complex, yaw: float, v: np.ndarray, w: np.ndarray, times: np.ndarray) -> np.ndarray:
    """(candidates, T) positions along the circular arcs of constant (v, omega) from p facing yaw."""
    t = times[None, :]
    vv, ww = v[:, None], w[:, None]
    straight = np.abs(ww) < 1e-6
    safe_w = np.where(straight, 1.0, ww)
    turned = p + vv / safe_w * (np.exp(1j * (yaw + safe_w * t)) - np.exp(1j * yaw)) / 1j
    line = p + vv * t * np.exp(1j * yaw)
    return np.where(straight, line, turned)
