"""Time `location from-world` on the AWS small warehouse (the shipped test data) and on a generated
world of 2,000 models (shelves, crates and pillars on a grid, some turned), and print the agreement
with the SocRATES authors' map and the repository's SLAM map. One command, a printed table:

    python benchmarks/world_bench.py
"""

from __future__ import annotations

import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from tests.world.compare import best_rigid_iou, iou_in_world  # noqa: E402
from tests.world.conftest import DATA, static_model, unpack, world_file  # noqa: E402

from socnavgen.location.world_import import WorldImportOptions, import_world  # noqa: E402
from socnavgen.location.world_raster import SliceOptions  # noqa: E402


def generated_world(folder: Path, count: int = 2000) -> Path:
    kinds = ["<box><size>1 1 2.2</size></box>", "<box><size>1 1 0.6</size></box>",
             "<cylinder><radius>0.5</radius><length>2.5</length></cylinder>"]
    per_row = 50  # racks of 50 objects 1 m apart, rows 4 m apart: a 50 m x 160 m store
    body = "".join(static_model(f"shelf_{i}" if i % 3 == 0 else f"crate_{i}" if i % 3 == 1 else f"pillar_{i}",
                                f"{(i % per_row) * 1.0} {(i // per_row) * 4.0} 1 0 0 {(i % 4) * 1.5707963}", kinds[i % 3])
                   for i in range(count))
    return world_file(folder, body, name="generated.world")


def main() -> None:
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        tmp_path = Path(tmp)
        models = unpack(DATA / "aws_small_warehouse" / "models.tar.xz", tmp_path / "aws") / "models"
        warehouse = DATA / "aws_small_warehouse" / "no_roof_small_warehouse.world"
        cases = [("AWS small warehouse (default slab)", warehouse, [models], WorldImportOptions()),
                 ("AWS small warehouse (--head 0.5)", warehouse, [models],
                  WorldImportOptions(slice=SliceOptions(head=0.5))),
                 ("generated, 2,000 models", generated_world(tmp_path / "gen"), [], WorldImportOptions())]
        outs = {}
        for label, world, dirs, opts in cases:
            out = tmp_path / f"out{len(outs)}"
            start = time.perf_counter()
            result = import_world(world, out, dirs, opts)
            total = time.perf_counter() - start
            outs[label] = out
            rows.append((label, len(result.world.models), len(result.world.shapes), result.footprints,
                         f"{result.size[0]}x{result.size[1]}", result.stats.nodes, result.seconds, total))
        socrates = ROOT / "tests" / "extract" / "data" / "socrates_small_warehouse" / "map.yaml"
        slam = DATA / "aws_small_warehouse" / "map_005" / "map.yaml"
        agreement = [(label, iou_in_world(outs[label] / "map.yaml", socrates),
                      best_rigid_iou(outs[label] / "map.yaml", slam)) for label in list(outs)[:2]]
    print(f"{'world':36} {'models':>6} {'shapes':>6} {'slices':>6} {'cells':>9} {'nodes':>5} "
          f"{'read':>5} {'slice':>5} {'raster':>6} {'extract':>7} {'write':>5} {'total s':>7}")
    for label, m, s, f, cells, nodes, sec, total in rows:
        print(f"{label:36} {m:6d} {s:6d} {f:6d} {cells:>9} {nodes:5d} {sec['read']:5.2f} {sec['slice']:5.2f} "
              f"{sec['raster']:6.2f} {sec['extract']:7.2f} {sec['write']:5.2f} {total:7.2f}")
    print()
    print(f"{'occupied-cell IoU':36} {'SocRATES map (own transforms)':>30} {'AWS SLAM map 005 (best rigid)':>30}")
    for label, iou, (rigid, angle) in agreement:
        print(f"{label:36} {iou:30.3f} {f'{rigid:.3f} at {angle:g} deg':>30}")


if __name__ == "__main__":
    main()
