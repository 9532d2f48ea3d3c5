"""Stage 1's check over every recorded stage-1 answer of a fixture folder, without simulating: which answers the
checks of the tree on PYTHONPATH refuse, with their mistakes (seconds, where a replay of the suite takes ~14 min).
Run it on two trees and compare to see what a new check refuses.

    PYTHONPATH=src:. python scripts/stage1_refusals.py [tests/fixtures/new_requests] [--json OUT] [NAME ...]
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from socnavgen.evaluation.fixtures import fixture_paths, fixture_request
from socnavgen.llm.structured import parse_reply
from socnavgen.location import Location, load_location
from socnavgen.proposal.replies import ScenarioReply
from socnavgen.proposal.scenario import scenario_checker
from socnavgen.safeio import load_yaml_file


def refusals(folder: Path, names: list[str]) -> dict[str, list[list[str]]]:
    """{fixture: [mistakes of answer 0, of answer 1, ...]} ([] = accepted)."""
    root = Path.cwd()
    locations: dict[str, Location] = {}
    found: dict[str, list[list[str]]] = {}
    for path in fixture_paths(folder):
        if names and not any(n in path.stem for n in names):
            continue
        request = fixture_request(path, root)
        location = locations.setdefault(request.location, load_location(request.location))
        check = scenario_checker(location, request.target)
        rows = []
        for raw in (load_yaml_file(path).get("stages") or {}).get("scenario") or []:
            value, error = parse_reply(raw, ScenarioReply)
            rows.append([error or "not a reply"] if value is None else check(value))
        found[path.stem] = rows
    return found


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("folder", nargs="?", default="tests/fixtures/new_requests")
    parser.add_argument("names", nargs="*")
    parser.add_argument("--json", type=Path, help="write {fixture: [mistakes per answer]} here")
    args = parser.parse_args()
    found = refusals(Path(args.folder), args.names)
    for name, rows in found.items():
        marks = " ".join("ok" if not m else f"x{len(m)}" for m in rows)
        print(f"{name}: {marks}" + ("  (every answer refused)" if rows and all(rows) else ""))
        for i, mistakes in enumerate(rows):
            for m in mistakes:
                print(f"  [{i}] {m[:300]}")
    if args.json:
        args.json.write_text(json.dumps(found, indent=1))


if __name__ == "__main__":
    main()
