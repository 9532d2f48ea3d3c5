"""What the annotator adds on top of plain drawing: a suggested graph (location extract), a guessed type
for a new node, the location description, and the colours of the rendered PNG (so a type looks the
same on the page and in scene_graph.png)."""

from __future__ import annotations

from typing import Any

import yaml

from socnavgen.annotate.store import AnnotationStore, SaveRejected, _backup
from socnavgen.location.location import LOCATION_FILE, load_location
from socnavgen.location.models import LocationConfig, is_placeholder_description
from socnavgen.location.render import EDGE_COLOURS, NODE_COLOURS, UNKNOWN_TYPE_COLOUR
from socnavgen.safeio import atomic_write_text, load_yaml_file

MAX_DESCRIPTION_CHARS = 4000
DOORWAY, ROOM = "DOORWAY", "ROOM"


def page_extras(store: AnnotationStore) -> dict[str, Any]:
    """Added to the page's state: the description, the renderer's palettes, the default node type."""
    schema = store.location.schema
    return {"description": store.location.config.description,
            "palette": {"node": NODE_COLOURS, "edge": EDGE_COLOURS, "unknown": UNKNOWN_TYPE_COLOUR},
            "default_node_type": ROOM if ROOM in schema.node_types else schema.node_types[0]}


def suggest_graph(store: AnnotationStore, node_types: list[str], edge_types: list[str]) -> dict[str, Any]:
    """A scene graph from the map alone (`location extract`), with the page's schema extended by the
    types it uses; the page shows it as an edit the user can undo."""
    from socnavgen.location.extract import extract_scene_graph

    location = store.location
    graph, stats = extract_scene_graph(location.occupancy, location.transform.meters_per_pixel)
    nodes = list(dict.fromkeys([*node_types, *(n.type for n in graph.nodes)]))
    edges = list(dict.fromkeys([*edge_types, *(e.type for e in graph.links)]))
    return {"graph": {"nodes": [{"id": n.id, "type": n.type, "pos": [n.pos[0], n.pos[1]]} for n in graph.nodes],
                      "links": [{"source": e.source, "target": e.target, "type": e.type} for e in graph.links]},
            "schema": {"node_types": nodes, "edge_types": edges},
            "summary": f"{stats.nodes} nodes ({stats.rooms} rooms), {stats.edges} edges"}


def guess_node_type(store: AnnotationStore, x: float, y: float, node_types: list[str]) -> str | None:
    """A sensible type for a node placed at pixel (x, y): DOORWAY in a door-wide gap between wider
    space, ROOM where there is room all round; None when the map says nothing (keep the current type)."""
    occ = store.location.occupancy
    if not occ.inside(x, y) or occ.is_blocked(x, y):
        return None
    mpp = store.location.transform.meters_per_pixel
    clearance = occ.clearance_px
    here = float(clearance[int(y), int(x)]) * mpp
    reach = max(1, int(1.5 / mpp))
    r0, c0 = max(0, int(y) - reach), max(0, int(x) - reach)
    around = float(clearance[r0:int(y) + reach + 1, c0:int(x) + reach + 1].max()) * mpp
    if DOORWAY in node_types and here <= 0.65 and around >= 1.5 * max(here, 0.05):
        return DOORWAY
    if ROOM in node_types and here >= 1.2:
        return ROOM
    return None


def save_description(store: AnnotationStore, text: str) -> dict[str, Any]:
    """Replace the description in location.yaml (other keys kept in order; the old file kept as .bak)."""
    text = text.strip()
    if not text or len(text) > MAX_DESCRIPTION_CHARS or any(ord(c) < 32 and c not in "\n\t" for c in text):
        raise SaveRejected([f"the description must be 1-{MAX_DESCRIPTION_CHARS} printable characters"])
    if is_placeholder_description(text):
        raise SaveRejected(["the description still holds the placeholder sentence: replace it with what the place "
                            "is, who moves around in it and what each node and edge type means"])
    path = store.root / LOCATION_FILE
    data = load_yaml_file(path)
    data["description"] = text
    LocationConfig.model_validate(data)  # never write a config that would not load back
    _backup(path)
    atomic_write_text(path, yaml.safe_dump(data, sort_keys=False, allow_unicode=True, width=100))
    store.location = load_location(store.root)
    return {"saved": [LOCATION_FILE], "description": text}
