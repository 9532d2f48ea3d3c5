"""Where each piece of state lives in the compiled episode's arrays (row indices), shared by the lowering
(Python) and the compiled functions.

State tuple S = (cs, fs, cc, fc, bc, hi, hf, hc, qbuf, rc, rf, ri, wps, wpoff, sf, si, sc):
  cs, fs, cc, fc, bc  the crowd and its motion commands, packed as sim.kernels documents;
  hi int64 (HI_*, n)  per-human integers; hf float (HF_*, n); hc complex (HC_*, n);
  qbuf complex (n, capacity)  each human's goal queue as a ring (HI_QSTART, HI_QLEN);
  rc complex, rf float, ri int64  the robot (RC_*, RF_*, RI_*);
  wps complex (W,)  the robot's waypoints; wpoff float (W,)  arc length at each waypoint (segment starts);
  sf float (SF_*, L), si int64 (64, 3), sc complex (SC_*, L)  scratch (L >= people, waypoints, 64): the
  compiled helpers allocate nothing (see sim.kernels.no_alloc).
Program tuple P (one flat program for every human's tree), see compiled.lower.
"""

from __future__ import annotations

# statuses (bt_runtime's) and the compiled run's "give up, run the reference" signal
FAILURE, SUCCESS, RUNNING = 0, 1, 2
ERROR = -1

# hi rows
HI_GESTURE, HI_BSTATE, HI_PAUSED, HI_ACTION, HI_MOTION, HI_SUCCESS, HI_SIGHT = 0, 1, 2, 3, 4, 5, 6
HI_GW, HI_GW_PHASE, HI_QSTART, HI_QLEN, HI_QCYCLIC, HI_PAUSED_STEPS, HI_FIRST_PAUSE, HI_FACE = range(7, 15)
HI_ROWS = 15
# hf rows
HF_MAXVEL, HF_PACE, HF_FACE_WITHIN, HF_GW_AT = range(4)
HF_ROWS = 4
# hc rows
HC_GW_TARGET = 0
HC_ROWS = 1
# give-way phases (nodes.give_way_to_robot's "aside", "wait", "resume")
GW_ASIDE, GW_WAIT, GW_RESUME = 0, 1, 2

# robot
RC_POS, RC_VEL, RC_DIR = range(3)
RC_ROWS = 3
RF_YAW, RF_OMEGA, RF_RADIUS, RF_T, RF_DT, RF_GOAL_TOL, RF_PROGRESS = range(7)
RF_ROWS = 7
RI_GESTURE, RI_SAID, RI_SEG, RI_PROGRESS_STEP, RI_STEP, RI_PROGRESS_SEG = range(6)
RI_ROWS = 6

# scratch rows
SF_A, SF_B, SF_FLAGS, SF_LEFT, SF_LEFT_IM = range(5)
SF_ROWS = 5
SC_BEFORE, SC_SNAP = range(2)
SC_ROWS = 2

# program: node kinds
K_SEQUENCE, K_FALLBACK, K_REACTIVE_SEQUENCE, K_REACTIVE_FALLBACK = 0, 1, 2, 3
K_INVERTER, K_FORCE_SUCCESS, K_FORCE_FAILURE, K_REPEAT, K_KEEP_RUNNING = 4, 5, 6, 7, 8
K_SET_BLACKBOARD, K_CONDITION, K_ACTION = 9, 10, 11
# program: ni rows (int64, (NI_ROWS, nodes))
NI_KIND, NI_FIRST, NI_COUNT, NI_END, NI_LEAF, NI_OWNER, NI_MOTION, NI_AGENT_PORT = range(8)
NI_REPEAT, NI_UNTIL, NI_SB_OUT, NI_SB_SRC = range(8, 12)
NI_ROWS = 12
# program: how a port is read (pslot values below 0)
PORT_LITERAL, PORT_ABSENT, PORT_DYNAMIC = -1, -2, -3
# value types of ports and blackboard slots (Python's int, float, bool; 0 = unset slot)
T_UNSET, T_INT, T_FLOAT, T_BOOL = 0, 1, 2, 3
