"""Two measurements of a map that a planner needs and a scene graph does not say: how wide the way
between two nodes is, and from how far two people approaching a turn can see each other.

Both are measured on the occupancy map (location/occupancy.py) in pixels and returned in metres.
"""

from __future__ import annotations

import math

import numpy as np
from scipy import ndimage

from socnavgen.location.location import Location
from socnavgen.location.traverse import DETOUR_BAND_M

SIGHT_STEP_M = 0.1  # m: how finely two approaching people are moved toward a turn when testing sight


def passage_width_m(location: Location, a: str, b: str, band_m: float = DETOUR_BAND_M) -> float:
    """Free width (m) of the widest way from node a to node b that stays within `band_m` of the straight
    edge (the band the traversability rule lets a person step aside in): twice the largest clearance a
    disc can keep all the way, the two nodes included. A door node in a 0.9 m door gives 0.9 m; a
    diagonal approach that grazes a table corner does not make a wide room narrow."""
    sg = location.scene_graph
    clearance = location.occupancy.clearance_px
    mpp = location.transform.meters_per_pixel
    pa, pb = np.asarray(sg.node(a).pos, float), np.asarray(sg.node(b).pos, float)
    band = band_m / mpp
    margin = int(math.ceil(band)) + 2
    h, w = clearance.shape
    r0, r1 = max(0, int(min(pa[1], pb[1])) - margin), min(h, int(max(pa[1], pb[1])) + margin + 1)
    c0, c1 = max(0, int(min(pa[0], pb[0])) - margin), min(w, int(max(pa[0], pb[0])) + margin + 1)
    sa = (int(round(pa[1])) - r0, int(round(pa[0])) - c0)
    sb = (int(round(pb[1])) - r0, int(round(pb[0])) - c0)
    if not (0 <= sa[0] < r1 - r0 and 0 <= sa[1] < c1 - c0 and 0 <= sb[0] < r1 - r0 and 0 <= sb[1] < c1 - c0):
        return 0.0  # a node outside the image: `location check` reports it
    window = clearance[r0:r1, c0:c1]
    rows, cols = np.ogrid[r0:r1, c0:c1]
    d = pb - pa
    t = np.clip(((cols - pa[0]) * d[0] + (rows - pa[1]) * d[1]) / max(1e-9, float(d @ d)), 0.0, 1.0)
    in_band = (cols - (pa[0] + t * d[0])) ** 2 + (rows - (pa[1] + t * d[1])) ** 2 <= band * band
    ceiling = min(window[sa], window[sb])
    if ceiling <= 0:
        return 0.0
    levels = np.unique(window[in_band & (window > 0) & (window <= ceiling)])
    if levels.size == 0:
        return 0.0

    def joined(level: float) -> bool:
        labels, _ = ndimage.label((window >= level) & in_band, structure=np.ones((3, 3)))
        return bool(labels[sa]) and labels[sa] == labels[sb]

    if not joined(float(levels[0])):
        return 0.0
    lo, hi = 0, len(levels) - 1  # the largest level at which a and b are still joined (bisection)
    while lo < hi:
        mid = (lo + hi + 1) // 2
        if joined(float(levels[mid])):
            lo = mid
        else:
            hi = mid - 1
    return round(2 * float(levels[lo]) * mpp, 2)


def segments_clear_px(blocked: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Line of sight between pixel points a[k] and b[k] (complex x + iy) on a blocked grid, by the rule of the
    simulator's sim/world/queries.line_of_sight that the verifier's `los` signal uses: no blocked cell (nor
    one off the map) among samples every half pixel or closer, the two end samples not looked at. (numpy
    here, numba there: location sits below sim; tests/location checks that the two agree.)"""
    a, b = np.broadcast_arrays(np.asarray(a, complex).ravel(), np.asarray(b, complex).ravel())
    d = b - a
    count = np.maximum(2, np.ceil(np.abs(d) / 0.5).astype(np.intp) + 1)
    k = np.arange(1, int(count.max()) - 1 if count.size else 1)
    if k.size == 0:
        return np.ones(a.shape, dtype=bool)
    frac = k[None, :] / (count[:, None] - 1)
    points = a[:, None] + d[:, None] * frac
    cols, rows = np.floor(points.real + 0.5).astype(np.intp), np.floor(points.imag + 0.5).astype(np.intp)
    h, w = blocked.shape
    inside = (cols >= 0) & (cols < w) & (rows >= 0) & (rows < h)
    hit = ~inside | blocked[np.clip(rows, 0, h - 1), np.clip(cols, 0, w - 1)]
    return ~np.any(hit & (k[None, :] < (count[:, None] - 1)), axis=1)


def _ways_in(location: Location, turn: str, first: str) -> list[list[str]]:
    """The ways into node `turn` through its neighbour `first`: [turn, first, before] for each other neighbour
    `before` of `first` (the edge and the edge before it), or [turn, first] when `first` is a dead end."""
    before = [n for n in sorted(location.graph.neighbors(first)) if n != turn]
    return [[turn, first, n] for n in before] or [[turn, first]]


def _along(chain: np.ndarray, s: np.ndarray) -> np.ndarray:
    """Points at arc lengths `s` (pixels) along a polyline from its first point (clamped to its end)."""
    seg = np.abs(np.diff(chain))
    cum = np.concatenate([[0.0], np.cumsum(seg)])
    s = np.clip(s, 0.0, cum[-1])
    i = np.clip(np.searchsorted(cum, s, side="right") - 1, 0, len(seg) - 1)
    frac = np.where(seg[i] > 0, (s - cum[i]) / np.where(seg[i] > 0, seg[i], 1.0), 0.0)
    return chain[i] + (chain[i + 1] - chain[i]) * frac


def approach_sights(location: Location, turn: str, a: str, b: str, ratios: tuple[float, ...] = (1.0,)
                    ) -> dict[tuple[str, str], float | None]:
    """The robot walks into node `turn` through `a`, a person through `b`, each along every way in (the edge and
    the edge before it), both arriving together, the person at each of `ratios` times the robot's speed. Per
    pair of ways (keyed by the node each comes from), the largest centre distance (m) at which they first see
    each other by the verifier's line of sight, or None when they see each other from where they come
    (nothing hides them on that approach)."""
    sg, mpp = location.scene_graph, location.transform.meters_per_pixel
    blocked = location.occupancy.blocked

    def line(chain: list[str]) -> np.ndarray:
        return np.array([complex(*sg.node(n).pos) for n in chain])

    step = SIGHT_STEP_M / mpp
    out: dict[tuple[str, str], float | None] = {}
    for robot_way in _ways_in(location, turn, a):
        for person_way in _ways_in(location, turn, b):
            robot, person = line(robot_way), line(person_way)
            worst: float | None = 0.0
            for k in ratios:
                length = max(float(np.abs(np.diff(robot)).sum()), float(np.abs(np.diff(person)).sum()) / k)
                s = np.arange(length, -step / max(1.0, k), -step / max(1.0, k))  # from afar to the node
                r, q = _along(robot, s), _along(person, k * s)
                seen = np.flatnonzero(segments_clear_px(blocked, r, q))
                if seen.size and seen[0] == 0:
                    worst = None
                    break
                if seen.size:
                    worst = max(worst or 0.0, round(float(abs(r[seen[0]] - q[seen[0]])) * mpp, 1))
            out[(robot_way[-1], person_way[-1])] = worst
    return out
