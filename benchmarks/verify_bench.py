"""How long the strict verifier takes: per fitting scenario card of the warehouse (trace simulated once,
then only `verify_trace` timed) and on synthetic 120 s traces (dt 0.05 s, 2400 steps) with 1 to 16 humans
and a spec asking, for every human, a meeting, no line of sight until 3 m, and no collision / deadlock.
CPU time of the measuring thread (a busy machine does not count); "first" is a run's first verification
(formulas parsed, run prepared), "again" the same trace verified again (what each further episode of a
campaign costs).

    python benchmarks/verify_bench.py
"""

from __future__ import annotations

import tempfile
import time
from pathlib import Path

import numpy as np

from socnavgen.cards.generate import fit_all, write_card_run
from socnavgen.location import load_location
from socnavgen.run import RunFolder
from socnavgen.run.spec import Criterion, Encounter, HumanPart, ScenarioSpec
from socnavgen.sim import simulate_run
from socnavgen.sim.trace import Trace
from socnavgen.verify import verify_trace

WAREHOUSE = Path(__file__).resolve().parents[1] / "examples" / "locations" / "warehouse"


def _timed(fn) -> tuple[float, object]:  # noqa: ANN001
    t0 = time.thread_time()
    out = fn()
    return time.thread_time() - t0, out


def cards_rows(tmp: Path) -> list[tuple[str, str, str, str]]:
    location = load_location(WAREHOUSE)
    first, again, passed, findings = [], [], 0, 0
    for fit in (f for f in fit_all(location) if f.fits):
        run = write_card_run(fit.card.name, WAREHOUSE, tmp / fit.card.name)
        trace = simulate_run(run.root, location=location, save=False)
        seconds, report = _timed(lambda: verify_trace(run.root, trace, location=location))  # noqa: B023
        first.append(seconds)
        again.append(min(_timed(lambda: verify_trace(run.root, trace, location=location))[0]  # noqa: B023
                         for _ in range(3)))
        passed += report.passed
        findings += len(report.findings)
    return [(f"warehouse cards ({len(first)})", f"{np.mean(first) * 1000:.1f} ms / card",
             f"{np.mean(again) * 1000:.1f} ms / card", f"{findings / max(len(first), 1):.1f} findings, "
                                                       f"{passed}/{len(first)} pass")]


def synthetic(n_humans: int, tmp: Path) -> tuple[str, str, str, str]:
    location = load_location(WAREHOUSE)
    nodes = location.scene_graph.node_ids()
    t = np.arange(2400) * 0.05
    start, end = np.array(location.node_world(nodes[0])), np.array(location.node_world(nodes[-1]))
    robot = start + (end - start) * (t / t[-1])[:, None]
    rng = np.random.default_rng(0)
    humans = np.stack([robot[::-1] + rng.normal(0, 1.0, 2) for _ in range(n_humans)], axis=1)

    def states(xy: np.ndarray) -> np.ndarray:
        v = np.gradient(xy, t, axis=0)
        return np.concatenate([xy, np.arctan2(v[..., 1], v[..., 0])[..., None], v, np.zeros(xy.shape[:-1] + (1,))],
                              axis=-1)

    names = [f"human{i + 1}" for i in range(n_humans)]
    trace = Trace(dt=0.05, t=t, robot=states(robot), humans=states(humans), human_names=names,
                  group_ids=[-1] * n_humans, human_radii=np.full(n_humans, 0.4), robot_radius=0.35,
                  node_names=["RegularNav"], action=np.zeros((2400, n_humans), np.int16),
                  succeeded=np.zeros((2400, n_humans), np.int64), human_gesture=np.zeros((2400, n_humans), np.int8),
                  robot_gesture=np.zeros(2400, np.int8), behavior_state=np.zeros((2400, n_humans), np.int8),
                  robot_goal=tuple(end))
    spec = ScenarioSpec(encounters=[Encounter(id="e1", place="ANY", node=nodes[len(nodes) // 2],
                                              humans=[HumanPart(human=n) for n in names])],
                        criteria=[Criterion(id=f"h{i}", kind="hidden_until", human=n) for i, n in enumerate(names)])
    run = RunFolder(tmp / f"synthetic{n_humans}")
    run.root.mkdir(parents=True)
    from socnavgen.run import HumanPlan, PathPlan, ScenarioRequest

    run.write_request(ScenarioRequest(location=str(WAREHOUSE), context="bench", task="bench"))
    run.write_paths(PathPlan(robot=[nodes[0], nodes[-1]], humans=[HumanPlan(name=n, path=[nodes[-1]]) for n in names]))
    run.write_spec(spec)
    seconds, report = _timed(lambda: verify_trace(run.root, trace, location=location))
    again = min(_timed(lambda: verify_trace(run.root, trace, location=location))[0] for _ in range(3))
    return (f"120 s trace, {n_humans} humans", f"{seconds * 1000:.0f} ms", f"{again * 1000:.1f} ms",
            f"{len(report.findings)} findings, {2400 / again:,.0f} steps/s")


def main() -> None:
    with tempfile.TemporaryDirectory() as tmp:
        rows = cards_rows(Path(tmp) / "cards") + [synthetic(n, Path(tmp)) for n in (1, 5, 16)]
    print(f"{'case':28s} {'first':>16s} {'again':>16s}  {'':28s}")
    for row in rows:
        print(f"{row[0]:28s} {row[1]:>16s} {row[2]:>16s}  {row[3]:28s}")


if __name__ == "__main__":
    main()
