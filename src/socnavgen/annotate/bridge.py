"""Bridges from the annotator to `location check` and to the scene-graph renderer, so the page shows
exactly the problems the CLI reports and saves exactly the image the CLI renders."""

from __future__ import annotations

import io
from typing import Any

from PIL import Image, ImageDraw

from socnavgen.location.location import Location


def run_check(location: Location) -> list[dict[str, Any]]:
    """Problems of the location as dicts: message, severity, nodes (ids) and edge ([a, b]) to highlight."""
    try:
        from socnavgen.location import check as check_module
    except ImportError:
        return _basic_problems(location)
    return [_problem_dict(p) for p in check_module.check_location(location)]


def _problem_dict(problem: Any) -> dict[str, Any]:
    get = (lambda k: problem.get(k)) if isinstance(problem, dict) else (lambda k: getattr(problem, k, None))
    nodes = get("nodes") or ([get("node")] if get("node") else [])
    edge = get("edge")
    return {"message": str(get("message") or problem), "severity": str(get("severity") or "warning"),
            "hint": str(get("hint") or ""), "nodes": [str(n) for n in nodes], "edge": list(edge) if edge else None}


def _basic_problems(location: Location) -> list[dict[str, Any]]:
    """The two checks the page cannot do without: nodes on obstacles and edges through walls."""
    occ = location.occupancy
    graph = location.scene_graph
    pos = {n.id: n.pos for n in graph.nodes}
    problems: list[dict[str, Any]] = []
    for n in graph.nodes:
        if not occ.inside(*n.pos) or occ.is_blocked(*n.pos):
            problems.append({"message": f"node {n.id} is on an obstacle or outside the free space",
                             "severity": "error", "nodes": [n.id], "edge": None})
    for e in graph.links:
        if e.source in pos and e.target in pos:
            hits = occ.segment_blocked_pixels(pos[e.source], pos[e.target])
            if hits:
                problems.append({"message": f"edge {e.source}-{e.target} crosses {len(hits)} blocked pixel(s), "
                                            f"first at {hits[0]}", "severity": "error",
                                 "nodes": [e.source, e.target], "edge": [e.source, e.target]})
    return problems


def render_overlay(location: Location) -> bytes:
    """PNG bytes of the map with the scene graph drawn on it."""
    try:
        from socnavgen.location import render as render_module
    except ImportError:
        return _basic_overlay(location)
    return render_module.png_bytes(render_module.render_location(location))


def _basic_overlay(location: Location) -> bytes:
    """Plain Pillow overlay used only when the shared renderer is unavailable."""
    gray = Image.fromarray(location.map_gray).convert("RGB")
    scale = max(1, 800 // max(gray.size))
    img = gray.resize((gray.width * scale, gray.height * scale), Image.NEAREST)
    draw = ImageDraw.Draw(img)
    graph = location.scene_graph
    pos = {n.id: ((n.pos[0] + 0.5) * scale, (n.pos[1] + 0.5) * scale) for n in graph.nodes}
    for e in graph.links:
        if e.source in pos and e.target in pos:
            draw.line([pos[e.source], pos[e.target]], fill=(40, 110, 220), width=max(1, scale // 2))
    r = max(2, scale)
    for n in graph.nodes:
        x, y = pos[n.id]
        draw.ellipse([x - r, y - r, x + r, y + r], fill=(220, 60, 40))
        draw.text((x + r + 1, y - r - 1), n.id, fill=(0, 0, 0))
    buf = io.BytesIO()
    img.save(buf, format="PNG")
    return buf.getvalue()
