"""How close people come to the robot: the smallest robot-person gap and the time spent within CLOSE m, per run.

    python scripts/passing_gaps.py --eval /tmp/ev            # the final runs of an `eval --fixtures` out folder
    python scripts/passing_gaps.py --cards /tmp/cards        # every fitting card on the bundled locations

Prints one table row per run (and a total), so two branches can be compared before/after a change to the
people's rules."""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from socnavgen.sim.contact import row_min, trace_gaps
from socnavgen.sim.trace import Trace

CLOSE = 0.15  # m: a gap a person looking at the animation sees as touching


def gap_numbers(trace: Trace) -> tuple[float, float]:
    """(smallest robot-person gap in m, seconds with some gap <= CLOSE) of one trace."""
    gaps = trace_gaps(trace)
    if gaps.size == 0:
        return float("inf"), 0.0
    closest = row_min(gaps)
    return float(closest.min()), float((closest <= CLOSE).sum() * trace.dt)


def eval_rows(out: Path) -> list[tuple[str, float, float]]:
    """One row per fixture's final run (not the `.first` ones) of an eval out folder."""
    rows = []
    for trace_path in sorted((out / "fixtures").glob("*/sim/trace.npz")):
        name = trace_path.parents[1].name
        if name.endswith(".first"):
            continue
        rows.append((name, *gap_numbers(Trace.load(trace_path))))
    return rows


def card_rows(work: Path) -> list[tuple[str, float, float]]:
    """One row per fitting card on each bundled location, simulated with the default robot."""
    from socnavgen.cards.generate import fit_all, write_card_run
    from socnavgen.location import load_location
    from socnavgen.sim import simulate_run

    rows = []
    for name in ("warehouse", "hospital", "home"):
        path = Path(__file__).resolve().parents[1] / "examples" / "locations" / name
        location = load_location(path)
        for fit in fit_all(location):
            if not fit.fits:
                continue
            run = write_card_run(fit.card.name, path, work / name / fit.card.name)
            trace = simulate_run(run.root, location=location, save=False)
            rows.append((f"{name}/{fit.card.name}", *gap_numbers(trace)))
    return rows


def main() -> None:
    """Print the table."""
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--eval", type=Path, help="an `eval --fixtures` out folder")
    parser.add_argument("--cards", type=Path, help="a scratch folder to write the card runs to")
    args = parser.parse_args()
    rows = (eval_rows(args.eval) if args.eval else []) + (card_rows(args.cards) if args.cards else [])
    print(f"| run | min gap (m) | s within {CLOSE} m |")
    print("|---|---|---|")
    for name, gap, close in rows:
        print(f"| {name} | {gap:.3f} | {close:.1f} |")
    if rows:
        gaps = np.array([r[1] for r in rows])
        print(f"| **all {len(rows)}** | min {gaps.min():.3f}, median {np.median(gaps):.3f}, "
              f"{int((gaps <= CLOSE).sum())} runs <= {CLOSE} | {sum(r[2] for r in rows):.1f} |")


if __name__ == "__main__":
    main()
