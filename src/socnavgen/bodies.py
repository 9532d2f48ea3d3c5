"""Bodies and the distances between them: the one home of the physical facts that every stage shares
(prompts, cards, paths, simulator, metrics, verifier, exporters, map checks). Import them from here;
never type a radius or a sum of radii again.

Values are HuNavSim's and the SocRATES Gazebo wrapper's (see ../shared/reference/hunav-node-library.md
§1.3, §9.3) unless said otherwise.
"""

from __future__ import annotations

import math

# -- bodies ---------------------------------------------------------------------------------------
PERSON_RADIUS = 0.4  # m: a simulated person's disc (HuNavSim agent radius)
PERSON_HEIGHT = 1.8  # m: what a walking person's body fills above the floor: a shelf lower than this blocks
ROBOT_RADIUS = 0.35  # m: the robot's disc (SocRATES Gazebo wrapper)
TOUCH_DISTANCE = PERSON_RADIUS + ROBOT_RADIUS  # m centre to centre: robot and person touch (0.75)
PERSON_TOUCH_DISTANCE = 2 * PERSON_RADIUS  # m centre to centre: two people touch (0.8)
GROUP_SPAWN_RADIUS = 0.6  # m: the members of a group start evenly on a circle this far from their first node
#   (wider for four or more: group_ring)

# -- motion ---------------------------------------------------------------------------------------
PERSON_MAX_SPEED = 1.5  # m/s: HuNavSim's max_vel default
PERSON_TOP_SPEED = 1.8  # m/s: the most a scenario may give a person (HuNavSim 2.x clamps an agent's vel to it)
PERSON_START_LAG = 0.5  # s: a person setting off from rest arrives this much later than at full speed (SFM's tau)
CLEAR_LEAD = 1.5  # m: at a door, a person meeting the robot there goes through while the robot is this far before it
PERSON_PASS_GAP = 0.5  # m: the gap a person leaves passing the robot where there is room (sim.people.avoid)
PERSON_GOAL_RADIUS = 0.5  # m: a person's goal is reached within this (HuNavSim goal_radius)
PERSON_GOAL_SLACK = 0.1  # m: IsGoalReached accepts goal_radius + this
ROBOT_GOAL_TOLERANCE = 0.2  # m: hunav_evaluator's "completed"
ROBOT_MAX_SPEED = 2.0  # m/s: the simulated robot never moves faster, whatever its policy asks
STANDING = 0.1  # m/s: a person or the robot slower than this stands (people jitter in place below it)
# A comfortable deceleration for people near or on a moving vehicle: 0.11-0.15 g is the limit ground-transport
# comfort studies find acceptable (Hoberock 1977, "A survey of longitudinal acceleration comfort studies in
# ground transportation vehicles", J. Dyn. Sys. Meas. Control 99(2)); 0.15 g = 1.5 m/s^2. The default robot brakes
# no harder unless a collision is imminent (robot.brake), and the smooth_braking check holds every robot to it.
COMFORT_DECELERATION = 1.5  # m/s^2

# -- contact and proxemics (gaps are surface to surface: centre distance minus both radii) ---------
CONTACT_MARGIN = 0.05  # m: a robot-person (or person-person) gap at or under this is contact (bodies touching)
PERSON_KEEP_GAP = 0.1  # m: two people keep at least this gap (> CONTACT_MARGIN): a walker's own step never closes
#   it (sim.people.spacing) and the contact step (sim.people.physics) pushes people apart to it
PERSON_STAND_GAP = 0.3  # m: people standing or waiting side by side keep this gap (people keep ~0.3-0.5 m between
#   bodies; a 0.4 m disc is wider than a body, so 0.3 m between discs is ~0.6 m between shoulders; 0.1 m read as
#   "pressed together" to the eyes): the spots round a shared goal (sim.people.spots), a walker coming to stand
#   beside someone standing (sim.people.spacing) and the queue at a goal (sim.people.state.queued_at)
PERSON_ROBOT_GAP = 0.2  # m: a person's own step never brings them closer than this to the robot's body where there
#   is room (sim.people.avoid.keep_off), and no person squeezes past a standing robot closer (sim.people.spots): at the
#   GIF's ~4 cm a pixel 0.1 m read as touching (a nurse walking back into the robot's side: hospital_08)
ROBOT_SOCIAL_GAP = 0.3  # m: the gap the default robot keeps from a person where there is room: it never drives
# closer (robot.polite.keep_clear), steps off the way of someone walking at it, and waits rather than squeezes past
ROBOT_WALL_ROOM = 0.08  # m beyond its radius: the default robot moves aside only where this much room from walls is left
ROBOT_WALL_MARGIN = 0.05  # m beyond its radius on each side: the room from walls the narrowest way a scene graph routes
#   the robot through leaves it (a way the robot's body only just fills gives every planner wall contacts)
ROBOT_PASSAGE_WIDTH = round(2 * (ROBOT_RADIUS + ROBOT_WALL_MARGIN), 2)  # m wall to wall (0.8): `location extract` keeps
#   no edge (nor node) narrower, so a card's route never leads the robot through a gap it cannot pass (traverse)
INTIMATE_SPACE, PERSONAL_SPACE, SOCIAL_SPACE = 0.45, 1.2, 3.6  # m: Hall's proxemic zone limits (gaps)


def walk_time(distance: float, speed: float) -> float:
    """Seconds a person standing still needs to walk `distance` m at `speed` m/s (its own speed): THE time by
    which pacing (sim.people.pacing) and the export's timing (export.timing) let a waiting person set off."""
    return distance / max(speed, 1e-3) + PERSON_START_LAG


def group_ring(members: int) -> float:
    """The circle a group of `members` starts on: GROUP_SPAWN_RADIUS, or wider where neighbours on it would be
    closer than PERSON_KEEP_GAP (four and more; a group of four on 0.6 m stood 0.05 m apart, touching by the
    contact rule, so the spawn moved three of them elsewhere and the prompt's placement was wrong)."""
    if members < 2:
        return GROUP_SPAWN_RADIUS
    apart = (PERSON_TOUCH_DISTANCE + PERSON_KEEP_GAP) / (2 * math.sin(math.pi / members))
    return max(GROUP_SPAWN_RADIUS, math.ceil(apart * 100 - 1e-9) / 100)
