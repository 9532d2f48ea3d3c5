"""Runtime of `location extract` on procedurally generated office/warehouse maps.

    python benchmarks/extract_bench.py            # 1000x1000 and 1500x1500, densities 0.5 / 1 / 2

Prints one row per run: map size, skeleton pixels, graph size, time per stage and in total
(nodes -1: more nodes than the 1296 two-character ids allow at that density).
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from skimage.morphology import skeletonize

from socnavgen.errors import ValidationFailed
from socnavgen.location.extract import ExtractOptions, ExtractStats, extract_scene_graph, walkable_space
from socnavgen.location.occupancy import occupancy_from_image

RES = 0.05  # metres per pixel


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


def run(size: int, density: float, seed: int) -> dict:
    img = office_map(size, seed)
    t0 = time.perf_counter()
    occ = occupancy_from_image(img)
    _ = occ.clearance_px
    t1 = time.perf_counter()
    skel = skeletonize(walkable_space(occ, max(1.0, 0.25 / RES), False))
    t2 = time.perf_counter()
    try:
        graph, stats = extract_scene_graph(occ, RES, ExtractOptions(density=density, seed=seed))
    except ValidationFailed:  # more nodes than 2-character ids allow: report it as a row
        stats = ExtractStats(nodes=-1, edges=-1)
    t3 = time.perf_counter()
    return {"size": f"{size}x{size}", "density": density, "skeleton px": int(skel.sum()), "nodes": stats.nodes,
            "edges": stats.edges, "intersections": stats.types.get("INTERSECTION", 0),
            "occupancy+EDT s": t1 - t0, "skeleton s": t2 - t1, "extract total s": t3 - t2}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[1000, 1500])
    parser.add_argument("--densities", type=float, nargs="+", default=[0.5, 1.0, 2.0])
    parser.add_argument("--repeat", type=int, default=3, help="runs per row; the fastest is reported")
    args = parser.parse_args()
    rows = []
    for size in args.sizes:
        for density in args.densities:
            runs = [run(size, density, seed=0) for _ in range(args.repeat)]
            rows.append(min(runs, key=lambda r: r["extract total s"]))
    headers = list(rows[0])
    widths = [max(len(h), *(len(_fmt(r[h])) for r in rows)) for h in headers]
    print(" | ".join(h.ljust(w) for h, w in zip(headers, widths, strict=True)))
    print("-|-".join("-" * w for w in widths))
    for r in rows:
        print(" | ".join(_fmt(r[h]).rjust(w) for h, w in zip(headers, widths, strict=True)))


def _fmt(value: object) -> str:
    return f"{value:.3f}" if isinstance(value, float) else str(value)


if __name__ == "__main__":
    main()
