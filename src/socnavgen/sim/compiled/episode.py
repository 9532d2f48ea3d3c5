"""Run a ready Simulation compiled: pack its state, run the loop in one call, give the Simulation its final
state back and hand the recorded columns to the engine's trace builder. `run_compiled` returns None when
the simulation cannot run compiled or a tree failed while running; the engine then runs the reference."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from socnavgen.sim.compiled.geometry import world_tuple
from socnavgen.sim.compiled.layout import (
    GW_ASIDE,
    GW_RESUME,
    GW_WAIT,
    HC_GW_TARGET,
    HC_ROWS,
    HF_GW_AT,
    HF_MAXVEL,
    HF_PACE,
    HF_ROWS,
    HI_ACTION,
    HI_BSTATE,
    HI_FIRST_PAUSE,
    HI_GESTURE,
    HI_GW,
    HI_GW_PHASE,
    HI_PAUSED,
    HI_PAUSED_STEPS,
    HI_QCYCLIC,
    HI_QLEN,
    HI_QSTART,
    HI_ROWS,
    HI_SUCCESS,
    RC_DIR,
    RC_POS,
    RC_ROWS,
    RC_VEL,
    RF_DT,
    RF_GOAL_TOL,
    RF_OMEGA,
    RF_RADIUS,
    RF_ROWS,
    RF_T,
    RF_YAW,
    RI_GESTURE,
    RI_PROGRESS_STEP,
    RI_ROWS,
    RI_SAID,
    SC_ROWS,
    SF_ROWS,
)
from socnavgen.sim.compiled.loop import REASON_ALL_DONE, REASON_GOAL, run_episode
from socnavgen.sim.compiled.lower import (
    MAX_GESTURE,
    Unsupported,
    fresh_program,
    lower_rules,
    lower_script,
    lower_throttle,
    lower_trees,
)
from socnavgen.sim.compiled.robots import robot_params, store_params
from socnavgen.sim.compiled.script import LOG_ASK_AGAIN, LOG_FIRED, Q_SAY, Q_SPEED, Q_WAIT, TS_K
from socnavgen.sim.engine import CONTACT_SLACK
from socnavgen.sim.gestures import _describe
from socnavgen.sim.kernels import advance_work

REASONS = {REASON_GOAL: "robot_goal", REASON_ALL_DONE: "all_done"}
_PHASES = {"aside": GW_ASIDE, "wait": GW_WAIT, "resume": GW_RESUME}


def _state(sim: Any) -> tuple:
    """S (see compiled.layout) from the Simulation, copied: a run that gives up leaves the Simulation as it was."""
    crowd, n = sim.crowd, sim.crowd.n
    cap = max([len(q.goals) for q in crowd.queues] + [0]) + 2
    hi = np.zeros((HI_ROWS, n), dtype=np.int64)
    hf = np.zeros((HF_ROWS, n))
    hc = np.zeros((HC_ROWS, n), dtype=complex)
    qbuf = np.zeros((n, cap), dtype=complex)
    hi[HI_GESTURE], hi[HI_BSTATE], hi[HI_PAUSED] = crowd.gesture, crowd.behavior_state, crowd.paused
    hi[HI_ACTION], hi[HI_SUCCESS] = sim.tick_action, sim.tick_success
    hf[HF_MAXVEL], hf[HF_PACE] = crowd.max_vel, crowd.pace
    for i, q in enumerate(crowd.queues):
        qbuf[i, :len(q.goals)] = q.goals
        hi[HI_QLEN, i], hi[HI_QCYCLIC, i] = len(q.goals), q.cyclic
        state = sim.give_way[i]
        if state is not None:
            hi[HI_GW, i], hi[HI_GW_PHASE, i] = 1, _PHASES[state["phase"]]
            hc[HC_GW_TARGET, i], hf[HF_GW_AT, i] = state["target"], state["at"]
    if sim.throttle is not None:
        for i, steps in sim.throttle.paused_steps.items():
            hi[HI_PAUSED_STEPS, i] = steps
    rc = np.zeros(RC_ROWS, dtype=complex)
    rc[RC_POS], rc[RC_VEL], rc[RC_DIR] = sim.robot_pos, sim.robot_vel, sim._robot_dir
    rf = np.zeros(RF_ROWS)
    rf[RF_YAW], rf[RF_OMEGA], rf[RF_RADIUS], rf[RF_T] = sim.robot_yaw, sim.robot_omega, sim.robot_radius, sim.t
    rf[RF_DT], rf[RF_GOAL_TOL] = sim.dt, sim.config.goal_tolerance
    ri = np.zeros(RI_ROWS, dtype=np.int64)
    ri[RI_GESTURE], ri[RI_PROGRESS_STEP] = sim.robot_gesture, -1
    if any(not 0 <= g <= MAX_GESTURE for g in sim.robot_said) or not 0 <= sim.robot_gesture <= MAX_GESTURE:
        raise Unsupported("robot gesture codes beyond the gesture mask")
    ri[RI_SAID] = sum(1 << g for g in sim.robot_said)
    if sim.t != 0.0 or "_robot_progress" in sim.__dict__:
        raise Unsupported("the simulation has already been stepped")
    wps = np.ascontiguousarray(sim.robot_waypoints, dtype=complex)
    lengths = np.abs(wps[1:] - wps[:-1])
    wpoff = np.concatenate([[0.0], np.cumsum(lengths)[:-1]]) if len(wps) > 1 else np.zeros(1)
    scratch = max(n, len(wps), 64) + 8
    return (crowd.cs.copy(), crowd.fs.copy(), sim.cc.copy(), sim.fc.copy(), sim.bc.copy(), hi, hf, hc, qbuf,
            rc, rf, ri, wps, np.ascontiguousarray(wpoff), np.zeros((SF_ROWS, scratch)), np.zeros((64, 3), dtype=np.int64),
            np.zeros((SC_ROWS, scratch), dtype=complex))


def _give_back(sim: Any, S: tuple, T: tuple, C: tuple, R: tuple) -> None:
    """The Simulation's state after the compiled run (crowd, robot, throttle, script, policy)."""
    crowd = sim.crowd
    cs, fs, cc, fc, bc, hi, hf, hc, qbuf, rc, rf, ri = S[:12]
    crowd.cs[:], crowd.fs[:], sim.cc[:], sim.fc[:], sim.bc[:] = cs, fs, cc, fc, bc
    crowd.gesture[:] = hi[HI_GESTURE].tolist()
    crowd.behavior_state[:] = hi[HI_BSTATE].tolist()
    crowd.paused[:] = [bool(x) for x in hi[HI_PAUSED]]
    crowd.pace[:] = hf[HF_PACE].tolist()
    cap = qbuf.shape[1]
    for i, q in enumerate(crowd.queues):
        start, length = int(hi[HI_QSTART, i]), int(hi[HI_QLEN, i])
        q.goals = [complex(qbuf[i, (start + j) % cap]) for j in range(length)]
    sim.tick_action, sim.tick_success = hi[HI_ACTION].tolist(), hi[HI_SUCCESS].tolist()
    sim.robot_dist = fc[3].tolist()
    sim.robot_pos, sim.robot_vel, sim._robot_dir = complex(rc[RC_POS]), complex(rc[RC_VEL]), complex(rc[RC_DIR])
    sim.robot_yaw, sim.robot_omega, sim.t = float(rf[RF_YAW]), float(rf[RF_OMEGA]), float(rf[RF_T])
    sim.robot_gesture = int(ri[RI_GESTURE])
    sim.robot_said = {g for g in range(MAX_GESTURE + 1) if (int(ri[RI_SAID]) >> g) & 1}
    if sim.throttle is not None:
        sim.throttle.k = int(T[7][TS_K])
        paused = [i for i in range(crowd.n) if hi[HI_PAUSED_STEPS, i] > 0]
        paused.sort(key=lambda i: hi[HI_FIRST_PAUSE, i])  # the reference's dict fills in order of first pause
        sim.throttle.paused_steps = {i: int(hi[HI_PAUSED_STEPS, i]) for i in paused}
    cues = sim.cues
    cues.say, cues.wait, cues.speed = int(C[5][Q_SAY]), bool(C[5][Q_WAIT]), float(C[5][Q_SPEED])
    if sim.script is not None:
        items = sim.script.script.cues
        log_t, log_i, count = C[6], C[7], int(C[8][0])
        for m in range(min(count, log_t.shape[0])):
            cue = items[int(log_i[m, 0])]
            event = int(log_i[m, 1])
            text = (_describe(cue) if event == LOG_FIRED else f"still blocked: say {cue.say} again"
                    if event == LOG_ASK_AGAIN else "still blocked: stop waiting, go around")
            cues.fired.append((round(float(log_t[m]), 3), text))
    store_params(sim.policy, R)
    sim.meta["engine"] = "compiled"


def run_compiled(sim: Any, progress: Callable[[int, int], None] | None = None) -> Any:
    """The trace of `sim` run compiled, or None (with sim.meta["compiled_skipped"] saying why) when it cannot."""
    R = robot_params(sim.policy)
    if R is None:
        sim.meta["compiled_skipped"] = f"robot policy {type(sim.policy).__name__} has no compiled twin"
        return None
    cfg_, max_steps = sim.config, sim.max_steps
    try:
        S = _state(sim)
        P = fresh_program(sim.program) if sim.program is not None else lower_trees(sim.trees)
        T, has_throttle = lower_throttle(sim.throttle, sim.crowd.specs)
        C, has_script = lower_script(sim.script, sim.cues, sim.crowd.n, max_steps)
        G, has_rules = lower_rules(sim.gestures)
    except Unsupported as exc:
        sim.meta["compiled_skipped"] = str(exc)
        return None
    W = world_tuple(sim.world)
    K = (sim._labels, sim._sizes, sim._prm, sim._obs_table, sim._affine, advance_work(sim.crowd.n))
    cfg = np.array([sim.dt, max_steps, cfg_.idle_end, cfg_.goal_tolerance, CONTACT_SLACK, has_throttle, has_script,
                    has_rules], dtype=float)
    columns = sim.trace_columns(max_steps + 1)
    steps, reason = run_episode(S, W, P, K, R, T, C, G, tuple(columns), cfg, complex(sim._robot_goal))
    if steps < 0:
        sim.meta["compiled_skipped"] = "a behavior tree failed while running"
        return None
    _give_back(sim, S, T, C, R)
    if progress is not None:
        progress(max_steps, max_steps)
    return sim.trace_from(columns, steps, REASONS.get(reason, "timeout"))


_WARM = False


def warm_up() -> None:
    """Compile (or load from the cache) the compiled episode in this process now, on a tiny built-in
    scenario: campaign workers call it before their first episode, so that numba's first compile (~40 s on
    a new machine) is not counted against an episode's wall-clock limit."""
    global _WARM
    if _WARM:
        return
    from socnavgen.bt.library import regular_walker_xml
    from socnavgen.sim.agents import HumanSpec
    from socnavgen.sim.engine import SimConfig, Simulation
    from socnavgen.sim.robot import WaypointsPolicy
    from socnavgen.sim.world import empty_room

    sim = Simulation(empty_room(4.0, 4.0, resolution=0.1), [HumanSpec(name="human1", start=(1.0, 1.0),
                                                                       goals=[(3.0, 3.0)])],
                     [regular_walker_xml()], [(1.0, 3.0), (3.0, 1.0)], WaypointsPolicy(), SimConfig(timeout=0.1))
    run_compiled(sim)
    _WARM = True
