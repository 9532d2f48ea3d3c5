"""Every threshold of the verifier, in one place (metres, seconds, m/s). The user-settable ones are the fields of
`VerifySettings` (verify/models.py), whose defaults are read from here and which is the only source of the
`verify` command's defaults; the others are fixed definitions of what an event is. Body sizes and proxemic
zones come from socnavgen.bodies, the "in the robot's way" margins from socnavgen.proxemics.
"""

from socnavgen.bodies import TOUCH_DISTANCE
from socnavgen.sim.people.leaves import BLOCK_AHEAD, BLOCK_HOLD

# -- user-settable (VerifySettings defaults) --------------------------------------------------------
MEET_DISTANCE = 2.0  # m centre to centre: robot and person "meet" this close
NEAR_NODE = 1.0  # m: how close to its encounter node a meeting must happen (runs without spec.json)
PASSING_DISTANCE = 2.5  # m: a tree's GiveWaytoRobot counts "while the robot passes" this close
GROUP_SPREAD = 2.5  # m: largest distance between group members, the whole run
DEADLOCK_SECONDS = 10.0  # s: longest the robot may make no progress with someone in its way
REACTION_SECONDS = 5.0  # s: default time a reaction has after its cause
REACTION_SLACK = 0.5  # m: the robot comes this much closer while a reaction asked for at a distance begins

# -- definitions of events (fixed) ------------------------------------------------------------------
STILL_SPEED = 0.05  # m/s: the robot stands still below this
STOP_SPEED = 0.1  # m/s: a person has stopped below this
WALK_SPEED = 0.3  # m/s: a person walks above this (following, walking before a stop)
FOLLOW_AHEAD = TOUCH_DISTANCE  # m: a follower of the robot is never farther ahead of it along its route while it drives
#                                (level with it, beside it: a body's length; one walking in front of it leads, not follows)
FOLLOW_SEEN = 2.0  # s: a follower is seen walking after the driving robot this long at least (trailing it)
MOVED_DISTANCE = 0.5  # m: a person "has walked" once this far from where it started
WAY_REACH = 1.2  # m: a person passes a node of their planned way within this (a step to either side of it: walking
#                  abreast of another, or round someone standing on it); verify/way_in.py
AHEAD_HALF_ANGLE = 45.0  # degrees: the robot is "ahead of" a person inside this cone around the person's heading
APPROACH = 0.5  # m: a meeting needs the two to be this much closer than at the start, each having come this
#                 much closer to the place (or being at it)
ASIDE_DISTANCE = 0.25  # m: a person giving way moves at least this far from where it last stood in the way
PROGRESS_STEP = 0.25  # m of new progress along its route that restarts the robot's deadlock clock
IDLE_SECONDS = 8.0  # s: longest the robot may get nowhere along its route with its way clear and no cue asking it to
#                     stand (verify/idle.py): an idle robot nobody can see a cause for (no_deadlock holds it too)
NOTICE_RANGE = 5.0  # m: a person notices a visible robot this close (keeps_away)
STOP_NOTICE_RANGE = 3.0  # m: stops_near_robot's cause: the person walked while the robot was this close (at least)
STOP_HOLD = 1.0  # s: a stop lasts at least this long
HELD_ON = 10.0  # s: a stop lasting while the robot is near, still held this long when the run ends, reads as one that
#   never ends (round 34's warehouse_26: a picker stood 22 s to the end; round 32's home_25: a parent waiting 7 s
#   for the robot and a follower to pass as the run ended read as waiting, as its text says)
ROBOT_STOP_SECONDS = 2.0  # s: robot_stops, unless it says: the robot stands still this long (a stop people see as one)
PERCEIVED_SECONDS = 0.5  # s: a person sees the mean speed over this window (about a step): verify/perceived.py; a
#                          standstill of STOP_HOLD is seen standing STOP_HOLD less the window (perceived.seen_hold)
WAIT_MARGIN = 5.0  # s a scripted wait may overrun before it counts as a deadlock
DEFAULT_GOAL_RADIUS = 0.5  # m, when neither the settings nor the trace give one
MIN_RUN_SECONDS = 1.0  # s: a run shorter than this ended before anything could happen
FAR = 1.0e3  # m: the value of a distance that does not exist (no humans, unreachable)

# -- per-kind default distances, when a criterion gives none (metres) --------------------------------
# blocks_robot: where BlockRobot stands, its point ahead of the robot, as far off as she stands still there (a
# blocker standing 1.53 m in front of the robot, facing it, failed 1.5 m: home_18 of round 22)
KIND_DISTANCE = {"stops_near_robot": 1.5, "gives_way": 2.0, "follows_robot": 2.0, "follows_human": 2.0,
                 "hidden_until": 3.0, "keeps_away": 1.5, "blocks_robot": BLOCK_AHEAD + BLOCK_HOLD,
                 "stop_together": 3.0}  # stop_together: a greeting "a couple of metres" apart, inside social space
# The verifier's margins of "in the robot's way" are proxemics.WAY_MARGIN_VERIFY (inway_<human>) and
# proxemics.HELD_UP_DISTANCE (someone in the way this close holds the robot up: deadlock, wait_until_clear).
