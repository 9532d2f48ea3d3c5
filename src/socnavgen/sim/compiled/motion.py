"""What a leaf does to a human, compiled: its motion commands (Simulation.command_*), its goal queue
(agents.GoalQueue as a ring per human) and the queries it asks (sight of the robot, bearing)."""

from __future__ import annotations

import math

from socnavgen.bodies import PERSON_GOAL_SLACK
from socnavgen.sim.compiled.geometry import line_of_sight
from socnavgen.sim.compiled.layout import (
    HI_QCYCLIC,
    HI_QLEN,
    HI_QSTART,
    HI_SIGHT,
    RC_POS,
)
from socnavgen.sim.kernels import no_alloc


@no_alloc
def wrap(a):  # noqa: ANN001, ANN201
    return (a + math.pi) % (2 * math.pi) - math.pi


# ---- commands (Simulation.command_*) ------------------------------------------------------------------
@no_alloc
def walk_goal(S, i, v0, extra):  # noqa: ANN001, ANN201
    fc, bc, cc = S[3], S[4], S[2]
    bc[0][i] = True
    bc[1][i] = True
    fc[1][i] = v0
    cc[1][i] = extra
    bc[2][i] = False


@no_alloc
def walk(S, i, target, radius, v0):  # noqa: ANN001, ANN201
    fc, bc, cc = S[3], S[4], S[2]
    bc[0][i] = True
    bc[1][i] = False
    cc[0][i] = target
    fc[0][i] = radius
    fc[1][i] = v0
    cc[1][i] = 0j
    bc[2][i] = False


@no_alloc
def turn(S, i, yaw):  # noqa: ANN001, ANN201
    S[4][0][i] = False
    S[4][2][i] = True
    S[3][2][i] = yaw


@no_alloc
def stand(S, i):  # noqa: ANN001, ANN201
    S[4][0][i] = False
    S[4][2][i] = False


# ---- goal queues (agents.GoalQueue as a ring per human) ------------------------------------------------
@no_alloc
def refresh_goal(S, i):  # noqa: ANN001, ANN201
    """Crowd.refresh_goal."""
    cs, bc, hi, qbuf = S[0], S[4], S[5], S[8]
    if hi[HI_QLEN][i] > 0:
        bc[3][i] = True
        cs[2][i] = qbuf[i, hi[HI_QSTART][i]]
    else:
        bc[3][i] = False
        cs[2][i] = cs[0][i]


@no_alloc
def pop_goal(S, i, keep_last):  # noqa: ANN001, ANN201
    """GoalQueue.update_goal (keep_last) / consume: drop the front (not the only one with keep_last);
    a cyclic queue appends it again."""
    hi, qbuf = S[5], S[8]
    n = hi[HI_QLEN][i]
    if n == 0:
        return
    cap = qbuf.shape[1]
    start = hi[HI_QSTART][i]
    g = qbuf[i, start]
    if not keep_last or n != 1:
        start = (start + 1) % cap
        n -= 1
    if hi[HI_QCYCLIC][i]:
        qbuf[i, (start + n) % cap] = g
        n += 1
    hi[HI_QSTART][i] = start
    hi[HI_QLEN][i] = n


@no_alloc
def goal_reached(S, i):  # noqa: ANN001, ANN201
    """GoalQueue.reached (IsGoalReached)."""
    cs, fs, hi, qbuf = S[0], S[1], S[5], S[8]
    return hi[HI_QLEN][i] > 0 and abs(qbuf[i, hi[HI_QSTART][i]] - cs[0][i]) <= fs[2][i] + PERSON_GOAL_SLACK


# ---- queries ----------------------------------------------------------------------------------------
@no_alloc
def in_sight(S, W, i):  # noqa: ANN001, ANN201
    """Simulation.robot_in_sight: computed at most once per human and step."""
    hi = S[5]
    seen = hi[HI_SIGHT][i]
    if seen < 0:
        seen = 1 if line_of_sight(W, S[9][RC_POS], S[0][0][i]) else 0
        hi[HI_SIGHT][i] = seen
    return seen == 1


@no_alloc
def bearing(S, i):  # noqa: ANN001, ANN201
    """nodes.robot_bearing."""
    d = S[9][RC_POS] - S[0][0][i]
    return wrap(math.atan2(d.imag, d.real) - S[1][0][i])
