"""Scenario cards on the bundled locations: how many fit, how fast they generate and export, and how
many verify in the headless simulator with each built-in robot.

    python benchmarks/cards_bench.py            # the table (about a minute)
"""

from __future__ import annotations

import shutil
import tempfile
import time
from pathlib import Path

from socnavgen.cards.generate import fit_all, write_card_run
from socnavgen.export import export_run
from socnavgen.location import load_location
from socnavgen.verify import verify_run

LOCATIONS = Path(__file__).resolve().parents[1] / "examples" / "locations"
ROBOTS = ("sfm", "waypoints")


def main() -> None:
    print(f"{'location':10s} {'fit':>5s} {'gen s/card':>10s} {'export s/card':>13s} "
          + " ".join(f"{'verify ' + r:>16s}" for r in ROBOTS) + "  failing (waypoints)")
    for loc_dir in sorted(p for p in LOCATIONS.iterdir() if (p / "location.yaml").is_file()):
        fits = [f for f in fit_all(load_location(loc_dir)) if f.fits]
        passed: dict[str, list[str]] = {}
        tmp = Path(tempfile.mkdtemp())
        try:
            t0 = time.perf_counter()
            runs = [write_card_run(f.card.name, loc_dir, tmp / f.card.name) for f in fits]
            gen = (time.perf_counter() - t0) / max(len(runs), 1)
            t0 = time.perf_counter()
            for run in runs:
                export_run(run.root, "socrates", tmp / "export" / run.root.name)
            exp = (time.perf_counter() - t0) / max(len(runs), 1)
            for robot in ROBOTS:
                passed[robot] = []
                for run in runs:
                    shutil.rmtree(run.sim_dir, ignore_errors=True)
                    if verify_run(run.root, simulate_options={"robot": robot, "timeout": 120.0}).passed:
                        passed[robot].append(run.root.name)
        finally:
            shutil.rmtree(tmp, ignore_errors=True)
        failing = sorted({f.card.name for f in fits} - set(passed["waypoints"]))
        print(f"{loc_dir.name:10s} {len(fits):>2d}/25 {gen:>10.3f} {exp:>13.3f} "
              + " ".join(f"{len(passed[r]):>13d}/{len(fits):<2d}" for r in ROBOTS) + "  " + ", ".join(failing))


if __name__ == "__main__":
    main()
