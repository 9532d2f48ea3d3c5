"""Bridges from the annotator to `location check` and to the scene-graph renderer, so the page shows
exactly the problems the CLI reports and saves exactly the image the CLI renders."""

from __future__ import annotations

from typing import Any

from socnavgen.location.check import check_location
from socnavgen.location.location import Location
from socnavgen.location.render import png_bytes, render_location


def run_check(location: Location) -> list[dict[str, Any]]:
    """Problems of the location as dicts: message, severity, nodes (ids) and edge ([a, b]) to highlight."""
    return [_problem_dict(p) for p in check_location(location)]


def _problem_dict(problem: Any) -> dict[str, Any]:
    get = (lambda k: problem.get(k)) if isinstance(problem, dict) else (lambda k: getattr(problem, k, None))
    nodes = get("nodes") or ([get("node")] if get("node") else [])
    edge = get("edge")
    return {"message": str(get("message") or problem), "severity": str(get("severity") or "warning"),
            "hint": str(get("hint") or ""), "nodes": [str(n) for n in nodes], "edge": list(edge) if edge else None}


def render_overlay(location: Location) -> bytes:
    """PNG bytes of the map with the scene graph drawn on it (the same picture `location show` writes)."""
    return png_bytes(render_location(location))
