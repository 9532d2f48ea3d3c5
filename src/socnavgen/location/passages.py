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


def first_sight_m(location: Location, turn: str, a: str, b: str) -> float | None:
    """Two people walk toward node `turn`, one along the edge from `a`, the other along the edge from `b`,
    equally far from it: the centre distance at which they first see each other (line of sight on the
    map). None when they see each other from the far ends of the edges already (nothing hides them)."""
    sg, occ = location.scene_graph, location.occupancy
    mpp = location.transform.meters_per_pixel
    p = np.asarray(sg.node(turn).pos, float)
    ends = [np.asarray(sg.node(n).pos, float) for n in (a, b)]
    lengths = [float(np.linalg.norm(e - p)) for e in ends]
    if min(lengths) < 1e-9:
        return None
    units = [(e - p) / n for e, n in zip(ends, lengths, strict=True)]
    step = SIGHT_STEP_M / mpp
    s = max(lengths)
    first = True
    while s > 0:
        qa, qb = (p + u * min(s, n) for u, n in zip(units, lengths, strict=True))
        if occ.segment_clear((float(qa[0]), float(qa[1])), (float(qb[0]), float(qb[1]))):
            return None if first else round(float(np.linalg.norm(qa - qb)) * mpp, 1)
        first = False
        s -= step
    return 0.0
