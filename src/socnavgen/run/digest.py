"""Digests of what decides a simulation: the run's files, its location's files, the robot policy's source
and socnavgen's version. One home for "what was this made from", used by the outputs in RUN/sim/ (to
refuse or redo a stale trace) and by campaigns (an episode whose inputs changed runs again).

A digest is sha256 over each file's name and bytes; files that do not exist count as absent (a run without
spec.json is not the same run as one with it)."""

from __future__ import annotations

import hashlib
import importlib.util
from collections.abc import Iterable
from pathlib import Path
from typing import TYPE_CHECKING, Any

from socnavgen import __version__

if TYPE_CHECKING:
    from socnavgen.location import Location

RUN_FILES = ("request.json", "scenario.json", "spec.json", "paths.json")


def files_digest(root: Path, names: Iterable[str]) -> str:
    """sha256 of the named files under `root` (name, size and bytes; an absent file is recorded as absent)."""
    h = hashlib.sha256()
    for name in sorted(set(names)):
        path = root / name
        h.update(name.encode() + b"\0")
        if path.is_file():
            data = path.read_bytes()
            h.update(len(data).to_bytes(8, "little") + data)
        else:
            h.update(b"absent")
    return h.hexdigest()


def run_files_digest(run_root: Path | str) -> str:
    """The run folder's files that decide a simulation: request, scenario, spec, paths and every tree."""
    root = Path(run_root)
    trees = sorted(f"behaviors/{p.name}" for p in (root / "behaviors").glob("*.xml")) \
        if (root / "behaviors").is_dir() else []
    return files_digest(root, [*RUN_FILES, *trees])


def location_digest(location: Location) -> str:
    """location.yaml, the scene graph, the map and its transform / occupancy files."""
    config = location.config
    names = ["location.yaml", "scene_graph.json", config.map,
             *(n for n in (config.nav2_map, config.occupancy_image) if n)]
    return files_digest(Path(location.root), names)


def policy_digest(robot: str) -> str:
    """The policy's own source file (`file.py:Class`, or the module of `module:Class`); a built-in robot is
    part of socnavgen, so its version stands for it ("builtin")."""
    module, sep, _ = robot.rpartition(":")
    if not sep:
        return "builtin"
    if module.endswith(".py"):
        path: Path | None = Path(module)
    else:
        try:
            found = importlib.util.find_spec(module)
        except (ImportError, ValueError):
            found = None
        path = Path(found.origin) if found is not None and found.origin else None
    if path is None or not path.is_file():
        return "missing"
    return hashlib.sha256(path.read_bytes()).hexdigest()


def combine(*parts: Any) -> str:
    """One short digest of several (JSON-able) values."""
    import json

    text = json.dumps(parts, sort_keys=True, default=str)
    return hashlib.sha256(text.encode()).hexdigest()[:20]


def version() -> str:
    return __version__
