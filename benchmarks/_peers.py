"""The benchmark crowd and the same crowd in other pedestrian simulators installed from PyPI (the `bench`
extra): JuPedSim (its social force model and its default collision-free speed model), ORCA through pyrvo,
navground's social force behaviour and pysocialforce.

The crowd: n people in an open walled square sized for 0.1 pedestrians/m^2 (at least 20 m x 20 m), each
starting at least 1 m from everyone else and 1 m from the walls, walking to a random goal and back, for
ever (a cyclic two-goal route), radius 0.4 m, desired speed 1.5 m/s, dt 0.05 s. Every simulator runs the
same number of steps of the same crowd; each reports the CPU seconds per step of the simulating thread
(time.thread_time) and its crowd's mean speed at the end, so a crowd that does not walk shows.

(A module of helpers, not a benchmark: run_all.py skips files whose name starts with "_".)
"""

from __future__ import annotations

import logging
import math
import os
import tempfile
import time
import warnings
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

DT, DENSITY, RADIUS, SPEED, GOAL_RADIUS, SPACING = 0.05, 0.1, 0.4, 1.5, 0.5, 1.0


@dataclass(frozen=True)
class Crowd:
    side: float  # m: the walled square is [0, side]^2
    starts: np.ndarray  # (n, 2)
    goals: np.ndarray  # (n, 2): each person walks start -> goal -> start -> ...


@dataclass(frozen=True)
class Timing:
    per_step: float  # CPU s per step
    mean_speed: float  # m/s, the crowd's mean speed after the run


def crowd(n: int, seed: int = 0) -> Crowd:
    """n starts at least SPACING apart (rejection sampling on a grid of SPACING cells), goals uniform."""
    side = max(20.0, math.sqrt(n / DENSITY))
    rng = np.random.default_rng(seed)
    lo, hi = 1.0, side - 1.0
    cells: dict[tuple[int, int], list[int]] = {}
    starts: list[np.ndarray] = []
    while len(starts) < n:
        p = rng.uniform(lo, hi, 2)
        cx, cy = int(p[0] // SPACING), int(p[1] // SPACING)
        near = [k for dx in (-1, 0, 1) for dy in (-1, 0, 1) for k in cells.get((cx + dx, cy + dy), [])]
        if all(np.hypot(*(starts[k] - p)) >= SPACING for k in near):
            cells.setdefault((cx, cy), []).append(len(starts))
            starts.append(p)
    return Crowd(side, np.array(starts).reshape(n, 2), rng.uniform(lo, hi, (n, 2)))


def _timed(step: Callable[[int], None], steps: int) -> float:
    step(2)  # warm: compilation or first-step set-up stays out of the timing
    start = time.thread_time()
    step(steps)
    return (time.thread_time() - start) / steps


def _speed(velocities: np.ndarray) -> float:
    return float(np.mean(np.hypot(velocities[:, 0], velocities[:, 1]))) if len(velocities) else 0.0


def jupedsim(c: Crowd, steps: int, model: str = "sfm") -> Timing:
    """JuPedSim: `sfm` its SocialForceModel, `cfsm` its default CollisionFreeSpeedModel. Each person a
    journey of two waypoints with fixed transitions between them (cyclic)."""
    import jupedsim as jps
    from shapely import Polygon

    if model == "sfm":
        sim_model, agent = jps.SocialForceModel(), jps.SocialForceModelAgentParameters
    else:
        sim_model, agent = jps.CollisionFreeSpeedModel(), jps.CollisionFreeSpeedModelAgentParameters
    square = Polygon([(0, 0), (c.side, 0), (c.side, c.side), (0, c.side)])
    sim = jps.Simulation(model=sim_model, geometry=square, dt=DT)
    for s, g in zip(c.starts, c.goals, strict=True):
        first = sim.add_waypoint_stage(tuple(g), GOAL_RADIUS)
        back = sim.add_waypoint_stage(tuple(s), GOAL_RADIUS)
        journey = jps.JourneyDescription([first, back])
        journey.set_transition_for_stage(first, jps.Transition.create_fixed_transition(back))
        journey.set_transition_for_stage(back, jps.Transition.create_fixed_transition(first))
        jid = sim.add_journey(journey)
        sim.add_agent(agent(journey_id=jid, stage_id=first, position=tuple(s), desired_speed=SPEED, radius=RADIUS))

    def step(k: int) -> None:
        for _ in range(k):
            sim.iterate()

    per_step = _timed(step, steps)
    if model == "sfm":
        vel = np.array([a.model.velocity for a in sim.agents()])
    else:  # the collision-free speed model keeps no velocity: its speed times its orientation
        vel = np.array([a.model.desired_speed * np.asarray(a.orientation) for a in sim.agents()])
    return Timing(per_step, _speed(vel))


def orca(c: Crowd, steps: int) -> Timing:
    """ORCA (RVO2 via pyrvo): the preferred velocity toward each person's current goal is set from Python
    every step, as its users do."""
    import pyrvo

    sim = pyrvo.RVOSimulator(DT, 8.0, 10, 2.0, 2.0, RADIUS, SPEED)
    for s in c.starts:
        sim.add_agent((float(s[0]), float(s[1])))
    sim.add_obstacle([(0.0, 0.0), (0.0, c.side), (c.side, c.side), (c.side, 0.0)])  # clockwise: inside free
    sim.process_obstacles()
    targets = [c.goals, c.starts]
    leg = np.zeros(len(c.starts), dtype=int)

    def step(k: int) -> None:
        for _ in range(k):
            for i in range(len(c.starts)):
                p = sim.get_agent_position(i)
                gx, gy = targets[leg[i]][i]
                dx, dy = gx - p.x, gy - p.y
                d = math.hypot(dx, dy)
                if d < GOAL_RADIUS:
                    leg[i] ^= 1
                scale = SPEED / d if d > 1e-9 else 0.0
                sim.set_agent_pref_velocity(i, (dx * scale, dy * scale))
            sim.do_step()

    per_step = _timed(step, steps)
    vel = np.array([(v.x, v.y) for v in (sim.get_agent_velocity(i) for i in range(len(c.starts)))])
    return Timing(per_step, _speed(vel))


def navground(c: Crowd, steps: int) -> Timing:
    """navground's SocialForce behaviour, omnidirectional people, a looping Waypoints task, neighbours
    within 8 m, the four walls."""
    from navground import sim

    s = c.side
    walls = "\n".join(f"  - line: [[{a}, {b}], [{x}, {y}]]" for a, b, x, y in
                      ((0, 0, s, 0), (s, 0, s, s), (s, s, 0, s), (0, s, 0, 0)))
    agents = "\n".join(
        f"  - position: [{p[0]}, {p[1]}]\n    radius: {RADIUS}\n"
        f"    kinematics: {{type: Omni, max_speed: {SPEED}}}\n"
        f"    behavior: {{type: SocialForce, optimal_speed: {SPEED}, horizon: 8.0}}\n"
        f"    state_estimation: {{type: Bounded, range: 8.0}}\n"
        f"    task: {{type: Waypoints, loop: true, tolerance: {GOAL_RADIUS}, "
        f"waypoints: [[{g[0]}, {g[1]}], [{p[0]}, {p[1]}]]}}"
        for p, g in zip(c.starts, c.goals, strict=True))
    world = sim.load_world(f"walls:\n{walls}\nagents:\n{agents}\n")

    def step(k: int) -> None:
        world.run(k, DT)

    per_step = _timed(step, steps)
    return Timing(per_step, _speed(np.array([a.velocity for a in world.agents])))


def _import_pysocialforce():  # noqa: ANN202
    """pysocialforce sets a logger named "root" to DEBUG and opens ./file.log on import: import it from a
    temporary folder and quieten the loggers."""
    here = os.getcwd()
    logging.disable(logging.INFO)
    with tempfile.TemporaryDirectory() as tmp:
        os.chdir(tmp)
        try:
            import pysocialforce as psf
        finally:
            os.chdir(here)
            root = logging.getLogger()
            for handler in list(root.handlers):
                root.removeHandler(handler)
                handler.close()
            root.setLevel(logging.WARNING)
            logging.disable(logging.NOTSET)
    return psf


def pysocialforce(c: Crowd, steps: int) -> Timing:
    """pysocialforce with its default forces and our dt. It takes each person's initial speed as their
    desired speed (times 1.3 as the cap), so people start walking toward their goal at 1.5 m/s; it has one
    goal per person (no route): people who arrive stop there."""
    psf = _import_pysocialforce()
    to = c.goals - c.starts
    v0 = SPEED * to / np.maximum(np.hypot(to[:, 0], to[:, 1]), 1e-9)[:, None]
    state = np.hstack([c.starts, v0, c.goals])
    s = c.side
    walls = [(0.0, s, 0.0, 0.0), (0.0, s, s, s), (0.0, 0.0, 0.0, s), (s, s, 0.0, s)]
    with tempfile.NamedTemporaryFile("w", suffix=".toml", delete=False) as cfg:
        cfg.write(f"step_width = {DT}\n[scene]\nenable_group = false\n")  # step_width: top level
    try:
        with warnings.catch_warnings():  # it divides by zero once a walker has arrived
            warnings.simplefilter("ignore", RuntimeWarning)
            sim = psf.Simulator(state, groups=None, obstacles=walls, config_file=cfg.name)
            per_step = _timed(sim.step, steps)
        return Timing(per_step, _speed(sim.peds.vel()))
    finally:
        os.unlink(cfg.name)


PEERS: dict[str, Callable[[Crowd, int], Timing]] = {
    "JuPedSim SFM": jupedsim,
    "JuPedSim CFSM": lambda c, steps: jupedsim(c, steps, "cfsm"),
    "ORCA (pyrvo)": orca,
    "navground SF": navground,
    "pysocialforce": pysocialforce,
}


def measure(name: str, c: Crowd, steps: int) -> Timing | str:
    """A peer's timing on this crowd, or why it could not run ("not installed")."""
    try:
        return PEERS[name](c, steps)
    except ImportError as err:
        return f"not installed ({err.name})"
