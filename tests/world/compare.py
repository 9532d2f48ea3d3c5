"""Compare an imported map with a reference map: IoU of occupied cells through both maps' own
transforms (no alignment), and IoU after the best rigid alignment (for SLAM maps drawn in their own
rotated frame). Used by the tests and by benchmarks/world_bench.py."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from socnavgen.location.location import read_nav2_yaml
from socnavgen.location.occupancy import load_image_gray, occupancy_from_image
from socnavgen.location.transform import Transform


def occupied_map(map_yaml: Path) -> tuple[np.ndarray, Transform]:
    nav2 = read_nav2_yaml(map_yaml)
    gray = load_image_gray(map_yaml.parent / Path(nav2.image).name)
    occ = occupancy_from_image(gray, nav2.thresholds).occupied
    return occ, Transform.from_nav2(nav2.resolution, nav2.origin, gray.shape[0])


def iou_in_world(ours_yaml: Path, ref_yaml: Path) -> float:
    """IoU on the reference's grid: a reference cell counts as ours when any of our occupied cells'
    centres falls inside it (both maps' transforms, no alignment)."""
    ours, t_ours = occupied_map(ours_yaml)
    ref, t_ref = occupied_map(ref_yaml)
    rows, cols = np.nonzero(ours)
    world = t_ours.pixels_to_world(np.stack([cols, rows], axis=1))
    px = np.floor(t_ref.worlds_to_pixel(world) + 0.5).astype(int)  # pixel centres are integers
    inside = (px[:, 0] >= 0) & (px[:, 0] < ref.shape[1]) & (px[:, 1] >= 0) & (px[:, 1] < ref.shape[0])
    mine = np.zeros_like(ref)
    mine[px[inside, 1], px[inside, 0]] = True
    return float((mine & ref).sum() / max(1, (mine | ref).sum()))


def best_rigid_iou(ours_yaml: Path, ref_yaml: Path, angles_deg: np.ndarray | None = None) -> tuple[float, float]:
    """(IoU, angle in degrees) of our occupied cells against the reference's after the rotation (a
    quarter turn plus a small angle) and integer shift that overlap them most. Both maps must share
    the resolution."""
    from scipy import ndimage, signal

    ours, t_ours = occupied_map(ours_yaml)
    ref, t_ref = occupied_map(ref_yaml)
    if not math.isclose(t_ours.meters_per_pixel, t_ref.meters_per_pixel, rel_tol=1e-6):
        raise ValueError("the maps must share the resolution")
    angles = np.arange(-6.0, 6.01, 0.5) if angles_deg is None else angles_deg
    best = (0.0, 0.0)
    ref_f = ref.astype(np.float32)
    for quarter in range(4):
        base = np.rot90(ours, quarter)
        for angle in angles:
            turned = ndimage.rotate(base.astype(np.uint8), angle, order=0, reshape=True) > 0
            score = signal.fftconvolve(ref_f, turned[::-1, ::-1].astype(np.float32), mode="full")
            dy, dx = np.unravel_index(int(np.argmax(score)), score.shape)
            oy, ox = dy - (turned.shape[0] - 1), dx - (turned.shape[1] - 1)
            placed = np.zeros_like(ref)
            r0, c0 = max(0, oy), max(0, ox)
            r1, c1 = min(ref.shape[0], oy + turned.shape[0]), min(ref.shape[1], ox + turned.shape[1])
            if r1 <= r0 or c1 <= c0:
                continue
            placed[r0:r1, c0:c1] = turned[r0 - oy:r1 - oy, c0 - ox:c1 - ox]
            iou = float((placed & ref).sum() / max(1, (placed | ref).sum()))
            if iou > best[0]:
                best = (iou, quarter * 90 + float(angle))
    return best
