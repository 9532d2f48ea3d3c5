"""How close people come to the robot and to each other, per run.

    python scripts/passing_gaps.py --eval /tmp/ev            # the final runs of an `eval --fixtures` out folder
    python scripts/passing_gaps.py --cards /tmp/cards        # every fitting card on the bundled locations

Prints one table row per run (and a total), so two branches can be compared before/after a change to the
people's rules: the smallest robot-person gap and the seconds with some robot-person gap <= CLOSE; the smallest
person-person gap (with the pair and when), the seconds with some pair in contact (gap <= CONTACT_MARGIN) and
with some pair within CLOSE. Also the smallest robot-person gap while the robot drives toward the nearest person
(faster than MOVING: a gap it drove into, not one someone walked into) and when the robot reached its goal (the polite robot's
cost)."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import NamedTuple

import numpy as np

from socnavgen.bodies import CONTACT_MARGIN, ROBOT_GOAL_TOLERANCE, ROBOT_SOCIAL_GAP
from socnavgen.sim.contact import lengths, row_min, trace_gaps
from socnavgen.sim.trace import Trace

CLOSE = 0.15  # m: a gap a person looking at the animation sees as touching
MOVING = 0.05  # m/s: the robot drives toward someone this fast


class Row(NamedTuple):
    name: str
    robot_gap: float  # m: smallest robot-person gap
    robot_close: float  # s with a robot-person gap <= CLOSE
    person_gap: float  # m: smallest person-person gap (inf with fewer than two people)
    person_pair: str  # who, and when
    person_contact: float  # s with a pair at gap <= CONTACT_MARGIN
    person_close: float  # s with a pair at gap <= CLOSE
    moving_gap: float = float("inf")  # m: smallest robot-person gap while the robot drives toward them (MOVING)
    goal_time: float = float("nan")  # s: when the robot first came within ROBOT_GOAL_TOLERANCE of its goal after
    # leaving it (NaN: never)


def person_gaps(trace: Trace) -> np.ndarray:
    """(T, P) surface gaps of every pair of people (P = H (H - 1) / 2, pairs in np.triu_indices order)."""
    h = trace.humans.shape[1] if trace.humans.ndim == 3 else 0
    i, j = np.triu_indices(h, 1)
    xy = trace.humans[:, :, :2]
    return lengths(xy[:, i] - xy[:, j]) - (trace.human_radii[i] + trace.human_radii[j])[None, :]


def gap_numbers(name: str, trace: Trace) -> Row:
    """The row of one trace."""
    gaps = trace_gaps(trace)
    robot_gap, robot_close, moving_gap = float("inf"), 0.0, float("inf")
    if gaps.size:
        closest = row_min(gaps)
        robot_gap, robot_close = float(closest.min()), float((closest <= CLOSE).sum() * trace.dt)
        near = np.argmin(gaps, axis=1)
        to = trace.humans[np.arange(trace.steps), near, :2] - trace.robot[:, :2]
        toward = (trace.robot[:, 3] * to[:, 0] + trace.robot[:, 4] * to[:, 1]) / np.maximum(np.hypot(*to.T), 1e-9)
        moves = toward > MOVING  # driving toward the nearest person
        moving_gap = float(closest[moves].min()) if moves.any() else float("inf")
    goal_time = float("nan")
    if trace.robot_goal is not None:
        there = np.hypot(trace.robot[:, 0] - trace.robot_goal[0], trace.robot[:, 1] - trace.robot_goal[1])
        away = np.flatnonzero(there > 2 * ROBOT_GOAL_TOLERANCE)  # a route may start at its goal (a patrol's loop)
        hit = np.flatnonzero(there <= ROBOT_GOAL_TOLERANCE)
        hit = hit[hit > away[0]] if away.size else hit
        goal_time = float(trace.t[hit[0]]) if hit.size else float("nan")
    pg = person_gaps(trace)
    if pg.size == 0:
        return Row(name, robot_gap, robot_close, float("inf"), "", 0.0, 0.0, moving_gap, goal_time)
    closest = pg.min(axis=1)
    k, m = np.unravel_index(int(np.argmin(pg)), pg.shape)
    i, j = np.triu_indices(trace.humans.shape[1], 1)
    pair = f"{trace.human_names[i[m]]}-{trace.human_names[j[m]]} @{trace.t[k]:.1f}s"
    return Row(name, robot_gap, robot_close, float(closest.min()), pair,
               float((closest <= CONTACT_MARGIN).sum() * trace.dt), float((closest <= CLOSE).sum() * trace.dt),
               moving_gap, goal_time)


def eval_rows(out: Path) -> list[Row]:
    """One row per fixture's final run (not the `.first` ones) of an eval out folder."""
    rows = []
    for trace_path in sorted((out / "fixtures").glob("*/sim/trace.npz")):
        name = trace_path.parents[1].name
        if name.endswith(".first"):
            continue
        rows.append(gap_numbers(name, Trace.load(trace_path)))
    return rows


def card_rows(work: Path) -> list[Row]:
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
            rows.append(gap_numbers(f"{name}/{fit.card.name}", trace))
    return rows


def main() -> None:
    """Print the table."""
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--eval", type=Path, help="an `eval --fixtures` out folder")
    parser.add_argument("--cards", type=Path, help="a scratch folder to write the card runs to")
    args = parser.parse_args()
    rows = (eval_rows(args.eval) if args.eval else []) + (card_rows(args.cards) if args.cards else [])
    print(f"| run | robot: min gap (m) | driving at them: min gap (m) | s within {CLOSE} m | goal at (s) | "
          f"people: min gap (m) | pair | s in contact (<= {CONTACT_MARGIN} m) | s within {CLOSE} m |")
    print("|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r.name} | {r.robot_gap:.3f} | {r.moving_gap:.3f} | {r.robot_close:.1f} | {r.goal_time:.1f} | "
              f"{r.person_gap:.3f} | {r.person_pair} | {r.person_contact:.1f} | {r.person_close:.1f} |")
    if rows:
        gaps = np.array([r.robot_gap for r in rows])
        pgaps = np.array([r.person_gap for r in rows])
        moving = np.array([r.moving_gap for r in rows])
        social = int((moving < ROBOT_SOCIAL_GAP - 0.01).sum())
        reached = int(sum(not np.isnan(r.goal_time) for r in rows))
        print(f"| **all {len(rows)}** | min {gaps.min():.3f}, median {np.median(gaps):.3f}, "
              f"{int((gaps <= CLOSE).sum())} runs <= {CLOSE} | min {moving.min():.3f}, {social} runs < "
              f"{ROBOT_SOCIAL_GAP - 0.01:.2f} | {sum(r.robot_close for r in rows):.1f} | {reached} reached | "
              f"min {pgaps.min():.3f}, {int((pgaps <= CONTACT_MARGIN).sum())} runs in contact, "
              f"{int((pgaps <= CLOSE).sum())} runs <= {CLOSE} | | {sum(r.person_contact for r in rows):.1f} | "
              f"{sum(r.person_close for r in rows):.1f} |")


if __name__ == "__main__":
    main()
