"""One step of the simulation, and the episode as a generator of steps (compiled).

Per step:
1. pacing sets who is held at their interaction point; every tree is ticked once (person-id order) on the
   current snapshot (distances to the robot and environment forces were computed for it at the end of the
   last step); actions only set motion commands; people standing in the way of a robot that waits make room
   (people.make_room); each walker's way there (around walls and the robot);
2. the robot's script plays; the robot's policy acts on the same snapshot - a built-in one right here, a
   Python one between two resumptions of the generator (it answers through `s.action[0]`); its velocity is
   capped at the robot's max speed and a move that would cross or end inside a wall is refused;
3. one social-force step for every walking person, then the contact step (people.physics);
4. goals reached are consumed, people blocking the robot face it, the clock advances, the robot's gesture
   is the policy's, else the script's; the new state is recorded.

The generator yields an event whenever Python has something to do: ACT (a Python policy must answer),
STEPPED (one step done, when asked for single steps), PROGRESS (every `progress_every` steps), ENDED (the
run ended: clock.end says why), FAILED (a tree could not go on: clock.error_* say where) or ROUTES (before a
step: route fields the last step asked for, world.routes). All the state
lives in `s`, so a new generator resumes where the last one stopped.

The parts of a step are inlined into `steps` (a call that is not inlined passes every array of the state
field by field: inlining them took a 5-person step from 3.6 to 3.0 us).
"""

from __future__ import annotations

import math

from socnavgen import proxemics
from socnavgen.bodies import STANDING
from socnavgen.sim.engine.state import ALL_DONE, ROBOT_GOAL, RUNNING, TIMEOUT
from socnavgen.sim.jit import generator, jit
from socnavgen.sim.people.grace import ARRIVAL_GRACE, coming
from socnavgen.sim.people.make_room import make_room
from socnavgen.sim.people.pacing import pace
from socnavgen.sim.people.physics import advance, resolve_contacts
from socnavgen.sim.people.routing import plan, robot_progress
from socnavgen.sim.people.state import done, pop_goal
from socnavgen.sim.people.vm import ERROR, tick
from socnavgen.sim.robot.body import drive
from socnavgen.sim.robot.policies import act, cruise, stopped_short
from socnavgen.sim.robot.polite import corner_late
from socnavgen.sim.robot.script import play, scripted_gesture, start_waits, still_waits, waiting_for

STEPPED, ACT, PROGRESS, ENDED, FAILED, ROUTES = 0, 1, 2, 3, 4, 5
IDLE_SPEED = 1e-3  # m/s: a robot slower than this is idle (the run ends once everything stopped)
STALL_PROGRESS = 0.1  # m along its route: a robot that has not got this much farther than its best, and has
STALL_REACH = 0.5  # m: ... stayed this close to where it began to, waits (clock.stalled), however it edges about
#   there (the polite robot's small moves reset clock.idle every second or so); one driving round someone does not
CREEP_IDLE = 2.0  # s without STALL_PROGRESS: a robot creeping about is idle as if it stood (clock.idle)


@jit(inline=True)
def think(s, trees, pacing, script, scratch):  # noqa: ANN001, ANN201
    """Pacing, every tree, the script: what everyone wants this step. ERROR when a tree cannot go on."""
    people = s.people
    for i in range(people.shape[0]):
        p = people[i]
        p.sees_robot = -1
        p.walks, p.turns, p.face_robot_within = False, False, 0.0
        p.action, p.action_moves, p.succeeded, p.coming = -1, False, 0, False
        scratch.before[i] = p.pos  # the contact step compares with where everyone stood
    if people.shape[0]:
        cruising = cruise(s, script.now[0])
        corner_late(s, cruising, pacing.robot_late)  # the robot's ETA knows its slower blind corners
        pace(s, pacing, cruising, still_waits(script, s.clock[0].t), waiting_for(script), start_waits(script, s.clock[0].t))
    nodes, ports, slots, texts, kids, stack, args = trees
    dt = s.clock[0].dt
    for i in range(people.shape[0]):
        if s.clock[0].t < people[i].start_delay:  # not started yet: stands at its spawn point
            continue
        if tick(s, nodes, ports, slots, texts, kids, stack, args, dt, i) == ERROR:
            return ERROR
    now = script.now[0]  # someone standing in the way of a robot that waits steps aside (after their tree), not
    make_room(s, now.timed or now.letting >= 0)  # while its script stands it (last step's cues: script.play)
    plan(s)
    for i in range(min(people.shape[0], script.finished.shape[0])):  # whom a let_pass need not wait for (script.gone_by)
        script.finished[i] = done(people, s.goals, i)
    play(s, script)
    return 0


@jit(inline=True)
def settle(s, script, scratch, reached, gesture):  # noqa: ANN001, ANN201
    """After the walking step: contacts, goals consumed, faces turned, the clock, the robot's gesture."""
    people, robot, clock = s.people, s.robot[0], s.clock[0]
    if resolve_contacts(people, robot, s.world, clock.contact_slack, scratch.before, scratch.snap, scratch.grid):
        for i in range(people.shape[0]):
            people[i].robot_distance = abs(robot.pos - people[i].pos)
    for i in range(people.shape[0]):
        p = people[i]
        if reached and p.reached:
            pop_goal(people, s.goals, i, False)
        if p.face_robot_within > 0:
            d = robot.pos - p.pos
            if abs(d) <= p.face_robot_within:
                p.yaw = math.atan2(d.imag, d.real)
    clock.t += clock.dt
    clock.step += 1
    robot.scripted = scripted_gesture(s, script)
    robot.held = script.now[0].timed or script.now[0].letting >= 0
    robot.gesture = gesture if gesture >= 0 else robot.scripted
    if robot.gesture != 0:
        robot.said |= 1 << robot.gesture


@jit(inline=True)
def record(s, trace):  # noqa: ANN001, ANN201
    """The current state into the trace's row of this step (steps beyond its rows are not recorded)."""
    k, robot = s.clock[0].step, s.robot[0]
    if k >= trace.robot.shape[0]:
        return
    for i in range(s.people.shape[0]):
        p = s.people[i]
        trace.pos[k, i], trace.vel[k, i], trace.yaw[k, i], trace.omega[k, i] = p.pos, p.vel, p.yaw, p.omega
        trace.action[k, i], trace.succeeded[k, i] = p.action, p.succeeded
        trace.gesture[k, i], trace.behavior[k, i] = p.gesture, p.behavior
    trace.robot[k, 0], trace.robot[k, 1], trace.robot[k, 2] = robot.pos.real, robot.pos.imag, robot.yaw
    trace.robot[k, 3], trace.robot[k, 4], trace.robot[k, 5] = robot.vel.real, robot.vel.imag, robot.omega
    trace.robot_gesture[k] = robot.gesture


@jit(inline=True)
def ending(s):  # noqa: ANN001, ANN201
    """Why the run ends after this step (RUNNING: it goes on)."""
    robot, clock = s.robot[0], s.clock[0]
    # at its goal after coming near each other waypoint in turn (as close as the robots skip an occupied one):
    # a round trip [A, B, A] starts on its goal and must not end at t = 0
    wps = s.waypoints
    while robot.passed < wps.shape[0] - 2 and abs(wps[1 + robot.passed] - robot.pos) <= proxemics.OCCUPIED_REACH:
        robot.passed += 1
    progress, _ = robot_progress(s)
    if progress > clock.best_progress + STALL_PROGRESS or abs(robot.pos - clock.stalled_at) > STALL_REACH:
        clock.best_progress, clock.stalled_at, clock.stalled = max(progress, clock.best_progress), robot.pos, 0.0
    else:
        clock.stalled += clock.dt
    # idle: standing, or getting nowhere for CREEP_IDLE s however it creeps (progress along its route counts, not
    # speed > 0: a robot inching at 5 mm/s 1.07 m from someone beyond its goal never arrived nor ended the run)
    idle = abs(robot.vel) < IDLE_SPEED or clock.stalled >= CREEP_IDLE
    clock.idle = max(clock.idle + clock.dt, clock.stalled) if idle else 0.0
    clock.standing = clock.standing + clock.dt if abs(robot.vel) < STANDING else 0.0  # pacing reads it
    if robot.passed >= wps.shape[0] - 2 and (abs(robot.goal - robot.pos) <= robot.goal_tolerance or (
            clock.idle >= proxemics.GOAL_STOP_DWELL and not robot.held and stopped_short(s))):  # stood short of
        # someone at its goal, not standing for its script (a handover: round 22's first-aid kit run ended 5 s into
        # the robot's 10 s wait when the colleague taking the kit came up between it and its goal)
        if not clock.stop_at_end:  # single steps: the caller decides what happens next
            return ROBOT_GOAL
        if clock.arrived < 0:
            clock.arrived = clock.t
    if clock.arrived >= 0:  # a run: it goes on while a follower still walks in (people.grace), within the grace
        late = clock.t - clock.arrived >= ARRIVAL_GRACE - 1e-9 or clock.step >= clock.max_steps
        return ROBOT_GOAL if late or not coming(s) else RUNNING
    if clock.idle >= clock.idle_end and not robot.held:  # a robot its script stands (a timed wait, a let_pass)
        finished = True  # goes on when the wait ends: home_19's 16 s wait at a bedroom door ended the run 10 s in
        for i in range(s.people.shape[0]):
            finished = finished and done(s.people, s.goals, i)
        if finished:
            return ALL_DONE
    return TIMEOUT if clock.step >= clock.max_steps else RUNNING


@jit(inline=True)
def after(s):  # noqa: ANN001, ANN201
    """The event to hand to Python after this step (-1: none, go on)."""
    clock = s.clock[0]
    clock.end = ending(s)
    if clock.stop_at_end and clock.end != RUNNING:
        return ENDED
    if clock.each_step:
        return STEPPED
    if clock.progress_every > 0 and clock.step % clock.progress_every == 0:
        return PROGRESS
    return -1


@jit(inline=True)
def move_robot(s, script):  # noqa: ANN001, ANN201
    """The robot's move: a Python policy's answer (left in s.action), else the built-in policy's; returns the
    gesture the policy makes (-1: none, the script's)."""
    if s.clock[0].arrived >= 0:  # arrived: it stands at its goal while its followers come in (people.grace)
        drive(s, 0j, 0j, False, False, 0.0, 0.0, math.nan, math.nan)
        return -1
    if s.clock[0].python_policy:
        action = s.action[0]
        drive(s, complex(action.vx, action.vy), action.heading, action.has_heading, action.unicycle, action.forward,
              action.turn, math.nan, math.nan)
        return action.gesture
    policy = s.policy[0]
    v = act(s, script.now[0])
    guard = math.nan if script.now[0].misbehave else policy.guard  # a scripted misbehaving robot is rude on purpose
    drive(s, v, policy.heading, policy.has_heading, policy.unicycle, policy.forward, policy.turn, guard, policy.decel)
    return -1


@jit(inline=True)
def walk(s, scratch):  # noqa: ANN001, ANN201
    """Everyone's social-force step; how many reached their real goal."""
    if s.people.shape[0] == 0:
        return 0
    robot = s.robot[0]
    return advance(s.people, s.group_sizes, s.forces, s.world, robot.pos, robot.vel, robot.radius, s.clock[0].dt,
                   scratch, True)


@jit(inline=True)
def timed_out(s):  # noqa: ANN001, ANN201
    clock = s.clock[0]
    if clock.stop_at_end and clock.step >= clock.max_steps:
        clock.end = TIMEOUT
        return True
    return False


@jit
def steps(e, acted):  # noqa: ANN001, ANN201
    """Steps until Python has something to do; returns the event. `acted`: a Python policy has just
    answered ACT, so this step goes on from the robot's move. (The loop lives here, not in the generator:
    numba optimises a generator's body less well.)"""
    s, trees, script, pacing, scratch, trace = e
    while True:
        if not acted:
            if timed_out(s):
                return ENDED
            if s.routes.pending[0] > 0:  # route fields asked for last step: Python grows them first
                return ROUTES
            if think(s, trees, pacing, script, scratch) == ERROR:
                return FAILED
            if s.clock[0].python_policy and s.clock[0].arrived < 0:
                return ACT
        acted = False
        gesture = move_robot(s, script)
        reached = walk(s, scratch)
        settle(s, script, scratch, reached, gesture)
        record(s, trace)
        event = after(s)
        if event >= 0:
            return event


@generator
def episode(e):  # noqa: ANN001, ANN201
    """Steps until the run ends (clock.stop_at_end) or forever, yielding the events above. It holds no
    record across a yield (numba's generators would keep a copy): everything lives in the episode's arrays."""
    acted = False
    while True:
        event = steps(e, acted)
        yield event
        if event in (ENDED, FAILED):
            return
        acted = event == ACT
