"""Who is near whom in a large crowd: a cell list (compiled).

Above GRID_MIN people, the physics does not look at every pair: each step the people are sorted into square
cells (a counting sort, stable: people of one cell in index order), so that a person's neighbours within a
distance are found in the few cells around theirs. Cells are numbered row by row, so the cells lo..hi of one
row are one contiguous slice of `order` (`span`). Built once per step on the positions after the walking step,
it serves both the social force and the contact step. Nothing is allocated per step: the arrays are made
with the simulation and the cells grow larger when the crowd spreads over more of them than were made.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from socnavgen.bodies import PERSON_KEEP_GAP, PERSON_STAND_GAP
from socnavgen.sim.jit import jit

LOOK_AHEAD = 0.5  # m: people this much beyond the (standing) keep gap are in a walker's step's reach (people.spacing)
GRID_MIN = 64  # above this many people, neighbours come from the cell list (linear cost)
CELLS_PER_PERSON = 4  # cells made per person (the cells grow when the crowd's extent needs more)
NX, NY, REACH_SOCIAL, REACH_CONTACT = 0, 1, 2, 3  # Grid.dims


class Grid(NamedTuple):
    """The cell list of one simulation (zero-sized below GRID_MIN people)."""

    cell: np.ndarray  # (n,) int64: each person's cell
    order: np.ndarray  # (n,) int64: people sorted by cell (stable)
    start: np.ndarray  # (cells + 1,) int64: cell c holds order[start[c]:start[c + 1]]
    dims: np.ndarray  # (4,) int64: NX, NY, and how many cells around a person the social force and the contacts reach
    found: np.ndarray  # (n,) int64: the contact step's list of one person's overlaps
    pos: np.ndarray  # (n,) complex: the positions in `order` (contiguous: the pair loops read them in a row)
    vel: np.ndarray  # (n,) complex: the velocities in `order`
    acc: np.ndarray  # (n,) complex: a sum per person in `order` (the social force's)


def new_grid(n: int, cells: bool | None = None) -> Grid:
    """The arrays of n people's cell list; `cells`: whether they use one (default: above GRID_MIN people)."""
    m = n if (n > GRID_MIN if cells is None else cells) else 0
    return Grid(np.zeros(m, np.int64), np.zeros(m, np.int64), np.zeros(CELLS_PER_PERSON * m + 1 if m else 0, np.int64),
                np.zeros(4, np.int64), np.zeros(n, np.int64), np.zeros(m, complex), np.zeros(m, complex),
                np.zeros(m, complex))


@jit(inline=True)
def active(grid, n):  # noqa: ANN001, ANN201
    """Whether this crowd uses the cell list."""
    return n > 0 and grid.order.shape[0] == n


@jit
def build(grid, people, social_reach):  # noqa: ANN001, ANN201
    """Sort the people into cells of half the social force's reach (at least the contact distance: the sum of
    the two largest radii) over the box of their positions; a position that is not finite lands in a border
    cell, and an infinite reach makes one cell of everyone."""
    n = people.shape[0]
    x0, y0, x1, y1, radius = math.inf, math.inf, -math.inf, -math.inf, 0.0
    for i in range(n):
        p = people[i].pos
        if p.real < x0:
            x0 = p.real
        if p.real > x1:
            x1 = p.real
        if p.imag < y0:
            y0 = p.imag
        if p.imag > y1:
            y1 = p.imag
        radius = max(radius, people[i].radius)
    if not (x1 >= x0 and y1 >= y0):  # nobody at a finite position
        x0, y0, x1, y1 = 0.0, 0.0, 0.0, 0.0
    contact = 2.0 * radius + max(PERSON_KEEP_GAP, PERSON_STAND_GAP) + LOOK_AHEAD
    if math.isfinite(social_reach):
        size = max(0.5 * social_reach, contact, 1e-3)
        cap = grid.start.shape[0] - 1
        while True:
            nx = int(min((x1 - x0) / size, 1e9)) + 1
            ny = int(min((y1 - y0) / size, 1e9)) + 1
            if nx * ny <= cap:
                break
            size *= 2.0
        inv = 1.0 / size
        grid.dims[REACH_SOCIAL] = int(math.ceil(social_reach * inv))
    else:
        nx, ny, inv = 1, 1, 0.0
        grid.dims[REACH_SOCIAL] = 1
    grid.dims[NX], grid.dims[NY] = nx, ny
    grid.dims[REACH_CONTACT] = max(int(math.ceil(contact * inv)), 1)
    start, cell, order = grid.start, grid.cell, grid.order
    for c in range(nx * ny + 1):
        start[c] = 0
    for i in range(n):
        p = people[i].pos
        cx = min(max(int((p.real - x0) * inv), 0), nx - 1) if math.isfinite(p.real) else 0
        cy = min(max(int((p.imag - y0) * inv), 0), ny - 1) if math.isfinite(p.imag) else 0
        cell[i] = cx + nx * cy
        start[cell[i] + 1] += 1
    for c in range(nx * ny):
        start[c + 1] += start[c]
    for i in range(n):  # stable counting sort; start[c] ends at the end of cell c ...
        order[start[cell[i]]] = i
        start[cell[i]] += 1
    for c in range(nx * ny, 0, -1):  # ... and is moved back to its beginning
        start[c] = start[c - 1]
    start[0] = 0
    for k in range(n):
        grid.pos[k], grid.vel[k] = people[order[k]].pos, people[order[k]].vel


@jit(inline=True)
def span(grid, gy, lo, hi):  # noqa: ANN001, ANN201
    """The slice of `order` holding the cells lo..hi of row gy (clamped to the grid; empty when outside)."""
    nx, ny = grid.dims[NX], grid.dims[NY]
    lo, hi = max(lo, 0), min(hi, nx - 1)
    if gy < 0 or gy >= ny or lo > hi:
        return 0, 0
    return grid.start[lo + nx * gy], grid.start[hi + nx * gy + 1]


@jit(inline=True)
def overlaps(people, snap, i, j):  # noqa: ANN001, ANN201
    """Whether i and j came closer than PERSON_KEEP_GAP (by more than a micrometre) where the walking step left
    them (the squared distance first: most pairs are far apart, and then the exact test could not hold either)."""
    d, reach = snap[i] - snap[j], people[i].radius + people[j].radius + PERSON_KEEP_GAP
    if d.real * d.real + d.imag * d.imag > reach * reach:
        return False
    return reach - abs(d) > 1e-6


@jit
def near(grid, people, i):  # noqa: ANN001, ANN201
    """The other people within reach of a walker's step (their bodies, the standing keep gap and LOOK_AHEAD) of person
    i, into grid.found; returns how many. Everyone else in index order when the crowd has no cell list, else
    those of the cells around i's (built at the end of the last step) in cell order (the same
    order every run, so a step stays deterministic)."""
    n, found, m = people.shape[0], grid.found, 0
    if not active(grid, n):
        for j in range(n):
            if j != i:
                found[m] = j
                m += 1
        return m
    nx, reach = grid.dims[NX], grid.dims[REACH_CONTACT]
    cx, cy = grid.cell[i] % nx, grid.cell[i] // nx
    for gy in range(cy - reach, cy + reach + 1):
        a, b = span(grid, gy, cx - reach, cx + reach)
        for k in range(a, b):
            j = grid.order[k]
            if j != i:
                found[m] = j
                m += 1
    return m


@jit
def later_overlaps(grid, people, snap, i):  # noqa: ANN001, ANN201
    """The people j > i closer than PERSON_KEEP_GAP to person i (`overlaps`), in index order, into grid.found;
    returns how many. The candidates are `near`'s (every other person, or those of the cells around i's), filtered
    in place: a kept index is written at or before the slot it was read from."""
    found, m = grid.found, 0
    for k in range(near(grid, people, i)):
        j = found[k]
        if j > i and overlaps(people, snap, i, j):
            at = m  # insertion sort: a person overlaps few others
            while at > 0 and found[at - 1] > j:
                found[at] = found[at - 1]
                at -= 1
            found[at] = j
            m += 1
    return m
