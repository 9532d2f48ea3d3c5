"""Letting a walker by (compiled; robot.polite reads it): who tails the robot, and whether it must stop for them.

A person held behind the robot in a corridor walks its pace WAIT_GAP behind it (people.avoid): never seen catching
up, they were never made room for, and the two walked a corridor's length half a metre apart. `tails` names such a
walker (pass_aside then moves the robot to its side); `let_by` tells whether the walls leave them room past it only
while it stands (people.avoid passes a standing robot at MIN_PASS_GAP, a moving one at MOVING_PASS_GAP): then
follow_speed stops it against the wall until they are by.
"""

from __future__ import annotations

import math

from socnavgen.bodies import PERSONAL_SPACE
from socnavgen.sim.jit import jit
from socnavgen.sim.people.avoid import MOVING_PASS_GAP
from socnavgen.sim.people.avoid import room_beside as person_room
from socnavgen.sim.people.spots import MIN_PASS_GAP
from socnavgen.sim.robot.lead import goes_with_robot

WALKING = 0.2  # m/s along the robot's way: a person walks its way (follow_speed)
SAME_WAY = math.cos(math.radians(30))  # their heading within 30 degrees of its way
ABREAST_WALKING = 0.05  # m/s along its way: someone beside the robot within intimate space this fast is let ahead
TAILING = PERSONAL_SPACE  # m (gap): someone walking the robot's way this close behind it tails it


@jit
def tails(s, i, back, gap):  # noqa: ANN001, ANN201
    """Person i, `gap` from the robot and not ahead of it, walks its way (`back`: the conjugate of its unit direction)
    within TAILING of it: faster than WALKING along it, within SAME_WAY, not someone who goes with it (robot.lead)."""
    q = s.people[i]
    along = (q.vel * back).real
    return gap < TAILING and along > WALKING and along >= SAME_WAY * abs(q.vel) and not goes_with_robot(s, i)


@jit
def let_by(s, i, direction):  # noqa: ANN001, ANN201
    """Person i, behind the robot, fits past it on one side (people.avoid.room_beside: off the walls) standing but not
    moving: only if it stops do they get by (else they walk behind it for good)."""
    reach = s.people[i].radius + s.robot[0].radius
    moving, standing = False, False
    for side in (1j, -1j):
        moving = moving or person_room(s, side * direction, reach, MOVING_PASS_GAP, MOVING_PASS_GAP) >= 0
        standing = standing or person_room(s, side * direction, reach, MIN_PASS_GAP, MIN_PASS_GAP) >= 0
    return standing and not moving
