"""THE traversability rule of a scene-graph edge, used by `location check`, the annotator's live check,
the importer and `location extract` alike, so all of them give the same verdict at the same level.

People walk edges as straight lines with a body, not as one-pixel rays:
- ok: a disc of a person's radius slides along the straight segment without touching an obstacle
  (the radius shrinks to the clearance at the end nodes, so a node in a narrow door still counts),
  or the line only goes through small things (chairs, pillars, speckle: at most CLUTTER_M across) or
  clips a wall by one pixel, and a short detour of the disc close beside the line joins the two ends;
- warning: the line itself crosses no blocked pixel but the disc does not fit (people squeeze through);
- error: anything else (the line goes through a rack, a wall or unknown space with no way round
  close beside it).

The robot is wider than the gaps people squeeze through: `robot_fits_along` says whether its body (with a margin,
bodies.ROBOT_PASSAGE_WIDTH) gets from one end of an edge to the other; `location extract` keeps only such edges.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import numpy as np

from socnavgen.bodies import PERSON_RADIUS, ROBOT_PASSAGE_WIDTH

DETOUR_FACTOR, DETOUR_EXTRA_M = 1.25, 0.5  # a detour is short: at most 1.25 x the straight length + 0.5 m ...
DETOUR_BAND_M = 1.0  # ... and never farther than this from the straight line
CLUTTER_M = 1.5  # an obstacle whose bounding box fits in this square can be stepped around
CLIP_M = 0.05  # a line may clip a larger obstacle (a wall corner) by this much (at least one pixel)

Verdict = Literal["ok", "warning", "error"]


@dataclass
class EdgeVerdict:
    """How an edge can be walked; `detour_m` is the length of the way around when it had to be searched."""

    level: Verdict
    need_m: float
    length_m: float
    detour_m: float | None = None
    tight_at: tuple[int, int] | None = None  # (x, y) of the first pixel where the disc does not fit


def required_clearance_px(clearance: np.ndarray, a: tuple[float, float], b: tuple[float, float],
                          meters_per_pixel: float, radius_m: float = PERSON_RADIUS) -> float:
    """Clearance (pixels) the straight segment must keep: the person's radius, or less when an end node
    itself stands in a narrower spot (never under one pixel: the line must at least be free)."""
    ends = [float(clearance[int(round(p[1])), int(round(p[0]))]) for p in (a, b)]
    return max(1.0, min(radius_m / meters_per_pixel, *ends))


def _line(a: tuple[float, float], b: tuple[float, float], shape: tuple[int, int]) -> tuple[np.ndarray, np.ndarray]:
    from skimage.draw import line as raster_line

    rows, cols = raster_line(int(round(a[1])), int(round(a[0])), int(round(b[1])), int(round(b[0])))
    keep = (rows >= 0) & (rows < shape[0]) & (cols >= 0) & (cols < shape[1])
    return rows[keep], cols[keep]


def first_tight_pixel(clearance: np.ndarray, a: tuple[float, float], b: tuple[float, float],
                      need_px: float) -> tuple[int, int] | None:
    """(x, y) of the first pixel of segment a-b (drawn both ways) with less than `need_px` clearance."""
    for p, q in ((a, b), (b, a)):
        rows, cols = _line(p, q, clearance.shape)
        tight = np.nonzero(clearance[rows, cols] < need_px)[0]
        if len(tight):
            return int(cols[tight[0]]), int(rows[tight[0]])
    return None


def detour_length_px(clearance: np.ndarray, a: tuple[float, float], b: tuple[float, float], need_px: float,
                     budget_px: float, band_px: float) -> float | None:
    """Length of the shortest way from a to b where the disc fits without leaving the band of
    `band_px` around the segment; None when there is none within `budget_px`."""
    from skimage.graph import MCP_Geometric

    h, w = clearance.shape
    margin = int(math.ceil(band_px)) + 2
    r0, r1 = max(0, int(min(a[1], b[1])) - margin), min(h, int(max(a[1], b[1])) + margin + 1)
    c0, c1 = max(0, int(min(a[0], b[0])) - margin), min(w, int(max(a[0], b[0])) + margin + 1)
    window = clearance[r0:r1, c0:c1]
    rows, cols = np.ogrid[r0:r1, c0:c1]
    dx, dy = b[0] - a[0], b[1] - a[1]
    t = np.clip(((cols - a[0]) * dx + (rows - a[1]) * dy) / max(1e-9, dx * dx + dy * dy), 0.0, 1.0)
    off2 = (cols - (a[0] + t * dx)) ** 2 + (rows - (a[1] + t * dy)) ** 2
    costs = np.where((window >= need_px) & (off2 <= band_px * band_px), 1.0, np.inf)
    start = (int(round(a[1])) - r0, int(round(a[0])) - c0)
    end = (int(round(b[1])) - r0, int(round(b[0])) - c0)
    costs[start] = costs[end] = 1.0  # the end nodes themselves are judged by their own clearance
    mcp = MCP_Geometric(costs, fully_connected=True)
    cumulative, _ = mcp.find_costs([start], [end])
    length = float(cumulative[end])
    return length if math.isfinite(length) and length <= budget_px else None


def _only_small_or_clipped(clearance: np.ndarray, a: tuple[float, float], b: tuple[float, float],
                           meters_per_pixel: float) -> bool:
    """True when every obstacle the straight line enters is small, or is entered by at most CLIP_M."""
    from scipy import ndimage

    rows, cols = _line(a, b, clearance.shape)
    hit = clearance[rows, cols] <= 0
    if not hit.any():
        return True
    reach = int(math.ceil(CLUTTER_M / meters_per_pixel)) + 2
    clip_px = max(1, int(CLIP_M / meters_per_pixel))
    r0, c0 = max(0, int(rows.min()) - reach), max(0, int(cols.min()) - reach)
    window = clearance[r0:int(rows.max()) + reach + 1, c0:int(cols.max()) + reach + 1] <= 0
    labels, _ = ndimage.label(window, structure=np.ones((3, 3)))
    crossed = labels[rows[hit] - r0, cols[hit] - c0]
    boxes = ndimage.find_objects(labels)
    for label in np.unique(crossed):
        box = boxes[label - 1]
        at_edge = box[0].start == 0 or box[1].start == 0 or box[0].stop == window.shape[0] \
            or box[1].stop == window.shape[1]
        small = not at_edge and max(box[0].stop - box[0].start, box[1].stop - box[1].start) <= CLUTTER_M / meters_per_pixel
        if not small and int((crossed == label).sum()) > clip_px:
            return False
    return True


def _parallel_detour(clearance: np.ndarray, a: tuple[float, float], b: tuple[float, float], need_px: float,
                     budget_px: float, band_px: float) -> float | None:
    """Length of a way a -> a' -> b' -> b where a'b' is the segment shifted sideways (within the band)
    and every piece keeps the disc clear; None when no such shift works. A cheap search that finds the
    step around a chair or a speck without the full shortest-path search."""
    dx, dy = b[0] - a[0], b[1] - a[1]
    length = math.hypot(dx, dy)
    if length < 1e-9:
        return None
    nx_, ny_ = -dy / length, dx / length
    for k in range(2, int(band_px) + 1, 2):
        for sign in (1, -1):
            o = sign * k
            a2, b2 = (a[0] + o * nx_, a[1] + o * ny_), (b[0] + o * nx_, b[1] + o * ny_)
            total = length + 2 * k
            if total > budget_px:
                return None
            if all(first_tight_pixel(clearance, p, q, need_px) is None for p, q in ((a2, b2), (a, a2), (b2, b))):
                return total
    return None


def edge_verdict(clearance: np.ndarray, a: tuple[float, float], b: tuple[float, float], meters_per_pixel: float,
                 radius_m: float = PERSON_RADIUS) -> EdgeVerdict:
    """Apply the rule to the edge a-b (pixel positions) on a clearance map (pixels to the nearest
    blocked pixel, as OccupancyGrid.clearance_px)."""
    need = required_clearance_px(clearance, a, b, meters_per_pixel, radius_m)
    length = math.dist(a, b)
    tight = first_tight_pixel(clearance, a, b, need)
    verdict = EdgeVerdict("ok", need * meters_per_pixel, length * meters_per_pixel, tight_at=tight)
    if tight is None:
        return verdict
    if not _only_small_or_clipped(clearance, a, b, meters_per_pixel):
        verdict.level = "warning" if first_tight_pixel(clearance, a, b, 1.0) is None else "error"
        return verdict
    budget = DETOUR_FACTOR * length + DETOUR_EXTRA_M / meters_per_pixel
    band = DETOUR_BAND_M / meters_per_pixel
    detour = _parallel_detour(clearance, a, b, need, budget, band)  # the usual case, found cheaply
    if detour is None:
        detour = detour_length_px(clearance, a, b, need, budget, band)
    if detour is not None:
        verdict.detour_m = detour * meters_per_pixel
        return verdict
    verdict.level = "warning" if first_tight_pixel(clearance, a, b, 1.0) is None else "error"
    return verdict


def segment_walkable(clearance: np.ndarray, a: tuple[float, float], b: tuple[float, float],
                     meters_per_pixel: float, radius_m: float = PERSON_RADIUS) -> bool:
    """The straight test alone (no detour search): what `location extract` guarantees for its own edges."""
    need = required_clearance_px(clearance, a, b, meters_per_pixel, radius_m)
    return first_tight_pixel(clearance, a, b, need) is None


def robot_fits_along(blocked: np.ndarray, a: tuple[float, float], b: tuple[float, float], meters_per_pixel: float,
                     width_m: float = ROBOT_PASSAGE_WIDTH, band_m: float = DETOUR_BAND_M) -> bool:
    """Whether a body `width_m` wide (wall to wall) gets from a to b (pixel positions x, y), the end nodes included,
    without leaving the band of `band_m` round the straight edge (the band a person may step aside in).
    The free width is measured on a half-pixel grid, where a gap n pixels wide measures n pixels: on the pixel
    grid a 7- and an 8-pixel gap both measure 8 (pixel centre to blocked pixel centre, twice), so a 0.7 m gap
    would pass for the 0.8 m the robot needs. Cells off the map count as blocked."""
    from scipy import ndimage

    h, w = blocked.shape
    band = band_m / meters_per_pixel
    margin = int(math.ceil(band + width_m / meters_per_pixel)) + 2  # walls farther out cannot narrow the band
    r0, r1 = max(0, int(min(a[1], b[1])) - margin), min(h, int(max(a[1], b[1])) + margin + 1)
    c0, c1 = max(0, int(min(a[0], b[0])) - margin), min(w, int(max(a[0], b[0])) + margin + 1)
    window = np.pad(blocked[r0:r1, c0:c1], ((int(r0 == 0), int(r1 == h)), (int(c0 == 0), int(c1 == w))),
                    constant_values=True)
    r0, c0 = r0 - int(r0 == 0), c0 - int(c0 == 0)  # the window's first row and column in map pixels
    fine = np.repeat(np.repeat(window, 2, axis=0), 2, axis=1)
    half = ndimage.distance_transform_edt(~fine)  # half pixels to the nearest blocked half-pixel's centre
    rows, cols = np.ogrid[:fine.shape[0], :fine.shape[1]]
    y, x = r0 + (rows - 0.5) / 2, c0 + (cols - 0.5) / 2  # each half-pixel's centre in map pixels
    dx, dy = b[0] - a[0], b[1] - a[1]
    t = np.clip(((x - a[0]) * dx + (y - a[1]) * dy) / max(1e-9, dx * dx + dy * dy), 0.0, 1.0)
    in_band = (x - (a[0] + t * dx)) ** 2 + (y - (a[1] + t * dy)) ** 2 <= band * band
    labels, _ = ndimage.label((half * meters_per_pixel >= width_m - 1e-6) & in_band, structure=np.ones((3, 3)))

    def at(p: tuple[float, float]) -> set[int]:
        r, c = 2 * (int(round(p[1])) - r0), 2 * (int(round(p[0])) - c0)
        return set(labels[r:r + 2, c:c + 2].ravel().tolist()) - {0}

    return bool(at(a) & at(b))
