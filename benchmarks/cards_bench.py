"""Scenario cards x bundled locations: generated, simulated with the default robot, judged by the strict
verifier. One row per (location, card): PASS/FAIL, the smallest robot-human gap, the encounter's offset
from its place (robot-human midpoint while within 2 m, to the encounter node; worst encounter), and the
failing checks.

    python benchmarks/cards_bench.py                 # every card on every bundled location
    python benchmarks/cards_bench.py --robot sfm     # another built-in robot
    python benchmarks/cards_bench.py --card blind-corner --location warehouse
"""

from __future__ import annotations

import argparse
import shutil
import tempfile
import time
from pathlib import Path

import numpy as np

from socnavgen.cards.generate import fit_all, write_card_run
from socnavgen.location import load_location
from socnavgen.sim import simulate_run
from socnavgen.sim.contact import trace_distances, trace_gaps
from socnavgen.verify import verify_trace

LOCATIONS = Path(__file__).resolve().parents[1] / "examples" / "locations"
MEET = 2.0  # m, centre distance that counts as meeting (the verifier's default)


def encounter_offset(run, trace, location) -> float | None:  # noqa: ANN001
    """Largest over the spec's encounters of: how far from the encounter node the robot and its human meet
    (the robot-human midpoint, over the steps they are within 2 m of each other; inf if they never are)."""
    spec = run.read_spec()
    if spec is None or not trace.human_names:
        return None
    dist = trace_distances(trace)
    worst = None
    for enc in spec.encounters:
        if not enc.node:
            continue
        node = np.array(location.node_world(enc.node))
        k = trace.human_names.index(enc.humans[0].human)
        close = dist[:, k] <= MEET
        mid = (trace.robot[:, :2] + trace.humans[:, k, :2]) / 2
        off = float(np.linalg.norm(mid[close] - node, axis=1).min()) if close.any() else float("inf")
        worst = off if worst is None else max(worst, off)
    return worst


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--robot", default="scripted")
    ap.add_argument("--card", action="append")
    ap.add_argument("--location", action="append")
    args = ap.parse_args()
    print(f"{'location':10s} {'card':30s} {'verdict':7s} {'min gap':>8s} {'enc off':>8s} {'sim s':>6s}  failing")
    totals: dict[str, list[int]] = {}
    for loc_dir in sorted(p for p in LOCATIONS.iterdir() if (p / "location.yaml").is_file()):
        if args.location and loc_dir.name not in args.location:
            continue
        location = load_location(loc_dir)
        fits = [f for f in fit_all(location) if f.fits and (not args.card or f.card.name in args.card)]
        tmp = Path(tempfile.mkdtemp())
        ok = 0
        try:
            for fit in fits:
                run = write_card_run(fit.card.name, loc_dir, tmp / fit.card.name)
                t0 = time.perf_counter()
                trace = simulate_run(run.root, robot=args.robot, location=location, save=False)
                secs = time.perf_counter() - t0
                report = verify_trace(run.root, trace, location=location)
                gaps = trace_gaps(trace)
                gap = f"{float(gaps.min()):8.2f}" if gaps.size else f"{'-':>8s}"
                off = encounter_offset(run, trace, location)
                failing = [f"{f.name}" for f in report.findings if f.required and not f.passed]
                ok += report.passed
                print(f"{loc_dir.name:10s} {fit.card.name:30s} {'PASS' if report.passed else 'FAIL':7s} {gap} "
                      f"{'-' if off is None else f'{off:.2f}':>8s} {secs:6.1f}  {'; '.join(failing)[:150]}",
                      flush=True)
        finally:
            shutil.rmtree(tmp, ignore_errors=True)
        totals[loc_dir.name] = [ok, len(fits)]
    print("\n" + "  ".join(f"{name}: {a}/{b} pass" for name, (a, b) in totals.items()))


if __name__ == "__main__":
    main()
