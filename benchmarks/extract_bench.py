"""`location extract` against the graphs a person drew, and its runtime on large generated maps.

    PYTHONPATH=src:. python benchmarks/extract_bench.py              # both tables
    PYTHONPATH=src:. python benchmarks/extract_bench.py --quality    # only the person's-graph table

Quality table, one row per map (the bundled examples and the maps of tests/extract/drawn_maps.py,
with the person's graphs of tests/extract/data/person_graphs.json): node counts, their ratio, rooms
with a ROOM node, recall (person's nodes with a compatible extracted node within 2 m) and precision
(extracted nodes with a compatible person's node within 2 m), and the extraction time. SocRATES's
graphs cover one part of their maps (a lobby, a corridor loop): they are compared with the extracted
nodes within 2 m of what the person drew (their nodes and edges); "whole map" is the full extracted count.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT / "src"), str(ROOT)]

import numpy as np  # noqa: E402
from skimage.morphology import skeletonize  # noqa: E402

from socnavgen.errors import ValidationFailed  # noqa: E402
from socnavgen.location.extract import (  # noqa: E402
    ExtractOptions,
    ExtractStats,
    extract_location,
    extract_scene_graph,
    walkable_space,
)
from socnavgen.location.extract_score import rooms_with_room_node, score, within_drawn_part  # noqa: E402
from socnavgen.location.occupancy import occupancy_from_image  # noqa: E402

RES = 0.05  # metres per pixel


def quality_rows(detail: float) -> list[dict]:
    from tests.extract.person_graphs import NAMES, SOCRATES, person_map

    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for name in NAMES + SOCRATES:
            pm = person_map(name, Path(tmp))
            t0 = time.perf_counter()
            location, stats = extract_location(pm.map_yaml, Path(tmp) / f"out_{name}",
                                               ExtractOptions(seed=1, detail=detail))
            elapsed = time.perf_counter() - t0
            graph = location.scene_graph
            if pm.partial:  # the person drew one part of the map: compare there
                graph = within_drawn_part(pm.graph, graph, pm.meters_per_pixel)
            s = score(pm.graph, graph, pm.meters_per_pixel, aliases=pm.aliases)
            rooms_found = rooms_with_room_node(location.scene_graph, pm.rooms, location.occupancy.blocked,
                                               pm.meters_per_pixel)
            rows.append({"map": name, "compared on": "drawn part" if pm.partial else "whole map",
                         "whole map": stats.nodes, "person nodes": s.person_nodes, "extracted": s.extracted_nodes,
                         "ratio": round(s.size_ratio, 2),
                         "rooms with ROOM": f"{rooms_found}/{len(pm.rooms)}",
                         "recall": round(s.recall, 2), "precision": round(s.precision, 2),
                         "time s": round(elapsed, 2), "missed": "; ".join(s.missed)})
    return rows


def office_map(size: int, seed: int = 0) -> np.ndarray:
    """A grid of 1.6 m corridors; each block is two rooms with 0.9 m doors, a shelf hall or an open hall,
    plus sensor speckle: enough structure to exercise every stage."""
    rng = np.random.default_rng(seed)
    img = np.zeros((size, size), np.uint8)
    pitch, corridor, door = 250, 32, 18
    for k in range(1, size // pitch + 1):
        c = min(size - corridor - 10, k * pitch - pitch // 2)
        img[10:size - 10, c:c + corridor] = 254
        img[c:c + corridor, 10:size - 10] = 254
    starts = [min(size - corridor - 10, k * pitch - pitch // 2) for k in range(1, size // pitch + 1)]
    for r0, r1 in zip(starts, starts[1:], strict=False):
        for c0, c1 in zip(starts, starts[1:], strict=False):
            top, bottom, left, right = r0 + corridor + 10, r1 - 10, c0 + corridor + 10, c1 - 10
            kind = rng.integers(3)
            img[top:bottom, left:right] = 254
            if kind == 0:  # two rooms side by side, each with a door onto a corridor
                mid = (left + right) // 2
                img[top:bottom, mid - 5:mid + 5] = 0
                for lo, hi in ((left, mid - 5), (mid + 5, right)):
                    d = int(rng.integers(lo + 10, hi - door - 10))
                    img[bottom:bottom + 10, d:d + door] = 254
            elif kind == 1:  # shelf rows
                for y in range(top + 30, bottom - 30, 40):
                    img[y:y + 14, left + 30:right - 30] = 0
                d = (left + right) // 2
                img[top - 10:top, d:d + 2 * door] = 254
            else:  # open hall with pillars, opened on two sides
                for y in range(top + 40, bottom - 20, 60):
                    for x in range(left + 40, right - 20, 60):
                        img[y:y + 8, x:x + 8] = 0
                img[(top + bottom) // 2:(top + bottom) // 2 + 2 * door, left - 10:left] = 254
                img[(top + bottom) // 2:(top + bottom) // 2 + 2 * door, right:right + 10] = 254
    speckle = rng.random(img.shape) < 0.0005
    img[speckle & (img > 0)] = 0
    return img


def run(size: int, detail: float, seed: int) -> dict:
    img = office_map(size, seed)
    t0 = time.perf_counter()
    occ = occupancy_from_image(img)
    _ = occ.clearance_px
    t1 = time.perf_counter()
    skel = skeletonize(walkable_space(occ, max(1.0, 0.25 / RES), False))
    t2 = time.perf_counter()
    try:
        _, stats = extract_scene_graph(occ, RES, ExtractOptions(detail=detail, seed=seed))
    except ValidationFailed:  # more nodes than 2-character ids allow: report it as a row
        stats = ExtractStats(nodes=-1, edges=-1)
    t3 = time.perf_counter()
    return {"size": f"{size}x{size}", "detail": detail, "skeleton px": int(skel.sum()), "nodes": stats.nodes,
            "edges": stats.edges, "rooms": stats.rooms, "occupancy+EDT s": round(t1 - t0, 3),
            "skeleton s": round(t2 - t1, 3), "extract total s": round(t3 - t2, 3)}


def print_table(rows: list[dict], skip: tuple[str, ...] = ()) -> None:
    keys = [k for k in rows[0] if k not in skip]
    widths = {k: max(len(k), *(len(str(r[k])) for r in rows)) for k in keys}
    print(" | ".join(k.ljust(widths[k]) for k in keys))
    print("-+-".join("-" * widths[k] for k in keys))
    for r in rows:
        print(" | ".join(str(r[k]).ljust(widths[k]) for k in keys))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quality", action="store_true", help="only the person's-graph table")
    parser.add_argument("--detail", type=float, default=1.0)
    parser.add_argument("--sizes", type=int, nargs="+", default=[1000, 1500])
    args = parser.parse_args()
    rows = quality_rows(args.detail)
    print_table(rows, skip=("missed",))
    for r in rows:
        if r["missed"]:
            print(f"  {r['map']} missed: {r['missed']}")
    if args.quality:
        return
    print()
    print_table([run(size, detail, seed=0) for size in args.sizes for detail in (0.5, 1.0, 2.0)])


if __name__ == "__main__":
    main()
