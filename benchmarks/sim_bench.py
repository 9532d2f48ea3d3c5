"""Simulator speed: steps per second and real-time factor for 1..300 pedestrians, beside pysocialforce.

Scene: an open walled square sized for a constant density (0.1 pedestrians per m^2, at least 20 m x 20 m),
every pedestrian walking a cyclic two-goal route with the RegularNav tree exactly as the generator writes it
(SetBlackboard x2 + SubTree RegularNavTree), and the robot crossing with the `waypoints` plugin. The same
crowd (positions, goals, walls) runs in pysocialforce with its default forces and step width set to our dt.
Times are CPU seconds of the simulating thread (time.thread_time): one core, unaffected by other load
and by numpy's idle BLAS threads (which spin for a while after the large matrix product that builds a map).

    python benchmarks/sim_bench.py              # the table (about a minute)
    python benchmarks/sim_bench.py --quick      # fewer steps
"""

from __future__ import annotations

import argparse
import math
import os
import tempfile
import time
import warnings

import numpy as np

from socnavgen.bt.library import regular_walker_xml
from socnavgen.sim import HumanSpec, RobotAction, SimConfig, Simulation, empty_room, load_policy
from socnavgen.sim.jit import AVAILABLE

DT = 0.05
DENSITY = 0.1
COUNTS = (1, 5, 20, 100, 300)


def scene(n: int, seed: int = 0) -> tuple[float, list[HumanSpec]]:
    side = max(20.0, math.sqrt(n / DENSITY))
    rng = np.random.default_rng(seed)
    lo, hi = 1.0, side - 1.0
    humans = []
    for i in range(n):
        start, goal = rng.uniform(lo, hi, 2), rng.uniform(lo, hi, 2)
        humans.append(HumanSpec(name=f"human{i + 1}", start=tuple(start), goals=[tuple(goal), tuple(start)],
                                cyclic=True))
    return side, humans


class Toward:
    """A trivial robot policy of the user's: straight at its goal at 0.6 m/s."""

    def act(self, obs):  # noqa: ANN001, ANN201
        to = obs.waypoints_c[-1] - obs.position_c
        v = 0.6 * to / max(abs(to), 1e-9)
        return RobotAction(v.real, v.imag)


def run_ours(n: int, steps: int, python_policy: bool) -> float:
    """Seconds per step of the full simulation loop (trees, physics, robot, trace): the built-in waypoints
    robot inside the compiled step, or a Python policy called between two steps."""
    side, humans = scene(n)
    world = empty_room(side, side, resolution=0.1)
    policy = Toward() if python_policy else load_policy("waypoints")
    sim = Simulation(world, humans, [regular_walker_xml()] * n, [(0.8, side / 2), (side - 0.8, side / 2)],
                     policy, SimConfig(dt=DT, timeout=steps * DT, idle_end=1e9))
    start = time.thread_time()
    trace = sim.run()
    elapsed = time.thread_time() - start
    return elapsed / max(trace.steps - 1, 1)


def _import_pysocialforce():  # noqa: ANN202
    """pysocialforce sets a logger named "root" to DEBUG and opens ./file.log on import: import it from a
    temporary folder and quieten the loggers."""
    import logging

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


def run_pysocialforce(n: int, steps: int) -> float | str:
    try:
        psf = _import_pysocialforce()
    except ImportError:
        return "not installed (pip install pysocialforce)"
    side, humans = scene(n)
    state = np.array([[*h.start, 0.0, 0.0, *h.goals[0]] for h in humans], dtype=float)
    walls = [(0.0, side, 0.0, 0.0), (0.0, side, side, side), (0.0, 0.0, 0.0, side), (side, side, 0.0, side)]
    with tempfile.NamedTemporaryFile("w", suffix=".toml", delete=False) as cfg:
        cfg.write(f"[scene]\nenable_group = false\nstep_width = {DT}\n")
    try:
        with warnings.catch_warnings():  # it divides by a zero desired speed once a walker has arrived
            warnings.simplefilter("ignore", RuntimeWarning)
            sim = psf.Simulator(state, groups=None, obstacles=walls, config_file=cfg.name)
            sim.step(2)  # numba compilation happens here, not in the timing
            start = time.thread_time()
            sim.step(steps)
            return (time.thread_time() - start) / steps
    finally:
        os.unlink(cfg.name)


def warm_up() -> None:
    run_ours(3, 5, True)
    run_ours(3, 5, False)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--quick", action="store_true", help="fewer steps per row")
    parser.add_argument("--counts", type=int, nargs="*", default=list(COUNTS))
    args = parser.parse_args()
    warm_up()
    rows = []
    for n in args.counts:
        steps = (400 if n <= 20 else 200) // (4 if args.quick else 1)
        fast = run_ours(n, steps, False)
        slow = run_ours(n, steps, True)
        other = run_pysocialforce(n, steps)
        rows.append((n, fast, slow, other))

    def fmt(sec: float | None) -> tuple[str, str, str]:
        if sec is None:
            return "-", "-", "-"
        return f"{1 / sec:,.0f}", f"{DT / sec:,.0f}x", f"{sec * 1e6:,.0f}"

    print(f"dt = {DT} s, open walled square at {DENSITY} pedestrians/m^2, RegularNav trees, waypoints robot; "
          f"numba {'on' if AVAILABLE else 'OFF (plain Python)'}")
    print("| pedestrians | socnavgen steps/s | real-time factor | us/step | with a Python policy steps/s | "
          "Python policy RTF | pysocialforce steps/s | pysocialforce RTF |")
    print("|---:|---:|---:|---:|---:|---:|---:|---:|")
    for n, fast, slow, other in rows:
        f_steps, f_rtf, f_us = fmt(fast)
        s_steps, s_rtf, _ = fmt(slow)
        if isinstance(other, str):
            o_steps, o_rtf = other, "-"
        else:
            o_steps, o_rtf, _ = fmt(other)
        print(f"| {n} | {f_steps} | {f_rtf} | {f_us} | {s_steps} | {s_rtf} | {o_steps} | {o_rtf} |")
    times = [(n, fast) for n, fast, _, _ in rows if fast]
    if len(times) >= 2:
        (n0, t0), (n1, t1) = times[-2], times[-1]
        print(f"\ncost growth {n0}->{n1} pedestrians: x{t1 / t0:.1f} for x{n1 / n0:.1f} pedestrians "
              f"(exponent {math.log(t1 / t0) / math.log(n1 / n0):.2f}; 1 = linear, 2 = quadratic)")


if __name__ == "__main__":
    main()
