"""Do the cards' expected-behaviour checks separate the robots? Per check x per policy: the pass rate over the
episodes where the check applied (and in how many it applied), from a finished campaign folder:

    python scripts/check_rates.py OUT                # the rates the campaign stored (column expected_checks)
    python scripts/check_rates.py OUT --rescore      # the checks of THIS code, re-run on the stored trajectories
    python scripts/check_rates.py OUT --by-card      # one row per check and card

--rescore re-reads each episode's trajectory file (OUT/trajectories, kept at the campaign's rate, 10 Hz by
default) and the card's checks and place, so a change to sim/behaviour_checks.py is measured on the same
episodes without simulating them again (a campaign re-run says the same at the simulation's own dt)."""

from __future__ import annotations

import argparse
import json
from collections import defaultdict
from pathlib import Path
from typing import Any

import numpy as np
import pyarrow.parquet as pq

from socnavgen.sim.trace import Trace


def trace_from_npz(path: Path) -> Trace:
    """A Trace (positions, velocities, radii, route) from a campaign's trajectory file."""
    from socnavgen.sim.outputs.trajectory import read_trajectory

    d = read_trajectory(path)
    meta, t = d["meta"], np.asarray(d["t"], dtype=float)
    n, h = len(t), d["humans"].shape[1]

    def states(a: np.ndarray) -> np.ndarray:
        return np.concatenate([np.asarray(a, dtype=float), np.zeros(a.shape[:-1] + (1,))], axis=-1)

    return Trace(dt=float(t[1] - t[0]) if n > 1 else meta["dt"], t=t, robot=states(d["robot"]),
                 humans=states(d["humans"]), human_names=meta["human_names"], group_ids=meta["group_ids"],
                 human_radii=np.asarray(meta["human_radii"]), robot_radius=meta["robot_radius"], node_names=[],
                 action=np.full((n, h), -1, np.int16), succeeded=np.zeros((n, h), np.int64),
                 human_gesture=d["human_gesture"], robot_gesture=d["robot_gesture"],
                 behavior_state=np.zeros((n, h), np.int8),
                 robot_goal=tuple(meta["robot_goal"]) if meta["robot_goal"] else None,
                 robot_waypoints=[tuple(w) for w in meta["robot_waypoints"]], end_reason=meta["end_reason"])


def _places(out: Path) -> dict[str, complex | None]:
    """scenario id -> the world point of its first encounter's node (what campaign/episode.py judges at)."""
    from socnavgen.run import RunFolder

    places: dict[str, complex | None] = {}
    for paths in sorted((out / "scenarios").glob("*/*/paths.json")):
        run = RunFolder(paths.parent)
        spec = run.read_spec()
        node = spec.encounters[0].node if spec is not None and spec.encounters else None
        places[f"{paths.parent.parent.name}/{paths.parent.name}"] = complex(*run.location().node_world(node)) \
            if node else None
    return places


def rows(out: Path, rescore: bool) -> list[dict[str, Any]]:
    """{policy, card, details} per episode: stored, or re-run with this code on the trajectories."""
    table = pq.read_table(out / "episodes.parquet", columns=["scenario", "policy", "card", "expected_checks",
                                                              "trajectory"]).to_pylist()
    if not rescore:
        return [{"policy": r["policy"], "card": r["card"], "details": json.loads(r["expected_checks"] or "[]")}
                for r in table]
    from socnavgen.cards.library import card_names, get_card
    from socnavgen.sim.behaviour_checks import check_behaviour

    places = _places(out)
    result = []
    for r in table:
        if not r["card"] or r["card"] not in card_names() or not r["trajectory"]:
            continue
        trace = trace_from_npz(out / r["trajectory"])
        _, details = check_behaviour(trace, get_card(r["card"]).expected_checks, places.get(r["scenario"]), None)
        result.append({"policy": r["policy"], "card": r["card"], "details": details})
    return result


def rates(episodes: list[dict[str, Any]], by_card: bool) -> str:
    """The markdown table: rows check (x card), columns policy: 'pass % (passed/applied)'."""
    count: dict[tuple[str, str], list[int]] = defaultdict(lambda: [0, 0])
    policies = sorted({e["policy"] for e in episodes})
    for e in episodes:
        for d in e["details"]:
            if d["passed"] is not None:
                key = (f"{d['check']} ({e['card']})" if by_card else d["check"], e["policy"])
                count[key][0] += bool(d["passed"])
                count[key][1] += 1
    lines = ["| check | " + " | ".join(policies) + " |", "|---" * (len(policies) + 1) + "|"]
    for check in sorted({c for c, _ in count}):
        cells = [f"{100 * count[(check, p)][0] / count[(check, p)][1]:.0f} % ({count[(check, p)][0]}/"
                 f"{count[(check, p)][1]})" if count[(check, p)][1] else "–" for p in policies]
        lines.append(f"| {check} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out", type=Path)
    parser.add_argument("--rescore", action="store_true")
    parser.add_argument("--by-card", action="store_true")
    args = parser.parse_args()
    print(rates(rows(args.out, args.rescore), args.by_card))


if __name__ == "__main__":
    main()
