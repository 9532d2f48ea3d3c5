"""Scenarios as the export targets run them: every scenario card on every bundled location and every replay
fixture, simulated from each target's exported trees (socrates, hunav2; hunav1 runs the trees it accepts, its
built-in behaviors, untimed, and refuses the rest) with our pacing off and a waypoint
robot at 0.5x, 1x and 1.5x its script's cruise speed (socnavgen.export.as_target), judged by the verifier.
Counted against what verifies in our own simulator (the scripted robot, our pacing, the run's own trees);
a refused export counts as not verified. Two references, the same robot at the same speed with our pacing
instead of the export's timing: with the run's own trees (what the robot itself manages), and with the hunav2
translation (what the translation alone does).

    python benchmarks/export_targets_bench.py                      # the full matrix (~3 min on 2 cores)
    python benchmarks/export_targets_bench.py --robot waypoints    # the plain waypoints robot (pushes into people)
    python benchmarks/export_targets_bench.py --robot script       # the robot plays its part (robot_script.yaml)
    python benchmarks/export_targets_bench.py --location warehouse --card blind-corner
    python benchmarks/export_targets_bench.py --no-cards               # the replay fixtures only
"""

from __future__ import annotations

import argparse
import tempfile
import time
from collections import defaultdict
from pathlib import Path

from socnavgen.cards.generate import fit_all, write_card_run
from socnavgen.evaluation.fixtures import fixture_paths, replay_fixture
from socnavgen.export.as_target import (
    AS_TARGETS,
    ROBOTS,
    SPEEDS,
    TIMED_TARGETS,
    at_speed,
    run_as_target,
    target_twin,
    timeout_for,
    waypoint_robot,
)
from socnavgen.export.scene import build_scene
from socnavgen.export.timing import start_wait
from socnavgen.location import load_location
from socnavgen.run import load_run
from socnavgen.sim import simulate_run
from socnavgen.verify import verify_trace

ROOT = Path(__file__).resolve().parents[1]
LOCATIONS = ROOT / "examples" / "locations"
FIXTURES = (ROOT / "tests" / "fixtures" / "replay", ROOT / "tests" / "fixtures" / "new_requests")
OWN, TRANSLATED = "(our pacing, own trees)", "(our pacing, hunav2 trees)"
UNTIMED = {t: f"({t} trees without timing)" for t in ("socrates", "hunav2")}


def runs(work: Path, location: str | None, card: str | None, fixtures: bool,
         cards: bool = True) -> list[tuple[str, str, Path]]:
    """(kind, label, run folder) of every card on every bundled location, and of every replay fixture (the capable
    fixtures and the new requests, each at its final answers)."""
    out = []
    for loc in sorted(p for p in LOCATIONS.iterdir() if (p / "location.yaml").is_file()):
        if not cards or (location and loc.name != location):
            continue
        for fit in fit_all(load_location(loc)):
            if fit.placement is None or (card and fit.card.name != card):
                continue
            label = f"{loc.name}/{fit.card.name}"
            out.append(("cards", label, write_card_run(fit.card.name, loc, work / label.replace("/", "__")).root))
    if fixtures and not card:
        for path in (p for folder in FIXTURES for p in fixture_paths(folder)):
            replay_fixture(path, work / path.stem, root=ROOT, verify=True)
            if not (work / path.stem / "paths.json").is_file():  # its recording ends before the paths
                print(f"  ({path.stem}: the replay ends before a run with paths; not counted)")
                continue
            out.append(("fixtures", path.stem, work / path.stem))
    return out


def _whose(passed: dict[tuple, bool], label: str, target: str, speed: float) -> str:
    """Whether a miss is the export's own: our pacing makes it with the same robot and the run's own trees (and,
    for hunav2, with the translated trees: then the timing's own)."""
    if not passed[(label, OWN, speed)]:
        return "[shared: misses with our pacing too]"
    if target == "hunav1":
        return "[hunav1 loads its built-in trees only: no timing can go with them]"
    if target == "hunav2" and not passed[(label, TRANSLATED, speed)]:
        return "[the export's own: the translation (the hunav2 trees miss with our pacing too)]"
    return "[the export's own: the timing (our pacing makes it)]"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--robot", choices=sorted(ROBOTS), default="careful")
    ap.add_argument("--location")
    ap.add_argument("--card")
    ap.add_argument("--no-fixtures", action="store_true")
    ap.add_argument("--no-cards", action="store_true", help="the replay fixtures only")
    args = ap.parse_args()
    started = time.process_time()
    tally: dict[tuple, list[int]] = defaultdict(lambda: [0, 0, 0])  # (kind, target, speed) -> verified, refused, total
    failures: list[str] = []
    passed: dict[tuple, bool] = {}  # (label, reference row, speed) -> verified
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        for kind, label, run in runs(work / "runs", args.location, args.card, not args.no_fixtures,
                                    not args.no_cards):
            if not verify_trace(run, simulate_run(run, save=False)).passed:
                print(f"  ({label}: does not verify in our simulator; not counted)")
                continue
            scene, _ = build_scene(run)
            for speed in SPEEDS:  # the robot itself: our pacing, the run's own trees
                robot = waypoint_robot(args.robot, scene.robot_speed * speed, start_wait(scene))
                trace = simulate_run(at_speed(load_run(run), args.robot, speed), robot=robot,
                                     timeout=timeout_for(speed), save=False)
                ok = passed[(label, OWN, speed)] = verify_trace(run, trace).passed
                count = tally[(kind, OWN, speed)]
                count[0], count[2] = count[0] + ok, count[2] + 1
            for target in TIMED_TARGETS:
                plain = target_twin(run, target, work / "plain" / target / label.replace("/", "__"), timing=False)
                for speed in SPEEDS:  # no timing in the trees: as the target runs them, and with our pacing
                    for row, pacing in ((UNTIMED[target], False), (TRANSLATED, True)):
                        if row == TRANSLATED and target != "hunav2":
                            continue
                        count = tally[(kind, row, speed)]
                        count[2] += 1
                        count[1] += bool(plain.refused)
                        ok = not plain.refused and run_as_target(plain, speed, args.robot, pacing=pacing).passed
                        count[0], passed[(label, row, speed)] = count[0] + ok, ok
            for target in AS_TARGETS:
                twin = target_twin(run, target, work / "twins" / target / label.replace("/", "__"))
                for speed in SPEEDS:
                    count = tally[(kind, target, speed)]
                    count[2] += 1
                    if twin.refused:
                        count[1] += 1
                        if speed == SPEEDS[0]:  # once per run
                            failures.append(f"{target} {label}: refused: {twin.refused.splitlines()[0][:150]}")
                        continue
                    report = run_as_target(twin, speed, args.robot)
                    count[0] += report.passed
                    if not report.passed:
                        failures.append(f"{target} {speed:g}x {label}: " + "; ".join(f.name for f in report.failures)
                                        + " " + _whose(passed, label, target, speed))
    print(f"\nAs the targets run them: {args.robot} robot at x its cruise speed; our pacing off; verified / refused "
          "/ total of the runs that verify in our simulator")
    print("\n| target | speed | cards | % | fixtures | % |\n|---|---:|---|---:|---|---:|")
    for target in (*AS_TARGETS, *UNTIMED.values(), OWN, TRANSLATED):
        for speed in SPEEDS:
            cells = []
            for kind in ("cards", "fixtures"):
                v, r, n = tally[(kind, target, speed)]
                cells += [f"{v} / {r} / {n}", f"{100 * v / n:.0f}" if n else "-"]
            print(f"| {target} | {speed:g}x | " + " | ".join(cells) + " |")
    print("\nnot verified:\n" + "\n".join(f"- {f}" for f in failures) if failures else "\nall verified")
    print(f"\nCPU time {time.process_time() - started:.0f} s")


if __name__ == "__main__":
    main()
