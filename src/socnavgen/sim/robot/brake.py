"""How hard the default robot brakes (compiled): within the comfort limit (bodies.COMFORT_DECELERATION, 0.15 g)
unless a collision is imminent, as a service robot's velocity smoother limits its deceleration and only its
safety field stops it hard (issue 29: braking at the body's 2 m/s2, the default robot passed its smooth_braking
check in 22 % of the acceptance campaign's episodes).

Imminent: stopping comfortably from its speed toward someone (its own velocity along the line to them; a person
walking into it is not stopped by its brakes) would take it within its protective field (policy.guard: the gap
it keeps) of them, one step's travel counted. Then the body brakes at its own limit (robot.body.drive), and the
protective field still stops it at once where even that is too late. The policy's speed profile (its `brake`)
slows it within the comfort limit beforehand, so that the hard brake stays the exception.
"""

from __future__ import annotations

import math

from socnavgen.bodies import COMFORT_DECELERATION
from socnavgen.sim.jit import jit


@jit
def brake_limit(s):  # noqa: ANN001, ANN201
    """The most the robot may brake this step (m/s2): COMFORT_DECELERATION, or NaN (the body's own limit) when a
    comfortable stop would take it within its protective field of someone it drives toward."""
    robot, policy = s.robot[0], s.policy[0]
    guard = policy.guard if math.isfinite(policy.guard) else 0.0
    dt = s.clock[0].dt
    for i in range(s.people.shape[0]):
        q = s.people[i]
        d = q.pos - robot.pos
        dist = abs(d)
        if dist < 1e-9:
            return math.nan
        toward = (robot.vel * (d / dist).conjugate()).real
        if toward <= 0.0:
            continue
        room = dist - q.radius - robot.radius - guard - toward * dt
        if room < toward * toward / (2.0 * COMFORT_DECELERATION):
            return math.nan
    return COMFORT_DECELERATION
